"""The embedded Dask cluster shares the server's event loop and cores, so its
upkeep is turned down (cluster.EMBEDDED_DASK_CONFIG): no work stealing, no
sampling profiler, no memory monitor that could pause the server's own worker."""


def test_the_embedded_cluster_does_no_upkeep_it_does_not_need(client):
    local = client.app.state.cluster._local
    assert "stealing" not in local.scheduler.extensions
    (worker,) = local.workers.values()
    assert "profile" not in worker.periodic_callbacks
    assert "memory_monitor" not in worker.periodic_callbacks
    assert worker.memory_manager.memory_pause_fraction is False


def test_tiles_are_planned_for_the_embedded_workers_threads_from_the_start(client):
    assert client.app.state.cluster.total_threads() == client.app.state.settings.embedded_threads == 2


def test_jobs_plan_for_every_thread_of_the_cluster_on_the_event_loop(client):
    """JobManager._run asks on the event loop, where Dask's client answers its
    cache, whose per-worker part is empty (summing it gave 1 thread)."""
    import time

    cluster = client.app.state.cluster
    time.sleep(2.5)  # past a refresh of the client's cache
    assert client.portal.call(cluster.total_threads) == 2
    assert client.portal.call(cluster.worker_count) == 1
    health = client.get("/api/health").json()
    assert (health["workers"], health["threads"]) == (1, 2)


def test_tiles_render_on_as_many_threads_as_the_worker_has(client):
    """RenderWorkerSetup sizes rtcore's render pool to the worker, and keeps freed memory for reuse."""
    import numpy as np
    import rtcore

    (worker,) = client.app.state.cluster._local.workers.values()
    assert rtcore.render_threads() == worker.state.nthreads
    assert not np._core.multiarray._get_madvise_hugepage()


def test_the_rest_of_the_process_keeps_dask_defaults(client):
    import dask

    assert dask.config.get("distributed.scheduler.work-stealing") is True
    assert dask.config.get("distributed.worker.profile.enabled") is True


def test_the_objects_made_at_start_up_are_left_out_of_garbage_collection(client):
    """core/collector.py: full collections walked every start-up object, and
    held the event loop for 70-90 ms under load."""
    import gc

    from app.core.collector import THRESHOLDS

    assert gc.get_freeze_count() > 10_000
    assert gc.get_threshold() == THRESHOLDS


def test_the_embedded_worker_holds_two_tiles_at_a_time(client):
    """tile_slots.TileSlots, registered on every scheduler the server sets up,
    the embedded one's too."""
    from distributed.scheduler import _task_slots_available

    from app.services.tile_slots import TILES_PER_WORKER

    local = client.app.state.cluster._local
    (worker,) = local.scheduler.workers.values()
    assert "rt-tile-slots" in local.scheduler.plugins
    assert _task_slots_available(worker, local.scheduler.WORKER_SATURATION) == TILES_PER_WORKER
