// Keeps the view interactive on a slow GPU, while the camera moves only; the
// first frame after it stops is full detail again. On a GPU that draws the
// scene within budget nothing changes.
// - Geometry: after a scene loads, one full-detail frame is timed; if it is
//   over budget, every large mesh gets a vertex-clustered proxy (Rossignac &
//   Borrel) with as many triangles as the measured speed allows.
// - Pixels: while moving, frames slower than the budget lower the pixel ratio
//   step by step (down to a third), frames well within it raise it again.
// - Overlays: when that is not enough, large line sets (debug rays, BVH boxes)
//   draw every k-th ray or box while moving, through an index over the same
//   vertex buffers; k doubles while frames stay slow and halves when fast.
import * as THREE from "three";

const FRAME_BUDGET_MS = 33; // 30 frames per second
const PROXY_SHARE = 0.2; // of the budget, for the proxies: overlays, compositing and the page take the rest
const STILL_AFTER_MS = 180;
const MIN_PROXY_SOURCE = 20_000; // triangles: smaller meshes are drawn as they are
const MIN_RESOLUTION = 0.35;
const MAX_STRIDE = 64;
const RAISE_AFTER_FAST_FRAMES = 12;
const MIN_THINNED_LINES = 4_000;

/**
 * Vertex clustering: vertices snapped to an n³ grid over the box merge into one
 * (their mean); triangles whose corners merge vanish. Returns an indexed geometry.
 */
export function clusterGeometry(geometry, box, n) {
  const position = geometry.attributes.position;
  const index = geometry.index;
  const size = box.getSize(new THREE.Vector3());
  const scale = [n / (size.x || 1), n / (size.y || 1), n / (size.z || 1)];
  const cellOf = new Int32Array(position.count);
  const cells = new Map();
  const sums = [];
  for (let v = 0; v < position.count; v++) {
    const x = position.getX(v);
    const y = position.getY(v);
    const z = position.getZ(v);
    const cx = Math.min(n - 1, Math.max(0, Math.floor((x - box.min.x) * scale[0])));
    const cy = Math.min(n - 1, Math.max(0, Math.floor((y - box.min.y) * scale[1])));
    const cz = Math.min(n - 1, Math.max(0, Math.floor((z - box.min.z) * scale[2])));
    const key = (cx * n + cy) * n + cz;
    let cell = cells.get(key);
    if (cell === undefined) {
      cell = sums.length / 4;
      cells.set(key, cell);
      sums.push(0, 0, 0, 0);
    }
    sums[cell * 4] += x;
    sums[cell * 4 + 1] += y;
    sums[cell * 4 + 2] += z;
    sums[cell * 4 + 3] += 1;
    cellOf[v] = cell;
  }
  const cellCount = sums.length / 4;
  const positions = new Float32Array(cellCount * 3);
  for (let c = 0; c < cellCount; c++) {
    const k = sums[c * 4 + 3];
    positions[c * 3] = sums[c * 4] / k;
    positions[c * 3 + 1] = sums[c * 4 + 1] / k;
    positions[c * 3 + 2] = sums[c * 4 + 2] / k;
  }
  const triangles = index ? index.count / 3 : position.count / 3;
  const corner = index ? (i) => index.getX(i) : (i) => i;
  const out = [];
  // Triangles that merge into the same three cells are drawn once: the key is
  // the triangle rotated to start at its smallest cell (keeping its winding).
  const seen = cellCount < 200_000 ? new Set() : null;
  for (let t = 0; t < triangles; t++) {
    let a = cellOf[corner(t * 3)];
    let b = cellOf[corner(t * 3 + 1)];
    let c = cellOf[corner(t * 3 + 2)];
    if (a === b || b === c || a === c) continue;
    if (b < a && b < c) [a, b, c] = [b, c, a];
    else if (c < a && c < b) [a, b, c] = [c, a, b];
    if (seen) {
      const key = (a * cellCount + b) * cellCount + c;
      if (seen.has(key)) continue;
      seen.add(key);
    }
    out.push(a, b, c);
  }
  const proxy = new THREE.BufferGeometry();
  proxy.setAttribute("position", new THREE.BufferAttribute(positions, 3));
  proxy.setIndex(cellCount > 65535 ? new THREE.Uint32BufferAttribute(out, 1) : new THREE.Uint16BufferAttribute(out, 1));
  proxy.computeVertexNormals();
  return proxy;
}

