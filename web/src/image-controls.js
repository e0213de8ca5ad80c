// The image view's display controls: which layer and channel, exposure, tone
// map, false colour, and the colour bar over the values shown. They describe
// a view ({layer, channel, exposure, toneMap, falseColor}); the workspace
// turns it into pixels. Fires "change" when the user changes any of them.
import { channelChoices, displayBytes, ramp, TONE_MAPS } from "./display.js";

const $ = (id) => document.getElementById(id);
const fmt = (v) => (v === null || v === undefined ? "–" : Number(v.toPrecision(4)).toString());

export class ImageControls extends EventTarget {
  constructor() {
    super();
    this.layerSelect = $("image-layer");
    this.channelSelect = $("image-channel");
    this.exposure = $("image-exposure");
    this.exposureValue = $("image-exposure-value");
    this.toneMap = $("image-tonemap");
    this.falseColor = $("image-false-color");
    this.bar = $("image-colour-bar");
    this.low = $("image-range-low");
    this.high = $("image-range-high");
    this.toneMap.replaceChildren(...TONE_MAPS.map((name) => new Option(name[0] + name.slice(1).toLowerCase(), name)));
    const changed = () => this.dispatchEvent(new Event("change"));
    this.layerSelect.addEventListener("change", () => {
      this.channelSelect.value = ""; // another layer starts at its first view (RGB, or its one channel)
      this._fillChannels();
      changed();
    });
    for (const control of [this.channelSelect, this.toneMap, this.falseColor]) control.addEventListener("change", changed);
    this.exposure.addEventListener("input", () => {
      this.exposureValue.value = Number(this.exposure.value).toFixed(1);
      changed();
    });
    this.layers = new Map();
  }

  /** Offers the layers of a job (a Map of name to layer); null: none loaded (streaming). */
  setLayers(layers) {
    this.layers = layers ?? new Map();
    const names = [...this.layers.keys()];
    const keep = names.includes(this.layerSelect.value) ? this.layerSelect.value : names[0];
    this.layerSelect.replaceChildren(...names.map((n) => new Option(n, n)));
    if (keep) this.layerSelect.value = keep;
    this._fillChannels();
    for (const control of [this.layerSelect, this.channelSelect, this.exposure, this.toneMap, this.falseColor]) {
      control.disabled = !names.length;
    }
  }

  /** Exposure and tone map as a job's settings give them. */
  setDisplay(exposure, toneMap) {
    this.exposure.value = String(exposure);
    this.exposureValue.value = Number(exposure).toFixed(1);
    this.toneMap.value = toneMap;
  }

  get view() {
    return {
      layer: this.layerSelect.value, channel: this.channelSelect.value, exposure: Number(this.exposure.value),
      toneMap: this.toneMap.value, falseColor: this.falseColor.checked,
    };
  }

  _fillChannels() {
    const layer = this.layers.get(this.layerSelect.value);
    const choices = layer ? channelChoices(layer) : [];
    // The colour's alpha is a layer of its own (rt.AuxOutput ALPHA), offered among the colour's channels.
    if (this.layerSelect.value === "color" && this.layers.has("alpha")) choices.push({ value: "alpha", label: "Alpha" });
    const keep = choices.some((c) => c.value === this.channelSelect.value) ? this.channelSelect.value : choices[0]?.value;
    this.channelSelect.replaceChildren(...choices.map((c) => new Option(c.label, c.value)));
    if (keep !== undefined) this.channelSelect.value = keep;
  }

  /** Draws the bar: the values from `range[0]` to `range[1]` as the view shows them. */
  drawBar(view, range) {
    const width = this.bar.width;
    const ctx = this.bar.getContext("2d");
    const image = ctx.createImageData(width, 1);
    if (view.falseColor) {
      for (let x = 0; x < width; ++x) image.data.set([...ramp(x / (width - 1)), 255], 4 * x);
    } else {
      // Grey values through the same exposure and curve as the image.
      const values = new Float32Array(width * 3);
      for (let x = 0; x < width; ++x) values.fill(range[0] + ((range[1] - range[0]) * x) / (width - 1), 3 * x, 3 * x + 3);
      const grey = { name: "bar", width, height: 1, channels: ["R", "G", "B"], values };
      image.data.set(displayBytes(grey, { ...view, channel: "rgb", range }));
    }
    for (let y = 0; y < this.bar.height; ++y) ctx.putImageData(image, 0, y);
    this.low.value = fmt(range[0]);
    this.high.value = fmt(range[1]);
  }
}
