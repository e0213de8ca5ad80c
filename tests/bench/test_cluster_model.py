"""The cluster model (renderer/bench/cluster_model.py) against cases worked out
by hand."""
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "renderer" / "bench"))
import cluster_model as cm  # noqa: E402
from app.services.tile_plan import TileSpec  # noqa: E402  (cluster_model puts server/ on the path)


def costs(**changes) -> cm.ClusterCosts:
    base = dict(width=200, height=100, pixel_rays=1, interactive=False, pixel_s=1e-6, tile_s=0.0,
                encode_s_per_pixel=0.0, preview_factor=2.0, scheduler_s={1: 1e-3}, server_s=4e-3,
                server_s_per_byte=0.0, latency_s=2e-3, threads_per_worker=2)
    return cm.ClusterCosts(**{**base, **changes})


def row_of_tiles(count: int, side: int = 100) -> list[TileSpec]:
    return [TileSpec(1, i * side, 0, side, side, 1, -i) for i in range(count)]


def test_five_equal_tiles_on_two_workers():
    """Each tile: 10,000 pixels x 1 us = 10 ms of one thread, 5 ms on a worker
    of 2 threads. Two slots a worker take four at once, two each; the fifth
    goes to the first worker when its first tile ends (5 ms) and runs after its
    second (10 ms to 15 ms) while the other worker sits idle: makespan 15 ms. The scheduler
    needs 5 x 1 ms, the server 5 x 4 ms = 20 ms, which bounds the job:
    2 ms + 20 ms."""
    m = cm.model(costs(), 2, row_of_tiles(5))
    assert m.makespan_s == pytest.approx(15e-3)
    assert m.scheduler_s == pytest.approx(5e-3)
    assert m.server_s == pytest.approx(20e-3)
    assert m.bound == "server"
    assert m.seconds == pytest.approx(22e-3)


def test_compute_bound_with_a_slot_per_thread_and_tile_constants():
    """One worker of 2 threads, one slot each: 4 tiles of 10 ms + 1 ms constant
    + 10,000 x 0.1 us of encoding = 12 ms of one thread, 6 ms on the worker,
    rendered one after the other: 24 ms, plus the 2 ms latency; the serial
    stages (4 ms, 16 ms) hide behind it."""
    m = cm.model(costs(tile_s=1e-3, encode_s_per_pixel=1e-7), 1, row_of_tiles(4))
    assert m.makespan_s == pytest.approx(24e-3)
    assert m.bound == "compute" and m.seconds == pytest.approx(26e-3)


def test_a_tile_waits_for_its_preview_and_a_preview_pixel_costs_more():
    """A preview at scale 10 of a 100 x 100 tile traces 100 pixels at twice the
    cost: 0.2 ms of a thread, 0.1 ms on the worker; the full tile (5 ms) starts
    after it even on another worker."""
    preview = TileSpec(0, 0, 0, 100, 100, 10, 10)
    full = TileSpec(1, 0, 0, 100, 100, 1, 0, preview)
    m = cm.model(costs(server_s=0.0, scheduler_s={2: 0.0}), 2, [full, preview])
    assert m.makespan_s == pytest.approx(0.1e-3 + 5e-3)
    assert m.tiles == 2 and m.tile_side == 100


def test_the_cost_map_weights_pixels_by_where_they_are():
    """Cells of 50 pixels; the left half costs 3 times the right: a tile over
    the left 100 x 100 costs 1.5 x the mean, over the right 0.5 x."""
    cost_map = np.array([[1.5, 1.5, 0.5, 0.5], [1.5, 1.5, 0.5, 0.5]])
    c = costs(cost_map=cost_map, cell=50)
    assert c.pixels_cost(0, 0, 100, 100) == pytest.approx(1.5 * 1e-2)
    assert c.pixels_cost(100, 0, 100, 100) == pytest.approx(0.5 * 1e-2)
    assert c.pixels_cost(75, 0, 50, 100) == pytest.approx(1e-2 * 0.5 * (25 * 1.5 + 25 * 0.5) / 50)


def test_speedup_and_efficiency_against_one_worker():
    """Server cost off: one worker renders 4 tiles in 20 ms (+2 ms), two in
    10 ms (+2 ms): speed-up 22/12, efficiency half that."""
    c = costs(server_s=0.0)
    rows = cm.scaling(c, counts=(1, 2), plan=lambda n: row_of_tiles(4))
    assert rows[0].speedup == pytest.approx(1.0) and rows[0].efficiency == pytest.approx(1.0)
    assert rows[1].speedup == pytest.approx(22 / 12)
    assert rows[1].efficiency == pytest.approx(22 / 24)


def test_the_scheduler_cost_beyond_the_measured_workers_follows_their_line():
    c = costs(scheduler_s={1: 1e-3, 2: 1.1e-3, 4: 1.3e-3})
    assert c.scheduler_seconds(2) == pytest.approx(1.1e-3)
    assert c.scheduler_seconds(8) == pytest.approx(1.7e-3)
    flat = costs(scheduler_s={1: 1e-3, 16: 0.8e-3})
    assert flat.scheduler_seconds(64) == pytest.approx(0.8e-3), "never below the smallest measured"


def test_the_service_plan_is_used_unless_tiles_are_given():
    """Without tiles the model asks tile_plan for the cluster's threads."""
    from app.services.tile_plan import plan_passes
    c = costs(width=1024, height=1024, threads_per_worker=8)
    planned = [t for p in plan_passes(1024, 1024, 16, False, 1) for t in p]
    assert cm.model(c, 2).tiles == len(planned)


def test_two_tiles_a_worker_dealt_as_slots_free():
    """32 tasks, every fourth 0.4 s and the rest 0.05 s, on 4 workers (as
    renderer/bench/dask_dealing.py sent them to a real scheduler). Two a
    worker: the long ones spread out, and a worker that takes one holds the
    next behind it; 1.25 s, 11, 9, 7 and 5 tasks a worker, as measured. Dask's
    default sends all 32 at once, 8 to each worker, one of which gets every
    long one: 3.2 s."""
    seconds = [0.4 if i % 4 == 0 else 0.05 for i in range(32)]
    dealt = cm.deal(seconds, 4, 2)
    assert max(end for _, _, end in dealt) == pytest.approx(1.25)
    assert sorted((sum(1 for w, _, _ in dealt if w == k) for k in range(4)), reverse=True) == [11, 9, 7, 5]
    assert cm.dealing_slots("dask", 32, 4, 8) == float("inf")
    assert max(end for _, _, end in cm.deal(seconds, 4, cm.dealing_slots("dask", 32, 4, 8))) == pytest.approx(3.2)


def test_dask_queues_a_group_of_more_tasks_than_twice_the_threads_nine_a_worker():
    assert cm.dealing_slots("dask", 65, 4, 8) == 9
    assert cm.dealing_slots("service", 65, 4, 8) == cm.dealing_slots("service", 3, 64, 8) == 2


def test_a_task_waiting_for_another_is_dealt_once_that_one_ends():
    """One worker, two slots: a (1 s), then b waiting for a, then c. b cannot
    be queued before a ends, so c takes the free slot first: a 0-1, c 1-1.5,
    b 1.5-2."""
    dealt = cm.deal([1.0, 0.5, 0.5], 1, 2, after=[None, 0, None])
    assert [(start, end) for _, start, end in dealt] == [(0.0, 1.0), (1.5, 2.0), (1.0, 1.5)]
