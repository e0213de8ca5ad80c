// The background in the viewer (headless chromium against the real service):
// the 3D view draws the scene's background from model.glb, pixel for pixel the
// colours the render gives the same view; the default rig's sky and its
// switch; the settings panel's pickers start at the scene's colours and a
// chosen colour reaches both the 3D view and the job.
import assert from "node:assert/strict";
import { after, before, describe, test } from "node:test";
import { ARTIFACTS, launch, openPage, screenshot } from "./browser.mjs";
import { startServer } from "./server.mjs";
import { zipStored } from "./zip.mjs";

// Linear RGB, as the sidecar gives it.
const GRADIENT = { bottom: [0.02, 0.1, 0.05], horizon: [0.6, 0.3, 0.1], top: [0.1, 0.3, 0.9] };
const RIG_SKY = [0.55, 0.62, 0.72]; // load/light_rig.h
// One triangle and its light behind the camera (at z = 5, looking at the origin): every pixel is background.
const OBJ = "v -1 -1 10\nv 1 -1 10\nv 0 1 10\nf 1 2 3\n";
const VIEW = { position: [0, 0, 5], target: [0, 0, 0], up: [0, 1, 0], fovY: 60 };
const WIDTH = 64;
const HEIGHT = 48;

let server;
let browser;
let page;

const srgb8 = (linear) => linear.map((c) => {
  const v = Math.min(Math.max(c, 0), 1);
  return Math.round((v <= 0.0031308 ? 12.92 * v : 1.055 * v ** (1 / 2.4) - 0.055) * 255);
});

function gradientAt(y) {
  const to = y >= 0 ? GRADIENT.top : GRADIENT.bottom;
  return GRADIENT.horizon.map((h, i) => h + (to[i] - h) * Math.abs(y));
}

const farthest = (a, b) => Math.max(...a.map((v, i) => Math.abs(v - b[i])));

async function upload(name, files) {
  const form = new FormData();
  form.append("file", new Blob([zipStored(files)]), name);
  const response = await fetch(`${server.url}/api/scenes`, { method: "POST", body: form });
  const body = await response.text();
  assert.equal(response.status, 201, body);
  return JSON.parse(body).id;
}

async function show(name) {
  await page.locator("#scene-list .scene-pick", { hasText: name }).click();
  await page.waitForFunction((n) => window.rt.state.scene?.name === n && !document.querySelector("#viewport-status").textContent
    && window.rt.viewer.model.children.length > 0, name, { timeout: 30_000 });
  await page.evaluate((view) => window.rt.viewer.setView(view), VIEW);
}

/**
 * The 3D view's pixels at the centres of the WIDTH x HEIGHT image's pixels
 * `points` ([i, j]), with the height (world y) of the view's direction there.
 */
function viewPixels(points) {
  return page.evaluate((points) => {
    const { viewer } = window.rt;
    viewer.renderer.render(viewer.scene, viewer.camera);
    const gl = viewer.renderer.getContext();
    const [w, h] = [gl.drawingBufferWidth, gl.drawingBufferHeight];
    return points.map(([u, v]) => {
      const x = Math.floor(u * w), y = Math.floor(v * h);
      const rgba = new Uint8Array(4);
      gl.readPixels(x, h - 1 - y, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, rgba);
      const ndc = viewer.camera.position.clone().set(((x + 0.5) / w) * 2 - 1, 1 - ((y + 0.5) / h) * 2, 0.5);
      const direction = ndc.unproject(viewer.camera).sub(viewer.camera.position).normalize();
      return { rgb: [...rgba.slice(0, 3)], height: direction.y };
    });
  }, points.map(([i, j]) => [(i + 0.5) / WIDTH, (j + 0.5) / HEIGHT]));
}

/** Pixels [i, j] of a job's image.png. */
function imagePixels(jobId, points) {
  return page.evaluate(async ({ url, points }) => {
    const bitmap = await createImageBitmap(await (await fetch(url)).blob(), { colorSpaceConversion: "none", premultiplyAlpha: "none" });
    const canvas = new OffscreenCanvas(bitmap.width, bitmap.height);
    const ctx = canvas.getContext("2d");
    ctx.drawImage(bitmap, 0, 0);
    return points.map(([i, j]) => [...ctx.getImageData(i, j, 1, 1).data.slice(0, 3)]);
  }, { url: `/api/jobs/${jobId}/image.png`, points });
}

