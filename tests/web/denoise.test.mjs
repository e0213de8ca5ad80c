// A denoised job in the viewer (headless chromium against the real service):
// the Denoise setting goes with the job; its image view offers the image
// before denoising and the denoiser's guides beside the colour, each the
// EXR's floats; and the job compares with its own noisy image, the error map
// being the EXR's difference and the metrics the server's.
import assert from "node:assert/strict";
import { after, before, describe, test } from "node:test";
import { ARTIFACTS, launch, openPage, screenshot } from "./browser.mjs";
import { readExr } from "./exr.mjs";
import { startServer } from "./server.mjs";

const WIDTH = 96;
const HEIGHT = 72;

let server;
let browser;
let page;
let jobId;
let exr;

async function api(path) {
  const response = await fetch(`${server.url}${path}`);
  assert.ok(response.ok, `${path}: HTTP ${response.status} ${await response.clone().text()}`);
  return response;
}

const shownValues = () => page.evaluate(() => Array.from(window.rt.image.shown.values));

/** The EXR's channels `names` interleaved per pixel, as a layer holds them. */
const interleaved = (names) => Array.from({ length: WIDTH * HEIGHT * names.length },
  (_, i) => exr.channels[names[i % names.length]][Math.floor(i / names.length)]);

describe("denoising", { timeout: 150_000 }, () => {
  before(async () => {
    server = await startServer({ artifacts: ARTIFACTS, name: "denoise" });
    browser = await launch();
    page = await openPage(browser, server.url);
  });

  after(async () => {
    assert.deepEqual(page?.problems ?? [], [], "no console errors");
    await browser?.close();
    await server?.stop();
  });

  test("a denoised job renders from the viewer's settings", async () => {
    await page.goto("/");
    await page.waitForFunction(() => [...document.querySelectorAll("#scene-list .scene-pick")]
      .some((b) => b.textContent.includes("cornell_sphere_light")), null, { timeout: 30_000 });
    await page.locator("#scene-list .scene-pick", { hasText: "cornell_sphere_light" }).click();
    await page.waitForFunction(() => window.rt.state.scene?.name?.startsWith("cornell_sphere_light"), null,
      { timeout: 30_000 });
    const settings = { width: String(WIDTH), height: String(HEIGHT), samples_per_pixel: "4", light_samples: "1" };
    for (const [name, value] of Object.entries(settings)) await page.fill(`#setting-${name}`, value);
    assert.deepEqual(await page.$$eval("#setting-denoise option", (os) => os.map((o) => o.textContent)),
      ["No denoiser", "OIDN"]);
    await page.selectOption("#setting-denoise", { label: "OIDN" });
    const previous = page.url();
    await page.click("#render-button");
    await page.waitForURL((url) => url.href !== previous && /\/jobs\/[0-9a-f]+$/.test(url.href), { timeout: 15_000 });
    jobId = page.url().split("/").pop();
    await page.waitForFunction((id) => window.rt.state.job?.id === id && window.rt.state.job.state === 3, jobId,
      { timeout: 60_000 }); // DONE
    const job = await (await api(`/api/jobs/${jobId}`)).json();
    assert.equal(job.request.settings.denoise, "OIDN");
    assert.ok(job.denoise_seconds > 0, "the job says how long denoising took");
    exr = readExr(await (await api(`/api/jobs/${jobId}/image.exr`)).arrayBuffer());
    for (const c of ["R", "G", "B"]) assert.ok(exr.channels[`noisy.${c}`], `image.exr has noisy.${c}`);
  });

  test("the image view offers the noisy image and the guides, each the EXR's floats", async () => {
    await page.click("#show-image");
    await page.waitForFunction(() => window.rt.image.layers?.has("noisy"), null, { timeout: 30_000 });
    const names = await page.$$eval("#image-layer option", (os) => os.map((o) => o.value));
    for (const name of ["color", "noisy", "albedo", "normal"]) assert.ok(names.includes(name), `${name} in ${names}`);
    await page.selectOption("#image-layer", "noisy");
    assert.deepEqual(await shownValues(), interleaved(["noisy.R", "noisy.G", "noisy.B"]));
    await page.selectOption("#image-layer", "albedo");
    assert.deepEqual(await shownValues(), interleaved(["albedo.R", "albedo.G", "albedo.B"]));
    await page.selectOption("#image-layer", "color");
    const color = await shownValues();
    assert.deepEqual(color, interleaved(["R", "G", "B"]));
    assert.notDeepEqual(color, interleaved(["noisy.R", "noisy.G", "noisy.B"]), "denoising changed the image");
  });

  test("the job compares with its own image before denoising", async () => {
    const b = `${jobId}:noisy`;
    await page.waitForFunction((b) => [...document.querySelectorAll("#compare-job option")].some((o) => o.value === b),
      b, { timeout: 30_000 });
    await page.selectOption("#compare-job", b);
    await page.waitForFunction((b) => window.rt.image.compare.other === b, b, { timeout: 30_000 });
    await page.selectOption("#compare-mode", "absolute");
    const shown = await shownValues();
    const expected = Array.from({ length: WIDTH * HEIGHT }, (_, p) =>
      ["R", "G", "B"].reduce((s, c) => s + Math.abs(exr.channels[c][p] - exr.channels[`noisy.${c}`][p]), 0) / 3);
    const worst = Math.max(...shown.map((v, p) => Math.abs(v - expected[p]) / Math.max(1e-6, expected[p])));
    assert.ok(worst < 1e-5, `the absolute error map is the EXR's difference (worst relative ${worst})`);
    assert.ok(Math.max(...expected) > 0.01, "the two images differ");
    const server_ = await (await api(`/api/jobs/${jobId}/compare/${jobId}?reference_layer=noisy`)).json();
    const metrics = await page.$eval('#compare-metrics [data-scope="image"]', (e) => ({
      rmse: Number(e.dataset.rmse), relativeMse: Number(e.dataset.relativeMse), meanFlip: Number(e.dataset.meanFlip) }));
    assert.deepEqual(metrics, { rmse: server_.rmse, relativeMse: server_.relative_mse, meanFlip: server_.mean_flip });
    assert.ok(server_.rmse > 0, "denoised against noisy differs");
    await screenshot(page, "denoise-difference");
    await page.selectOption("#compare-mode", "wipe");
    await page.waitForFunction(() => !document.querySelector("#compare-handle").hidden);
    await screenshot(page, "denoise-wipe");
  });
});
