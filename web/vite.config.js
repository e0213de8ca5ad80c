// Vite builds the viewer into dist/, which the job service serves at /.
// `npm run dev` proxies the API (REST and the tile WebSocket) to a running
// server: RT_SERVER=http://127.0.0.1:8000 by default.
import { defineConfig } from "vite";

const server = process.env.RT_SERVER || "http://127.0.0.1:8000";

export default defineConfig({
  build: {
    outDir: "dist",
    emptyOutDir: true,
    sourcemap: true,
    chunkSizeWarningLimit: 1200,
  },
  server: {
    proxy: {
      "/api": { target: server, ws: true, changeOrigin: true },
    },
  },
});
