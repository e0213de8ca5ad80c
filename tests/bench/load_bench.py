#!/usr/bin/env python3
"""Many clients at once against the job service, as `make run` starts it.

--clients clients (threads of this process, each with its own connection)
each post --jobs small jobs, and between posts read the job they posted, the
job list and the health, as a dashboard would; then each waits for its jobs
to end. Every request's latency is kept by kind. While the posts go on, the
cluster is busy with the jobs posted before.

Two ways to send them, both run:
- open: each client posts a job every --period seconds, the clients' posts
  spread evenly over the period, and its reads a quarter, a half and three
  quarters of a period later. Each request's latency counts from when it was
  due, so a stalled server is charged for the requests it held back
  (coordinated omission). This is the load the targets are for: 50 clients
  at a post every 0.5 s offer 100 jobs a second, as many as the cluster
  renders or more (80-106 a second in closed runs on 2 cores), so it is busy
  throughout.
- closed: each client sends its next request as soon as the last one is
  answered, so the server is always saturated, and by Little's law the mean
  latency is the clients' count over the throughput. Printed for the
  throughput; its latencies measure the queue, not the service.

Printed: per mode and kind the count, errors, p50, p99 and max in ms, the
jobs' end states, CPU seconds of the clients and the server, and whether the
targets hold in the open run (POST p99 under --post-p99 ms, GET p99 under
--get-p99 ms, no error, every job done). Exits 1 when they do not.

  tests/bench/load_bench.py --scenes build/scenes [--clients 50] [--jobs 20] [--period 0.5]
"""

from __future__ import annotations

import argparse
import resource
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

    def timed(self, kind: str, send, due: float | None = None) -> httpx.Response | None:
        """`send()`'s answer, its latency kept from `due` (a perf_counter
        time) when the request was due then, else from now."""
        start = time.perf_counter() if due is None else due
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


JOB = {"settings": {"width": 64, "height": 48, "samples_per_pixel": 4}}


class Client:
    """One client: its connection, the jobs it posted, and one dashboard round."""

    def __init__(self, base: str, scene_id: str, seen: Latencies, ended: dict[str, str]):
        self.http = httpx.Client(base_url=base, timeout=120)
        self.body = {"scene_id": scene_id, **JOB}
        self.seen, self.ended = seen, ended
        self.mine: list[str] = []

    def post(self, due: float | None = None) -> None:
        posted = self.seen.timed("POST /api/jobs", lambda: self.http.post("/api/jobs", json=self.body), due)
        if posted is not None and posted.status_code == 202:
            self.mine.append(posted.json()["id"])

    def reads(self):
        """The dashboard's reads after a post, as (kind, send)."""
        if self.mine:
            job_id = self.mine[-1]
            yield "GET /api/jobs/{id}", lambda: self.http.get(f"/api/jobs/{job_id}")
        yield "GET /api/jobs", lambda: self.http.get("/api/jobs", params={"limit": 20})
        yield "GET /api/health", lambda: self.http.get("/api/health")

    def wait_for_jobs(self) -> None:
        for job_id in self.mine:
            while True:
                answer = self.seen.timed("GET /api/jobs/{id}", lambda: self.http.get(f"/api/jobs/{job_id}"))
                job = answer.json() if answer is not None and answer.status_code == 200 else {}
                state = job.get("state", "?")
                if state in ("DONE", "FAILED", "CANCELLED"):
                    self.ended[job_id] = state if state == "DONE" else f"{state}: {job.get('error', '')[:200]}"
                    break
                time.sleep(0.5)
        self.http.close()


def run_closed(client: Client, jobs: int) -> None:
    for _ in range(jobs):
        client.post()
        for kind, send in client.reads():
            client.seen.timed(kind, send)
    client.wait_for_jobs()


def run_open(client: Client, jobs: int, period: float, first_due: float) -> None:
    for i in range(jobs):
        due = first_due + i * period
        _sleep_until(due)
        client.post(due)
        for k, (kind, send) in enumerate(client.reads(), start=1):
            read_due = due + k * period / 4
            _sleep_until(read_due)
            client.seen.timed(kind, send, read_due)
    client.wait_for_jobs()


def _sleep_until(due: float) -> None:
    left = due - time.perf_counter()
    if left > 0:
        time.sleep(left)


