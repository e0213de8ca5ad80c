// The renderer's MikkTSpace port (renderer/src/geometry/mikktspace.h, reached
// through build/renderer/rt_tangents) against the reference: npm mikktspace,
// Mikkelsen's algorithm built to WebAssembly (through gltf-rs/mikktspace).
// Both get the same unindexed triangles; every corner's tangent must agree to
// 1e-4 per component with the same sign w. The meshes are the sample scenes'
// teapot, bunny and dragon (build/scenes, `make samples`) with projected
// texture coordinates (their seams fold and stretch triangles, and flat
// projections give triangles of zero uv area), a UV sphere with its seam and
// poles, a disc of 300 triangles around one vertex, and a grid with a
// mirrored half (w = -1) and degenerate triangles.
import assert from "node:assert/strict";
import { spawnSync } from "node:child_process";
import { existsSync, readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { join } from "node:path";
import { describe, test } from "node:test";
import { ROOT } from "./server.mjs";

const require = createRequire(join(ROOT, "web", "package.json"));
const { generateTangents } = require("mikktspace");

const TOOL = process.env.RT_TANGENTS ?? join(ROOT, "build", "renderer", "rt_tangents");
const SCENES = join(ROOT, "build", "scenes");
const TOLERANCE = 1e-4;

/** Our tangents: 4 floats per corner from rt_tangents. */
function ourTangents(positions, normals, uvs) {
  const corners = positions.length / 3;
  const input = new Float32Array(1 + corners * 8);
  new Uint32Array(input.buffer, 0, 1)[0] = corners;
  for (let c = 0; c < corners; c++) {
    input.set(positions.subarray(3 * c, 3 * c + 3), 1 + 8 * c);
    input.set(normals.subarray(3 * c, 3 * c + 3), 4 + 8 * c);
    input.set(uvs.subarray(2 * c, 2 * c + 2), 7 + 8 * c);
  }
  const run = spawnSync(TOOL, [], { input: Buffer.from(input.buffer), maxBuffer: 1 << 30 });
  assert.equal(run.status, 0, `rt_tangents failed: ${run.stderr}`);
  const out = new Float32Array(run.stdout.buffer, run.stdout.byteOffset, run.stdout.length / 4);
  assert.equal(out.length, corners * 4, "rt_tangents gives one tangent per corner");
  return out;
}

/** Compares both implementations corner by corner; returns what was compared. */
function compare(name, positions, normals, uvs) {
  const reference = generateTangents(positions, normals, uvs);
  const ours = ourTangents(positions, normals, uvs);
  assert.equal(reference.length, ours.length);
  let worst = 0;
  const bad = [];
  let mirrored = 0;
  for (let c = 0; c < ours.length / 4; c++) {
    let diff = 0;
    for (let k = 0; k < 3; k++) diff = Math.max(diff, Math.abs(ours[4 * c + k] - reference[4 * c + k]));
    worst = Math.max(worst, diff);
    if (reference[4 * c + 3] < 0) mirrored++;
    if (diff > TOLERANCE || ours[4 * c + 3] !== reference[4 * c + 3]) bad.push(c);
  }
  const show = (c) =>
    `corner ${c}: ours ${Array.from(ours.subarray(4 * c, 4 * c + 4))} reference ${Array.from(reference.subarray(4 * c, 4 * c + 4))}`;
  assert.equal(bad.length, 0, `${name}: ${bad.length} of ${ours.length / 4} corners differ, first ${bad.slice(0, 3).map(show).join("; ")}`);
  return { corners: ours.length / 4, worst, mirrored };
}

/** The first primitive with normals of a GLB, unindexed: positions, normals. */
function readGlb(path) {
  const bytes = readFileSync(path);
  const jsonLength = bytes.readUInt32LE(12);
  const json = JSON.parse(bytes.subarray(20, 20 + jsonLength).toString("utf8"));
  const binStart = 20 + jsonLength + 8;
  const accessor = (index) => {
    const a = json.accessors[index];
    const view = json.bufferViews[a.bufferView];
    const size = { SCALAR: 1, VEC2: 2, VEC3: 3 }[a.type];
    const Type = { 5126: Float32Array, 5125: Uint32Array, 5123: Uint16Array, 5121: Uint8Array }[a.componentType];
    const stride = view.byteStride ?? size * Type.BYTES_PER_ELEMENT;
    const base = binStart + (view.byteOffset ?? 0) + (a.byteOffset ?? 0);
    const out = new Float64Array(a.count * size);
    const data = new DataView(bytes.buffer, bytes.byteOffset);
    for (let i = 0; i < a.count; i++)
      for (let k = 0; k < size; k++) {
        const at = base + i * stride + k * Type.BYTES_PER_ELEMENT;
        out[i * size + k] = Type === Float32Array ? data.getFloat32(at, true) : Type === Uint32Array ? data.getUint32(at, true) : Type === Uint16Array ? data.getUint16(at, true) : data.getUint8(at);
      }
    return out;
  };
  // The model, not the floor: the primitive with the most corners. Without
  // normals (the samples leave them to the loader) they are area-weighted
  // sums over the indexed mesh, as the loader computes them.
  const primitive = json.meshes.flatMap((m) => m.primitives).reduce((a, b) => (json.accessors[b.indices].count > json.accessors[a.indices].count ? b : a));
  const p = accessor(primitive.attributes.POSITION);
  const indices = accessor(primitive.indices);
  let n = primitive.attributes.NORMAL !== undefined ? accessor(primitive.attributes.NORMAL) : null;
  if (!n) {
    n = new Float64Array(p.length);
    for (let t = 0; t < indices.length; t += 3) {
      const [a, b, c] = [indices[t], indices[t + 1], indices[t + 2]].map((v) => p.subarray(3 * v, 3 * v + 3));
      const e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]], e2 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
      const cross = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]];
      for (const v of [indices[t], indices[t + 1], indices[t + 2]]) for (let k = 0; k < 3; k++) n[3 * v + k] += cross[k];
    }
    for (let v = 0; v < n.length; v += 3) {
      const len = Math.hypot(n[v], n[v + 1], n[v + 2]) || 1;
      for (let k = 0; k < 3; k++) n[v + k] /= len;
    }
  }
  const positions = new Float32Array(indices.length * 3);
  const normals = new Float32Array(indices.length * 3);
  indices.forEach((v, c) => {
    positions.set(p.subarray(3 * v, 3 * v + 3), 3 * c);
    normals.set(n.subarray(3 * v, 3 * v + 3), 3 * c);
  });
  return { positions, normals };
}

