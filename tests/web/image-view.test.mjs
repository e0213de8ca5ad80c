// The image view (headless chromium against the real service): a done job's
// render fills the main area; at the job's exposure and tone map it shows
// image.png; zoomed past 32x its texels are sharp squares and the readout
// holds image.exr's floats (read here by tests/web/exr.mjs, not by the
// viewer's code); exposure, tone map, channel and false colour change it
// without a new job; a Shift-dragged rectangle's statistics are the EXR's;
// a click traces the pixel in the debugger; the wipe lays the render over the
// 3D view at the job's camera.
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
let job;
let exr;

async function api(path, init) {
  const response = await fetch(`${server.url}${path}`, init);
  assert.ok(response.ok, `${path}: HTTP ${response.status} ${await response.clone().text()}`);
  return response;
}

/** The image view canvas's CSS-pixel position of image pixel (x, y)'s centre. */
function screenOf(x, y) {
  return page.evaluate(([x, y]) => {
    const view = window.rt.image.view;
    const rect = view.canvas.getBoundingClientRect();
    return [rect.left + view.offset[0] + (x + 0.5) * view.scale, rect.top + view.offset[1] + (y + 0.5) * view.scale];
  }, [x, y]);
}

/** What the display canvas holds (the layer as shown), RGBA bytes. */
function shown() {
  return page.evaluate(() => {
    const c = window.rt.image.display;
    return Array.from(c.getContext("2d").getImageData(0, 0, c.width, c.height).data);
  });
}

const jobCount = async () => (await (await api("/api/jobs?limit=200")).json()).jobs.length;

