// Headless Debian chromium driven by playwright-core (from web/node_modules;
// no browser download), WebGL through SwiftShader, with every console error
// and page error kept so a test can assert there were none.
import { mkdirSync, rmSync } from "node:fs";
import { createRequire } from "node:module";
import { join } from "node:path";
import { ROOT } from "./server.mjs";

const require = createRequire(join(ROOT, "web", "package.json"));
const { chromium } = require("playwright-core");

export const CHROMIUM = process.env.RT_CHROMIUM || "/usr/bin/chromium";
export const ARTIFACTS = join(ROOT, "test-artifacts", "web");

/** A fresh test-artifacts/web/ (the screenshots of the last run only). */
export function cleanArtifacts() {
  rmSync(ARTIFACTS, { recursive: true, force: true });
  mkdirSync(ARTIFACTS, { recursive: true });
}

export async function launch() {
  mkdirSync(ARTIFACTS, { recursive: true });
  return chromium.launch({
    executablePath: CHROMIUM,
    headless: true,
    args: [
      "--use-angle=swiftshader",
      "--enable-unsafe-swiftshader",
      "--ignore-gpu-blocklist",
      "--no-sandbox",
    ],
  });
}

/** A page at 1280x800 whose console errors and uncaught exceptions are collected in `page.problems`. */
export async function openPage(browser, baseURL, viewport = { width: 1280, height: 800 }) {
  const context = await browser.newContext({ baseURL, viewport, deviceScaleFactor: 1 });
  const page = await context.newPage();
  page.problems = [];
  page.expectedProblems = [];
  page.on("console", (message) => {
    if (message.type() !== "error") return;
    const text = `${message.text()} (${message.location().url || "?"})`;
    const expected = page.expectedProblems.find((pattern) => pattern.test(text));
    if (!expected) page.problems.push(text);
  });
  page.on("pageerror", (error) => page.problems.push(`uncaught: ${error.stack || error.message}`));
  return page;
}

let shot = 0;
/** Saves test-artifacts/web/NN-name.png. */
export async function screenshot(page, name, options = {}) {
  shot += 1;
  const path = join(ARTIFACTS, `${String(shot).padStart(2, "0")}-${name}.png`);
  await page.screenshot({ path, ...options });
  return path;
}

/**
 * Drags a wipe's line (the `handle` selector) along the middle row of `box`
 * (a bounding box) to `fraction` of its width; answers that row's y.
 */
export async function dragLine(page, handle, box, fraction) {
  const grip = await page.locator(handle).boundingBox();
  const middle = box.y + box.height / 2;
  await page.mouse.move(grip.x + grip.width / 2, middle);
  await page.mouse.down();
  await page.mouse.move(box.x + fraction * box.width, middle, { steps: 4 });
  await page.mouse.up();
  return middle;
}
