// Who is signed in (GET /api/me, rt.UserInfo) in the top bar: the user's name,
// and their use of the server against its per-user quotas, so that a 413 or
// 429 never comes as a surprise. "Sign out" forgets this browser's token; the
// next request asks for one again (another user's, say).
import { forgetToken, hasToken, me } from "./api.js";
import { formatBytes } from "./format.js";

/** "12.0 MB stored of 100.0 MB · 2 of 10 jobs queued": the use, with each limit that is set. */
export function usageText(info) {
  const stored = `${formatBytes(info.storedBytes)} stored`
    + (Number(info.quotaBytes) ? ` of ${formatBytes(info.quotaBytes)}` : "");
  const queued = info.quotaQueuedJobs
    ? `${info.queuedJobs} of ${info.quotaQueuedJobs} jobs queued` : `${info.queuedJobs} jobs queued`;
  return `${stored} · ${queued}`;
}

export class UserBadge {
  constructor(root) {
    this.name = root.getElementById("user-name");
    this.usage = root.getElementById("user-usage");
    this.signOut = root.getElementById("sign-out");
    this.named = false;
    this.signOut.addEventListener("click", () => {
      forgetToken();
      location.reload();
    });
  }

  /** Asks the server who this is; shows it, or why it could not. */
  async refresh() {
    try {
      const info = await me();
      this.name.textContent = info.name;
      this.name.title = info.name === "local" ? "This server has one local user" : `Signed in as ${info.name}`;
      this.usage.textContent = usageText(info);
      this.named = info.name !== "local"; // a server with named users: samples are shared, read-only
      delete this.name.dataset.kind;
    } catch (e) {
      this.name.textContent = "not signed in";
      this.name.title = e.message;
      this.name.dataset.kind = "error";
      this.usage.textContent = "";
    }
    this.signOut.hidden = !hasToken();
  }
}
