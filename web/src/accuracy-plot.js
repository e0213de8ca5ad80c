// A view's speed-against-error plot: one point per done job, render time
// across and mean HDR-FLIP against the reference up, both on log scales
// (a halving of either is the same step anywhere), the open job ringed.
// Hovering a point names its settings; clicking one opens that job.
import { enumName } from "./proto.js";

const SVG = "http://www.w3.org/2000/svg";
const PAD = { left: 44, right: 10, top: 10, bottom: 28 };

function el(name, attributes, text) {
  const node = document.createElementNS(SVG, name);
  for (const [k, v] of Object.entries(attributes)) node.setAttribute(k, String(v));
  if (text !== undefined) node.textContent = text;
  return node;
}

const fmt = (v) => Number(v.toPrecision(3)).toString();

/** What a point says on hover: its settings, time and errors. */
export function pointLabel(p) {
  const s = p.settings;
  const parts = [`${s.samplesPerPixel} spp`, `${s.lightSamples} light samples`,
    s.adaptiveThreshold ? `adaptive ${fmt(s.adaptiveThreshold)}` : "", enumName("PixelFilter", s.pixelFilter ?? 0).toLowerCase(),
    `${fmt(p.seconds)} s`, `FLIP ${fmt(p.error.meanFlip)}`, `RMSE ${fmt(p.error.rmse)}`];
  return `${p.jobId.slice(0, 8)}: ${parts.filter(Boolean).join(", ")}`;
}

/** Draws `points` (rt.AccuracyPoint) into the <svg>; onPick(jobId) on a click. */
export function drawAccuracyPlot(svg, points, currentId, onPick) {
  const width = svg.clientWidth || 340;
  const height = svg.clientHeight || 190;
  svg.setAttribute("viewBox", `0 0 ${width} ${height}`);
  svg.replaceChildren();
  // Errors of exactly zero (a job identical to the reference) sit on the floor of the axis.
  const shown = points.filter((p) => p.seconds > 0);
  if (!shown.length) return;
  const floor = Math.min(...shown.map((p) => p.error.meanFlip).filter((v) => v > 0), 1e-4) / 2;
  const logs = (f) => shown.map((p) => Math.log10(Math.max(f(p), floor)));
  const xs = logs((p) => p.seconds);
  const ys = logs((p) => p.error.meanFlip);
  const span = (v) => {
    const lo = Math.floor(Math.min(...v) * 4) / 4;
    const hi = Math.ceil(Math.max(...v) * 4) / 4;
    return hi > lo ? [lo, hi] : [lo - 0.25, hi + 0.25];
  };
  const [x0, x1] = span(xs);
  const [y0, y1] = span(ys);
  const sx = (v) => PAD.left + ((v - x0) / (x1 - x0)) * (width - PAD.left - PAD.right);
  const sy = (v) => height - PAD.bottom - ((v - y0) / (y1 - y0)) * (height - PAD.top - PAD.bottom);
  svg.append(el("line", { class: "axis", x1: PAD.left, y1: height - PAD.bottom, x2: width - PAD.right, y2: height - PAD.bottom }));
  svg.append(el("line", { class: "axis", x1: PAD.left, y1: PAD.top, x2: PAD.left, y2: height - PAD.bottom }));
  svg.append(el("text", { x: width - PAD.right, y: height - 4, "text-anchor": "end" }, "render time (s), log"));
  svg.append(el("text", { x: PAD.left + 4, y: PAD.top + 8 }, "mean FLIP, log"));
  for (const [v, anchor] of [[x0, "start"], [x1, "end"]]) {
    svg.append(el("text", { x: sx(v), y: height - PAD.bottom + 12, "text-anchor": anchor }, fmt(10 ** v)));
  }
  for (const v of [y0, y1]) svg.append(el("text", { x: PAD.left - 4, y: sy(v) + 3, "text-anchor": "end" }, fmt(10 ** v)));
  shown.forEach((p, i) => {
    const dot = el("circle", { cx: sx(xs[i]), cy: sy(ys[i]), r: p.jobId === currentId ? 6 : 4, "data-job": p.jobId,
      class: p.jobId === currentId ? "current" : "" });
    dot.append(el("title", {}, pointLabel(p)));
    dot.addEventListener("click", () => onPick(p.jobId));
    svg.append(dot);
  });
}
