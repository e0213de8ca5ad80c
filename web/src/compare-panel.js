// A/B: the open job (A) against another done job of the same size (B), or a
// denoised job's image before denoising (A itself too: what denoising did). It
// picks B among the jobs, loads B's linear colour and, for the HDR-FLIP map,
// the server's map; it shows the server's metrics (RMSE, relative MSE, mean
// HDR-FLIP, as `make charts` measures them) for the whole image and for the
// rectangle dragged. The key X flips between A and B. Fires "change" when
// what the image view shows must change.
import { compareJobs, flipMap, jobLayer, listJobs } from "./api.js";
import { ERROR_KINDS, errorLayer } from "./error-maps.js";
import { isDenoised as denoised } from "./job-layers.js";
import { enumName } from "./proto.js";

const $ = (id) => document.getElementById(id);
const fmt = (v) => Number(v.toPrecision(4)).toString();
/** B's job and colour layer from its choice's value ("<id>" or "<id>:noisy"). */
const parseB = (value) => {
  const [id, layer = "color"] = value.split(":");
  return { id, layer };
};

export const COMPARE_MODES = {
  wipe: "A | B wipe", flip: "Flip A/B (key X)",
  ...Object.fromEntries(Object.entries(ERROR_KINDS).map(([k, v]) => [k, v.label])),
  "flip-map": "HDR-FLIP",
};

export class ComparePanel extends EventTarget {
  constructor() {
    super();
    this.jobSelect = $("compare-job");
    this.modeSelect = $("compare-mode");
    this.metrics = $("compare-metrics");
    this.job = null;
    this.other = null; // B: its job's id, with ":noisy" for that job's image before denoising
    this.b = null; // B's colour layer
    this.flip = null; // the HDR-FLIP map of A against B, once asked for
    this.showB = false; // what Flip shows
    this.whole = null; // the server's metrics over the whole image
    this.errors = null; // the last error map made: {kind, layer}
    this.modeSelect.replaceChildren(...Object.entries(COMPARE_MODES).map(([v, label]) => new Option(label, v)));
    this.jobSelect.addEventListener("change", () => this._pick(this.jobSelect.value));
    this.modeSelect.addEventListener("change", () => this._modeChanged());
    document.addEventListener("keydown", (e) => {
      const typing = e.target.closest?.("input, select, textarea");
      if (e.key !== "x" || typing || e.ctrlKey || e.metaKey || e.altKey || !this.active || this.mode !== "flip") return;
      this.showB = !this.showB;
      this.dispatchEvent(new Event("change"));
    });
  }

  get active() {
    return Boolean(this.b);
  }

  get mode() {
    return this.modeSelect.value;
  }

  /**
   * Offers the done jobs of A's size (A itself too: a job against itself
   * measures zero). Listing the same job again (the image view does once A's
   * layers have loaded) keeps the B chosen meanwhile, or being loaded.
   */
  async setJob(job) {
    const same = this.job?.id === job.id;
    this.job = job;
    if (!same) this._clear();
    const ticket = (this._ticket = (this._ticket ?? 0) + 1); // only the latest listing is shown
    const { width, height } = job.request.settings;
    const list = (await listJobs(0, 200)).jobs.filter((j) => enumName("JobState", j.state) === "DONE"
      && j.request.settings.width === width && j.request.settings.height === height);
    if (ticket !== this._ticket) return;
    const label = (j) => `${j.id.slice(0, 8)} · ${j.request.settings.samplesPerPixel} spp`
      + `${denoised(j) ? " · denoised" : ""}${j.id === job.id ? " (this job)" : ""}`;
    const chosen = this.jobSelect.value;
    this.jobSelect.replaceChildren(new Option("–", ""), ...list.flatMap((j) => [
      new Option(label(j), j.id),
      ...(denoised(j) ? [new Option(`${label(j)} before denoising`, `${j.id}:noisy`)] : []),
    ]));
    this.jobSelect.value = chosen;
    if (chosen && this.jobSelect.value !== chosen) { // B is gone (deleted)
      this._clear();
      this.dispatchEvent(new Event("change"));
    }
  }

  _clear() {
    this.other = null;
    this.b = null;
    this.flip = null;
    this.showB = false;
    this.whole = null;
    this.errors = null;
    this.modeSelect.disabled = true;
    this.metrics.replaceChildren();
    this.jobSelect.value = "";
  }

  async _pick(value) {
    const job = this.job;
    this._clear();
    this.jobSelect.value = value;
    if (!value || !job) return this.dispatchEvent(new Event("change"));
    const { id, layer } = parseB(value);
    this._say(`Loading job ${id.slice(0, 8)}…`);
    try {
      const [b, whole] = await Promise.all([jobLayer(id, layer), compareJobs(job.id, id, null, layer)]);
      if (this.job?.id !== job.id || this.jobSelect.value !== value) return;
      this.other = value;
      this.b = { ...b, name: "B" };
      this.whole = whole;
      this.modeSelect.disabled = false;
      this._showMetrics(whole, null);
      await this._modeChanged();
    } catch (e) {
      this._say(`Job ${id.slice(0, 8)} could not be compared: ${e.message}`);
    }
  }

  async _modeChanged() {
    if (this.mode === "flip-map" && this.active && !this.flip) {
      const other = this.other;
      try {
        const { id, layer } = parseB(other);
        const map = await flipMap(this.job.id, id, layer);
        if (this.other === other) this.flip = map;
      } catch (e) {
        this._say(`The HDR-FLIP map could not be made: ${e.message}`);
        return;
      }
    }
    this.dispatchEvent(new Event("change"));
  }

  /** The server's metrics over a rectangle ({x0, y0, x1, y1}) as well, or the whole image's only. */
  async measure(rect) {
    if (!this.active) return;
    const other = this.other;
    const { id, layer } = parseB(other);
    const part = rect ? await compareJobs(this.job.id, id,
      { x: rect.x0, y: rect.y0, w: rect.x1 - rect.x0, h: rect.y1 - rect.y0 }, layer) : null;
    if (this.other === other) this._showMetrics(this.whole, part);
  }

  /** The `kind` error map (error-maps.js) of colour layer `a` against B, made once per B and kind. */
  errorMap(kind, a) {
    if (this.errors?.kind !== kind) this.errors = { kind, layer: errorLayer(kind, a, this.b) };
    return this.errors.layer;
  }

  _showMetrics(whole, part) {
    const line = (name, m) => {
      const span = document.createElement("span");
      span.className = "metrics";
      Object.assign(span.dataset, { rmse: String(m.rmse), relativeMse: String(m.relativeMse), meanFlip: String(m.meanFlip) });
      span.dataset.scope = name;
      span.textContent = `${name}: RMSE ${fmt(m.rmse)} · rel. MSE ${fmt(m.relativeMse)} · mean FLIP ${fmt(m.meanFlip)}`;
      return span;
    };
    this.metrics.replaceChildren(line("image", whole), ...(part ? [line(`(${part.x}, ${part.y}) ${part.w}×${part.h}`, part)] : []));
    if (part) this.metrics.lastChild.dataset.scope = "region";
  }

  _say(text) {
    this.metrics.textContent = text;
  }
}