function centre(positions) {
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < positions.length; i++) {
    lo[i % 3] = Math.min(lo[i % 3], positions[i]);
    hi[i % 3] = Math.max(hi[i % 3], positions[i]);
  }
  return { mid: lo.map((l, k) => (l + hi[k]) / 2), size: Math.max(...hi.map((h, k) => h - lo[k])) };
}

/** Spherical projection about the bounds' centre: a seam at -x, poles at ±y. */
function sphericalUvs(positions) {
  const { mid } = centre(positions);
  const uvs = new Float32Array((positions.length / 3) * 2);
  for (let c = 0; c < positions.length / 3; c++) {
    const x = positions[3 * c] - mid[0], y = positions[3 * c + 1] - mid[1], z = positions[3 * c + 2] - mid[2];
    const r = Math.hypot(x, y, z) || 1;
    uvs[2 * c] = 0.5 + Math.atan2(z, x) / (2 * Math.PI);
    uvs[2 * c + 1] = Math.acos(Math.max(-1, Math.min(1, y / r))) / Math.PI;
  }
  return uvs;
}

/** Planar projection onto xy: triangles seen edge-on get zero uv area. */
function planarUvs(positions) {
  const { mid, size } = centre(positions);
  const uvs = new Float32Array((positions.length / 3) * 2);
  for (let c = 0; c < positions.length / 3; c++) {
    uvs[2 * c] = (positions[3 * c] - mid[0]) / size + 0.5;
    uvs[2 * c + 1] = (positions[3 * c + 1] - mid[1]) / size + 0.5;
  }
  return uvs;
}

/** Indexed triangles to unindexed attribute arrays. */
function unindex(vertices, triangles) {
  const positions = [], normals = [], uvs = [];
  for (const v of triangles.flat()) {
    positions.push(...vertices[v].p);
    normals.push(...vertices[v].n);
    uvs.push(...vertices[v].uv);
  }
  return { positions: new Float32Array(positions), normals: new Float32Array(normals), uvs: new Float32Array(uvs) };
}

/** A UV sphere: the seam's column duplicated (u = 0 and 1), a vertex per pole corner. */
function uvSphere(columns, rows) {
  const vertices = [], triangles = [];
  for (let j = 0; j <= rows; j++)
    for (let i = 0; i <= columns; i++) {
      const theta = (j / rows) * Math.PI, phi = (i / columns) * 2 * Math.PI;
      const n = [Math.sin(theta) * Math.cos(phi), Math.cos(theta), -Math.sin(theta) * Math.sin(phi)];
      vertices.push({ p: n.map((x) => 2 * x), n, uv: [i / columns, j / rows] });
    }
  const at = (i, j) => j * (columns + 1) + i;
  for (let j = 0; j < rows; j++)
    for (let i = 0; i < columns; i++) {
      // The pole rows' triangles with two corners at the pole are degenerate.
      triangles.push([at(i, j), at(i, j + 1), at(i + 1, j + 1)], [at(i, j), at(i + 1, j + 1), at(i + 1, j)]);
    }
  return unindex(vertices, triangles);
}

