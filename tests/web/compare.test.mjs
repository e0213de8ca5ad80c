// A/B in the image view (headless chromium against the real service): a job
// against itself gives all-zero error maps and zero metrics; the metrics are
// the server's (flip-evaluator, as make charts), for the image and a dragged
// rectangle; the error maps are the EXRs' differences (read by the test's own
// decoder); the wipe shows A left of the handle and B right; X flips; a B
// picked while the jobs are listed again is kept; "Render reference" makes
// the view's reference, and the view's jobs are plotted as time against
// error; marking another job replaces it.
import assert from "node:assert/strict";
import { after, before, describe, test } from "node:test";
import { ARTIFACTS, dragLine, launch, openPage, screenshot } from "./browser.mjs";
import { readExr } from "./exr.mjs";
import { startServer } from "./server.mjs";

const WIDTH = 64;
const HEIGHT = 48;

let server;
let browser;
let page;
const jobs = {};
const exrs = {};

async function api(path, init) {
  const response = await fetch(`${server.url}${path}`, init);
  assert.ok(response.ok, `${path}: HTTP ${response.status} ${await response.clone().text()}`);
  return response;
}

async function render(sceneId, spp) {
  const body = { scene_id: sceneId, settings: { width: WIDTH, height: HEIGHT, samples_per_pixel: spp } };
  let job = await (await api("/api/jobs", { method: "POST", headers: { "Content-Type": "application/json" },
    body: JSON.stringify(body) })).json();
  while (job.state !== "DONE") {
    assert.ok(!["FAILED", "CANCELLED"].includes(job.state), `the job ended ${job.state}`);
    await new Promise((r) => setTimeout(r, 100));
    job = await (await api(`/api/jobs/${job.id}`)).json();
  }
  return job.id;
}

/** Picks B in "Compare with" and a mode; waits until the view shows it. */
async function compareWith(id, mode) {
  await page.selectOption("#compare-job", id);
  await page.waitForFunction((id) => window.rt.image.compare.other === id, id, { timeout: 30_000 });
  await page.selectOption("#compare-mode", mode);
  if (mode === "flip-map") await page.waitForFunction(() => window.rt.image.compare.flip, null, { timeout: 60_000 });
}

const shownValues = () => page.evaluate(() => Array.from(window.rt.image.shown.values));
const metrics = (scope) => page.$eval(`#compare-metrics [data-scope="${scope}"]`, (e) => ({
  rmse: Number(e.dataset.rmse), relativeMse: Number(e.dataset.relativeMse), meanFlip: Number(e.dataset.meanFlip) }));

/** The mean over R, G, B of f(a, b) at each pixel, from the EXRs. */
function perPixel(f) {
  const [a, b] = [exrs.a.channels, exrs.b.channels];
  return Array.from({ length: WIDTH * HEIGHT }, (_, p) => ["R", "G", "B"].reduce((s, c) => s + f(a[c][p], b[c][p]), 0) / 3);
}