async function renderThisView() {
  await page.fill("#setting-width", String(WIDTH));
  await page.fill("#setting-height", String(HEIGHT));
  const before = page.url();
  await page.click("#render-button");
  // A new job's address: the page may still be at the previous job's.
  await page.waitForURL((url) => /\/jobs\/[0-9a-f]+$/.test(url.pathname) && url.href !== before, { timeout: 15_000 });
  const id = page.url().split("/").pop();
  await page.waitForFunction((id) => window.rt.state.job?.id === id
    && document.querySelector("#job-state").textContent === "done", id, { timeout: 60_000 });
  return (await (await fetch(`${server.url}/api/jobs/${id}`)).json());
}

// A column down the middle and a row across, in image pixels.
const POINTS = [...Array.from({ length: 12 }, (_, k) => [WIDTH / 2, k * 4 + 1]), ...[0, 20, 63].map((i) => [i, 10])];

describe("the background", { timeout: 150_000 }, () => {
  before(async () => {
    server = await startServer({ artifacts: ARTIFACTS, samples: false, name: "background-server" });
    browser = await launch();
    page = await openPage(browser, server.url);
    await upload("gradient.zip", [{ name: "tri.obj", data: Buffer.from(OBJ) }, {
      name: "tri.rt.json",
      data: Buffer.from(JSON.stringify({ lights: [{ position: [0, 0, 20] }], background_gradient: GRADIENT })),
    }]);
    await upload("unlit.zip", [{ name: "tri.obj", data: Buffer.from(OBJ) }]);
    await page.goto("/");
    await page.waitForFunction(() => document.querySelectorAll("#scene-list .scene-pick").length === 2, null, { timeout: 30_000 });
  });

  after(async () => {
    await browser?.close();
    await server?.stop();
  });

  test("the 3D view shows the sidecar's gradient as the render does", async () => {
    await show("gradient.zip");
    const view = await viewPixels(POINTS);
    await screenshot(page, "background-gradient-view");
    for (const { rgb, height } of view) {
      assert.ok(farthest(rgb, srgb8(gradientAt(height))) <= 2, `the view at height ${height.toFixed(3)}: ${rgb}`);
    }
    assert.ok(view[0].height > 0.3 && view[11].height < -0.3, "the column spans sky and ground");

    const job = await renderThisView();
    assert.equal(job.state, "DONE");
    const image = await imagePixels(job.id, POINTS);
    await screenshot(page, "background-gradient-render");
    image.forEach((rgb, k) => {
      assert.ok(farthest(rgb, view[k].rgb) <= 3, `image pixel ${POINTS[k]} ${rgb} against the view's ${view[k].rgb}`);
    });
  });

  test("the pickers start at the scene's colours; a chosen colour reaches the view and the job", async () => {
    await page.goto("/");
    await show("gradient.zip");
    await page.selectOption("#setting-background", "gradient");
    for (const key of ["bottom", "horizon", "top"]) {
      const hex = await page.inputValue(`#background-${key}`);
      const rgb = [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16));
      assert.ok(farthest(rgb, srgb8(GRADIENT[key])) <= 1, `${key} starts at the scene's: ${hex}`);
    }
    await page.selectOption("#setting-background", "solid");
    await page.fill("#background-color", "#336699");
    const [{ rgb }] = await viewPixels([[5, 5]]);
    assert.deepEqual(rgb, [0x33, 0x66, 0x99], "the 3D view shows the chosen colour");

    const job = await renderThisView();
    const sent = job.request.settings.background;
    const linear = srgb8(sent);
    assert.deepEqual(linear, [0x33, 0x66, 0x99], `the job's settings.background (${sent}) is the colour, linear`);
    assert.equal(job.request.settings.background_gradient, undefined);
    const [pixel] = await imagePixels(job.id, [[5, 5]]);
    assert.deepEqual(pixel, [0x33, 0x66, 0x99], "the render shows it");
    await page.reload();
    await page.waitForFunction(() => document.querySelector("#job-state").textContent === "done", null, { timeout: 30_000 });
    assert.equal(await page.inputValue("#setting-background"), "solid", "a reloaded job shows its background");
    assert.equal(await page.inputValue("#background-color"), "#336699");
  });

  test("without lights, the default rig's sky, and black with the rig off", async () => {
    await page.goto("/");
    await show("unlit.zip");
    const [{ rgb: sky }] = await viewPixels([[5, 5]]);
    assert.ok(farthest(sky, srgb8(RIG_SKY)) <= 1, `the rig's sky: ${sky}`);
    await page.selectOption("#setting-light_rig", "1");
    const [{ rgb: black }] = await viewPixels([[5, 5]]);
    assert.deepEqual(black, [0, 0, 0], "no rig, no background: black");
    await screenshot(page, "background-no-rig");
  });

  test("no console errors", () => {
    assert.deepEqual(page.problems, []);
  });
});
