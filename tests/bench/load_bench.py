#!/usr/bin/env python3
"""Many clients at once against the job service, as `make run` starts it.

--clients clients (threads of this process, each with its own connection)
each post --jobs small jobs in turn, and between posts read the job they
posted, the job list and the health, as a dashboard would; then each waits
for its jobs to end. Every request's latency is kept by kind. While the posts
go on, the cluster is busy with the jobs posted before. Printed: per kind the
count, errors, p50, p99 and max in ms, the jobs' end states, and whether the
targets hold (POST p99 under --post-p99 ms, GET p99 under --get-p99 ms, no
error). Exits 1 when they do not.

  tests/bench/load_bench.py --scenes build/scenes [--clients 50] [--jobs 20]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import threading
import time
from collections import defaultdict
from pathlib import Path

import httpx
from service_bench import free_port, start_server


class Latencies:
    def __init__(self):
        self._lock = threading.Lock()
        self.ms: dict[str, list[float]] = defaultdict(list)
        self.errors: dict[str, list[str]] = defaultdict(list)

    def timed(self, kind: str, send) -> httpx.Response | None:
        start = time.perf_counter()
        try:
            answer = send()
        except httpx.HTTPError as e:
            answer, problem = None, repr(e)
        else:
            problem = "" if answer.status_code < 400 else f"{answer.status_code} {answer.text[:120]}"
        with self._lock:
            self.ms[kind].append((time.perf_counter() - start) * 1000)
            if problem:
                self.errors[kind].append(problem)
        return answer


def client_run(base: str, scene_id: str, jobs: int, seen: Latencies, ended: dict[str, str]) -> None:
    body = {"scene_id": scene_id, "settings": {"width": 64, "height": 48, "samples_per_pixel": 4}}
    mine = []
    with httpx.Client(base_url=base, timeout=120) as http:
        for _ in range(jobs):
            posted = seen.timed("POST /api/jobs", lambda: http.post("/api/jobs", json=body))
            if posted is not None and posted.status_code == 202:
                mine.append(posted.json()["id"])
                seen.timed("GET /api/jobs/{id}", lambda: http.get(f"/api/jobs/{mine[-1]}"))
            seen.timed("GET /api/jobs", lambda: http.get("/api/jobs", params={"limit": 20}))
            seen.timed("GET /api/health", lambda: http.get("/api/health"))
        for job_id in mine:
            while True:
                answer = seen.timed("GET /api/jobs/{id}", lambda: http.get(f"/api/jobs/{job_id}"))
                state = answer.json()["state"] if answer is not None and answer.status_code == 200 else "?"
                if state in ("DONE", "FAILED", "CANCELLED"):
                    ended[job_id] = state
                    break
                time.sleep(0.5)


def percentile(values: list[float], share: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(share * len(ordered)))]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scenes", type=Path, default=Path(__file__).resolve().parents[2] / "build" / "scenes")
    parser.add_argument("--clients", type=int, default=50)
    parser.add_argument("--jobs", type=int, default=20, help="jobs each client posts")
    parser.add_argument("--post-p99", type=float, default=250)
    parser.add_argument("--get-p99", type=float, default=100)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="rt-load-") as folder:
        samples = Path(folder, "samples")
        samples.mkdir()
        (samples / "teapot.glb").symlink_to(args.scenes / "teapot.glb")
        port = free_port()
        server = start_server(Path(folder, "data"), port, RT_SAMPLES_DIR=str(samples))
        try:
            base = f"http://127.0.0.1:{port}"
            scene_id = httpx.get(f"{base}/api/scenes").json()["scenes"][0]["id"]
            seen, ended = Latencies(), {}
            started = time.perf_counter()
            threads = [threading.Thread(target=client_run, args=(base, scene_id, args.jobs, seen, ended))
                       for _ in range(args.clients)]
            for thread in threads:
                thread.start()
            for thread in threads:
                thread.join()
            wall = time.perf_counter() - started
        finally:
            server.terminate()
            server.wait(30)
    print(f"{args.clients} clients x {args.jobs} jobs (64x48, 4 spp, teapot) in {wall:.1f} s; "
          f"jobs ended: {dict(_counts(ended.values()))}")
    print(f"{'request':<22}{'count':>7}{'errors':>8}{'p50 ms':>9}{'p99 ms':>9}{'max ms':>9}")
    for kind, values in sorted(seen.ms.items()):
        print(f"{kind:<22}{len(values):>7}{len(seen.errors[kind]):>8}{statistics.median(values):>9.1f}"
              f"{percentile(values, 0.99):>9.1f}{max(values):>9.1f}")
    for kind, problems in seen.errors.items():
        for problem in problems[:3]:
            print(f"  {kind}: {problem}")
    post = percentile(seen.ms["POST /api/jobs"], 0.99)
    gets = percentile([v for k, vs in seen.ms.items() if k.startswith("GET") for v in vs], 0.99)
    errors = sum(len(p) for p in seen.errors.values())
    done = sum(state == "DONE" for state in ended.values())
    holds = post < args.post_p99 and gets < args.get_p99 and errors == 0 and done == args.clients * args.jobs
    print(f"POST p99 {post:.1f} ms (target < {args.post_p99:g}), GET p99 {gets:.1f} ms (target < {args.get_p99:g}), "
          f"{errors} errors, {done} of {args.clients * args.jobs} jobs done: {'holds' if holds else 'DOES NOT HOLD'}")
    return 0 if holds else 1


def _counts(values) -> dict[str, int]:
    counts: dict[str, int] = defaultdict(int)
    for value in values:
        counts[value] += 1
    return counts


if __name__ == "__main__":
    sys.exit(main())
