// Starts the real job service for the browser tests: a free port, a fresh
// RT_DATA_DIR, the sample scenes from build/scenes and the viewer from web/dist;
// stop() ends it (and only it).
import { spawn } from "node:child_process";
import { createWriteStream, existsSync, mkdirSync, mkdtempSync, rmSync } from "node:fs";
import { createServer } from "node:net";
import { tmpdir } from "node:os";
import { join, resolve } from "node:path";

export const ROOT = resolve(import.meta.dirname, "..", "..");

function freePort() {
  return new Promise((done, fail) => {
    const probe = createServer();
    probe.once("error", fail);
    probe.listen(0, "127.0.0.1", () => {
      const { port } = probe.address();
      probe.close(() => done(port));
    });
  });
}

async function waitForHealth(url, child, log, timeoutMs, headers) {
  const deadline = Date.now() + timeoutMs;
  while (Date.now() < deadline) {
    if (child.exitCode !== null) throw new Error(`the server exited with ${child.exitCode}; see ${log}`);
    try {
      const response = await fetch(`${url}/api/health`, { headers });
      if (response.ok) return response.json();
    } catch {
      // not listening yet
    }
    await new Promise((r) => setTimeout(r, 250));
  }
  throw new Error(`the server did not answer /api/health within ${timeoutMs / 1000} s; see ${log}`);
}

// token: start it with RT_API_TOKEN; samples: false starts it without the sample scenes;
// env: more of its environment (RT_USERS, quotas); healthToken: the token its health check sends.
export async function startServer({ artifacts, timeoutMs = 90_000, token = "", samples: withSamples = true, name = "server",
  env = {}, healthToken = token } = {}) {
  // RT_WEB_TEST_URL: test a server that is already running (left as it is after).
  if (process.env.RT_WEB_TEST_URL) {
    const url = process.env.RT_WEB_TEST_URL.replace(/\/$/, "");
    const health = await (await fetch(`${url}/api/health`)).json();
    return { url, health, stop: async () => {}, log: null };
  }
  const python = join(ROOT, ".venv", "bin", "python");
  const samples = join(ROOT, "build", "scenes");
  const web = join(ROOT, "web", "dist");
  for (const [what, path] of [["the venv (make build)", python], ["the samples (make samples)", samples], ["the viewer (make web)", join(web, "index.html")]]) {
    if (!existsSync(path)) throw new Error(`missing ${what}: ${path}`);
  }
  const port = await freePort();
  const dataDir = mkdtempSync(join(tmpdir(), "rt-web-test-"));
  mkdirSync(artifacts, { recursive: true });  // a clean checkout has none yet
  const log = join(artifacts, `${name}.log`);
  const out = createWriteStream(log);
  const child = spawn(python, ["-m", "app"], {
    cwd: ROOT,
    env: {
      ...process.env,
      PYTHONPATH: join(ROOT, "server"),
      HOST: "127.0.0.1",
      PORT: String(port),
      RT_DATA_DIR: dataDir,
      RT_SAMPLES_DIR: withSamples ? samples : "",
      RT_WEB_DIR: web,
      RT_API_TOKEN: token,
      ...env,
    },
    stdio: ["ignore", "pipe", "pipe"],
  });
  child.stdout.pipe(out);
  child.stderr.pipe(out);
  const url = `http://127.0.0.1:${port}`;
  const stop = async () => {
    if (child.exitCode === null) {
      const exited = new Promise((r) => child.once("exit", r));
      child.kill("SIGTERM");
      const timer = setTimeout(() => child.kill("SIGKILL"), 10_000);
      await exited;
      clearTimeout(timer);
    }
    rmSync(dataDir, { recursive: true, force: true });
  };
  try {
    const health = await waitForHealth(url, child, log, timeoutMs, healthToken ? { Authorization: `Bearer ${healthToken}` } : {});
    return { url, port, dataDir, health, stop, log };
  } catch (e) {
    await stop();
    throw e;
  }
}
