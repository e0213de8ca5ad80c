// The BVH boxes of one level (GET /api/scenes/<id>/bvh?level=N) as the 12
// edges of each box in one LineSegments, inner nodes' and leaves' boxes in
// their own colours; optionally only the boxes that the debugged ray (or the
// pinned segment) visited.
import * as THREE from "three";
import { bvhBoxes } from "./api.js";

/** Edge colours: an inner node's box (its children are tested), a leaf's (its triangles are). */
export const BOX_COLORS = { node: "#7cf29a", leaf: "#ff8fc8" };
const COLORS = { node: new THREE.Color(BOX_COLORS.node), leaf: new THREE.Color(BOX_COLORS.leaf) };

// Corner pairs of a box's 12 edges; corner bits: x (1), y (2), z (4).
const EDGES = [0, 1, 2, 3, 4, 5, 6, 7, 0, 2, 1, 3, 4, 6, 5, 7, 0, 4, 1, 5, 2, 6, 3, 7];

/**
 * Line-segment positions of boxes (6 floats each: min xyz, max xyz), those
 * kept by `keep(i)`, and their vertex colours (`leaf[i]`: a leaf's colour).
 */
export function boxEdgePositions(bounds, keep = () => true, leaf = []) {
  const count = bounds.length / 6;
  const kept = [];
  for (let i = 0; i < count; i++) if (keep(i)) kept.push(i);
  const out = new Float32Array(kept.length * 24 * 3);
  const colors = new Float32Array(kept.length * 24 * 3);
  let o = 0;
  let leaves = 0;
  for (const i of kept) {
    const b = i * 6;
    const color = leaf[i] ? COLORS.leaf : COLORS.node;
    if (leaf[i]) leaves++;
    for (const corner of EDGES) {
      color.toArray(colors, o);
      out[o++] = bounds[b + (corner & 1 ? 3 : 0)];
      out[o++] = bounds[b + 1 + (corner & 2 ? 3 : 0)];
      out[o++] = bounds[b + 2 + (corner & 4 ? 3 : 0)];
    }
  }
  return { positions: out, colors, boxes: kept.length, leaves, kept };
}

/** The box numbers some ray segments visited: the nodes whose child boxes they tested and the leaves whose triangles they tested. */
export function visitedBoxes(segments) {
  return segments.flatMap((s) => [...s.visitedNodes, ...s.visitedLeaves]);
}

export class BvhBoxes extends EventTarget {
  constructor(viewer) {
    super();
    this.viewer = viewer;
    this.sceneId = null;
    this.level = 0;
    this.totalLevels = 0;
    this.nodeWidth = 0;
    this.data = null;
    this.visited = null; // Set of box numbers (nodes and leaves), or null: show all
    this.onlyVisited = false;
    this.cache = new Map();
    this.lines = new THREE.LineSegments(new THREE.BufferGeometry(),
      new THREE.LineBasicMaterial({ vertexColors: true, transparent: true, opacity: 0.55, depthWrite: false }));
    this.lines.name = "bvh boxes";
    this.lines.frustumCulled = false;
    this.lines.visible = false;
    viewer.overlays.add(this.lines);
    this.shownBoxes = 0;
    this.shownLeaves = 0;
  }

  /** A new scene: forget cached levels and learn the depth and width of its tree (the slider's range, the legend). */
  setScene(sceneId) {
    this.sceneId = sceneId;
    this.cache.clear();
    this.data = null;
    this.totalLevels = 0;
    this.nodeWidth = 0;
    this.level = 0;
    this._rebuild();
    if (!sceneId) return Promise.resolve();
    return bvhBoxes(sceneId, 0).then((root) => {
      if (this.sceneId !== sceneId) return;
      this.cache.set(`${sceneId}:0`, root);
      this.totalLevels = root.totalLevels;
      this.nodeWidth = root.nodeWidth;
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
    this.nodeWidth = data.nodeWidth;
    this._rebuild();
  }

  /** Box numbers (nodes and leaves) the selected ray visited (null: no ray selected). */
  setVisited(boxes) {
    this.visited = boxes ? new Set(boxes) : null;
    this._rebuild();
  }

  setOnlyVisited(only) {
    this.onlyVisited = only;
    this._rebuild();
  }

  _rebuild() {
    const data = this.data;
    let result = { positions: new Float32Array(0), colors: new Float32Array(0), boxes: 0, leaves: 0, kept: [] };
    if (data) {
      const filter = this.onlyVisited ? (i) => this.visited !== null && this.visited.has(data.nodes[i]) : undefined;
      result = boxEdgePositions(data.bounds, filter, data.leaf);
    }
    // The triangles in the leaves shown: those a ray that enters them tests.
    const leafTriangles = result.kept.reduce((n, i) => n + (data.leaf[i] ? data.leafTriangles[i] : 0), 0);
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.BufferAttribute(result.positions, 3));
    geometry.setAttribute("color", new THREE.BufferAttribute(result.colors, 3));
    this.lines.geometry.dispose();
    this.lines.geometry = geometry;
    this.shownBoxes = result.boxes;
    this.shownLeaves = result.leaves;
    this.viewer.requestRender();
    this.dispatchEvent(new CustomEvent("change", {
      detail: {
        level: this.level, totalLevels: this.totalLevels, nodeWidth: this.nodeWidth,
        shown: result.boxes, shownLeaves: result.leaves, leafTriangles,
        total: data ? data.nodes.length : 0, totalLeaves: data ? data.leaf.filter(Boolean).length : 0,
      },
    }));
  }
}
