// The visual debugger's controls: pick a pixel of the job's image (pointer, or
// arrow keys and Enter), trace it with the job's own camera and settings, and
// show its ray tree, its numbers and the BVH boxes (one level, or only those
// the ray visited: the nodes whose child boxes it tested and the leaves whose
// triangles it tested).
import { debugRay } from "./api.js";
import { BvhBoxes } from "./bvh-boxes.js";
import { boxCountText, renderBvhLegend } from "./bvh-legend.js";
import { BvhTreePicker } from "./bvh-tree-picker.js";
import { DebugRays, pathStats, renderLegend } from "./debug-rays.js";
import { RayHover } from "./ray-hover.js";

const $ = (id) => document.getElementById(id);
const fmt = (v) => Number(v.toPrecision(4)).toString();

export class DebugPanel extends EventTarget {
  constructor(viewer, tiles, overlay) {
    super();
    this.viewer = viewer;
    this.tiles = tiles;
    this.overlay = overlay;
    this.job = null;
    this.lights = [];
    this.pixel = null;
    this.rays = new DebugRays(viewer);
    this.bvh = new BvhBoxes(viewer);
    this.trees = new BvhTreePicker(this.bvh, (promise) => this._guard(promise));
    viewer.lod.addOverlay(this.rays.lines, 2);
    viewer.lod.addOverlay(this.bvh.lines, 24);
    this.hover = new RayHover(viewer, this.rays, $("ray-tooltip"));
    this.status = $("debug-status");
    this.stats = $("pixel-stats");
    this.legend = $("ray-legend");
    renderLegend(this.legend);
    this._wireImage();
    this._wireToolbar();
    this.hover.addEventListener("pin", () => this._updateVisited());
  }

  _wireImage() {
    const target = this.overlay.canvas;
    target.addEventListener("click", (e) => {
      const pixel = this.tiles.pixelAt(e);
      if (pixel) this.trace(pixel);
    });
    target.addEventListener("keydown", (e) => {
      if (!this.job) return;
      const { width, height } = this.tiles.canvas;
      const [x, y] = this.pixel ?? [Math.floor(width / 2), Math.floor(height / 2)];
      const step = e.shiftKey ? 10 : 1;
      const moves = { ArrowLeft: [-step, 0], ArrowRight: [step, 0], ArrowUp: [0, -step], ArrowDown: [0, step] };
      if (moves[e.key]) {
        e.preventDefault();
        this.pixel = [Math.min(width - 1, Math.max(0, x + moves[e.key][0])), Math.min(height - 1, Math.max(0, y + moves[e.key][1]))];
        this.overlay.setPixel(this.pixel);
        this.status.textContent = `Pixel (${this.pixel[0]}, ${this.pixel[1]}): press Enter to trace it.`;
      } else if (e.key === "Enter" || e.key === " ") {
        e.preventDefault();
        this.trace([x, y]);
      }
    });
  }

  _wireToolbar() {
    const show = $("bvh-show");
    const level = $("bvh-level");
    const visited = $("bvh-visited");
    const count = $("bvh-count");
    const legend = $("bvh-legend");
    show.addEventListener("change", () => this._guard(this.bvh.setVisible(show.checked)));
    let timer = null;
    level.addEventListener("input", () => {
      clearTimeout(timer);
      timer = setTimeout(() => this._guard(this.bvh.setLevel(Number(level.value))), 60);
      if (!show.checked) {
        show.checked = true;
        this.bvh.setVisible(true);
      }
    });
    visited.addEventListener("change", () => this.bvh.setOnlyVisited(visited.checked));
    this.bvh.addEventListener("change", (e) => {
      const { level: l, totalLevels, nodeWidth, shown, shownLeaves } = e.detail;
      if (totalLevels) level.max = String(totalLevels - 1);
      level.setAttribute("aria-valuetext", `level ${l} of ${Math.max(totalLevels - 1, 0)}`);
      count.textContent = boxCountText(e.detail);
      count.dataset.boxes = String(shown);
      count.dataset.leaves = String(shownLeaves);
      renderBvhLegend(legend, nodeWidth);
      this.trees.update(e.detail);
    });
    $("rays-show").addEventListener("change", (e) => this.rays.setVisible(e.target.checked));
    $("rays-clear").addEventListener("click", () => this.clear());
  }

