// The record of the job being followed: fetched once when the job is opened,
// then taken from its tile stream (read by TileView), which carries the record
// each time the job's state or progress changes (rt.TileStreamMessage `job`)
// and once more at its end (`end`). Nothing polls the server.
import { getJob } from "./api.js";
import { enumName } from "./proto.js";

const FINAL = new Set(["DONE", "FAILED", "CANCELLED"]);

/** True for a record of a job that is over (done, failed or cancelled). */
export const isFinal = (job) => FINAL.has(enumName("JobState", job.state));

export class JobFollower extends EventTarget {
  /** `tiles`: the TileView whose stream's "job" and "end" events carry the records. */
  constructor(tiles) {
    super();
    this.jobId = null;
    this.job = null;
    tiles.addEventListener("job", (e) => this._record(e.detail, "job"));
    tiles.addEventListener("end", (e) => this._record(e.detail, "end"));
  }

  /** Follows job `id` from now on: its record as the server has it, or null
   *  when another job was opened meanwhile. Throws what getJob throws. */
  async open(id) {
    this.jobId = id;
    this.job = null;
    let job;
    try {
      job = await getJob(id);
    } catch (e) {
      if (this.jobId === id) this.jobId = null;
      throw e;
    }
    if (this.jobId !== id) return null;
    this.job = job;
    return job;
  }

  stop() {
    this.jobId = null;
    this.job = null;
  }

  /** A record from the stream: dispatched as "job" (while it runs) or "end". */
  _record(job, kind) {
    if (job.id !== this.jobId) return;
    // The replayed stream of a finished job still carries its last running record.
    if (kind === "job" && this.job && isFinal(this.job)) return;
    this.job = job;
    this.dispatchEvent(new CustomEvent(kind, { detail: job }));
  }
}
