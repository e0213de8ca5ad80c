// Shared meshes in the viewer (headless chromium against the real service):
// a glTF whose nodes share one mesh comes through model.glb as one mesh drawn
// by many nodes, and the view draws it as one InstancedMesh (but for the
// nodes that mirror it); its pixels are those of the same scene with a copy
// of the mesh per node. The debugger reaches the instance tree a traced ray
// entered and draws its boxes where the instance stands.
import assert from "node:assert/strict";
import { after, before, describe, test } from "node:test";
import { ARTIFACTS, launch, openPage, screenshot } from "./browser.mjs";
import { startServer } from "./server.mjs";

const NODES = 30;

/** An octahedron drawn by NODES nodes: one shared mesh, or (copies) one mesh per node. */
function sceneGltf(copies) {
  const positions = new Float32Array([1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1]);
  const indices = new Uint32Array([0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5]);
  const data = Buffer.concat([Buffer.from(positions.buffer), Buffer.from(indices.buffer)]);
  const nodes = Array.from({ length: NODES }, (_, k) => ({
    mesh: copies ? k : 0,
    translation: [2.5 * (k % 6) - 6, 0.8, -2.5 * Math.floor(k / 6)],
    rotation: [0, Math.sin(0.15 * k), 0, Math.cos(0.15 * k)],
    scale: [0.8, 0.8 + 0.05 * k, k % 7 === 3 ? -0.8 : 0.8],
  }));
  const mesh = { primitives: [{ attributes: { POSITION: 0 }, indices: 1 }] };
  return JSON.stringify({
    asset: { version: "2.0" },
    scene: 0,
    scenes: [{ nodes: nodes.map((_, k) => k) }],
    nodes,
    meshes: Array.from({ length: copies ? NODES : 1 }, () => mesh),
    buffers: [{ byteLength: data.length, uri: `data:application/octet-stream;base64,${data.toString("base64")}` }],
    bufferViews: [{ buffer: 0, byteOffset: 0, byteLength: 72 }, { buffer: 0, byteOffset: 72, byteLength: 96 }],
    accessors: [
      { bufferView: 0, componentType: 5126, count: 6, type: "VEC3", min: [-1, -1, -1], max: [1, 1, 1] },
      { bufferView: 1, componentType: 5125, count: 24, type: "SCALAR" },
    ],
  });
}

let server;
let browser;
let page;

async function upload(name, gltf) {
  const form = new FormData();
  form.append("file", new Blob([gltf]), name);
  const response = await fetch(`${server.url}/api/scenes`, { method: "POST", body: form });
  const text = await response.text();
  assert.equal(response.status, 201, text);
  return JSON.parse(text);
}

async function open(name) {
  await page.goto("/");
  await page.locator("#scene-list .scene-pick", { hasText: name }).click();
  await page.waitForFunction((n) => window.rt.state.scene?.name === n
    && !document.querySelector("#viewport-status").textContent && window.rt.viewer.model.children.length > 0,
  name, { timeout: 30_000 });
  // One pose for both scenes (each one's default camera frames its own
  // bounds), then full detail again once the camera stands still.
  await page.evaluate(() => {
    const { viewer } = window.rt;
    viewer.camera.position.set(0, 6, 8);
    viewer.controls.target.set(0, 0.5, -5);
    viewer.controls.update();
    viewer.requestRender();
  });
  await page.waitForTimeout(400);
  await page.waitForFunction(() => !window.rt.viewer.lod.moving, null, { timeout: 10_000 });
}

/** What the view draws: its meshes, and its pixels at the scene's default camera. */
function drawn() {
  return page.evaluate(() => {
    const { viewer } = window.rt;
    const meshes = { instanced: [], plain: 0 };
    viewer.model.traverse((o) => {
      if (o.isInstancedMesh) meshes.instanced.push(o.count);
      else if (o.isMesh) meshes.plain++;
    });
    viewer.renderer.render(viewer.scene, viewer.camera);
    const gl = viewer.renderer.getContext();
    const rgba = new Uint8Array(gl.drawingBufferWidth * gl.drawingBufferHeight * 4);
    gl.readPixels(0, 0, gl.drawingBufferWidth, gl.drawingBufferHeight, gl.RGBA, gl.UNSIGNED_BYTE, rgba);
    return { meshes, pixels: Array.from(rgba) };
  });
}

