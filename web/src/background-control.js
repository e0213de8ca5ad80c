// The settings panel's background (rt.RenderSettings background and
// background_gradient): the scene's own (nothing sent), a solid colour or a
// gradient, from colour pickers that start at the scene's colours. Pickers
// speak 8-bit sRGB, the settings linear RGB like the renderer; values above 1
// (a bright sky for bloom) are shown clipped until a picker is touched.
import { backgroundOf } from "./background.js";

const MODES = [["scene", "Scene's"], ["solid", "Solid"], ["gradient", "Gradient"]];
const STOPS = [["top", "Top"], ["horizon", "Horizon"], ["bottom", "Bottom"]];

/** "#rrggbb" of a linear RGB colour, sRGB-encoded and clipped to [0, 1]. */
export function linearToHex(rgb) {
  return `#${rgb.map((c) => {
    const v = Math.min(Math.max(c, 0), 1);
    const s = v <= 0.0031308 ? 12.92 * v : 1.055 * v ** (1 / 2.4) - 0.055;
    return Math.round(s * 255).toString(16).padStart(2, "0");
  }).join("")}`;
}

/** The linear RGB colour of "#rrggbb". */
export function hexToLinear(hex) {
  return [1, 3, 5].map((i) => {
    const s = parseInt(hex.slice(i, i + 2), 16) / 255;
    return s <= 0.04045 ? s / 12.92 : ((s + 0.055) / 1.055) ** 2.4;
  });
}

function colorInput(id, label) {
  const row = document.createElement("div");
  row.className = "field";
  const text = document.createElement("label");
  text.htmlFor = id;
  text.textContent = label;
  const input = document.createElement("input");
  input.type = "color";
  input.id = id;
  row.append(text, input);
  return { row, input };
}

export class BackgroundControl extends EventTarget {
  /** Appends the controls to `container`. */
  constructor(container) {
    super();
    this.scene = null; // the scene's background, {bottom, horizon, top}
    this.touched = new Set(); // pickers the user set: they stop following the scene
    const row = document.createElement("div");
    row.className = "field";
    const label = document.createElement("label");
    label.htmlFor = "setting-background";
    label.textContent = "Background";
    this.mode = document.createElement("select");
    this.mode.id = "setting-background";
    this.mode.title = "What rays that miss see; linear RGB in the settings";
    for (const [value, text] of MODES) this.mode.append(new Option(text, value));
    row.append(label, this.mode);
    container.append(row);

    this.pickers = new Map();
    this.solid = colorInput("background-color", "Colour");
    this.pickers.set("color", this.solid.input);
    container.append(this.solid.row);
    this.stops = STOPS.map(([key, text]) => {
      const picker = colorInput(`background-${key}`, text);
      this.pickers.set(key, picker.input);
      container.append(picker.row);
      return picker.row;
    });
    this.mode.addEventListener("change", () => this._changed());
    for (const [key, input] of this.pickers) {
      input.addEventListener("input", () => {
        this.touched.add(key);
        this._changed();
      });
    }
    this._fill();
    this._layout();
  }

  /** The scene's background (the view's, linear), which the pickers start at. */
  setSceneBackground(background) {
    this.scene = background;
    this._fill();
  }

  /** The chosen background ({bottom, horizon, top}, linear), or null for the scene's. */
  current() {
    if (this.mode.value === "solid") return backgroundOf({ background: hexToLinear(this.pickers.get("color").value) });
    if (this.mode.value !== "gradient") return null;
    const [bottom, horizon, top] = ["bottom", "horizon", "top"].map((k) => hexToLinear(this.pickers.get(k).value));
    return { bottom, horizon, top };
  }

  /** The rt.RenderSettings fields it sets (none for the scene's). */
  settings() {
    const chosen = this.current();
    if (!chosen) return {};
    if (this.mode.value === "solid") return { background: chosen.top };
    return { backgroundGradient: chosen };
  }

  /** Shows a job's settings (rt.RenderSettings as parsed). */
  show(settings) {
    const given = backgroundOf(settings);
    const solid = settings.background?.length === 3;
    this.mode.value = given ? (solid ? "solid" : "gradient") : "scene";
    if (given) {
      this.pickers.get("color").value = linearToHex(given.top);
      for (const key of ["bottom", "horizon", "top"]) this.pickers.get(key).value = linearToHex(given[key]);
      for (const key of this.pickers.keys()) this.touched.add(key);
    }
    this._changed();
  }

  _fill() {
    const scene = this.scene ?? { bottom: [0, 0, 0], horizon: [0, 0, 0], top: [0, 0, 0] };
    const values = { color: scene.horizon, ...scene };
    for (const [key, input] of this.pickers) if (!this.touched.has(key)) input.value = linearToHex(values[key]);
  }

  _layout() {
    this.solid.row.hidden = this.mode.value !== "solid";
    for (const row of this.stops) row.hidden = this.mode.value !== "gradient";
  }

  _changed() {
    this._layout();
    this.dispatchEvent(new CustomEvent("change", { detail: this.current() }));
  }
}
