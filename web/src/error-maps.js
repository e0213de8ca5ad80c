// What two images of the same size differ by, pixel by pixel, as layers the
// image view shows like any other (web/src/display.js): image A against
// reference B, on their linear colour. Relative error divides by the
// reference as tev does, |A − B| / (|B| + 0.01): the 0.01 the server's
// relative MSE adds too (server/app/services/comparisons.py), so that black
// does not divide by zero.

export const ERROR_KINDS = {
  difference: { label: "Difference |A − B|", channels: ["|A−B|.R", "|A−B|.G", "|A−B|.B"] },
  absolute: { label: "Absolute error", channels: ["absolute error"] },
  relative: { label: "Relative error", channels: ["relative error"] },
  squared: { label: "Squared error", channels: ["squared error"] },
};

const RELATIVE_EPSILON = 0.01;

/** The `kind` map of colour layers `a` and `b` (3 channels each), as a layer. */
export function errorLayer(kind, a, b) {
  if (a.width !== b.width || a.height !== b.height) throw new Error("the images differ in size");
  const spec = ERROR_KINDS[kind];
  if (!spec) throw new Error(`no error map ${kind}`);
  const pixels = a.width * a.height;
  const values = new Float32Array(pixels * spec.channels.length);
  const x = a.values;
  const y = b.values;
  for (let p = 0, o = 0; p < pixels; ++p, o += 3) {
    if (kind === "difference") {
      for (let c = 0; c < 3; ++c) values[o + c] = Math.abs(x[o + c] - y[o + c]);
      continue;
    }
    let sum = 0;
    for (let c = 0; c < 3; ++c) {
      const e = x[o + c] - y[o + c];
      sum += kind === "absolute" ? Math.abs(e) : kind === "squared" ? e * e : Math.abs(e) / (Math.abs(y[o + c]) + RELATIVE_EPSILON);
    }
    values[p] = sum / 3;
  }
  return { name: spec.label, width: a.width, height: a.height, channels: spec.channels, values };
}
