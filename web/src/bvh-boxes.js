// The BVH boxes of one level (GET /api/scenes/<id>/bvh?level=N) as the 12
// edges of each box in one LineSegments; optionally only the boxes that the
// debugged ray (or the pinned segment) visited.
import * as THREE from "three";
import { bvhBoxes } from "./api.js";

// Corner pairs of a box's 12 edges; corner bits: x (1), y (2), z (4).
const EDGES = [0, 1, 2, 3, 4, 5, 6, 7, 0, 2, 1, 3, 4, 6, 5, 7, 0, 4, 1, 5, 2, 6, 3, 7];

/** Line-segment positions of boxes (6 floats each: min xyz, max xyz), those kept by `keep(i)`. */
export function boxEdgePositions(bounds, keep = () => true) {
  const count = bounds.length / 6;
  const kept = [];
  for (let i = 0; i < count; i++) if (keep(i)) kept.push(i);
  const out = new Float32Array(kept.length * 24 * 3);
  let o = 0;
  for (const i of kept) {
    const b = i * 6;
    for (const corner of EDGES) {
      out[o++] = bounds[b + (corner & 1 ? 3 : 0)];
      out[o++] = bounds[b + 1 + (corner & 2 ? 3 : 0)];
      out[o++] = bounds[b + 2 + (corner & 4 ? 3 : 0)];
    }
  }
  return { positions: out, boxes: kept.length };
}

export class BvhBoxes extends EventTarget {
  constructor(viewer) {
    super();
    this.viewer = viewer;
    this.sceneId = null;
    this.level = 0;
    this.totalLevels = 0;
    this.data = null;
    this.visited = null; // Set of node indices, or null: show all
    this.onlyVisited = false;
    this.cache = new Map();
    this.lines = new THREE.LineSegments(new THREE.BufferGeometry(),
      new THREE.LineBasicMaterial({ color: 0x7cf29a, transparent: true, opacity: 0.55, depthWrite: false }));
    this.lines.name = "bvh boxes";
    this.lines.frustumCulled = false;
    this.lines.visible = false;
    viewer.overlays.add(this.lines);
    this.shownBoxes = 0;
  }

  /** A new scene: forget cached levels and learn the depth of its tree (the slider's range). */
  setScene(sceneId) {
    this.sceneId = sceneId;
    this.cache.clear();
    this.data = null;
    this.totalLevels = 0;
    this.level = 0;
    this._rebuild();
    if (!sceneId) return Promise.resolve();
    return bvhBoxes(sceneId, 0).then((root) => {
      if (this.sceneId !== sceneId) return;
      this.cache.set(`${sceneId}:0`, root);
      this.totalLevels = root.totalLevels;
      if (this.lines.visible && !this.data) this.setLevel(this.level);
      else this._rebuild();
    });
  }

  setVisible(visible) {
    this.lines.visible = visible;
    this.viewer.requestRender();
    if (visible && !this.data && this.sceneId) return this.setLevel(this.level);
    return Promise.resolve();
  }

  /** Fetches and shows one level. */
  async setLevel(level) {
    this.level = level;
    if (!this.sceneId) return;
    const key = `${this.sceneId}:${level}`;
    let data = this.cache.get(key);
    if (!data) {
      data = await bvhBoxes(this.sceneId, level);
      this.cache.set(key, data);
    }
    if (key !== `${this.sceneId}:${this.level}`) return; // a newer request won
    this.data = data;
    this.totalLevels = data.totalLevels;
    this._rebuild();
  }

  /** Node indices the selected ray visited (null: no ray selected). */
  setVisited(nodes) {
    this.visited = nodes ? new Set(nodes) : null;
    this._rebuild();
  }

  setOnlyVisited(only) {
    this.onlyVisited = only;
    this._rebuild();
  }

  _rebuild() {
    const data = this.data;
    let result = { positions: new Float32Array(0), boxes: 0 };
    if (data) {
      const filter = this.onlyVisited ? (i) => this.visited !== null && this.visited.has(data.nodes[i]) : undefined;
      result = boxEdgePositions(data.bounds, filter);
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.BufferAttribute(result.positions, 3));
    this.lines.geometry.dispose();
    this.lines.geometry = geometry;
    this.shownBoxes = result.boxes;
    this.viewer.requestRender();
    this.dispatchEvent(new CustomEvent("change", {
      detail: { level: this.level, totalLevels: this.totalLevels, shown: result.boxes, total: data ? data.nodes.length : 0 },
    }));
  }
}
