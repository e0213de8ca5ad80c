// The peer check that UVs, texture transforms, vertex colours and alpha masks
// are read as a widely used glTF implementation reads them: a job's ALBEDO
// output equals three.js drawing the scene's model.glb unlit (each material's
// base colour × texture × vertex colour, MASK as alphaTest) at the same camera,
// in the browser, up to texture filtering at edges.
import assert from "node:assert/strict";
import { readFileSync, writeFileSync } from "node:fs";
import { join } from "node:path";
import { after, before, describe, test } from "node:test";
import { ARTIFACTS, launch, openPage } from "./browser.mjs";
import { ROOT, startServer } from "./server.mjs";

const ASSETS = join(ROOT, "build", "assets");
const THREE = join(ROOT, "web", "node_modules", "three");
const WIDTH = 320;
const HEIGHT = 240;

// The three.js page: an import map for the viewer's own three (web/node_modules),
// and drawUnlit(), which answers the RGBA8 pixels, top row first.
const PEER_PAGE = `<!doctype html><html><body>
<script type="importmap">{"imports": {"three": "/__peer/three/build/three.module.js",
  "three/addons/": "/__peer/three/examples/jsm/"}}</script>
<script type="module">
import * as THREE from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";

window.drawUnlit = async (modelUrl, camera, width, height) => {
  const gltf = await new GLTFLoader().loadAsync(modelUrl);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0, 0, 0);
  scene.add(gltf.scene);
  gltf.scene.traverse((object) => {
    if (!object.isMesh) return;
    const m = object.material;
    object.material = new THREE.MeshBasicMaterial({
      // ALBEDO is the first surface's colour: a BLEND surface is drawn opaque.
      color: m.color, map: m.map, vertexColors: m.vertexColors, alphaTest: m.alphaTest, side: THREE.DoubleSide,
    });
  });
  const renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  renderer.setSize(width, height);
  renderer.outputColorSpace = THREE.SRGBColorSpace;
  document.body.appendChild(renderer.domElement);
  const eye = new THREE.Vector3(...camera.position);
  const target = new THREE.Vector3(...camera.target);
  const distance = eye.distanceTo(target);
  const view = new THREE.PerspectiveCamera(camera.fov_y ?? camera.fovY, width / height, distance / 1000, distance * 1000);
  view.position.copy(eye);
  view.up.set(...(camera.up?.length ? camera.up : [0, 1, 0]));
  view.lookAt(target);
  renderer.render(scene, view);
  const canvas = new OffscreenCanvas(width, height);
  const context = canvas.getContext("2d");
  context.drawImage(renderer.domElement, 0, 0);
  return Array.from(context.getImageData(0, 0, width, height).data);
};

window.decodePng = async (url) => {
  const bitmap = await createImageBitmap(await (await fetch(url)).blob(),
    { colorSpaceConversion: "none", premultiplyAlpha: "none" });
  const canvas = new OffscreenCanvas(bitmap.width, bitmap.height);
  const context = canvas.getContext("2d");
  context.drawImage(bitmap, 0, 0);
  return Array.from(context.getImageData(0, 0, bitmap.width, bitmap.height).data);
};
window.encodePng = async (pixels, width, height) => {
  const canvas = new OffscreenCanvas(width, height);
  canvas.getContext("2d").putImageData(new ImageData(new Uint8ClampedArray(pixels), width, height), 0, 0);
  const bytes = new Uint8Array(await (await canvas.convertToBlob({ type: "image/png" })).arrayBuffer());
  let text = "";
  for (const b of bytes) text += String.fromCharCode(b);
  return btoa(text);
};
window.peerReady = true;
</script></body></html>`;

let server;
let browser;
let page;

async function api(path, init) {
  const response = await fetch(`${server.url}${path}`, init);
  const body = await response.text();
  if (!response.ok) throw new Error(`${path}: HTTP ${response.status} ${body}`);
  return body ? JSON.parse(body) : null;
}

async function upload(file) {
  const form = new FormData();
  form.append("file", new Blob([readFileSync(join(ASSETS, file))]), file);
  return api("/api/scenes", { method: "POST", body: form });
}

