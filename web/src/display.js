// What the image view shows of a layer's linear floats, made in the browser so
// that exposure, tone map, channel and false colour change without a render.
// The colour path is the renderer's own (renderer/src/image/display.cpp):
// 2^exposure, the curve, a clamp to [0, 1] (NaN to 0), then sRGB; in doubles
// here, so a byte may differ from image.png's by one where it rounds.
import { enumOf } from "./proto.js";

// Rec. 709 luminance, as util/math.h weighs it.
export const luminance = (r, g, b) => 0.2126 * r + 0.7152 * g + 0.0722 * b;

// Narkowicz's fit of the ACES filmic curve, clipped where it passes 1.
function aces(x) {
  const v = Math.min(x > 0 ? x : 0, 100);
  return Math.min((v * (2.51 * v + 0.03)) / (v * (2.43 * v + 0.59) + 0.14), 1);
}

export const toSrgb = (linear) => {
  const v = linear > 0 ? Math.min(linear, 1) : 0; // NaN fails the test: black, as the renderer clamps it
  return v <= 0.0031308 ? 12.92 * v : 1.055 * v ** (1 / 2.4) - 0.055;
};

// The tone maps the renderer knows, by their rt.ToneMap names.
export const TONE_MAPS = enumOf("ToneMap").values.map((v) => v.name);

// A perceptually uniform ramp, matplotlib's viridis by eleven of its
// colours, interpolated between them: for false colour and its bar.
const VIRIDIS = [[68, 1, 84], [72, 35, 116], [64, 67, 135], [52, 94, 141], [41, 120, 142], [32, 144, 140],
  [34, 167, 132], [68, 190, 112], [121, 209, 81], [189, 222, 38], [253, 231, 37]];

/** RGB bytes of the false-colour ramp at t in [0, 1]. */
export function ramp(t) {
  const x = Math.min(Math.max(Number.isFinite(t) ? t : 0, 0), 1) * (VIRIDIS.length - 1);
  const i = Math.min(Math.floor(x), VIRIDIS.length - 2);
  const f = x - i;
  return VIRIDIS[i].map((c, k) => Math.round(c + (VIRIDIS[i + 1][k] - c) * f));
}

/**
 * The view choices a layer offers: "rgb" for three channels, each channel by
 * its name, and "luminance" for colour layers.
 */
export function channelChoices(layer) {
  const choices = [];
  if (layer.channels.length === 3) choices.push({ value: "rgb", label: "RGB" });
  layer.channels.forEach((name, i) => choices.push({ value: String(i), label: name }));
  if (layer.channels.length === 3) choices.push({ value: "luminance", label: "Luminance" });
  return choices;
}

/** The scalar a single-valued view reads at value offset `o` (null for "rgb"). */
function scalarReader(layer, channel) {
  const { values, channels } = layer;
  if (channel === "rgb") return null;
  if (channel === "luminance") return (o) => luminance(values[o], values[o + 1], values[o + 2]);
  const c = Number(channel);
  if (!(c >= 0 && c < channels.length)) throw new Error(`no channel ${channel} in layer ${layer.name}`);
  return (o) => values[o + c];
}

/** The finite range of what a view shows (for false colour and its bar): [min, max]. */
export function viewRange(layer, channel) {
  const read = scalarReader(layer, channel === "rgb" ? "luminance" : channel);
  const n = layer.channels.length;
  let lo = Infinity;
  let hi = -Infinity;
  for (let o = 0; o < layer.values.length; o += n) {
    const v = read(o);
    if (v < lo) lo = v;
    if (v > hi) hi = v;
  }
  return lo <= hi ? [lo, hi] : [0, 1];
}

/**
 * RGBA bytes of a layer as the view shows it. `view`: {channel, exposure,
 * toneMap, falseColor, range: [lo, hi]}. Colour (or one channel as grey)
 * goes through exposure, the tone map and sRGB; false colour maps the
 * scalar's [lo, hi] linearly onto the ramp, ignoring exposure. NaN and Inf
 * pixels show in magenta in false colour, so that they can be found.
 */
export function displayBytes(layer, view, out = new Uint8ClampedArray(layer.width * layer.height * 4)) {
  const { values } = layer;
  const n = layer.channels.length;
  const scale = 2 ** view.exposure;
  const curve = view.toneMap;
  const read = scalarReader(layer, view.channel);
  const mapped = [0, 0, 0];
  const map = (r, g, b) => {
    r *= scale, g *= scale, b *= scale;
    if (curve === "REINHARD") {
      const l = luminance(r, g, b);
      if (l > 0) r /= 1 + l, g /= 1 + l, b /= 1 + l;
    } else if (curve === "ACES") {
      r = aces(r), g = aces(g), b = aces(b);
    }
    mapped[0] = Math.round(toSrgb(r) * 255);
    mapped[1] = Math.round(toSrgb(g) * 255);
    mapped[2] = Math.round(toSrgb(b) * 255);
  };
  const [lo, hi] = view.range ?? [0, 1];
  const span = hi > lo ? hi - lo : 1;
  for (let p = 0, o = 0; o < values.length; p += 4, o += n) {
    if (view.falseColor) {
      const v = read ? read(o) : luminance(values[o], values[o + 1], values[o + 2]);
      const [r, g, b] = Number.isFinite(v) ? ramp((v - lo) / span) : [255, 0, 255];
      out[p] = r, out[p + 1] = g, out[p + 2] = b;
    } else if (read) {
      const v = read(o);
      map(v, v, v);
      out[p] = mapped[0], out[p + 1] = mapped[1], out[p + 2] = mapped[2];
    } else {
      map(values[o], values[o + 1], values[o + 2]);
      out[p] = mapped[0], out[p + 1] = mapped[1], out[p + 2] = mapped[2];
    }
    out[p + 3] = 255;
  }
  return out;
}
