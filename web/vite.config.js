// Vite builds the viewer (index.html) and the Charts page (charts.html) into
// dist/, which the job service serves at / and /charts. `npm run dev` proxies
// the API (REST and the tile WebSocket) to a running server:
// RT_SERVER=http://127.0.0.1:8000 by default.
import { defineConfig } from "vite";
import { chartFiles } from "./scripts/chart-files.js";

const server = process.env.RT_SERVER || "http://127.0.0.1:8000";

export default defineConfig({
  plugins: [chartFiles()],
  build: {
    outDir: "dist",
    emptyOutDir: true,
    sourcemap: true,
    chunkSizeWarningLimit: 1200,
    rollupOptions: { input: { main: "index.html", charts: "charts.html" } },
  },
  server: {
    proxy: {
      "/api": { target: server, ws: true, changeOrigin: true },
    },
  },
});
