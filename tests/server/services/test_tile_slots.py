"""services/tile_slots.py: a worker holds two tile tasks at a time, the next
in priority order going to the first worker with a free slot, on a real
(in-process) Dask scheduler, as RenderCluster sends a job's tiles."""

import asyncio
import threading
import time
from collections import defaultdict

from distributed import Client, LocalCluster, get_worker

from app.services.cluster import RenderCluster
from app.services.tile_slots import TILES_PER_WORKER, TileSlots, queued_tasks, set_up, slots, worker_saturation

_pools: dict[str, threading.Lock] = defaultdict(threading.Lock)  # each worker's render pool
_held: dict[str, int] = defaultdict(int)
_most_held: dict[str, int] = defaultdict(int)
_counts = threading.Lock()


def hold(seconds: float, index: int) -> tuple[str, int, float]:
    """A tile: held by its worker from the start, rendered when the pool is free."""
    worker = get_worker().address
    with _counts:
        _held[worker] += 1
        _most_held[worker] = max(_most_held[worker], _held[worker])
    with _pools[worker]:
        began = time.monotonic()
        time.sleep(seconds)
    with _counts:
        _held[worker] -= 1
    return worker, index, began


async def _deal(seconds: list[float], plugin: bool) -> list[tuple[str, int, float]]:
    async with LocalCluster(n_workers=2, threads_per_worker=4, processes=False, asynchronous=True,
                            dashboard_address=None) as local, Client(local, asynchronous=True) as client:
        cluster = RenderCluster(client, local)
        if plugin:
            await client.register_plugin(TileSlots())
        tasks = {f"tile-test-{i}": (hold, s, i) for i, s in enumerate(seconds)}
        futures = cluster.submit("job", tasks, {key: -i for i, key in enumerate(tasks)})
        return await client.gather(futures)


def test_workers_hold_two_tiles_and_take_the_next_as_one_ends():
    """12 tiles on 2 workers of 4 threads, the first 0.5 s and the rest 0.02
    s: Dask alone would send all 12 at once, 6 to each worker; dealt two at a
    time, the worker with the long tile holds one more, and the other renders
    the other ten meanwhile."""
    seconds = [0.5] + [0.02] * 11
    _most_held.clear()
    found = asyncio.run(_deal(seconds, plugin=True))
    assert set(_most_held.values()) == {TILES_PER_WORKER}
    by_worker = defaultdict(list)
    for worker, index, _ in found:
        by_worker[worker].append(index)
    assert sorted(map(len, by_worker.values())) == [2, 10], by_worker
    first = {worker: min(indexes) for worker, indexes in by_worker.items()}
    assert sorted(first.values()) == [0, 1], "the first two tiles went to different workers"


def test_without_the_plugin_dask_deals_tiles_by_count():
    """The control: the same job under Dask's default saturation (the tasks
    still queued) gives each worker more than two at a time."""
    _most_held.clear()
    asyncio.run(_deal([0.05] * 12, plugin=False))
    assert max(_most_held.values()) > TILES_PER_WORKER


def test_the_saturation_gives_the_largest_workers_two_tiles():
    assert slots(8, worker_saturation([8])) == slots(2, worker_saturation([2])) == 2
    assert slots(16, worker_saturation([16, 4])) == 2 and slots(4, worker_saturation([16, 4])) == 1
    assert slots(1, worker_saturation([1])) == 2


def test_tile_tasks_are_queued_data_producers_that_keep_their_dependencies():
    def render(*args):
        return args

    tasks = queued_tasks({"preview": (render, b"request", 8), "tile": (render, b"request", 1, "preview")})
    assert all(t.data_producer for t in tasks.values())
    assert tasks["tile"].dependencies == {"preview"} and not tasks["preview"].dependencies
    assert tasks["preview"].args == (b"request", 8)


def test_a_scheduler_without_the_servers_code_still_runs_tiles_and_the_log_says_why(caplog):
    class Client:
        async def register_plugin(self, plugin):
            raise ModuleNotFoundError("No module named 'app'")

    asyncio.run(set_up(Client()))
    assert "cannot import app.services.tile_slots" in caplog.text and "PYTHONPATH" in caplog.text