  _guard(promise) {
    promise?.catch?.((e) => {
      this.status.textContent = `BVH boxes could not be loaded: ${e.message}`;
      this.status.dataset.kind = "error";
    });
  }

  /** A new scene: its lights colour shadow rays; the BVH follows it. */
  setScene(info) {
    this.sceneId = info?.id ?? null;
    this.lights = info?.lights ?? [];
    this.clear();
    const level = $("bvh-level");
    level.value = "0";
    level.max = "0";
    this._guard(this.bvh.setScene(this.sceneId));
  }

  /** The job whose image is shown: its camera and settings trace the pixels. */
  setJob(job) {
    this.job = job;
  }

  clear() {
    this.pixel = null;
    this.overlay.setPixel(null);
    this.hover.reset();
    this.rays.show(null);
    this.bvh.setVisited(null);
    this.trees.showEntered(null);
    this.stats.replaceChildren();
    renderLegend(this.legend);
    this.status.dataset.kind = "";
    this.status.textContent = "Click a pixel of the image to trace its rays.";
  }

  async trace(pixel) {
    const job = this.job;
    if (!job) return;
    this.pixel = pixel;
    this.overlay.setPixel(pixel);
    this.status.dataset.kind = "busy";
    this.status.textContent = `Tracing pixel (${pixel[0]}, ${pixel[1]})…`;
    let path;
    try {
      path = await debugRay(job.request.sceneId, job.request.camera, job.request.settings, pixel);
    } catch (e) {
      this.status.dataset.kind = "error";
      this.status.textContent = `Pixel (${pixel[0]}, ${pixel[1]}) could not be traced: ${e.message}`;
      return;
    }
    if (this.pixel !== pixel) return; // another pixel was picked meanwhile
    this.hover.reset();
    this.rays.show(path, this.lights);
    this._updateVisited();
    this._showStats(path);
    renderLegend(this.legend, this.rays.categories);
    this.status.dataset.kind = "ok";
    this.status.textContent = `Pixel (${path.pixelX}, ${path.pixelY}): ${path.segments.length} rays. Hover a ray in the 3D view for its numbers; click it to pin.`;
    this.dispatchEvent(new CustomEvent("traced", { detail: path }));
  }

  _updateVisited() {
    const path = this.rays.path;
    if (!path) {
      this.bvh.setVisited(null);
      this.trees.showEntered(null);
      return;
    }
    const pinned = this.hover.pinned;
    const segments = pinned >= 0 ? [path.segments[pinned]] : path.segments;
    this.bvh.setVisited(segments);
    this.trees.showEntered(segments);
  }

  _showStats(path) {
    const s = pathStats(path);
    const color = Array.from(path.color, fmt).join(", ");
    const rows = [
      ["Pixel", `(${path.pixelX}, ${path.pixelY})`],
      ["Colour (linear)", `(${color})`],
      ["Rays traced", `${s.rays}: ${s.primary} primary, ${s.reflection} reflection, ${s.refraction} refraction, ${s.shadow} shadow`],
      ["Shadow samples taken", String(s.shadow)],
      ["BVH nodes visited", s.nodes.toLocaleString()],
      ["BVH leaves visited", s.leaves.toLocaleString()],
      ["Triangles tested", s.triangles.toLocaleString()],
    ];
    this.stats.replaceChildren(...rows.flatMap(([k, v]) => {
      const div = document.createElement("div");
      const dt = document.createElement("dt");
      dt.textContent = k;
      const dd = document.createElement("dd");
      dd.textContent = v;
      div.append(dt, dd);
      return [div];
    }));
  }
}
