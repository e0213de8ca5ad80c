// The current job's progress (bar, tiles done/total, elapsed, time left),
// cancel and downloads, and the job history with thumbnails.
import { deleteJob, jobImageUrl, listJobs, pinJob } from "./api.js";
import { layerNames } from "./job-layers.js";
import { enumName } from "./proto.js";

const ACTIVE = new Set(["QUEUED", "RUNNING"]);

export function formatSeconds(s) {
  if (!Number.isFinite(s) || s < 0) return "–";
  if (s < 60) return `${s.toFixed(s < 10 ? 1 : 0)} s`;
  const m = Math.floor(s / 60);
  if (m < 60) return `${m} min ${Math.round(s - m * 60)} s`;
  return `${Math.floor(m / 60)} h ${m % 60} min`;
}

export const stateOf = (job) => enumName("JobState", job.state);

export class JobPanel extends EventTarget {
  constructor(root) {
    super();
    this.el = {
      title: root.querySelector("#job-title"),
      state: root.querySelector("#job-state"),
      bar: root.querySelector("#job-progress"),
      tiles: root.querySelector("#job-tiles"),
      elapsed: root.querySelector("#job-elapsed"),
      left: root.querySelector("#job-left"),
      cancel: root.querySelector("#job-cancel"),
      pin: root.querySelector("#job-pin"),
      downloads: root.querySelector("#job-downloads"),
      error: root.querySelector("#job-error"),
      history: root.querySelector("#history-list"),
      more: root.querySelector("#history-more"),
    };
    this.job = null;
    this.tilesReceived = 0;
    this.el.cancel.addEventListener("click", () => this._cancel());
    this.el.pin.addEventListener("click", () => this._pin());
    this.el.more.addEventListener("click", () => this.refreshHistory(this.historyCount + 20));
    this.historyCount = 20;
    this.errors = new Map(); // job id -> its mean FLIP against its view's reference, once a plot told it
    this.references = new Set();
    this._ticker = setInterval(() => this._showTimes(), 250);
  }

  /** Shows a job record (fetched when the job is opened, from its stream, or a cancel's answer). */
  show(job) {
    this.job = job;
    const state = stateOf(job);
    const size = job.request?.settings ? `${job.request.settings.width}×${job.request.settings.height}` : "";
    this.el.title.textContent = `Job ${job.id}${size ? ` · ${size}` : ""}`;
    this.el.state.textContent = state.toLowerCase();
    this.el.state.dataset.state = state;
    this.el.bar.value = state === "DONE" ? 1 : job.progress;
    this.el.bar.setAttribute("aria-valuetext", `${Math.round(this.el.bar.value * 100)} percent`);
    this._showTiles();
    this.el.cancel.disabled = !ACTIVE.has(state);
    this.el.pin.disabled = false;
    this.el.pin.setAttribute("aria-pressed", String(Boolean(job.pinned)));
    this.el.pin.textContent = job.pinned ? "Pinned" : "Pin";
    this.el.error.hidden = !job.error || state === "DONE";
    this.el.error.textContent = job.error;
    this._showDownloads(job, state);
    this._showTimes();
  }

  /** Tiles received on the stream so far (they may run ahead of the last record). */
  setTilesReceived(count) {
    this.tilesReceived = count;
    this._showTiles();
  }

  _showTiles() {
    const job = this.job;
    if (!job) return;
    const total = job.tilesTotal;
    const done = stateOf(job) === "DONE" ? total : Math.min(Math.max(job.tilesDone, this.tilesReceived), total);
    this.el.tiles.textContent = total ? `${done} / ${total}` : "–";
    this.el.tiles.title = tileRoutes(job);
  }

  _showTimes() {
    const job = this.job;
    if (!job) return;
    const state = stateOf(job);
    const now = Date.now() / 1000;
    const start = job.startedAt || 0;
    let elapsed = NaN;
    if (start) elapsed = (job.finishedAt || (ACTIVE.has(state) ? now : start)) - start;
    this.el.elapsed.textContent = formatSeconds(elapsed);
    let left = NaN;
    if (state === "RUNNING" && job.progress > 0.02 && Number.isFinite(elapsed)) {
      left = (elapsed * (1 - job.progress)) / job.progress;
    } else if (state === "DONE") {
      left = 0;
    }
    this.el.left.textContent = state === "QUEUED" ? "waiting for a worker" : formatSeconds(left);
  }

  _showDownloads(job, state) {
    const box = this.el.downloads;
    box.replaceChildren();
    if (state !== "DONE") return;
    const links = [["PNG", jobImageUrl(job.id, "image", "png")], ["EXR", jobImageUrl(job.id, "image", "exr")]];
    for (const name of layerNames(job).slice(1)) links.push([`${name} PNG`, jobImageUrl(job.id, name, "png")]);
    for (const [label, href] of links) {
      const a = document.createElement("a");
      a.href = href;
      a.download = `${job.id}-${href.split("/").pop()}`;
      a.textContent = label;
      a.className = "button";
      box.append(a);
    }
  }