/** A bumpy grid whose right half mirrors u (w = -1 there), with a few degenerate triangles. */
function mirroredGrid(size) {
  const vertices = [], triangles = [];
  for (let j = 0; j <= size; j++)
    for (let i = 0; i <= size; i++) {
      const x = i / size, y = j / size;
      const h = 0.1 * Math.sin(5 * x) * Math.cos(4 * y);
      const n = [-0.5 * Math.cos(5 * x) * Math.cos(4 * y), 0.4 * Math.sin(5 * x) * Math.sin(4 * y), 1];
      const len = Math.hypot(...n);
      vertices.push({ p: [x, y, h], n: n.map((c) => c / len), uv: [x <= 0.5 ? x : 1 - x, y] });
    }
  const at = (i, j) => j * (size + 1) + i;
  for (let j = 0; j < size; j++)
    for (let i = 0; i < size; i++)
      triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)], [at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
  // Degenerate triangles: two corners on one vertex, and one with all three.
  triangles.push([at(2, 2), at(2, 2), at(3, 2)], [at(size, 1), at(size - 1, 1), at(size, 1)], [at(4, 4), at(4, 4), at(4, 4)]);
  return unindex(vertices, triangles);
}

/**
 * A disc of `count` triangles around one centre vertex: that many corners at
 * one position (the port welds a crowd like that through a hash), some of
 * them written with z = -0, which welds with +0 as the reference compares.
 */
function disc(count) {
  const vertices = [{ p: [0, 0, 0], n: [0, 0, 1], uv: [0.5, 0.5] }, { p: [0, 0, -0], n: [0, 0, 1], uv: [0.5, 0.5] }];
  for (let i = 0; i < count; i++) {
    const a = (2 * Math.PI * i) / count;
    vertices.push({ p: [Math.cos(a), Math.sin(a), 0.1 * Math.sin(3 * a)], n: [0, 0, 1], uv: [0.5 + 0.4 * Math.cos(2 * a), 0.5 + 0.4 * Math.sin(2 * a)] });
  }
  const triangles = [];
  for (let i = 0; i < count; i++) triangles.push([i % 3 === 0 ? 1 : 0, 2 + i, 2 + ((i + 1) % count)]);
  return unindex(vertices, triangles);
}

describe("MikkTSpace port against the reference", { timeout: 120_000 }, () => {
  test("rt_tangents is built", () => {
    assert.ok(existsSync(TOOL), `${TOOL} is missing: build the renderer (make build)`);
  });

  for (const [scene, project] of [["teapot", sphericalUvs], ["bunny", planarUvs], ["dragon_4", sphericalUvs]]) {
    test(`${scene} with ${project.name}`, (t) => {
      const path = join(SCENES, `${scene}.glb`);
      assert.ok(existsSync(path), `${path} is missing: make samples`);
      const { positions, normals } = readGlb(path);
      const result = compare(scene, positions, normals, project(positions));
      t.diagnostic(`${result.corners} corners, worst component difference ${result.worst.toExponential(2)}, ${result.mirrored} with w = -1`);
      assert.ok(result.corners > 1000);
    });
  }

  test("UV sphere with a seam and poles", (t) => {
    const { positions, normals, uvs } = uvSphere(24, 12);
    const result = compare("uv sphere", positions, normals, uvs);
    t.diagnostic(`${result.corners} corners, worst ${result.worst.toExponential(2)}`);
  });

  test("a disc of 300 triangles around one vertex", (t) => {
    const { positions, normals, uvs } = disc(300);
    const result = compare("disc", positions, normals, uvs);
    t.diagnostic(`${result.corners} corners, worst ${result.worst.toExponential(2)}`);
  });

  test("mirrored uvs give w = -1 on the mirrored half", (t) => {
    const { positions, normals, uvs } = mirroredGrid(16);
    const result = compare("mirrored grid", positions, normals, uvs);
    t.diagnostic(`${result.corners} corners, worst ${result.worst.toExponential(2)}, ${result.mirrored} with w = -1`);
    // The reference's sign convention: w = -1 where u runs against x, about half.
    assert.ok(result.mirrored > result.corners / 3 && result.mirrored < (2 * result.corners) / 3, `${result.mirrored} mirrored`);
  });
});
