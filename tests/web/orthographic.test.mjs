// Orthographic cameras in the viewer (headless chromium against the real
// service): a glTF scene's orthographic camera, chosen in "View from", makes
// the 3D view a THREE.OrthographicCamera of the same height; "Render this
// view" sends an orthographic rt.Camera whose image lines up with the view
// (the lit rectangle's bounding box within a pixel and a half); dollying
// changes the height and still lines up; the projection switch swaps the
// camera; the pixel debugger's primary ray is drawn where the clicked pixel is.
import assert from "node:assert/strict";
import { after, before, describe, test } from "node:test";
import { ARTIFACTS, launch, openPage, screenshot } from "./browser.mjs";
import { startServer } from "./server.mjs";

const WIDTH = 128;
const HEIGHT = 96;
const BRIGHT = 100; // of 255, any channel: the rectangle, never the background

/** A rectangle off the centre (so a mirrored or shifted view shows), an orthographic camera 5 up +z, a light. */
function sceneGltf() {
  const [x0, x1, y0, y1] = [-0.3, 0.7, -0.6, 0.2];
  const positions = new Float32Array([x0, y0, 0, x1, y0, 0, x1, y1, 0, x0, y1, 0]);
  const indices = new Uint32Array([0, 1, 2, 0, 2, 3]);
  const data = Buffer.concat([Buffer.from(positions.buffer), Buffer.from(indices.buffer)]);
  return JSON.stringify({
    asset: { version: "2.0" },
    extensionsUsed: ["KHR_lights_punctual"],
    extensions: { KHR_lights_punctual: { lights: [{ type: "point", intensity: 200 }] } },
    scene: 0,
    scenes: [{ nodes: [0, 1, 2] }],
    nodes: [
      { mesh: 0 },
      { camera: 0, translation: [0, 0, 5] },
      { translation: [0, 0, 3], extensions: { KHR_lights_punctual: { light: 0 } } },
    ],
    cameras: [{ type: "orthographic", name: "plan", orthographic: { xmag: 1, ymag: 1, znear: 0, zfar: 100 } }],
    materials: [{ pbrMetallicRoughness: { baseColorFactor: [1, 1, 1, 1], metallicFactor: 0, roughnessFactor: 1 },
      emissiveFactor: [0.8, 0.8, 0.8] }],
    meshes: [{ primitives: [{ attributes: { POSITION: 0 }, indices: 1, material: 0 }] }],
    buffers: [{ byteLength: data.length, uri: `data:application/octet-stream;base64,${data.toString("base64")}` }],
    bufferViews: [{ buffer: 0, byteOffset: 0, byteLength: 48 }, { buffer: 0, byteOffset: 48, byteLength: 24 }],
    accessors: [
      { bufferView: 0, componentType: 5126, count: 4, type: "VEC3", min: [x0, y0, 0], max: [x1, y1, 0] },
      { bufferView: 1, componentType: 5125, count: 6, type: "SCALAR" },
    ],
  });
}

let server;
let browser;
let page;

/** The bright pixels' box in the 3D view, in image pixels ([left, top, right, bottom) edges). */
function viewBox() {
  return page.evaluate(({ W, H, bright }) => {
    const { viewer } = window.rt;
    viewer.renderer.render(viewer.scene, viewer.camera);
    const gl = viewer.renderer.getContext();
    const [w, h] = [gl.drawingBufferWidth, gl.drawingBufferHeight];
    const rgba = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, rgba);
    const box = [Infinity, Infinity, -Infinity, -Infinity];
    for (let y = 0; y < h; y++) {
      for (let x = 0; x < w; x++) {
        const k = ((h - 1 - y) * w + x) * 4; // rows bottom-up
        if (Math.max(rgba[k], rgba[k + 1], rgba[k + 2]) <= bright) continue;
        box[0] = Math.min(box[0], x); box[1] = Math.min(box[1], y);
        box[2] = Math.max(box[2], x + 1); box[3] = Math.max(box[3], y + 1);
      }
    }
    return [box[0] * W / w, box[1] * H / h, box[2] * W / w, box[3] * H / h];
  }, { W: WIDTH, H: HEIGHT, bright: BRIGHT });
}