function triangleCount(geometry) {
  return (geometry.index ? geometry.index.count : geometry.attributes.position.count) / 3;
}

// What a mesh draws: an InstancedMesh its geometry once per instance.
function drawnTriangles(mesh) {
  return triangleCount(mesh.geometry) * (mesh.isInstancedMesh ? mesh.count : 1);
}

export class InteractiveLod {
  constructor(viewer) {
    this.viewer = viewer;
    this.pairs = []; // { full, proxy }
    this.moving = false;
    this.fullFrameMs = 0;
    this.resolution = 1; // share of the pixel ratio used while moving
    this._changed = false;
    this._lastChange = 0;
    this._lastFrame = 0;
    this.stride = 1; // every k-th ray or box of large overlays while moving
    this._fast = 0;
    this.overlays = []; // { lines, group, thin, source, stride }
    viewer.addEventListener("camerachange", () => this._moved());
  }

  /** A LineSegments that may be thinned while moving, `group` vertices per item (2 for a ray, 24 for a box). */
  addOverlay(lines, group) {
    const thin = new THREE.LineSegments(new THREE.BufferGeometry(), lines.material);
    thin.name = `${lines.name} (thinned while moving)`;
    thin.visible = false;
    thin.frustumCulled = false;
    thin.matrixAutoUpdate = lines.matrixAutoUpdate;
    thin.renderOrder = lines.renderOrder;
    lines.parent.add(thin);
    this.overlays.push({ lines, group, thin, source: null, stride: 1 });
  }

  _thin(overlay, thinned) {
    const { lines, group, thin } = overlay;
    const count = lines.geometry.attributes.position?.count ?? 0;
    const use = thinned && this.stride > 1 && lines.visible && count / 2 >= MIN_THINNED_LINES;
    if (use && (overlay.source !== lines.geometry || overlay.stride !== this.stride)) {
      const items = count / group;
      const kept = Math.ceil(items / this.stride);
      const index = new Uint32Array(kept * group);
      for (let i = 0, o = 0; i < items; i += this.stride) {
        for (let k = 0; k < group; k++) index[o++] = i * group + k;
      }
      const geometry = new THREE.BufferGeometry();
      for (const [name, attribute] of Object.entries(lines.geometry.attributes)) geometry.setAttribute(name, attribute);
      geometry.setIndex(new THREE.BufferAttribute(index, 1));
      thin.geometry.dispose();
      thin.geometry = geometry;
      overlay.source = lines.geometry;
      overlay.stride = this.stride;
    }
    lines.userData.thinned = use;
    thin.visible = use;
    // The thinned copy stands where the lines do (an instance tree's boxes have a transform).
    thin.matrixAutoUpdate = lines.matrixAutoUpdate;
    if (use) {
      thin.matrix.copy(lines.matrix);
      thin.matrixWorldNeedsUpdate = true;
    }
    if (use) lines.layers.disable(0);
    else lines.layers.enable(0);
  }

  /** Called for every frame drawn: adapts the detail of moving frames to the last frame's time. */
  frame(now) {
    const interval = now - this._lastFrame;
    this._lastFrame = now;
    if (!this.moving) return;
    if (this._moveFrames++ === 0) return; // the interval before a move's first frame is idle time
    let next = this.resolution;
    let stride = this.stride;
    if (interval > FRAME_BUDGET_MS * 1.2) {
      // Pixels scale with the square of the resolution: step by the square root of the overshoot.
      const factor = Math.sqrt(Math.max(0.25, FRAME_BUDGET_MS / interval));
      if (this.resolution > MIN_RESOLUTION) next = Math.max(MIN_RESOLUTION, this.resolution * Math.min(0.85, factor));
      else stride = Math.min(MAX_STRIDE, stride * 2 ** Math.min(3, Math.ceil(Math.log2(interval / FRAME_BUDGET_MS))));
      this._fast = 0;
    } else if (interval < FRAME_BUDGET_MS * 0.6 && ++this._fast >= RAISE_AFTER_FAST_FRAMES) {
      // Detail comes back only after a run of fast frames, so it does not flicker.
      this._fast = 0;
      if (stride > 1) stride = Math.max(1, stride / 2);
      else next = Math.min(1, this.resolution * 1.1);
    }
    if (Math.abs(next - this.resolution) > 0.01) {
      this.resolution = next;
      this.viewer.setResolution(next);
    }
    this.stride = stride;
    for (const overlay of this.overlays) this._thin(overlay, true);
  }