def percentile(values: list[float], share: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(share * len(ordered)))]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scenes", type=Path, default=Path(__file__).resolve().parents[2] / "build" / "scenes")
    parser.add_argument("--clients", type=int, default=50)
    parser.add_argument("--jobs", type=int, default=20, help="jobs each client posts")
    parser.add_argument("--period", type=float, default=0.5, help="seconds between a client's posts in the open run")
    parser.add_argument("--post-p99", type=float, default=250)
    parser.add_argument("--get-p99", type=float, default=100)
    args = parser.parse_args()
    holds = load_run(args, "open")
    load_run(args, "closed")  # for its throughput: a saturated server has no latency target
    return 0 if holds else 1


def load_run(args, mode: str) -> bool:
    """One run against a new server; whether the targets hold."""
    with tempfile.TemporaryDirectory(prefix="rt-load-") as folder:
        samples = Path(folder, "samples")
        samples.mkdir()
        (samples / "teapot.glb").symlink_to((args.scenes / "teapot.glb").resolve())
        port = free_port()
        server = start_server(Path(folder, "data"), port, RT_SAMPLES_DIR=str(samples))
        try:
            base = f"http://127.0.0.1:{port}"
            scene_id = httpx.get(f"{base}/api/scenes").json()["scenes"][0]["id"]
            seen, ended = Latencies(), {}
            clients = [Client(base, scene_id, seen, ended) for _ in range(args.clients)]
            started = time.perf_counter()
            if mode == "open":
                first = started + 0.1
                runs = [(run_open, (c, args.jobs, args.period, first + i * args.period / len(clients)))
                        for i, c in enumerate(clients)]
            else:
                runs = [(run_closed, (c, args.jobs)) for c in clients]
            threads = [threading.Thread(target=target, args=run_args) for target, run_args in runs]
            for thread in threads:
                thread.start()
            for thread in threads:
                thread.join()
            wall = time.perf_counter() - started
            client_cpu = _cpu(resource.RUSAGE_SELF)
        finally:
            server.terminate()
            server.wait(30)
    return report(args, mode, seen, ended, wall, client_cpu)


def report(args, mode: str, seen: Latencies, ended: dict[str, str], wall: float, client_cpu: float) -> bool:
    """Prints a run's figures; whether the targets hold (the open run's)."""
    how = f"a post every {args.period:g} s each" if mode == "open" else "each request when the last is answered"
    print(f"\n{mode}: {args.clients} clients x {args.jobs} jobs (64x48, 4 spp, teapot), {how}: {wall:.1f} s; "
          f"jobs ended: {dict(_counts(s.split(':')[0] for s in ended.values()))}")
    print(f"CPU seconds so far: the clients {client_cpu:.1f}, the servers {_cpu(resource.RUSAGE_CHILDREN):.1f}")
    print(f"{'request':<22}{'count':>7}{'errors':>8}{'p50 ms':>9}{'p99 ms':>9}{'max ms':>9}{'per s':>8}")
    for kind, values in sorted(seen.ms.items()):
        print(f"{kind:<22}{len(values):>7}{len(seen.errors[kind]):>8}{statistics.median(values):>9.1f}"
              f"{percentile(values, 0.99):>9.1f}{max(values):>9.1f}{len(values) / wall:>8.0f}")
    for kind, problems in seen.errors.items():
        for problem in problems[:3]:
            print(f"  {kind}: {problem}")
    for state in sorted({s for s in ended.values() if s != "DONE"})[:3]:
        print(f"  job {state}")
    post = percentile(seen.ms["POST /api/jobs"], 0.99)
    gets = percentile([v for k, vs in seen.ms.items() if k.startswith("GET") for v in vs], 0.99)
    errors = sum(len(p) for p in seen.errors.values())
    done = sum(state == "DONE" for state in ended.values())
    holds = post < args.post_p99 and gets < args.get_p99 and errors == 0 and done == args.clients * args.jobs
    verdict = ("holds" if holds else "DOES NOT HOLD") if mode == "open" else "(saturated: no target)"
    print(f"POST p99 {post:.1f} ms (target < {args.post_p99:g}), GET p99 {gets:.1f} ms (target < {args.get_p99:g}), "
          f"{errors} errors, {done} of {args.clients * args.jobs} jobs done: {verdict}")
    return holds


def _cpu(who: int) -> float:
    usage = resource.getrusage(who)
    return usage.ru_utime + usage.ru_stime


def _counts(values) -> dict[str, int]:
    counts: dict[str, int] = defaultdict(int)
    for value in values:
        counts[value] += 1
    return counts


if __name__ == "__main__":
    sys.exit(main())
