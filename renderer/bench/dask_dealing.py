"""How a real Dask scheduler deals tile tasks to workers, against the cluster
model's dealing (cluster_model.deal).

A `dask scheduler` and `dask worker` processes of 8 threads on loopback
(dask_costs._Processes), set up as the service sets up a scheduler it joins
(RenderCluster._set_up: the worker plugin and tile_slots.TileSlots), are sent
one graph of tasks by RenderCluster.submit with descending priorities, as a
job's tiles. Each task holds its worker's one lock for its time, as tiles
share their worker's render pool and render one after the other, and answers
which worker ran it and when. The same tasks under Dask's default dealing (no
TileSlots, tasks not marked: what the service did before) are the control.

    python renderer/bench/dask_dealing.py     # a few seconds of sleeping tasks

Prints, for each case and dealing (and for one tile a worker at a time), the
job's measured time (submit to the last result) and the model's makespan for
the same task times and slots, how long a worker sat idle between tasks, and
the tasks and seconds each worker was dealt, measured and modelled.
"""

from __future__ import annotations

import asyncio
import random
import statistics
import sys
import threading
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import cluster_model  # noqa: E402  (puts server/ on the path)
import dask_costs  # noqa: E402

_pool = threading.Lock()  # the worker's render pool: one tile at a time on all its threads


def hold(seconds: float) -> tuple[str, float, float]:
    """A tile that renders for `seconds` once its worker's pool is free."""
    from distributed import get_worker

    with _pool:
        began = time.time()
        time.sleep(seconds)
        return get_worker().name, began, time.time()


def cases() -> list[tuple[str, int, list[float]]]:
    """(name, workers, task seconds in priority order)."""
    every_fourth = [0.4 if i % 4 == 0 else 0.05 for i in range(32)]
    rng = random.Random(18)
    # Costly first, as centre-out tiles of a centred subject: 96 tiles from 0.2 s down to 0.02 s, +-50%.
    falling = [(0.02 + 0.18 * (1 - i / 95) ** 2) * rng.uniform(0.5, 1.5) for i in range(96)]
    return [("every fourth task 0.4 s, the rest 0.05 s", 4, every_fourth),
            ("96 tasks from 0.2 s down to 0.02 s", 8, falling)]


async def _run(address: str, seconds: list[float], dealing: str) -> tuple[float, list[tuple[str, float, float]]]:
    """One job of tasks holding their worker's lock for `seconds`, dealt as
    `dealing` says: "dask" (Dask's default, the service before tile_slots),
    "service" (as the service has them dealt) or "one" (the same, a tile a
    worker at a time)."""
    from dask.highlevelgraph import HighLevelGraph, MaterializedLayer
    from distributed import Client, wait

    from app.services.cluster import RenderCluster, RenderWorkerSetup
    from app.services.tile_slots import TileSlots

    # The tasks' function by its module's name, which workers import: one of
    # __main__ would be pickled by value, and its lock with it.
    module = sys.modules[__name__] if __name__ != "__main__" else __import__("dask_dealing")
    client = await Client(address, asynchronous=True, timeout="60s")
    try:
        cluster = RenderCluster(client, None, address)
        tasks = {f"tile-{i}": (module.hold, s) for i, s in enumerate(seconds)}
        priorities = {key: -i for i, key in enumerate(tasks)}
        if dealing == "dask":
            await client.register_plugin(RenderWorkerSetup())

            def submit(name, tasks, priorities):  # RenderCluster.submit before tile_slots
                layer = MaterializedLayer(tasks, annotations={"priority": priorities.__getitem__})
                return client.get(HighLevelGraph({name: layer}, {name: set()}), list(tasks), sync=False,
                                  fifo_timeout="0ms")
        else:
            await cluster._set_up()  # noqa: SLF001  (what the service does with a scheduler it joins)
            await client.register_plugin(TileSlots(1 if dealing == "one" else 2))
            submit = cluster.submit
        warm = submit("warm", {f"warm-{i}": (module.hold, 0.001) for i in range(8)}, {f"warm-{i}": 0 for i in range(8)})
        await wait(warm)
        started = time.time()
        futures = submit("job", tasks, priorities)
        results = await client.gather(futures)
        return time.time() - started, results
    finally:
        await client.close()


def _gaps(found: list[tuple[str, float, float]]) -> list[float]:
    """Each worker's idle time between one task's end and the next one's start."""
    by: dict[str, list[tuple[float, float]]] = {}
    for name, began, ended in found:
        by.setdefault(name, []).append((began, ended))
    return [b - e for spans in by.values() for (_, e), (b, _) in zip(sorted(spans), sorted(spans)[1:])]


def _per_worker(found: list[tuple[str, float, float]]) -> list[tuple[int, float]]:
    """Tasks and seconds of holding per worker, most seconds first."""
    by = {}
    for name, began, ended in found:
        count, total = by.get(name, (0, 0.0))
        by[name] = (count + 1, total + ended - began)
    return sorted(by.values(), key=lambda v: -v[1])


def _modelled_per_worker(seconds: list[float], workers: int, slots: int) -> list[tuple[int, float]]:
    """The same from the model."""
    by = [(0, 0.0)] * workers
    for s, (w, _, _) in zip(seconds, cluster_model.deal(seconds, workers, slots)):
        by[w] = (by[w][0] + 1, by[w][1] + s)
    return sorted(by, key=lambda v: -v[1])


def main() -> int:
    labels = {"dask": "Dask's default dealing", "service": "the service's dealing", "one": "a tile a worker"}
    for name, workers, seconds in cases():
        with dask_costs._Processes(workers) as procs:  # noqa: SLF001
            for dealing in ("dask", "service", "one"):
                wall, found = asyncio.run(_run(procs.address, seconds, dealing))
                slots = 1 if dealing == "one" else cluster_model.dealing_slots(
                    dealing, len(seconds), workers, dask_costs.THREADS_PER_WORKER)
                model = max(end for _, _, end in cluster_model.deal(seconds, workers, slots))
                print(f"{name}, {workers} workers of {dask_costs.THREADS_PER_WORKER} threads, {labels[dealing]}: "
                      f"measured {wall:.3f} s, modelled {model:.3f} s ({slots:g} a worker); "
                      f"{sum(seconds) / workers:.3f} s if perfectly shared; a worker idle between tasks "
                      f"{statistics.median(_gaps(found)) * 1e3:.2f} ms (median)", flush=True)
                print("  measured per worker (tasks, s):",
                      ", ".join(f"{c} {t:.2f}" for c, t in _per_worker(found)), flush=True)
                print("  modelled per worker (tasks, s):",
                      ", ".join(f"{c} {t:.2f}" for c, t in _modelled_per_worker(seconds, workers, slots)),
                      flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
