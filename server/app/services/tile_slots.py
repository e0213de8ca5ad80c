"""How Dask hands tiles to workers: two at a time, from the scheduler's queue.

A tile renders on all of its worker's threads (rtcore's render pool, oldest
tile first), so a worker needs two tiles, one rendering and the next waiting
(which also renders in the threads the first leaves idle as it ends, and while
its task encodes and writes its pixels). Dask's own dealing holds more: a
job's tiles are root-ish only when they outnumber the cluster's threads twice
over, and then each worker holds 1.1 tasks a thread, 9 on 8 threads; a job of
fewer tiles (what the scheduler limit in tile_plan.py gives a large cluster)
is sent to the workers all at once, a few each. Either way the tiles are dealt
by count, before anyone knows what they cost, and a worker runs all it holds
on one pool: a 3840 x 2160 dragon at 16 samples on 32 workers of 8 threads,
135 tiles, 4 or 5 to each worker at once, waited for the workers dealt the
costly tiles of the middle (56% efficiency in renderer/bench/cluster_model.py;
74% dealt two at a time).

So every tile task is marked a data producer, which Dask always queues on the
scheduler (Scheduler.is_rootish), and the scheduler's worker saturation is set
so that a worker holds TILES_PER_WORKER of them: the next tile, in priority
order, goes to the first worker with a free slot (renderer/bench/dask_dealing.py
checks this on a real scheduler). A worker ending its tile is handed the next
while it renders the one it holds: it started it 0.16 ms (median) after the
last there, where a worker holding one tile at a time waited 3.5 ms for the
next. The queue also serves fair share: a tile of a newer, higher-priority job
waits for a slot, not behind a worker's backlog.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Iterable

from dask._task_spec import Task, convert_legacy_task
from distributed.diagnostics.plugin import SchedulerPlugin

log = logging.getLogger("rt.cluster")

# Tile tasks a worker holds at once: one rendering and one waiting.
TILES_PER_WORKER = 2


def worker_saturation(threads: Iterable[int], tiles: int = TILES_PER_WORKER) -> float:
    """Dask's worker saturation (tasks a worker holds per thread, rounded up)
    that gives the largest of workers of `threads` threads `tiles` tasks; a
    smaller worker gets as many or fewer (one at least)."""
    most = max(threads, default=0)
    if not most:
        return 1.0
    # Half a task under the mark: ceil() of the product is the count, whatever the rounding.
    return (tiles - 0.5) / most


def slots(threads: int, saturation: float) -> int:
    """Tasks a worker of `threads` threads holds (distributed.scheduler._task_slots_available)."""
    return max(math.ceil(saturation * threads), 1)


class TileSlots(SchedulerPlugin):
    """Sets the scheduler's worker saturation for its workers as they join.
    Registered by the server on every scheduler it meets, as RenderWorkerSetup
    is on every worker; the scheduler must import this module (the image's
    PYTHONPATH has it, as the workers do)."""

    name = "rt-tile-slots"

    def __init__(self, tiles: int = TILES_PER_WORKER):
        self.tiles = tiles

    async def start(self, scheduler) -> None:
        self._update(scheduler)

    def add_worker(self, scheduler, worker: str) -> None:
        self._update(scheduler)

    def _update(self, scheduler) -> None:
        if scheduler.workers:
            scheduler.WORKER_SATURATION = worker_saturation((ws.nthreads for ws in scheduler.workers.values()),
                                                            self.tiles)


async def set_up(client) -> None:
    """Registers TileSlots on the client's scheduler. One that cannot import
    this module still runs the tiles, queued but more to a worker, and the log
    says so for each scheduler set up."""
    try:
        await client.register_plugin(TileSlots())
    except ImportError as e:
        log.warning("the Dask scheduler cannot import %s (%r): its workers hold 1.1 tiles a thread, not %d "
                    "each; put the server's code on its PYTHONPATH, as the workers have it", __name__, e,
                    TILES_PER_WORKER)


def queued_tasks(tasks: dict[str, tuple[Callable, ...]]) -> dict[str, Task]:
    """`tasks` ({key: (function, *arguments)}, an argument naming another key
    depends on it) as Dask tasks marked data producers, which the scheduler
    queues and hands out as workers free their slots."""
    # Task's _data_producer is how Dask's own readers (read_parquet and the
    # like) have their tasks queued; tests/server/services/test_tile_slots.py
    # checks on a real scheduler that tiles are still dealt two a worker.
    keys = set(tasks)
    queued = {}
    for key, task in tasks.items():
        parsed = convert_legacy_task(key, task, keys)
        queued[key] = Task(key, parsed.func, *parsed.args, _data_producer=True, **parsed.kwargs)
    return queued
