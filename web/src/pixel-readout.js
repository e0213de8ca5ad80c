// What the image view says in numbers: the linear values of every layer under
// the cursor (colour and each auxiliary output), and a selected rectangle's
// statistics. Values are the floats of image.exr, shown to 6 significant
// digits; data-* attributes carry them whole, for tests and copying.
import { regionStats } from "./image-stats.js";

const fmt = (v) => (v === null ? "–" : Number.isFinite(v) ? Number(v.toPrecision(6)).toString() : String(v));

function row(cells, header = false) {
  const tr = document.createElement("tr");
  for (const cell of cells) {
    const td = document.createElement(header ? "th" : "td");
    td.textContent = cell;
    tr.append(td);
  }
  return tr;
}

export class PixelReadout {
  constructor(readout, stats) {
    this.readout = readout;
    this.stats = stats;
    this.layers = new Map();
  }

  setLayers(layers) {
    this.layers = layers ?? new Map();
    this.show(null);
    this.showStats(null);
  }

  /**
   * The values at pixel [x, y], or a hint when there is none; `shown`: the
   * layer the view shows when it is none of the job's (B's colour, an error map).
   */
  show(pixel, streaming = false, shown = null) {
    const table = document.createElement("table");
    if (!pixel) {
      this.readout.replaceChildren();
      this.readout.hidden = true;
      return;
    }
    const [x, y] = pixel;
    table.append(row([`(${x}, ${y})`, ""], true));
    const extra = shown && ![...this.layers.values()].includes(shown) ? [shown] : [];
    for (const layer of [...extra, ...this.layers.values()]) {
      const o = (y * layer.width + x) * layer.channels.length;
      layer.channels.forEach((name, c) => {
        const tr = row([extra.includes(layer) && layer.channels.length === 3 ? `${layer.name} ${name}` : name,
          fmt(layer.values[o + c])]);
        tr.dataset.channel = name;
        tr.dataset.value = String(layer.values[o + c]);
        table.append(tr);
      });
    }
    if (!this.layers.size) table.append(row([streaming ? "linear values once the job is done" : "no linear values", ""]));
    this.readout.replaceChildren(table);
    this.readout.hidden = false;
  }

  /** Statistics of `rect` ({x0, y0, x1, y1}) over every layer, or nothing. */
  showStats(rect) {
    if (!rect || !this.layers.size) {
      this.stats.replaceChildren();
      this.stats.hidden = true;
      return;
    }
    const table = document.createElement("table");
    const { x0, y0, x1, y1 } = rect;
    const bad = [];
    let pixels = 0;
    const caption = document.createElement("caption");
    table.append(caption);
    table.append(row(["channel", "mean", "min", "max", "std. dev."], true));
    for (const layer of this.layers.values()) {
      const s = regionStats(layer, x0, y0, x1, y1);
      pixels = s.pixels;
      bad.push(`${layer.name} ${s.nan} NaN, ${s.inf} Inf`);
      table.dataset[`${layer.name}Nan`] = String(s.nan);
      table.dataset[`${layer.name}Inf`] = String(s.inf);
      for (const c of s.channels) {
        const tr = row([c.name, fmt(c.mean), fmt(c.min), fmt(c.max), fmt(c.std)]);
        tr.dataset.channel = c.name;
        Object.assign(tr.dataset, { mean: String(c.mean), min: String(c.min), max: String(c.max), std: String(c.std) });
        table.append(tr);
      }
    }
    // Pixels holding a NaN or an infinity, per layer; the sums above leave them out.
    caption.textContent = `(${x0}, ${y0}) to (${x1 - 1}, ${y1 - 1}), ${pixels} pixels; ${bad.join("; ")}`;
    table.dataset.pixels = String(pixels);
    this.stats.replaceChildren(table);
    this.stats.hidden = false;
  }
}
