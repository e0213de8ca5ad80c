// Hovering a ray segment in the 3D view shows its numbers (kind, outcome, t,
// hit point, material, contribution, weight, BVH nodes and leaves visited,
// triangles tested); a click without a drag pins it (and the BVH "visited"
// filter then follows that one ray).
import * as THREE from "three";
import { enumName } from "./proto.js";

const fmt = (v, digits = 4) => (Number.isFinite(v) ? Number(v.toPrecision(digits)).toString() : "–");
const vec = (a) => (a && a.length ? `(${Array.from(a, (v) => fmt(v)).join(", ")})` : "–");

export function describeSegment(segment, index) {
  const kind = enumName("RayKind", segment.kind);
  const outcome = enumName("RayOutcome", segment.outcome);
  const rows = [
    ["ray", `#${index} ${kind.toLowerCase()}, ${outcome.toLowerCase().replace("_", " ")}`],
    ["depth", String(segment.depth)],
    ["parent", segment.parent < 0 ? "none (camera)" : `#${segment.parent}`],
    ["t", fmt(segment.t)],
    ["origin", vec(segment.origin)],
    [outcome === "HIT" ? "hit point" : "end", vec(segment.end)],
  ];
  if (outcome === "HIT") {
    rows.push(["normal", vec(segment.normal)]);
    rows.push(["material", segment.materialName ? `${segment.materialName} (#${segment.material})` : `#${segment.material}`]);
    rows.push(["primitive", String(segment.primitive)]);
  }
  rows.push(["contribution", vec(segment.contribution)]);
  rows.push(["weight", vec(segment.weight)]);
  const leaves = segment.visitedLeaves.length;
  rows.push(["BVH visited", `${segment.visitedNodes.length} nodes, ${leaves} ${leaves === 1 ? "leaf" : "leaves"}`]);
  rows.push(["triangles tested", String(segment.trianglesTested)]);
  return rows;
}

function fillTable(table, rows) {
  table.replaceChildren(...rows.map(([k, v]) => {
    const tr = document.createElement("tr");
    const th = document.createElement("th");
    th.scope = "row";
    th.textContent = k;
    const td = document.createElement("td");
    td.textContent = v;
    tr.append(th, td);
    return tr;
  }));
}

export class RayHover extends EventTarget {
  constructor(viewer, rays, tooltip) {
    super();
    this.viewer = viewer;
    this.rays = rays;
    this.tooltip = tooltip;
    this.table = tooltip.querySelector("table");
    this.raycaster = new THREE.Raycaster();
    this.hovered = -1;
    this.pinned = -1;
    this._pending = null;
    const canvas = viewer.renderer.domElement;
    canvas.addEventListener("pointermove", (e) => this._schedule(e));
    canvas.addEventListener("pointerleave", () => this._hover(-1));
    let down = null;
    canvas.addEventListener("pointerdown", (e) => { down = [e.clientX, e.clientY]; });
    canvas.addEventListener("pointerup", (e) => {
      if (down && Math.hypot(e.clientX - down[0], e.clientY - down[1]) < 4) this._pin(this._pick(e));
      down = null;
    });
  }

  _schedule(event) {
    if (event.buttons) return; // orbiting
    const first = this._pending === null;
    this._pending = event;
    if (first) {
      requestAnimationFrame(() => {
        const e = this._pending;
        this._pending = null;
        this._hover(this._pick(e), e);
      });
    }
  }

  _pick(event) {
    if (!this.rays.path) return -1;
    const camera = this.viewer.camera;
    this.raycaster.setFromCamera(this.viewer.ndc(event), camera);
    // About 6 CSS pixels at the orbit target's distance (at any, in an orthographic view).
    const pixel = this.viewer.viewHeight / this.viewer.renderer.domElement.clientHeight;
    this.raycaster.params.Line.threshold = pixel * 6;
    return this.rays.pick(this.raycaster);
  }

  _hover(index, event) {
    this.hovered = index;
    const shown = index >= 0 ? index : this.pinned;
    this.rays.setHighlight(shown);
    if (shown < 0) {
      this.tooltip.hidden = true;
      return;
    }
    fillTable(this.table, describeSegment(this.rays.path.segments[shown], shown));
    this.tooltip.hidden = false;
    if (event && index >= 0) {
      const box = this.viewer.container.getBoundingClientRect();
      const x = event.clientX - box.left + 14;
      const y = event.clientY - box.top + 14;
      this.tooltip.style.left = `${Math.min(x, box.width - this.tooltip.offsetWidth - 4)}px`;
      this.tooltip.style.top = `${Math.min(y, box.height - this.tooltip.offsetHeight - 4)}px`;
    }
  }

  _pin(index) {
    this.pinned = index;
    this._hover(index);
    this.dispatchEvent(new CustomEvent("pin", { detail: index }));
  }

  /** Forgets hover and pin (a new path). */
  reset() {
    this.pinned = -1;
    this.hovered = -1;
    this.tooltip.hidden = true;
    this.rays.setHighlight(-1);
  }
}
