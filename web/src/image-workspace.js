// The render in the main area: the streaming tiles while a job runs, then its
// linear layers (fetched once it is done) through the display controls; the
// numbers under the cursor and in a dragged rectangle; a click traces the
// pixel in the debugger, as a click on the side panel's image does.
import { jobLayer } from "./api.js";
import { displayBytes, viewRange } from "./display.js";
import { ImageControls } from "./image-controls.js";
import { ImageView } from "./image-view.js";
import { PixelReadout } from "./pixel-readout.js";
import { enumName } from "./proto.js";

const $ = (id) => document.getElementById(id);

/** The layer names a job has: "color" and its auxiliary outputs in lower case. */
export const layerNames = (job) =>
  ["color", ...job.request.outputs.map((o) => enumName("AuxOutput", o).toLowerCase())];

export class ImageWorkspace extends EventTarget {
  constructor(tiles, debug) {
    super();
    this.tiles = tiles;
    this.view = new ImageView($("image-view-canvas"));
    this.controls = new ImageControls();
    this.readout = new PixelReadout($("pixel-readout"), $("region-stats"));
    this.status = $("image-view-status");
    this.display = document.createElement("canvas");
    this.job = null;
    this.layers = null;
    this.hovered = null;
    this._loading = null;
    this.view.addEventListener("hover", (e) => {
      this.hovered = e.detail;
      this.readout.show(e.detail, !this.layers);
    });
    this.view.addEventListener("select", (e) => this.readout.showStats(e.detail));
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
    }
    if (done && !this.layers && !this._loading) this._loading = this._load(job);
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
      this.dispatchEvent(new Event("layers"));
    } catch (e) {
      if (this.job?.id === job.id) this._say(`The linear layers could not be loaded: ${e.message}`);
      this._loading = null;
    }
  }

  _redisplay() {
    const view = this.controls.view;
    const layer = this.layers?.get(view.layer);
    if (!layer) return;
    view.range = viewRange(layer, view.channel);
    this.display.width = layer.width;
    this.display.height = layer.height;
    const image = new ImageData(layer.width, layer.height);
    displayBytes(layer, view, image.data);
    this.display.getContext("2d").putImageData(image, 0, 0);
    this.controls.drawBar(view, view.range);
    this.view.setSource(this.display, layer.width, layer.height);
    this.view.invalidate();
    if (this.hovered) this.readout.show(this.hovered);
  }

  _say(text) {
    this.status.textContent = text;
    this.status.hidden = !text;
  }
}
