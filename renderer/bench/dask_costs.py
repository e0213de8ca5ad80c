"""What Dask costs per tile task on this machine, measured as the job service
spends it: a real `dask scheduler` process and `dask worker` processes of 8
threads (as tests/cluster/topology.py starts them), set up as the server sets
up a scheduler it joins (RenderCluster._set_up: tiles dealt two a worker,
tile_slots.py), one graph per job sent by RenderCluster.submit with the plan's
priorities, and each result handled as
JobManager._run handles it (awaited, its message published on a TileStream,
the job record updated and published). The tasks do nearly nothing (they
answer a TileResult carrying a tile's RGBA8 message), so what is left is
Dask's and the server's own cost:

- the scheduler's CPU per task (its process's CPU time over a job, less what it
  spends idle): the scheduler is single-threaded, so this is the cluster's
  serial cost per task, measured at each number of workers;
- the server's CPU per result (this process: the Dask client and the _run
  loop share its event loop), for a small and a large tile's message, so that
  it splits into a cost per result and a cost per result byte;
- the workers' CPU per task (summed over the workers): a task's own cost on
  its worker beyond its rendering;
- a job's fixed latency: a one-task job, from submit to its result handled.
"""

from __future__ import annotations

import asyncio
import os
import signal
import socket
import statistics
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import psutil

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "server"))

THREADS_PER_WORKER = 8


def noop_tile(side: int) -> bytes:
    """A tile task that renders nothing: the TileResult a shared-folder worker
    answers for a side x side tile (its RGBA8 message), serialized as Dask
    carries it."""
    from rt import job_pb2

    started = time.time()
    tile = job_pb2.Tile(job="bench", region=job_pb2.TileRegion(w=side, h=side), scale=1, pixels=bytes(side * side * 4))
    result = job_pb2.TileResult(message=job_pb2.TileStreamMessage(tile=tile).SerializeToString(), rays=side * side,
                                samples=side * side, started=started, shared_folder=True)
    result.seconds = time.time() - started
    return result


@dataclass
class Spread:
    """Median and range of repeated measurements."""
    median: float
    low: float
    high: float

    @classmethod
    def of(cls, values: list[float]) -> "Spread":
        return cls(statistics.median(values), min(values), max(values))

    def text(self, scale: float, unit: str, digits: int = 3) -> str:
        return (f"{self.median * scale:.{digits}g} {unit} ({self.low * scale:.{digits}g}-"
                f"{self.high * scale:.{digits}g})")


@dataclass
class DaskCosts:
    scheduler_s: dict[int, Spread]       # workers -> scheduler CPU seconds per task
    wall_s: dict[int, Spread]            # workers -> wall seconds per task of a job of no-op tasks
    worker_s: dict[int, Spread]          # workers -> the workers' CPU seconds per task, summed
    server_s: Spread                     # the server's CPU seconds per result, before its bytes
    server_s_per_byte: float             # and per byte of the result's message
    server_small_s: Spread               # measured: per result of a small tile's message
    server_large_s: Spread               # and of a large one's
    small_side: int
    large_side: int
    latency_s: Spread                    # a one-task job, submit to handled
    tasks: int                           # tasks per measured job


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class _Processes:
    """A scheduler and `workers` worker processes of THREADS_PER_WORKER threads
    on loopback, ended (by their own ids) when the block ends."""

    def __init__(self, workers: int):
        import rtcore
        self.address = f"tcp://127.0.0.1:{_free_port()}"
        bin_dir = Path(sys.executable).parent
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(
            [str(Path(__file__).resolve().parent), str(ROOT / "server"), str(Path(rtcore.__file__).parent)])}
        quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL, "start_new_session": True, "env": env}
        self.scheduler = subprocess.Popen([str(bin_dir / "dask"), "scheduler", "--host", "127.0.0.1",
                                           "--port", self.address.rsplit(":", 1)[1], "--dashboard-address", ":0",
                                           "--no-show"], **quiet)
        self.workers = [subprocess.Popen([str(bin_dir / "dask"), "worker", self.address, "--nthreads",
                                          str(THREADS_PER_WORKER), "--no-nanny", "--name", f"w{i}",
                                          "--dashboard-address", ":0"], **quiet) for i in range(workers)]

    def cpu(self, processes: list[subprocess.Popen]) -> float:
        total = 0.0
        for p in processes:
            times = psutil.Process(p.pid).cpu_times()
            total += times.user + times.system
        return total

    def __enter__(self) -> "_Processes":
        return self

    def __exit__(self, *exc) -> None:
        for p in [*self.workers, self.scheduler]:
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGTERM)
        for p in [*self.workers, self.scheduler]:
            try:
                p.wait(20)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)


