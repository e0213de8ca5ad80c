// The BVH boxes of one level of one tree (GET /api/scenes/<id>/bvh?level=N&tree=T)
// as the 12 edges of each box in one LineSegments, inner nodes' and leaves'
// boxes in their own colours; optionally only the boxes that the debugged ray
// (or the pinned segment) visited. With instances the tree is the top level,
// the one over the triangles placed once, or an instance's: its mesh's tree,
// drawn through the instance's transform, so its boxes stand where the
// instance does.
import * as THREE from "three";
import { bvhBoxes } from "./api.js";
import { enumOf } from "./proto.js";

const treeKind = (name) => enumOf("BvhTreeKind").values.find((v) => v.name === name).number;

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

/** The REST name of a tree a ray entered (a TreeVisit): "world" or the instance's number. */
export function treeName(visit) {
  return visit.tree === treeKind("BVH_TREE_WORLD") ? "world" : String(visit.instance);
}

/**
 * The box numbers some ray segments visited in `tree` ("top", "world" or an
 * instance number): the nodes whose child boxes they tested and the leaves
 * whose triangles they tested.
 */
export function visitedBoxes(segments, tree = "top") {
  if (tree === "top") return segments.flatMap((s) => [...s.visitedNodes, ...s.visitedLeaves]);
  return segments.flatMap((s) => s.trees.filter((t) => treeName(t) === String(tree))
    .flatMap((t) => [...t.visitedNodes, ...t.visitedLeaves]));
}

/** The trees below the top level some segments entered, by REST name, each once, in entering order. */
export function enteredTrees(segments) {
  return [...new Set(segments.flatMap((s) => s.trees.map(treeName)))];
}

export class BvhBoxes extends EventTarget {
  constructor(viewer) {
    super();
    this.viewer = viewer;
    this.sceneId = null;
    this.tree = "top";
    this.instanceCount = 0; // instances the top level places (0: one tree)
    this.hasWorldTree = false;
    this.level = 0;
    this.totalLevels = 0;
    this.nodeWidth = 0;
    this.data = null;
    this.segments = null; // the debugged ray's segments, or null: no ray selected
    this.onlyVisited = false;
    this.cache = new Map();
    this.lines = new THREE.LineSegments(new THREE.BufferGeometry(),
      new THREE.LineBasicMaterial({ vertexColors: true, transparent: true, opacity: 0.55, depthWrite: false }));
    this.lines.name = "bvh boxes";
    this.lines.frustumCulled = false;
    this.lines.matrixAutoUpdate = false; // the tree's to_world
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
    this.instanceCount = 0;
    this.hasWorldTree = false;
    this.tree = "top";
    this.level = 0;
    this._rebuild();
    if (!sceneId) return Promise.resolve();
    return this._learnTree(sceneId, "top");
  }

  /** Walks another tree ("top", "world" or an instance number) from its root level. */
  setTree(tree) {
    this.tree = String(tree);
    this.data = null;
    this.totalLevels = 0;
    this.level = 0;
    this._rebuild();
    if (!this.sceneId) return Promise.resolve();
    return this._learnTree(this.sceneId, this.tree);
  }

  _learnTree(sceneId, tree) {
    return bvhBoxes(sceneId, 0, tree).then((root) => {
      if (this.sceneId !== sceneId || this.tree !== tree) return;
      this.cache.set(`${sceneId}:${tree}:0`, root);
      this.totalLevels = root.totalLevels;
      this.nodeWidth = root.nodeWidth;
      this.instanceCount = root.instanceCount;
      this.hasWorldTree = root.hasWorldTree;
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
    const key = `${this.sceneId}:${this.tree}:${level}`;
    let data = this.cache.get(key);
    if (!data) {
      data = await bvhBoxes(this.sceneId, level, this.tree);
      this.cache.set(key, data);
    }
    if (key !== `${this.sceneId}:${this.tree}:${this.level}`) return; // a newer request won
    this.data = data;
    this.totalLevels = data.totalLevels;
    this.nodeWidth = data.nodeWidth;
    this._rebuild();
  }

  /** The segments of the selected ray (null: no ray selected), whose visited boxes "only visited" keeps. */
  setVisited(segments) {
    this.segments = segments;
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
      const visited = this.segments ? new Set(visitedBoxes(this.segments, this.tree)) : null;
      const filter = this.onlyVisited ? (i) => visited !== null && visited.has(data.nodes[i]) : undefined;
      result = boxEdgePositions(data.bounds, filter, data.leaf);
    }
    if (data?.toWorld.length === 16) this.lines.matrix.fromArray(data.toWorld);
    else this.lines.matrix.identity();
    this.lines.matrixWorldNeedsUpdate = true;
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
        level: this.level, totalLevels: this.totalLevels, nodeWidth: this.nodeWidth, tree: this.tree,
        instanceName: data?.instanceName ?? "",
        instanceCount: this.instanceCount, hasWorldTree: this.hasWorldTree,
        shown: result.boxes, shownLeaves: result.leaves, leafTriangles,
        total: data ? data.nodes.length : 0, totalLeaves: data ? data.leaf.filter(Boolean).length : 0,
      },
    }));
  }
}