describe("image view", { timeout: 150_000 }, () => {
  before(async () => {
    server = await startServer({ artifacts: ARTIFACTS, name: "image-view" });
    browser = await launch();
    page = await openPage(browser, server.url);
    const scenes = (await (await api("/api/scenes")).json()).scenes;
    const cornell = scenes.find((s) => s.name === "cornell.obj");
    assert.ok(cornell, `the sample Cornell box among ${scenes.map((s) => s.name)}`);
    const body = {
      scene_id: cornell.id, outputs: ["DEPTH", "NORMAL", "BVH_COST", "ALPHA"],
      settings: { width: WIDTH, height: HEIGHT, samples_per_pixel: 4, exposure: 0.7, tone_map: "REINHARD" },
    };
    job = await (await api("/api/jobs", { method: "POST", headers: { "Content-Type": "application/json" },
      body: JSON.stringify(body) })).json();
    for (let state = job.state; state !== "DONE";) {
      assert.ok(!["FAILED", "CANCELLED"].includes(state), `the job ended ${state}`);
      await new Promise((r) => setTimeout(r, 100));
      state = (await (await api(`/api/jobs/${job.id}`)).json()).state;
    }
    exr = readExr(await (await api(`/api/jobs/${job.id}/image.exr`)).arrayBuffer());
  });

  after(async () => {
    await browser?.close();
    await server?.stop();
  });

  test("a done job fills the main area and shows image.png at the job's exposure and tone map", async () => {
    await page.goto(`/jobs/${job.id}`);
    await page.click("#show-image");
    await page.waitForFunction(() => window.rt.image.layers?.size === 5, null, { timeout: 30_000 });
    assert.equal(await page.locator("#viewport").isHidden(), true, "the 3D view gave way");
    const area = await page.locator("#image-view-canvas").boundingBox();
    assert.ok(area.width > 500 && area.height > 400, `the render has the main area (${area.width}x${area.height})`);
    assert.equal(await page.inputValue("#image-exposure"), "0.7");
    assert.equal(await page.inputValue("#image-tonemap"), "REINHARD");
    const png = await page.evaluate(async (url) => {
      const bitmap = await createImageBitmap(await (await fetch(url)).blob(), { colorSpaceConversion: "none" });
      const ctx = new OffscreenCanvas(bitmap.width, bitmap.height).getContext("2d");
      ctx.drawImage(bitmap, 0, 0);
      return Array.from(ctx.getImageData(0, 0, bitmap.width, bitmap.height).data);
    }, `/api/jobs/${job.id}/image.png`);
    const view = await shown();
    assert.equal(view.length, png.length);
    const worst = Math.max(...view.map((v, i) => Math.abs(v - png[i])));
    assert.ok(worst <= 1, `the view is image.png within a code (worst ${worst})`);
    assert.ok(Math.max(...png) > 100, "the box is lit");
    await screenshot(page, "image-view-fit");
  });

  test("zoomed past 32x the texels are sharp and the readout holds the EXR's floats", async () => {
    const [x, y] = [37, 21];
    const [sx, sy] = await screenOf(x, y);
    await page.mouse.move(sx, sy);
    for (let i = 0; i < 12 && (await page.evaluate(() => window.rt.image.view.scale)) < 40; i++) {
      await page.mouse.wheel(0, -300);
      await page.waitForTimeout(30);
    }
    const scale = await page.evaluate(() => window.rt.image.view.scale);
    assert.ok(scale >= 32, `zoomed to ${scale}x`);
    const [cx, cy] = await screenOf(x, y);
    assert.ok(Math.abs(cx - sx) < scale && Math.abs(cy - sy) < scale, "the zoom kept the pixel under the cursor");
    await page.mouse.move(cx, cy);
    await page.waitForFunction(() => !document.querySelector("#pixel-readout").hidden);
    const readout = await page.$$eval("#pixel-readout tr[data-channel]", (rows) =>
      Object.fromEntries(rows.map((r) => [r.dataset.channel, Number(r.dataset.value)])));
    for (const [name, values] of Object.entries(exr.channels)) {
      assert.equal(readout[name], values[y * WIDTH + x], `${name} at (${x}, ${y})`);
    }
    assert.match(await page.textContent("#pixel-readout"), new RegExp(`\\(${x}, ${y}\\)`));
    // Nearest neighbour: every screen pixel inside one texel has the texel's colour.
    await page.waitForTimeout(50);
    const inside = await page.evaluate(([cx, cy, half]) => {
      const canvas = window.rt.image.view.canvas;
      const rect = canvas.getBoundingClientRect();
      const ctx = canvas.getContext("2d");
      const at = (dx, dy) => Array.from(ctx.getImageData(Math.round(cx - rect.left + dx), Math.round(cy - rect.top + dy), 1, 1).data);
      return [at(0, 0), at(-half, -half), at(half, half), at(-half, half), at(half, -half)];
    }, [cx, cy, Math.floor(scale / 2) - 2]);
    for (const colour of inside) assert.deepEqual(colour, inside[0], "one texel, one colour");
    await screenshot(page, "image-view-zoomed-readout");
    await page.click("#image-fit");
  });

  test("exposure, tone map, channel and false colour change the view, not the job", async () => {
    const jobs = await jobCount();
    const before = await shown();
    await page.$eval("#image-exposure", (input) => {
      input.value = "2.7";
      input.dispatchEvent(new Event("input"));
    });
    const brighter = await shown();
    const mean = (a) => a.reduce((s, v, i) => s + (i % 4 === 3 ? 0 : v), 0) / a.length;
    assert.ok(mean(brighter) > mean(before) + 5, `exposure +2 brightens (${mean(before)} -> ${mean(brighter)})`);
    await page.selectOption("#image-tonemap", "CLIP");
    const clipped = await shown();
    assert.notDeepEqual(clipped, brighter, "the tone map changed the view");
    // One channel, false colour: the bar spans the channel's range, as the EXR holds it.
    await page.selectOption("#image-layer", "depth");
    await page.check("#image-false-color");
    const depth = Array.from(exr.channels["depth.Z"]);
    const [low, high] = await page.evaluate(() => [document.querySelector("#image-range-low").value,
      document.querySelector("#image-range-high").value]);
    assert.equal(Number(low), Number(Math.min(...depth).toPrecision(4)));
    assert.equal(Number(high), Number(Math.max(...depth).toPrecision(4)));
    const ramp = await shown();
    const colours = new Set();
    for (let i = 0; i < ramp.length; i += 4) colours.add(ramp.slice(i, i + 3).join());
    assert.ok(colours.size > 20, `false colour spreads depth over the ramp (${colours.size} colours)`);
    await screenshot(page, "image-view-depth-false-colour");
    // Alpha, the colour's coverage, is among its channels: the EXR's A, the background 0.
    await page.selectOption("#image-layer", "color");
    await page.selectOption("#image-channel", "alpha");
    const alpha = await page.evaluate(() => Array.from(window.rt.image.shown.values));
    assert.deepEqual(alpha, Array.from(exr.channels.A));
    assert.ok(alpha.includes(0) && alpha.includes(1), "the box and the background");
    await page.click("#image-reset");
    assert.equal(await page.inputValue("#image-exposure"), "0.7");
    await page.selectOption("#image-layer", "color");
    await page.selectOption("#image-channel", "rgb");
    await page.uncheck("#image-false-color");
    assert.equal(await jobCount(), jobs, "no job was submitted");
  });

  test("a Shift-dragged rectangle gives the EXR's statistics, NaN and Inf counted apart", async () => {
    const [ax, ay] = await screenOf(10, 5);
    const [bx, by] = await screenOf(29, 24);
    await page.keyboard.down("Shift");
    await page.mouse.move(ax - 1, ay - 1);
    await page.mouse.down();
    await page.mouse.move(bx, by, { steps: 5 });
    await page.mouse.up();
    await page.keyboard.up("Shift");
    await page.waitForFunction(() => !document.querySelector("#region-stats").hidden);
    const rows = await page.$$eval("#region-stats tr[data-channel]", (trs) =>
      Object.fromEntries(trs.map((r) => [r.dataset.channel, Object.fromEntries(
        ["mean", "min", "max", "std"].map((k) => [k, Number(r.dataset[k])]))])));
    const pixels = Number(await page.getAttribute("#region-stats table", "data-pixels"));
    assert.equal(pixels, 20 * 20, "pixels 10..29 by 5..24");
    for (const name of ["R", "depth.Z", "bvh_cost.nodes"]) {
      const v = [];
      for (let y = 5; y < 25; y++) for (let x = 10; x < 30; x++) v.push(exr.channels[name][y * WIDTH + x]);
      const mean = v.reduce((a, b) => a + b, 0) / v.length;
      const std = Math.sqrt(v.reduce((a, b) => a + (b - mean) ** 2, 0) / v.length);
      assert.ok(Math.abs(rows[name].mean - mean) <= 1e-9 * Math.max(1, Math.abs(mean)), `${name} mean`);
      assert.equal(rows[name].min, Math.min(...v), `${name} min`);
      assert.equal(rows[name].max, Math.max(...v), `${name} max`);
      assert.ok(Math.abs(rows[name].std - std) <= 1e-6 * Math.max(1, std), `${name} std`);
    }
    assert.match(await page.textContent("#region-stats caption"), /color 0 NaN, 0 Inf/);
    await screenshot(page, "image-view-statistics");
    // A layer with a NaN and two infinities: counted, and left out of the sums.
    const bad = await page.evaluate(() => {
      const values = new Float32Array([1, NaN, 3, Infinity, 5, -Infinity]);
      const layer = { name: "probe", width: 3, height: 2, channels: ["v"], values };
      const { readout } = window.rt.image;
      const kept = readout.layers;
      readout.setLayers(new Map([["probe", layer]]));
      readout.showStats({ x0: 0, y0: 0, x1: 3, y1: 2 });
      const table = document.querySelector("#region-stats table");
      const answer = { nan: table.dataset.probeNan, inf: table.dataset.probeInf,
        mean: Number(table.querySelector("tr[data-channel]").dataset.mean) };
      readout.setLayers(kept);
      return answer;
    });
    assert.deepEqual(bad, { nan: "1", inf: "2", mean: 3 });
  });

  test("a click on the render traces that pixel in the debugger", async () => {
    const [x, y] = [31, 30];
    const [sx, sy] = await screenOf(x, y);
    await page.mouse.click(sx, sy);
    await page.waitForFunction(([x, y]) => document.querySelector("#debug-status").textContent.includes(`(${x}, ${y})`)
      && document.querySelector("#debug-status").dataset.kind === "ok", [x, y], { timeout: 20_000 });
    assert.deepEqual(await page.evaluate(() => window.rt.debug.pixel), [x, y]);
    await page.keyboard.press("v");
    assert.equal(await page.locator("#viewport").isVisible(), true, "V goes back to the 3D view");
  });

  test("the wipe lays the render over the 3D view from the job's camera: 3D left of the handle, render right", async () => {
    await page.click("#show-wipe");
    await page.waitForFunction(() => !document.querySelector("#wipe-handle").hidden);
    assert.equal(await page.locator("#viewport").isVisible(), true);
    const camera = await page.evaluate(() => {
      const { viewer, state } = window.rt;
      return { view: viewer.camera.position.toArray(), job: Array.from(state.job.request.camera.position) };
    });
    camera.view.forEach((v, i) => assert.ok(Math.abs(v - camera.job[i]) < 1e-4, `3D camera at the job's (${camera.view})`));
    const offBy = await page.evaluate(() => {
      const { image, viewer } = window.rt;
      const v = image.view;
      const mine = v.canvas.getBoundingClientRect();
      const theirs = viewer.renderer.domElement.getBoundingClientRect();
      return [mine.left + v.offset[0] - theirs.left, mine.top + v.offset[1] - theirs.top,
        v.scale * v.width - theirs.width, v.scale * v.height - theirs.height];
    });
    // Within half a pixel: the 3D canvas rounds its height to whole pixels.
    for (const d of offBy) assert.ok(Math.abs(d) <= 0.5, `the render lies on the 3D canvas (${offBy})`);
    const frame = await page.locator("#viewport canvas").boundingBox();
    const middle = await dragLine(page, "#wipe-handle", frame, 0.3);
    const fraction = await page.evaluate(() => window.rt.wipe.fraction);
    assert.ok(Math.abs(fraction - 0.3) < 0.01, `the handle followed the drag (${fraction})`);
    await page.waitForTimeout(50);
    const sides = await page.evaluate(([line, middle]) => {
      const { view, display } = window.rt.image;
      const rect = view.canvas.getBoundingClientRect();
      const at = (x) => Array.from(view.canvas.getContext("2d")
        .getImageData(Math.round(x - rect.left), Math.round(middle - rect.top), 1, 1).data);
      const source = (x) => {
        const px = Math.floor((x - rect.left - view.offset[0]) / view.scale);
        const py = Math.floor((middle - rect.top - view.offset[1]) / view.scale);
        return Array.from(display.getContext("2d").getImageData(px, py, 1, 1).data);
      };
      return { left: at(line - 12), right: at(line + 12), rightSource: source(line + 12) };
    }, [frame.x + 0.3 * frame.width, middle]);
    assert.equal(sides.left[3], 0, "left of the handle the 3D view shows through");
    assert.deepEqual(sides.right, sides.rightSource, "right of it, the render's pixel");
    await screenshot(page, "image-view-wipe");
    await page.click("#show-image");
    assert.equal(await page.locator("#wipe-handle").isHidden(), true);
  });

  test("no console errors", () => {
    assert.deepEqual(page.problems, []);
  });
});