async def _run_job(cluster, run: str, tiles: int, side: int) -> None:
    """One job of `tiles` no-op tasks, submitted and handled as JobManager._run does."""
    from distributed import as_completed
    from rt import job_pb2

    from app.services.streams import TileStream

    tasks = {f"tile-{run}-{i}": (noop_tile, side) for i in range(tiles)}
    priorities = {key: -i for i, key in enumerate(tasks)}  # centre-out order, as plan_passes gives
    futures = cluster.submit(f"job-{run}", tasks, priorities)
    stream = TileStream()
    job = job_pb2.Job(id=run, state=job_pb2.RUNNING, tiles_total=tiles)
    async for future in as_completed(futures):
        result = await future
        await stream.publish(result.message)
        job.tiles_done += 1
        job.progress = job.tiles_done / tiles
        job.render_seconds += result.seconds
        job.rays += result.rays
        await stream.update(job)


async def _measure_cluster(workers: int, tasks: int, repeats: int, small: int, large: int, with_server: bool) -> dict:
    from distributed import Client

    from app.services.cluster import RenderCluster

    with _Processes(workers) as procs:
        client = await Client(procs.address, asynchronous=True, timeout="60s")
        try:
            await client.wait_for_workers(workers, timeout=180)
            cluster = RenderCluster(client, None, procs.address)
            await cluster._set_up()  # noqa: SLF001  (as the service sets up a scheduler: tiles dealt as it has them)
            await _run_job(cluster, "warm", min(tasks, 200), small)
            await asyncio.sleep(1.0)
            before, idle_start = procs.cpu([procs.scheduler]), time.perf_counter()
            await asyncio.sleep(2.0)
            idle_rate = (procs.cpu([procs.scheduler]) - before) / (time.perf_counter() - idle_start)
            found = {"scheduler": [], "wall": [], "worker": [], "small": [], "large": [], "latency": []}
            for r in range(repeats):
                for side, count, key in ((small, tasks, "small"), (large, max(tasks // 10, 20), "large")):
                    if key == "large" and not with_server:
                        continue
                    s0, w0, c0, t0 = (procs.cpu([procs.scheduler]), procs.cpu(procs.workers), time.process_time(),
                                      time.perf_counter())
                    await _run_job(cluster, f"{key}{r}", count, side)
                    wall = time.perf_counter() - t0
                    found[key].append((time.process_time() - c0) / count)
                    if key == "small":
                        found["scheduler"].append((procs.cpu([procs.scheduler]) - s0 - idle_rate * wall) / count)
                        found["worker"].append((procs.cpu(procs.workers) - w0) / count)
                        found["wall"].append(wall / count)
            if with_server:
                for r in range(max(10, 3 * repeats)):
                    t0 = time.perf_counter()
                    await _run_job(cluster, f"one{r}", 1, small)
                    found["latency"].append(time.perf_counter() - t0)
        finally:
            await client.close()
    return found


def measure(worker_counts: tuple[int, ...] = (1, 2, 4, 8, 16), tasks: int = 2000, repeats: int = 3,
            small: int = 32, large: int = 512) -> DaskCosts:
    """Runs each cluster size in turn; the server's costs and the latency at the smallest."""
    runs = {}
    for n in worker_counts:
        runs[n] = asyncio.run(_measure_cluster(n, tasks, repeats, small, large, with_server=n == worker_counts[0]))
        s = Spread.of(runs[n]["scheduler"])
        print(f"dask: {n:2} workers x {THREADS_PER_WORKER} threads: scheduler {s.text(1e6, 'us')} CPU per task, "
              f"wall {Spread.of(runs[n]['wall']).text(1e6, 'us')} per task", flush=True)
    first = runs[worker_counts[0]]
    small_s, large_s = Spread.of(first["small"]), Spread.of(first["large"])
    message = lambda side: side * side * 4  # noqa: E731  (the RGBA8 pixels; the rest is a few dozen bytes)
    per_byte = max(0.0, (large_s.median - small_s.median) / (message(large) - message(small)))
    base = [max(0.0, v - per_byte * message(small)) for v in first["small"]]
    return DaskCosts(scheduler_s={n: Spread.of(r["scheduler"]) for n, r in runs.items()},
                     wall_s={n: Spread.of(r["wall"]) for n, r in runs.items()},
                     worker_s={n: Spread.of(r["worker"]) for n, r in runs.items()},
                     server_s=Spread.of(base), server_s_per_byte=per_byte, server_small_s=small_s,
                     server_large_s=large_s, small_side=small, large_side=large,
                     latency_s=Spread.of(first["latency"]), tasks=tasks)


if __name__ == "__main__":
    costs = measure()
    print(costs)