  async _cancel() {
    if (!this.job) return;
    this.el.cancel.disabled = true;
    await this._delete(this.job.id, "Cancel"); // a job that ended meanwhile goes
    this.dispatchEvent(new Event("cancelled"));
  }

  /** DELETE: a queued or running job is cancelled (shown, when open); one that has ended goes ("deleted"). */
  async _delete(jobId, what) {
    try {
      const cancelled = await deleteJob(jobId);
      if (!cancelled) this.dispatchEvent(new CustomEvent("deleted", { detail: jobId }));
      else if (this.job?.id === jobId) this.show(cancelled);
    } catch (e) {
      this.el.error.hidden = false;
      this.el.error.textContent = `${what} failed: ${e.message}`;
    }
  }

  async _pin() {
    if (!this.job) return;
    try {
      this.show(await pinJob(this.job.id, !this.job.pinned));
      this.refreshHistory();
    } catch (e) {
      this.el.error.hidden = false;
      this.el.error.textContent = `Pin failed: ${e.message}`;
    }
  }

  /** Notes a view's jobs' errors against its reference (an rt.AccuracyPlot), shown in the history. */
  showErrors(plot) {
    if (!plot.referenceId) return;
    this.references.add(plot.referenceId);
    for (const p of plot.points) this.errors.set(p.jobId, p.error.meanFlip);
    for (const small of this.el.history.querySelectorAll("small[data-job]")) this._describe(small);
  }

  /** Reloads the history list (newest first), `count` entries. */
  async refreshHistory(count = this.historyCount) {
    this.historyCount = count;
    let list;
    try {
      list = await listJobs(0, Math.min(count, 200));
    } catch (e) {
      this.el.history.replaceChildren(Object.assign(document.createElement("li"), { textContent: `Job history unavailable: ${e.message}` }));
      return;
    }
    const items = list.jobs.map((job) => this._historyItem(job));
    if (items.length === 0) items.push(Object.assign(document.createElement("li"), { textContent: "No jobs yet.", className: "empty" }));
    this.el.history.replaceChildren(...items);
    this.el.more.hidden = list.total <= list.jobs.length;
  }

  _historyItem(job) {
    const state = stateOf(job);
    const li = document.createElement("li");
    const a = document.createElement("a");
    a.href = `/jobs/${job.id}`;
    a.className = "history-item";
    if (this.job?.id === job.id) a.setAttribute("aria-current", "page");
    if (state === "DONE") {
      const img = document.createElement("img");
      img.src = jobImageUrl(job.id);
      img.alt = "";
      img.loading = "lazy";
      img.width = 64;
      img.height = 48;
      a.append(img);
    } else {
      const stateBadge = document.createElement("span");
      stateBadge.className = "thumb-empty";
      stateBadge.textContent = state.toLowerCase();
      a.append(stateBadge);
    }
    const text = document.createElement("span");
    const s = job.request?.settings;
    const when = job.createdAt ? new Date(job.createdAt * 1000).toLocaleTimeString() : "";
    text.innerHTML = `<strong></strong><small></small>`;
    text.querySelector("strong").textContent = `${s ? `${s.width}×${s.height}` : job.id}`;
    const small = text.querySelector("small");
    Object.assign(small.dataset, { job: job.id, state: state.toLowerCase(), when, pinned: job.pinned ? "1" : "" });
    this._describe(small);
    a.append(text);
    a.addEventListener("click", (e) => {
      if (e.button !== 0 || e.metaKey || e.ctrlKey || e.shiftKey) return;
      e.preventDefault();
      this.dispatchEvent(new CustomEvent("open", { detail: job.id }));
    });
    const remove = document.createElement("button");
    remove.type = "button";
    remove.className = "icon danger";
    remove.textContent = "✕";
    const what = ACTIVE.has(state) ? "Cancel" : "Delete";
    remove.title = `${what} job ${job.id}`;
    remove.setAttribute("aria-label", `${what} job ${job.id}`);
    remove.dataset.job = job.id;
    remove.addEventListener("click", () => this._remove(job, state));
    li.append(a, remove);
    return li;
  }

  /** The history's ✕: cancels a queued or running job, deletes one that has ended with its images. */
  async _remove(job, state) {
    const ending = ACTIVE.has(state);
    if (!ending && !window.confirm(`Delete job ${job.id} and its images?`)) return;
    await this._delete(job.id, ending ? "Cancel" : "Delete");
    this.refreshHistory();
  }

  /** A history entry's line: its state and time, and its error against its view's reference when known. */
  _describe(small) {
    const { job, state, when, pinned } = small.dataset;
    const flip = this.errors.get(job);
    const error = this.references.has(job) ? " · reference" : flip === undefined ? "" : ` · FLIP ${Number(flip.toPrecision(3))}`;
    small.textContent = `${state} · ${when}${pinned ? " · pinned" : ""}${error}`;
  }
}

/** How the job's full-resolution tiles reached its image: workers that see the
 * server's data folder write them there, others send them back. */
function tileRoutes(job) {
  const shared = job.tilesViaSharedFolder || 0;
  const network = job.tilesViaNetwork || 0;
  if (!shared && !network) return "";
  return `${shared} written by workers into the shared data folder, ${network} sent back over the network`;
}
