// The open job against its view's reference (a done job of the same scene,
// camera and size, marked as it, or rendered as it): the job's time and
// error, and the view's speed-against-error plot; "Mark as this view's
// reference" for a done job. Fires "scene" (the updated rt.SceneInfo) after
// a mark, "plot" (the rt.AccuracyPlot) when one is loaded, and "open" (a job
// id) when a point of the plot is clicked.
import { jobAccuracy, markReference } from "./api.js";
import { drawAccuracyPlot } from "./accuracy-plot.js";

const $ = (id) => document.getElementById(id);
const fmt = (v) => Number(v.toPrecision(4)).toString();

export class ReferencePanel extends EventTarget {
  constructor() {
    super();
    this.section = $("reference-section");
    this.mark = $("reference-mark");
    this.status = $("reference-status");
    this.plot = $("accuracy-plot");
    this.job = null;
    this.points = [];
    this.mark.addEventListener("click", () => this._mark());
  }

  /** Follows a job; once done, measures it against its view's reference. */
  async setJob(job, done) {
    const changed = this.job?.id !== job.id || this.done !== done;
    this.job = job;
    this.done = done;
    this.section.hidden = !done;
    if (!done || !changed) return;
    await this.refresh();
  }

  async refresh() {
    const job = this.job;
    const current = () => this.job?.id === job.id; // records of one job come as new objects
    this.plot.toggleAttribute("hidden", true); // an SVGElement has no `hidden` property
    this._say("Measuring this view's jobs against its reference…");
    let plot;
    try {
      plot = await jobAccuracy(job.id);
    } catch (e) {
      if (current()) this._say(`The reference could not be compared: ${e.message}`);
      return;
    }
    if (!current()) return;
    this.dispatchEvent(new CustomEvent("plot", { detail: plot }));
    if (!plot.referenceId) {
      this.mark.disabled = false;
      this._say("This view has no reference yet: mark a converged job of it as the reference, or use Render reference.");
      return;
    }
    this.points = plot.points;
    const mine = plot.points.find((p) => p.jobId === job.id);
    this.mark.disabled = plot.referenceId === job.id;
    if (plot.referenceId === job.id) this._say(`This job is its view's reference; ${plot.points.length} jobs measured against it.`);
    else if (mine) {
      this._say(`Against reference ${plot.referenceId.slice(0, 8)}: mean FLIP ${fmt(mine.error.meanFlip)}, `
        + `RMSE ${fmt(mine.error.rmse)}, in ${fmt(mine.seconds)} s.`);
    }
    this.status.dataset.reference = plot.referenceId;
    this.plot.toggleAttribute("hidden", !plot.points.length);
    if (plot.points.length) drawAccuracyPlot(this.plot, plot.points, job.id, (id) => this.dispatchEvent(new CustomEvent("open", { detail: id })));
  }

  async _mark() {
    const job = this.job;
    this.mark.disabled = true;
    try {
      const scene = await markReference(job.request.sceneId, job.id);
      this.dispatchEvent(new CustomEvent("scene", { detail: scene }));
      await this.refresh();
    } catch (e) {
      this._say(`The job could not be marked: ${e.message}`);
      this.mark.disabled = false;
    }
  }

  _say(text) {
    this.status.textContent = text;
  }
}
