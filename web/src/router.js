// Addresses the viewer answers to: / (no job) and /jobs/<id> (one job, which
// can be bookmarked and reloaded; the server hands index.html to both).
const JOB_PATH = /^\/jobs\/([A-Za-z0-9_-]+)\/?$/;

export class Router extends EventTarget {
  constructor() {
    super();
    window.addEventListener("popstate", () => this._emit());
  }

  /** The job id in the address, or null. */
  get jobId() {
    return JOB_PATH.exec(location.pathname)?.[1] ?? null;
  }

  /** Goes to a job's address (null: the start page); `replace` keeps history short. */
  go(jobId, { replace = false, silent = false } = {}) {
    const path = jobId ? `/jobs/${encodeURIComponent(jobId)}` : "/";
    if (path !== location.pathname) {
      if (replace) history.replaceState(null, "", path);
      else history.pushState(null, "", path);
    }
    if (!silent) this._emit();
  }

  start() {
    this._emit();
  }

  _emit() {
    this.dispatchEvent(new CustomEvent("route", { detail: { jobId: this.jobId } }));
  }
}