describe("shared meshes", { timeout: 120_000 }, () => {
  before(async () => {
    server = await startServer({ artifacts: ARTIFACTS, samples: false, name: "instancing-server" });
    browser = await launch();
    page = await openPage(browser, server.url);
    await upload("shared.gltf", sceneGltf(false));
    await upload("copies.gltf", sceneGltf(true));
  });

  after(async () => {
    await browser?.close();
    await server?.stop();
  });

  test("a mesh many nodes share is one InstancedMesh, drawn where the copies are", async () => {
    await open("shared.gltf");
    const shared = await drawn();
    await screenshot(page, "instancing-shared");
    // Mirroring nodes (every seventh from the fourth) keep meshes of their own.
    const mirrored = Array.from({ length: NODES }, (_, k) => k % 7 === 3).filter(Boolean).length;
    assert.deepEqual(shared.meshes.instanced, [NODES - mirrored], "one InstancedMesh of the other nodes");
    assert.equal(shared.meshes.plain, mirrored, "only the mirroring nodes drawn one by one");
    await open("copies.gltf");
    const copies = await drawn();
    await screenshot(page, "instancing-copies");
    assert.equal(copies.meshes.instanced.length, 0);
    assert.equal(copies.pixels.length, shared.pixels.length);
    let off = 0;
    let lit = 0;
    for (let i = 0; i < copies.pixels.length; i += 4) {
      const d = Math.max(...[0, 1, 2].map((c) => Math.abs(copies.pixels[i + c] - shared.pixels[i + c])));
      off += d > 24;
      lit += Math.abs(copies.pixels[i] - copies.pixels[0]) > 24;
    }
    assert.ok(lit > copies.pixels.length / 4 / 50, `the octahedra fill part of the view (${lit} pixels)`);
    assert.ok(off <= copies.pixels.length / 4 / 500, `${off} pixels differ from the copies' view`);
  });

  test("a traced ray's instance tree is one click away, its boxes drawn in world space", async () => {
    await open("shared.gltf");
    assert.equal(await page.isVisible("#bvh-tree-pick"), true, "a scene with instances offers its trees");
    const sceneId = await page.evaluate(() => window.rt.state.scene.id);
    const camera = { position: [0, 6, 8], target: [1.5, 0.8, -5], up: [0, 1, 0], fovY: 60 };
    const hit = await page.evaluate(async (request) => {
      const { debug } = window.rt;
      debug.setJob({ request });
      await debug.trace([32, 24]);
      return Array.from(debug.rays.path.segments[0].end);
    }, { sceneId, camera, settings: { width: 64, height: 48 } });
    const button = page.locator("#bvh-entered button").first();
    const tree = await button.getAttribute("data-tree");
    assert.match(tree, /^\d+$/, "the ray entered an instance");
    await button.click();
    await page.waitForFunction((t) => window.rt.debug.bvh.data?.instance === Number(t) && window.rt.debug.bvh.lines.visible,
      tree, { timeout: 10_000 });
    const expected = await (await fetch(`${server.url}/api/scenes/${sceneId}/bvh?level=0&tree=${tree}`)).json();
    const shown = await page.evaluate(() => {
      const { bvh } = window.rt.debug;
      bvh.lines.updateMatrixWorld(true);
      const box = new window.rt.viewer.camera.position.constructor(); // a THREE.Vector3
      const position = bvh.lines.geometry.attributes.position;
      const min = [Infinity, Infinity, Infinity];
      const max = [-Infinity, -Infinity, -Infinity];
      for (let i = 0; i < position.count; i++) {
        box.fromBufferAttribute(position, i).applyMatrix4(bvh.lines.matrixWorld);
        box.toArray().forEach((v, k) => { min[k] = Math.min(min[k], v); max[k] = Math.max(max[k], v); });
      }
      return { select: document.getElementById("bvh-tree").value, instance: document.getElementById("bvh-instance").value,
        matrix: bvh.lines.matrix.toArray(), boxes: bvh.shownBoxes, min, max };
    });
    assert.equal(await page.textContent("#bvh-instance-name"), `node ${expected.instance_name}`);
    assert.match(expected.instance_name, /^nodes\[\d+\]$/, "the file's nodes are unnamed: their places");
    assert.equal(shown.select, "instance");
    assert.equal(shown.instance, tree);
    assert.equal(shown.boxes, expected.nodes.length);
    shown.matrix.forEach((v, k) => assert.ok(Math.abs(v - expected.to_world[k]) < 1e-6, `to_world[${k}]`));
    for (let k = 0; k < 3; k++) {
      assert.ok(hit[k] >= shown.min[k] - 1e-3 && hit[k] <= shown.max[k] + 1e-3,
        `the instance's root box, in world space, holds the hit (axis ${k}: ${hit[k]} in ${shown.min[k]}..${shown.max[k]})`);
    }
    await screenshot(page, "instancing-instance-tree");
    await page.selectOption("#bvh-tree", "top");
    await page.waitForFunction(() => window.rt.debug.bvh.data?.tree === 0 && window.rt.debug.bvh.data.level === 0, null,
      { timeout: 10_000 });
    assert.deepEqual(await page.evaluate(() => window.rt.debug.bvh.lines.matrix.toArray()),
      [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], "the top level stands in world space");
  });

  test("no console errors", () => {
    assert.deepEqual(page.problems, []);
  });
});
