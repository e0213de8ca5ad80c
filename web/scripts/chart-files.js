// The measured charts (docs/charts: index.json, PNG, CSV, Markdown, written by
// `make charts`) at /charts/ of the built site and of the dev server, so that
// the Charts page shows the numbers committed with the code that made them.
import { cpSync, existsSync, readFileSync } from "node:fs";
import { extname, join, normalize, resolve, sep } from "node:path";
import { fileURLToPath } from "node:url";

const SOURCE = resolve(fileURLToPath(new URL("../../docs/charts", import.meta.url)));
const KINDS = { ".json": "application/json", ".png": "image/png", ".csv": "text/csv", ".md": "text/markdown" };

export function chartFiles() {
  let outDir;
  return {
    name: "rt-chart-files",
    configResolved(config) {
      outDir = resolve(config.root, config.build.outDir);
    },
    // The dev server answers /charts/<file> from docs/charts.
    configureServer(server) {
      server.middlewares.use("/charts/", (req, res, next) => {
        const file = normalize(join(SOURCE, decodeURIComponent(req.url.split("?")[0])));
        if (!file.startsWith(SOURCE + sep) || !KINDS[extname(file)] || !existsSync(file)) return next();
        res.setHeader("Content-Type", KINDS[extname(file)]);
        res.end(readFileSync(file));
      });
    },
    writeBundle() {
      if (!existsSync(SOURCE)) {
        this.warn(`no ${SOURCE}: the Charts page will say to run make charts`);
        return;
      }
      cpSync(SOURCE, join(outDir, "charts"), {
        recursive: true,
        filter: (path) => !extname(path) || Boolean(KINDS[extname(path)]),
      });
    },
  };
}