  /** Times one synchronous frame of what is shown now (after a warm-up frame). */
  timeFrame() {
    const { renderer, scene, camera } = this.viewer;
    const gl = renderer.getContext();
    const pixel = new Uint8Array(4);
    renderer.render(scene, camera);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel); // waits for the frame
    const start = performance.now();
    renderer.render(scene, camera);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
    return performance.now() - start;
  }

  /** A scene was loaded into viewer.model: measure, and build proxies when too slow. */
  prepare() {
    this.clear();
    const meshes = [];
    this.viewer.model.traverse((o) => {
      if (o.isMesh && drawnTriangles(o) >= MIN_PROXY_SOURCE) meshes.push(o);
    });
    if (!meshes.length) return;
    this.fullFrameMs = this.timeFrame();
    if (this.fullFrameMs <= FRAME_BUDGET_MS) return;
    // Far over budget: the first move starts at a lower resolution rather than finding it frame by frame.
    this.resolution = Math.max(MIN_RESOLUTION, Math.min(1, Math.sqrt((4 * FRAME_BUDGET_MS) / this.fullFrameMs)));
    const total = meshes.reduce((n, m) => n + drawnTriangles(m), 0);
    const perMs = total / this.fullFrameMs;
    const budget = Math.max(2_000, perMs * FRAME_BUDGET_MS * PROXY_SHARE);
    // Meshes drawn by several nodes share one geometry, and so one proxy.
    const proxies = new Map();
    for (const mesh of meshes) {
      // Triangles for one copy of this geometry: its share of the budget over the copies drawn.
      const share = (budget * triangleCount(mesh.geometry)) / total;
      let proxy = proxies.get(mesh.geometry) ?? null;
      if (!proxy) {
        mesh.geometry.computeBoundingBox();
        const box = mesh.geometry.boundingBox;
        // A surface over an n³ grid keeps about 2n² triangles: start a little above that.
        for (let n = Math.ceil(Math.sqrt(share) * 1.2); n >= 4; n = Math.floor(n / 1.25)) {
          proxy?.dispose();
          proxy = clusterGeometry(mesh.geometry, box, n);
          if (triangleCount(proxy) <= share) break;
        }
        proxies.set(mesh.geometry, proxy);
      }
      const stand = mesh.isInstancedMesh ? new THREE.InstancedMesh(proxy, mesh.material, mesh.count)
        : new THREE.Mesh(proxy, mesh.material);
      if (mesh.isInstancedMesh) stand.instanceMatrix = mesh.instanceMatrix;
      stand.name = `${mesh.name || "mesh"} (proxy while moving)`;
      stand.visible = false;
      stand.matrixAutoUpdate = false;
      mesh.parent.add(stand);
      stand.matrix.copy(mesh.matrix);
      this.pairs.push({ full: mesh, proxy: stand });
    }
    this.proxyTriangles = this.pairs.reduce((n, p) => n + drawnTriangles(p.proxy), 0);
  }

  clear() {
    for (const { proxy } of this.pairs) {
      proxy.parent?.remove(proxy);
      proxy.geometry.dispose();
    }
    this.pairs = [];
    this.proxyTriangles = 0;
  }

  get active() {
    return this.pairs.length > 0;
  }

  _moved() {
    this._changed = true;
    if (!this.moving) this._show(true);
  }

  /**
   * Called on every animation frame, drawn or not: a move ends once frames
   * have gone by with no camera change for a while. (Counting frames rather
   * than a timer: a slow frame must not end a move that is still going on.)
   */
  tick(now) {
    if (!this.moving) return;
    if (this._changed) {
      this._changed = false;
      this._lastChange = now;
    } else if (now - this._lastChange > STILL_AFTER_MS) {
      this._show(false);
      this.viewer.requestRender();
    }
  }

  _show(moving) {
    this.moving = moving;
    this._moveFrames = 0;
    this.viewer.setResolution(moving ? this.resolution : 1);
    for (const overlay of this.overlays) this._thin(overlay, moving);
    for (const { full, proxy } of this.pairs) {
      full.visible = !moving;
      proxy.visible = moving;
    }
  }
}
