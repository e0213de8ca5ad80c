// The render in the main area: the streaming tiles while a job runs, then its
// linear layers (fetched once it is done) through the display controls; the
// numbers under the cursor and in a dragged rectangle; a click traces the
// pixel in the debugger, as a click on the side panel's image does.
import { jobLayer } from "./api.js";
import { ComparePanel } from "./compare-panel.js";
import { displayBytes, viewRange } from "./display.js";
import { DragHandle } from "./drag-handle.js";
import { ERROR_KINDS } from "./error-maps.js";
import { ImageControls } from "./image-controls.js";
import { ImageView } from "./image-view.js";
import { layerNames } from "./job-layers.js";
import { PixelReadout } from "./pixel-readout.js";
import { enumName } from "./proto.js";

const $ = (id) => document.getElementById(id);

export class ImageWorkspace {
  constructor(tiles, debug) {
    this.tiles = tiles;
    this.view = new ImageView($("image-view-canvas"));
    this.controls = new ImageControls();
    this.readout = new PixelReadout($("pixel-readout"), $("region-stats"));
    this.status = $("image-view-status");
    this.display = document.createElement("canvas");
    this.displayB = document.createElement("canvas"); // B beside A in the A | B wipe
    this.compare = new ComparePanel();
    this.split = new DragHandle($("compare-handle"), () => this.view.canvas.getBoundingClientRect(),
      (x) => this.view.second && this.view.setSecond(this.displayB, x));
    this.shown = null; // the layer the view shows (A's, B's or an error map)
    this.job = null;
    this.layers = null;
    this.hovered = null;
    this._loading = null;
    this.view.addEventListener("hover", (e) => {
      this.hovered = e.detail;
      this.readout.show(e.detail, !this.layers, this.shown);
    });
    this.view.addEventListener("select", (e) => {
      this.readout.showStats(e.detail);
      this.compare.measure(e.detail).catch((err) => this._say(`The region could not be measured: ${err.message}`));
    });
    this.compare.addEventListener("change", () => this._redisplay());
    this.view.addEventListener("pick", (e) => {
      this.view.setMarker(e.detail);
      debug.trace(e.detail);
    });
    this.view.addEventListener("zoom", (e) => { $("image-zoom").value = `${Math.round(e.detail * 100)}%`; });
    this.controls.addEventListener("change", () => this._redisplay());
    $("image-fit").addEventListener("click", () => this.view.fit());
    $("image-actual").addEventListener("click", () => this.view.actualSize());
    $("image-reset").addEventListener("click", () => {
      if (!this.job) return;
      this._jobDisplay();
      this._redisplay();
    });
    tiles.addEventListener("tiles", () => {
      if (!this.layers) this.view.invalidate();
    });
  }

  /** Follows a job: its tiles now, its layers once `done`. */
  setJob(job, done) {
    const same = this.job?.id === job.id;
    this.job = job;
    if (!same) {
      this.layers = null;
      this._loading = null;
      this.readout.setLayers(null);
      this.controls.setLayers(null);
      this._jobDisplay();
      this.view.setMarker(null);
      const { width, height } = job.request.settings;
      this.view.setSource(this.tiles.canvas, width, height);
      this._say("");
      this._listComparable(job);
    }
    if (done && !this.layers && !this._loading) this._loading = this._load(job);
  }

  _listComparable(job) {
    this.compare.setJob(job).catch((e) => this._say(`The jobs to compare with could not be listed: ${e.message}`));
  }

  _jobDisplay() {
    const { exposure, toneMap } = this.job.request.settings;
    this.controls.setDisplay(exposure ?? 0, enumName("ToneMap", toneMap ?? 0));
  }

  async _load(job) {
    this._say("Loading the linear layers…");
    try {
      const loaded = await Promise.all(layerNames(job).map((name) => jobLayer(job.id, name)));
      if (this.job?.id !== job.id) return;
      this.layers = new Map(loaded.map((layer) => [layer.name, layer]));
      this.controls.setLayers(this.layers);
      this.readout.setLayers(this.layers);
      this._redisplay();
      this._say("");
      this._listComparable(job); // now with the job itself among the done ones
    } catch (e) {
      if (this.job?.id === job.id) this._say(`The linear layers could not be loaded: ${e.message}`);
      this._loading = null;
    }
  }

  _redisplay() {
    let view = this.controls.view;
    if (view.layer === "color" && view.channel === "alpha") view = { ...view, layer: "alpha", channel: "0" };
    let layer = this.layers?.get(view.layer);
    if (!layer) return;
    const { compare } = this;
    const mode = compare.active ? compare.mode : null;
    const a = this.layers.get("color");
    if (mode === "flip" && compare.showB) layer = compare.b;
    else if (mode === "wipe") layer = a;
    else if (ERROR_KINDS[mode]) layer = compare.errorMap(mode, a); // not remade as exposure and the rest change
    else if (mode === "flip-map" && compare.flip) layer = compare.flip;
    // Error maps read as numbers: false colour over their range. B's colour,
    // A's in the wipe and the difference (a colour too) take the colour view's channel.
    const scalar = Boolean(mode) && !["flip", "wipe", "difference"].includes(mode);
    const colourChannel = view.layer === "color" ? view.channel : "rgb";
    const shown = scalar ? { ...view, channel: "0", falseColor: true }
      : layer === this.layers.get(view.layer) ? { ...view } : { ...view, channel: colourChannel };
    shown.range = viewRange(layer, shown.channel);
    this.shown = layer;
    this._paint(this.display, layer, shown);
    const wiping = mode === "wipe";
    if (wiping) this._paint(this.displayB, compare.b, shown);
    this.controls.drawBar(shown, shown.range);
    this.view.setSource(this.display, layer.width, layer.height);
    this.view.setSecond(wiping ? this.displayB : null, 0);
    this.split.show(wiping);
    if (this.hovered) this.readout.show(this.hovered, false, layer);
  }

  _paint(canvas, layer, view) {
    canvas.width = layer.width;
    canvas.height = layer.height;
    const image = new ImageData(layer.width, layer.height);
    displayBytes(layer, view, image.data);
    canvas.getContext("2d").putImageData(image, 0, 0);
  }

  _say(text) {
    this.status.textContent = text;
    this.status.hidden = !text;
  }
}