describe("compare", { timeout: 200_000 }, () => {
  before(async () => {
    server = await startServer({ artifacts: ARTIFACTS, name: "compare" });
    browser = await launch();
    page = await openPage(browser, server.url);
    const cornell = (await (await api("/api/scenes")).json()).scenes.find((s) => s.name === "cornell.obj");
    jobs.a = await render(cornell.id, 1);
    jobs.b = await render(cornell.id, 16);
    for (const k of ["a", "b"]) exrs[k] = readExr(await (await api(`/api/jobs/${jobs[k]}/image.exr`)).arrayBuffer());
    await page.goto(`/jobs/${jobs.a}`);
    await page.click("#show-image");
    await page.waitForFunction((b) => [...document.querySelectorAll("#compare-job option")].some((o) => o.value === b),
      jobs.b, { timeout: 30_000 });
  });

  after(async () => {
    await browser?.close();
    await server?.stop();
  });

  test("a job against itself: all-zero error maps and zero metrics", async () => {
    await compareWith(jobs.a, "absolute");
    assert.deepEqual(await metrics("image"), { rmse: 0, relativeMse: 0, meanFlip: 0 });
    assert.ok((await shownValues()).every((v) => v === 0), "the absolute error map is all zero");
    await page.selectOption("#compare-mode", "flip-map");
    await page.waitForFunction(() => window.rt.image.compare.flip);
    assert.ok((await shownValues()).every((v) => v === 0), "the HDR-FLIP map is all zero");
  });

  test("the metrics are the server's flip-evaluator numbers, for the image and a dragged rectangle", async () => {
    await compareWith(jobs.b, "absolute");
    const server_ = await (await api(`/api/jobs/${jobs.a}/compare/${jobs.b}`)).json();
    assert.deepEqual(await metrics("image"), { rmse: server_.rmse, relativeMse: server_.relative_mse, meanFlip: server_.mean_flip });
    assert.ok(server_.rmse > 0.005 && server_.mean_flip > 0.005, "1 spp against 16 differs");
    const at = (x, y) => page.evaluate(([x, y]) => {
      const view = window.rt.image.view;
      const rect = view.canvas.getBoundingClientRect();
      return [rect.left + view.offset[0] + x * view.scale, rect.top + view.offset[1] + y * view.scale];
    }, [x, y]);
    const [ax, ay] = await at(8.3, 6.3);
    const [bx, by] = await at(39.7, 29.7);
    await page.keyboard.down("Shift");
    await page.mouse.move(ax, ay);
    await page.mouse.down();
    await page.mouse.move(bx, by, { steps: 4 });
    await page.mouse.up();
    await page.keyboard.up("Shift");
    await page.waitForSelector('#compare-metrics [data-scope="region"]');
    const region = await (await api(`/api/jobs/${jobs.a}/compare/${jobs.b}?x=8&y=6&w=32&h=24`)).json();
    assert.deepEqual(await metrics("region"), { rmse: region.rmse, relativeMse: region.relative_mse, meanFlip: region.mean_flip });
    assert.notEqual(region.rmse, server_.rmse);
    await page.keyboard.press("Escape");
  });

  test("the error maps are the EXRs' differences, with a legend over their range", async () => {
    const kinds = {
      absolute: (a, b) => Math.abs(a - b),
      relative: (a, b) => Math.abs(a - b) / (Math.abs(b) + 0.01),
      squared: (a, b) => (a - b) ** 2,
    };
    for (const [mode, f] of Object.entries(kinds)) {
      await page.selectOption("#compare-mode", mode);
      const shown = await shownValues();
      const expected = perPixel(f);
      const worst = Math.max(...shown.map((v, p) => Math.abs(v - expected[p]) / Math.max(1e-6, expected[p])));
      assert.ok(worst < 1e-5, `${mode}: worst relative difference ${worst}`);
      assert.equal(await page.isChecked("#image-false-color"), false, "the user's false-colour choice is left alone");
      const high = Number(await page.$eval("#image-range-high", (o) => o.value));
      assert.equal(high, Number(Math.max(...expected).toPrecision(4)), `${mode}: the legend's top`);
    }
    await page.selectOption("#compare-mode", "flip-map");
    await page.waitForFunction(() => window.rt.image.compare.flip);
    const flip = await shownValues();
    const mean = flip.reduce((s, v) => s + v, 0) / flip.length;
    const { meanFlip } = await metrics("image");
    assert.ok(Math.abs(mean - meanFlip) < 1e-4 * meanFlip, `the map's mean ${mean} is the metric's ${meanFlip}`);
    await screenshot(page, "compare-flip-map");
  });

  test("the wipe shows A left of the handle and B right of it", async () => {
    await page.selectOption("#compare-mode", "wipe");
    await page.waitForFunction(() => !document.querySelector("#compare-handle").hidden);
    const canvas = await page.locator("#image-view-canvas").boundingBox();
    const middle = await dragLine(page, "#compare-handle", canvas, 0.45);
    await page.waitForTimeout(50);
    const sides = await page.evaluate(([line, middle]) => {
      const { view, display, displayB } = window.rt.image;
      const rect = view.canvas.getBoundingClientRect();
      const screen = (x) => Array.from(view.canvas.getContext("2d")
        .getImageData(Math.round(x - rect.left), Math.round(middle - rect.top), 1, 1).data);
      const source = (canvas, x) => {
        const px = Math.floor((x - rect.left - view.offset[0]) / view.scale);
        const py = Math.floor((middle - rect.top - view.offset[1]) / view.scale);
        return Array.from(canvas.getContext("2d").getImageData(px, py, 1, 1).data);
      };
      const xs = Array.from({ length: 12 }, (_, i) => line + (i < 6 ? -4 - 9 * i : 4 + 9 * (i - 6)));
      return xs.map((x) => ({ left: x < line, screen: screen(x), a: source(display, x), b: source(displayB, x) }));
    }, [canvas.x + 0.45 * canvas.width, middle]);
    for (const s of sides) assert.deepEqual(s.screen, s.left ? s.a : s.b, s.left ? "A left of the line" : "B right of it");
    assert.ok(sides.some((s) => s.a.join() !== s.b.join()), "A and B differ there, so the sides were told apart");
    await screenshot(page, "compare-wipe");
  });

  test("X flips between A and B", async () => {
    await page.selectOption("#compare-mode", "flip");
    const red = (k) => Array.from(exrs[k].channels.R);
    const shownRed = async () => (await shownValues()).filter((_, i) => i % 3 === 0);
    assert.deepEqual(await shownRed(), red("a"));
    await page.click("#image-view-canvas", { position: { x: 5, y: 5 } });
    await page.keyboard.press("x");
    assert.deepEqual(await shownRed(), red("b"));
    await page.keyboard.press("x");
    assert.deepEqual(await shownRed(), red("a"));
  });

  test("a B picked while A's jobs are listed again is kept", async () => {
    // The image view lists the jobs again once A's layers have loaded; a pick
    // made just before, still loading B, once came back empty from that.
    await page.selectOption("#compare-job", "");
    await page.waitForFunction(() => window.rt.image.compare.other === null);
    await page.evaluate((b) => {
      const compare = window.rt.image.compare;
      const select = document.getElementById("compare-job");
      select.value = b;
      select.dispatchEvent(new Event("change"));
      return compare.setJob(compare.job);
    }, jobs.b);
    await page.waitForFunction((b) => window.rt.image.compare.other === b, jobs.b, { timeout: 30_000 });
    assert.equal(await page.$eval("#compare-job", (s) => s.value), jobs.b);
    assert.equal(await page.$eval("#compare-mode", (s) => s.disabled), false);
  });

  test("Render reference makes the view's reference; its jobs are plotted as time against error", async () => {
    const scene = (await (await api("/api/scenes")).json()).scenes.find((x) => x.name === "cornell.obj");
    const before = page.url();
    await page.click("#render-reference");
    await page.waitForURL((url) => url.href !== before && /\/jobs\/[0-9a-f]+$/.test(url.href), { timeout: 15_000 });
    const referenceId = page.url().split("/").pop();
    await page.waitForFunction(() => window.rt.state.job?.state === 3, null, { timeout: 120_000 }); // DONE
    const made = await (await api(`/api/jobs/${referenceId}`)).json();
    assert.equal(made.request.reference, true);
    assert.equal(made.request.interactive, false, "a batch job");
    assert.equal(made.request.settings.samples_per_pixel, 1024);
    assert.ok(made.request.settings.adaptive_threshold > 0, "adaptive");
    await page.waitForFunction(() => /reference/.test(document.querySelector("#reference-status").textContent)
      && document.querySelector("#reference-status").dataset.reference, null, { timeout: 60_000 });
    assert.ok((await (await api(`/api/scenes/${scene.id}`)).json()).reference_jobs.includes(referenceId));

    await page.goto(`/jobs/${jobs.a}`);
    await page.waitForFunction(() => /^Against reference/.test(document.querySelector("#reference-status").textContent),
      null, { timeout: 60_000 });
    const plot = await (await api(`/api/jobs/${jobs.a}/accuracy`)).json();
    assert.equal(plot.reference_id, referenceId, "the rendered reference is the view's");
    const mine = plot.points.find((p) => p.job_id === jobs.a);
    const status = await page.textContent("#reference-status");
    assert.ok(status.includes(`mean FLIP ${Number(mine.error.mean_flip.toPrecision(4))}`), status);
    const dots = await page.$$eval("#accuracy-plot circle", (cs) => cs.map((c) => ({ job: c.dataset.job,
      current: c.classList.contains("current"), title: c.querySelector("title").textContent })));
    assert.deepEqual(dots.map((d) => d.job).sort(), plot.points.map((p) => p.job_id).sort());
    assert.ok(dots.find((d) => d.job === jobs.a).current, "the open job is ringed");
    assert.match(dots.find((d) => d.job === jobs.b).title, /16 spp/);
    const line = await page.textContent(`#history-list small[data-job="${jobs.a}"]`);
    assert.ok(line.includes(`FLIP ${Number(mine.error.mean_flip.toPrecision(3))}`), `the history shows A's error: ${line}`);
    assert.match(await page.textContent(`#history-list small[data-job="${referenceId}"]`), /reference/);
    await screenshot(page, "compare-reference-plot");
    await page.click(`#accuracy-plot circle[data-job="${jobs.b}"]`);
    await page.waitForURL((url) => url.pathname === `/jobs/${jobs.b}`);
    await page.waitForFunction(() => !document.querySelector("#reference-mark").disabled
      && /^Against reference/.test(document.querySelector("#reference-status").textContent), null, { timeout: 60_000 });
    await page.click("#reference-mark");
    await page.waitForFunction(() => /is its view's reference/.test(document.querySelector("#reference-status").textContent));
    const references = (await (await api(`/api/scenes/${scene.id}`)).json()).reference_jobs;
    assert.ok(references.includes(jobs.b) && !references.includes(referenceId), "marking B replaced the view's reference");
  });

  test("no console errors", () => {
    assert.deepEqual(page.problems, []);
  });
});