/** The same box in a job's image.png. */
function imageBox(jobId) {
  return page.evaluate(async ({ url, bright }) => {
    const bitmap = await createImageBitmap(await (await fetch(url)).blob(), { colorSpaceConversion: "none" });
    const ctx = new OffscreenCanvas(bitmap.width, bitmap.height).getContext("2d");
    ctx.drawImage(bitmap, 0, 0);
    const { data, width, height } = ctx.getImageData(0, 0, bitmap.width, bitmap.height);
    const box = [Infinity, Infinity, -Infinity, -Infinity];
    for (let y = 0; y < height; y++) {
      for (let x = 0; x < width; x++) {
        const k = (y * width + x) * 4;
        if (Math.max(data[k], data[k + 1], data[k + 2]) <= bright) continue;
        box[0] = Math.min(box[0], x); box[1] = Math.min(box[1], y);
        box[2] = Math.max(box[2], x + 1); box[3] = Math.max(box[3], y + 1);
      }
    }
    return box;
  }, { url: `/api/jobs/${jobId}/image.png`, bright: BRIGHT });
}

function assertLinesUp(view, image, what) {
  assert.ok(image.every(Number.isFinite) && image[2] - image[0] > 4, `${what}: the render shows the rectangle (${image})`);
  view.forEach((v, k) => assert.ok(Math.abs(v - image[k]) <= 1.5,
    `${what}: edge ${k} of the view ${view.map((e) => e.toFixed(2))} against the image's ${image}`));
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

describe("orthographic cameras", { timeout: 150_000 }, () => {
  before(async () => {
    server = await startServer({ artifacts: ARTIFACTS, samples: false, name: "orthographic-server" });
    browser = await launch();
    page = await openPage(browser, server.url);
    const form = new FormData();
    form.append("file", new Blob([sceneGltf()]), "plan.gltf");
    const response = await fetch(`${server.url}/api/scenes`, { method: "POST", body: form });
    assert.equal(response.status, 201, await response.text());
    await page.goto("/");
    await page.locator("#scene-list .scene-pick", { hasText: "plan.gltf" }).click();
    await page.waitForFunction(() => window.rt.state.scene?.name === "plan.gltf"
      && !document.querySelector("#viewport-status").textContent && window.rt.viewer.model.children.length > 0,
    null, { timeout: 30_000 });
  });

  after(async () => {
    await browser?.close();
    await server?.stop();
  });

  test("the scene's orthographic camera makes the view orthographic, and its render lines up", async () => {
    await page.fill("#setting-width", String(WIDTH));
    await page.fill("#setting-height", String(HEIGHT));
    await page.selectOption("#scene-camera", { label: "Scene camera: plan" });
    const view = await page.evaluate(() => {
      const { viewer } = window.rt;
      return { ortho: viewer.camera.isOrthographicCamera === true, height: viewer.viewHeight };
    });
    assert.ok(view.ortho, "a THREE.OrthographicCamera");
    assert.ok(Math.abs(view.height - 2) < 1e-6, `2 * ymag tall: ${view.height}`);
    assert.equal(await page.inputValue("#view-projection"), "orthographic");
    assert.equal(Number(await page.inputValue("#view-ortho-height")), 2);
    const box = await viewBox();
    await screenshot(page, "orthographic-view");

    const job = await renderThisView();
    assert.equal(job.state, "DONE");
    assert.equal(job.request.camera.projection, "ORTHOGRAPHIC");
    assert.ok(Math.abs(job.request.camera.ortho_height - 2) < 1e-6);
    await screenshot(page, "orthographic-render");
    assertLinesUp(box, await imageBox(job.id), "the scene camera");
  });

  test("dollying changes the height, and the render still lines up", async () => {
    const canvas = await page.locator("#viewport canvas").boundingBox();
    await page.mouse.move(canvas.x + canvas.width / 2, canvas.y + canvas.height / 2);
    await page.mouse.wheel(0, -200);
    await page.waitForFunction(() => window.rt.viewer.viewHeight < 1.9, null, { timeout: 10_000 });
    assert.equal(await page.inputValue("#scene-camera"), "", "the view left the scene camera");
    const height = await page.evaluate(() => window.rt.viewer.viewHeight);
    assert.ok(Math.abs(Number(await page.inputValue("#view-ortho-height")) - height) < 1e-4, "the field shows it");
    const box = await viewBox();
    const job = await renderThisView();
    assert.ok(Math.abs(job.request.camera.ortho_height - height) < 1e-5, `${job.request.camera.ortho_height} vs ${height}`);
    assertLinesUp(box, await imageBox(job.id), "after dollying");
  });

  test("the pixel debugger draws the primary ray at the clicked pixel", async () => {
    const overlay = await page.locator("#image-overlay").boundingBox();
    const pixel = [70, 50]; // on the rectangle
    await page.mouse.click(overlay.x + ((pixel[0] + 0.5) / WIDTH) * overlay.width,
      overlay.y + ((pixel[1] + 0.5) / HEIGHT) * overlay.height);
    await page.waitForFunction(() => window.rt.debug.rays.path !== null, null, { timeout: 30_000 });
    const drawn = await page.evaluate(() => {
      const { rays, viewer } = window.rt.debug;
      const p = rays.lines.geometry.attributes.position.array;
      const at = (k) => viewer.camera.position.clone().set(p[k], p[k + 1], p[k + 2]).project(viewer.camera);
      const [origin, end] = [at(0), at(3)];
      return { pixel: [rays.path.pixelX, rays.path.pixelY], origin: [origin.x, origin.y], end: [end.x, end.y],
        kind: rays.path.segments[0].kind, ortho: viewer.camera.isOrthographicCamera === true };
    });
    assert.ok(drawn.ortho, "the job's camera is shown, orthographic");
    // Both ends of the primary ray project to the centre of the pixel it was traced for.
    const ndc = [((drawn.pixel[0] + 0.5) / WIDTH) * 2 - 1, 1 - ((drawn.pixel[1] + 0.5) / HEIGHT) * 2];
    for (const end of [drawn.origin, drawn.end]) {
      assert.ok(Math.abs(end[0] - ndc[0]) < 1 / WIDTH && Math.abs(end[1] - ndc[1]) < 1 / HEIGHT,
        `the primary ray at ${end} for pixel ${drawn.pixel} (${ndc})`);
    }
    await screenshot(page, "orthographic-debugged");
  });

  test("the projection switch swaps the view's camera both ways", async () => {
    await page.selectOption("#view-projection", "perspective");
    assert.ok(await page.evaluate(() => window.rt.viewer.camera.isPerspectiveCamera === true));
    assert.ok(await page.isHidden("#ortho-height-field"));
    assert.ok(await page.isVisible("#camera-fov_y"), "a perspective view shows its field of view");
    const shown = await page.evaluate(() => window.rt.viewer.viewHeight);
    await page.selectOption("#view-projection", "orthographic");
    const back = await page.evaluate(() => ({ ortho: window.rt.viewer.camera.isOrthographicCamera === true,
      height: window.rt.viewer.viewHeight }));
    assert.ok(back.ortho);
    assert.ok(await page.isHidden("#camera-fov_y"), "an orthographic view has no field of view to set");
    assert.ok(Math.abs(back.height - shown) < 1e-4 * shown, "it shows at the target what the perspective view did");
    await page.fill("#view-ortho-height", "3.5");
    assert.ok(Math.abs(await page.evaluate(() => window.rt.viewer.viewHeight) - 3.5) < 1e-6, "the height field sets it");
  });

  test("no console errors", () => {
    assert.deepEqual(page.problems, []);
  });
});
