// Statistics of a rectangle of a layer's linear floats, as tev shows them for
// a selection: per channel the mean, min, max and standard deviation of the
// finite values, and how many pixels hold a NaN or an infinity (which the
// sums leave out, so one bad pixel cannot hide the rest).

/**
 * `layer`: {width, height, channels, values}; the rectangle [x0, x1) x [y0, y1)
 * in pixels, clipped to the image. Returns {pixels, nan, inf, channels: [{name,
 * mean, min, max, std}]} (mean and the rest null for a channel with no finite value).
 */
export function regionStats(layer, x0, y0, x1, y1) {
  const n = layer.channels.length;
  const left = Math.max(0, Math.min(x0, x1));
  const right = Math.min(layer.width, Math.max(x0, x1));
  const top = Math.max(0, Math.min(y0, y1));
  const bottom = Math.min(layer.height, Math.max(y0, y1));
  const sum = new Float64Array(n);
  const squares = new Float64Array(n);
  const count = new Float64Array(n);
  const min = new Array(n).fill(Infinity);
  const max = new Array(n).fill(-Infinity);
  let nan = 0;
  let inf = 0;
  for (let y = top; y < bottom; ++y) {
    for (let x = left; x < right; ++x) {
      const o = (y * layer.width + x) * n;
      let hasNan = false;
      let hasInf = false;
      for (let c = 0; c < n; ++c) {
        const v = layer.values[o + c];
        if (Number.isNaN(v)) hasNan = true;
        else if (!Number.isFinite(v)) hasInf = true;
        else {
          sum[c] += v;
          squares[c] += v * v;
          count[c] += 1;
          if (v < min[c]) min[c] = v;
          if (v > max[c]) max[c] = v;
        }
      }
      nan += hasNan;
      inf += hasInf;
    }
  }
  const channels = layer.channels.map((name, c) => {
    if (!count[c]) return { name, mean: null, min: null, max: null, std: null };
    const mean = sum[c] / count[c];
    // The population deviation; clamped, as rounding can take the difference below 0.
    const std = Math.sqrt(Math.max(squares[c] / count[c] - mean * mean, 0));
    return { name, mean, min: min[c], max: max[c], std };
  });
  return { pixels: Math.max(0, right - left) * Math.max(0, bottom - top), nan, inf, channels };
}