async function albedoJob(scene) {
  const camera = scene.default_camera ?? scene.defaultCamera;
  let job = await api("/api/jobs", {
    method: "POST",
    headers: { "Content-Type": "application/json" },
    body: JSON.stringify({ scene_id: scene.id, camera, settings: { width: WIDTH, height: HEIGHT }, outputs: ["ALBEDO"] }),
  });
  const deadline = Date.now() + 60_000;
  while (!["DONE", "FAILED", "CANCELLED"].includes(job.state)) {
    assert.ok(Date.now() < deadline, `job ${job.id} did not finish`);
    await new Promise((r) => setTimeout(r, 200));
    job = await api(`/api/jobs/${job.id}`);
  }
  assert.equal(job.state, "DONE", JSON.stringify(job));
  return { job, camera };
}

/** Share of pixels whose largest channel difference is above `tolerance` (of 255), and the mean difference. */
function compare(a, b) {
  let off = 0;
  let sum = 0;
  for (let i = 0; i < a.length; i += 4) {
    const d = Math.max(Math.abs(a[i] - b[i]), Math.abs(a[i + 1] - b[i + 1]), Math.abs(a[i + 2] - b[i + 2]));
    sum += d;
    if (d > 24) off += 1;
  }
  const pixels = a.length / 4;
  return { offShare: off / pixels, mean: sum / pixels };
}

describe("ALBEDO against three.js unlit", { timeout: 150_000 }, () => {
  before(async () => {
    server = await startServer({ artifacts: ARTIFACTS, samples: false, name: "albedo-peer-server" });
    browser = await launch();
    page = await openPage(browser, server.url);
    await page.route("**/__peer/index.html", (route) => route.fulfill({ contentType: "text/html", body: PEER_PAGE }));
    await page.route("**/__peer/three/**", (route) => {
      const path = new URL(route.request().url()).pathname.replace("/__peer/three/", "");
      route.fulfill({ contentType: "text/javascript", body: readFileSync(join(THREE, path)) });
    });
    await page.goto("/__peer/index.html");
    await page.waitForFunction(() => window.peerReady === true, null, { timeout: 30_000 });
  });

  after(async () => {
    await browser?.close();
    await server?.stop();
  });

  for (const file of ["texture_transform.glb", "vertex_colors.glb", "alpha_modes.glb"]) {
    test(`${file}: the renderer's albedo is three.js's unlit drawing`, async (t) => {
      const scene = await upload(file);
      const { job, camera } = await albedoJob(scene);
      const ours = await page.evaluate((url) => window.decodePng(url), `/api/jobs/${job.id}/albedo.png`);
      const theirs = await page.evaluate(
        ([url, cam, w, h]) => window.drawUnlit(url, cam, w, h),
        [`/api/scenes/${scene.id}/model.glb`, camera, WIDTH, HEIGHT],
      );
      for (const [who, pixels] of [["rt", ours], ["three", theirs]]) {
        const png = await page.evaluate(([p, w, h]) => window.encodePng(p, w, h), [pixels, WIDTH, HEIGHT]);
        writeFileSync(join(ARTIFACTS, `albedo-peer-${file.replace(/\W+/g, "-")}-${who}.png`), Buffer.from(png, "base64"));
      }
      assert.equal(ours.length, theirs.length);
      // Something is drawn: a test of two black images would pass anything.
      const lit = theirs.filter((v, i) => i % 4 !== 3 && v > 40).length / (WIDTH * HEIGHT * 3);
      assert.ok(lit > 0.05, `three.js drew almost nothing (${lit})`);
      const { offShare, mean } = compare(ours, theirs);
      t.diagnostic(`${file}: ${(offShare * 100).toFixed(2)} % of pixels off by more than 24/255, mean difference ${mean.toFixed(2)}/255`);
      // Texture filtering differs at texel and silhouette edges only: a wrong
      // UV set, transform, colour or mask moves a large share of the pixels.
      assert.ok(offShare < 0.005, `${(offShare * 100).toFixed(2)} % of the pixels differ by more than 24/255 (mean ${mean.toFixed(2)})`);
      assert.ok(mean < 2, `mean difference ${mean.toFixed(2)} / 255`);
    });
  }

  test("no console errors", () => {
    assert.deepEqual(page.problems, []);
  });
});
