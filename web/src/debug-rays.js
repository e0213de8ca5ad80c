// One pixel's ray tree (rt.DebugPath) in the 3D view: every segment in one
// LineSegments with one BufferGeometry, coloured by kind and outcome, with
// the shading normal drawn at each hit; a legend, and the pixel's numbers.
import * as THREE from "three";
import { enumName } from "./proto.js";

export const CATEGORIES = [
  { id: "primary", label: "Primary ray", color: "#f2f2f2" },
  { id: "reflection", label: "Reflection", color: "#35c8ff" },
  { id: "refraction", label: "Refraction", color: "#5cffc8" },
  { id: "miss", label: "Left the scene (miss)", color: "#7d8694" },
  { id: "shadow-lit", label: "Shadow ray reached the light", color: "#ffd24a" },
  { id: "shadow-blocked", label: "Shadow ray blocked", color: "#ff4d4d" },
  { id: "soft-lit", label: "Soft-shadow sample, reached", color: "#ffa64d" },
  { id: "soft-blocked", label: "Soft-shadow sample, blocked", color: "#c05cff" },
  { id: "normal", label: "Surface normal at a hit", color: "#4cff7a" },
];
const COLORS = Object.fromEntries(CATEGORIES.map((c) => [c.id, new THREE.Color(c.color)]));

/**
 * The category of each segment. A shadow ray is a soft-shadow sample when the
 * light it aims at (its `light` index into the scene's lights) is spherical.
 */
export function categorize(segments, lights) {
  return segments.map((s) => {
    const kind = enumName("RayKind", s.kind);
    const outcome = enumName("RayOutcome", s.outcome);
    if (kind === "SHADOW") {
      // Each shadow ray names the light it aims at: a spherical light's rays are soft-shadow samples.
      const soft = (lights[s.light]?.radius ?? 0) > 0;
      const lit = outcome === "REACHED_LIGHT";
      return soft ? (lit ? "soft-lit" : "soft-blocked") : (lit ? "shadow-lit" : "shadow-blocked");
    }
    if (outcome === "MISS") return "miss";
    return kind === "PRIMARY" ? "primary" : kind === "REFRACTION" ? "refraction" : "reflection";
  });
}

/** Sums over a path: rays by kind, BVH nodes and leaves visited, triangles tested. */
export function pathStats(path) {
  const stats = { rays: path.segments.length, primary: 0, reflection: 0, refraction: 0, shadow: 0, nodes: 0, leaves: 0, triangles: 0 };
  for (const s of path.segments) {
    stats[enumName("RayKind", s.kind).toLowerCase()] += 1;
    stats.nodes += s.visitedNodes.length;
    stats.leaves += s.visitedLeaves.length;
    stats.triangles += s.trianglesTested;
  }
  return stats;
}

export class DebugRays {
  constructor(viewer) {
    this.viewer = viewer;
    this.path = null;
    this.lineToSegment = new Uint32Array(0);
    this.material = new THREE.LineBasicMaterial({ vertexColors: true, depthTest: false, transparent: true, opacity: 0.95 });
    this.lines = new THREE.LineSegments(new THREE.BufferGeometry(), this.material);
    this.lines.name = "debug rays";
    this.lines.renderOrder = 10;
    this.lines.frustumCulled = false;
    this.highlight = new THREE.LineSegments(new THREE.BufferGeometry(),
      new THREE.LineBasicMaterial({ color: 0xffffff, depthTest: false, linewidth: 1 }));
    this.highlight.renderOrder = 11;
    this.highlight.frustumCulled = false;
    this.highlight.visible = false;
    viewer.overlays.add(this.lines, this.highlight);
  }

  /** Draws a path's segments (and a normal at every hit); null clears. */
  show(path, lights = []) {
    this.path = path;
    const segments = path?.segments ?? [];
    const categories = categorize(segments, lights);
    const hits = segments.filter((s) => s.normal.length === 3 && enumName("RayOutcome", s.outcome) === "HIT").length;
    const lineCount = segments.length + hits;
    const positions = new Float32Array(lineCount * 6);
    const colors = new Float32Array(lineCount * 6);
    const lineToSegment = new Uint32Array(lineCount);
    const normalLength = this.viewer.sceneSize * 0.04;
    let line = 0;
    const put = (a, b, color, segment) => {
      positions.set(a, line * 6);
      positions.set(b, line * 6 + 3);
      color.toArray(colors, line * 6);
      color.toArray(colors, line * 6 + 3);
      lineToSegment[line] = segment;
      line++;
    };
    segments.forEach((s, i) => {
      put(s.origin, s.end, COLORS[categories[i]], i);
    });
    segments.forEach((s, i) => {
      if (s.normal.length !== 3 || enumName("RayOutcome", s.outcome) !== "HIT") return;
      const tip = s.end.map((v, k) => v + s.normal[k] * normalLength);
      put(s.end, tip, COLORS.normal, i);
    });
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.BufferAttribute(positions, 3));
    geometry.setAttribute("color", new THREE.BufferAttribute(colors, 3));
    geometry.computeBoundingSphere();
    this.lines.geometry.dispose();
    this.lines.geometry = geometry;
    this.lineToSegment = lineToSegment;
    this.categories = categories;
    this.setHighlight(null);
    this.viewer.requestRender();
  }

  setVisible(visible) {
    this.lines.visible = visible;
    if (!visible) this.highlight.visible = false;
    this.viewer.requestRender();
  }

  /** Total line segments drawn (rays and normals). */
  get lineCount() {
    return this.lineToSegment.length;
  }

  /** The segment index under a ray from the camera, or -1. */
  pick(raycaster) {
    if (!this.path || this.lineCount === 0) return -1;
    const hits = raycaster.intersectObject(this.lines, false);
    if (!hits.length) return -1;
    // The line nearest the pointer on screen (smallest angle from the pointer's ray), not the nearest in depth.
    const angle = (hit) => raycaster.ray.distanceToPoint(hit.point) / Math.max(hit.distance, 1e-9);
    const best = hits.reduce((a, b) => (angle(b) < angle(a) ? b : a));
    return this.lineToSegment[Math.floor(best.index / 2)];
  }

  /** Draws one segment brighter (index -1 or null: none). */
  setHighlight(index) {
    const segment = index >= 0 && this.path ? this.path.segments[index] : null;
    this.highlight.visible = !!segment && this.lines.visible;
    this.viewer.requestRender();
    if (!segment) return;
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.Float32BufferAttribute([...segment.origin, ...segment.end], 3));
    this.highlight.geometry.dispose();
    this.highlight.geometry = geometry;
  }
}

/** The legend: a swatch and a label per category, with its count in this path. */
export function renderLegend(list, categories = []) {
  const counts = new Map();
  for (const c of categories) counts.set(c, (counts.get(c) ?? 0) + 1);
  list.replaceChildren(...CATEGORIES.map((c) => {
    const li = document.createElement("li");
    const swatch = document.createElement("span");
    swatch.className = "swatch";
    swatch.style.background = c.color;
    const count = c.id === "normal" ? "" : ` (${counts.get(c.id) ?? 0})`;
    li.append(swatch, `${c.label}${categories.length ? count : ""}`);
    return li;
  }));
}
