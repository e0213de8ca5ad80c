"""The Dask cluster the tiles run on.

Without RT_SCHEDULER the server embeds a local cluster whose worker threads
live in the server process: no serialization on the way back and one scene
cache shared with the API (rendering releases the GIL, so the threads render in
parallel). With RT_SCHEDULER=tcp://host:8786 it joins a real cluster, whose
workers import app.services.tile_tasks (and reach the job's data as
services/data_access.py says). A joined scheduler may restart: the server keeps
reconnecting, and sets up every scheduler it meets anew (_keep_connected).
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Callable

import dask
import rtcore
from dask.highlevelgraph import HighLevelGraph, MaterializedLayer
from distributed import Client, Future, LocalCluster, WorkerPlugin
from distributed.client import FutureCancelledError
from distributed.comm.core import CommClosedError
from rt import job_pb2

from ..core.allocator import keep_freed_memory
from ..core.config import Settings
from . import tile_slots
from .tile_slots import queued_tasks
from .tile_tasks import stop_run

log = logging.getLogger("rt.cluster")

STOP_TIMEOUT_SECONDS = 5
# How often the server checks its scheduler connection, and how long it tries
# to connect at each attempt.
RECONNECT_INTERVAL_SECONDS = 1.0
CONNECT_TIMEOUT = "5s"
# Why Dask cancels a client's futures when the scheduler goes away.
SCHEDULER_LOST = "scheduler-connection-lost"

# The embedded cluster shares the server's event loop and cores with the API,
# so the upkeep Dask does by default for a cluster of its own is turned down or
# off: it cost 3.6% of a core with nothing to render (0.8% without). One worker
# has nobody to steal tasks from; a worker inside the server must not pause,
# spill or be terminated for the server's memory (the scene cache evicts scenes
# instead); the sampling profiler and the system monitor feed a dashboard the
# embedded cluster does not have; the event-loop tick only warns of stalls.
EMBEDDED_DASK_CONFIG = {
    "distributed.scheduler.work-stealing": False,
    "distributed.worker.profile.enabled": False,
    "distributed.worker.memory.target": False,
    "distributed.worker.memory.spill": False,
    "distributed.worker.memory.pause": False,
    "distributed.worker.memory.terminate": False,
    "distributed.admin.system-monitor.interval": "5s",
    "distributed.admin.tick.interval": "1s",
}


class RenderWorkerSetup(WorkerPlugin):
    """Runs in every worker as it joins, the embedded one included: the
    allocator keeps freed memory (core/allocator.py), and tiles render on a
    pool of as many threads as the worker has (rtcore.set_render_threads), so
    the worker's cores stay busy while its event loop hands out the next tile."""

    name = "rt-render-setup"

    def setup(self, worker) -> None:
        keep_freed_memory()
        rtcore.set_render_threads(worker.state.nthreads)


class RenderCluster:
    def __init__(self, client: Client, local: LocalCluster | None, address: str = ""):
        self.client = client
        self._local = local
        self._address = address  # of the scheduler joined, for a cluster not embedded
        self._topics: dict[str, Callable] = {}
        self._scheduler_id = ""
        self._watch: asyncio.Task | None = None

    @classmethod
    async def start(cls, settings: Settings) -> "RenderCluster":
        if settings.scheduler:
            cluster = cls(await Client(settings.scheduler, asynchronous=True, timeout="20s"), None, settings.scheduler)
            await cluster._set_up()
            cluster._watch = asyncio.create_task(cluster._keep_connected(), name="scheduler-connection")
            log.info("joined the Dask scheduler at %s", settings.scheduler)
            return cluster
        # Read as the scheduler and worker start, so the rest of the process keeps Dask's defaults.
        with dask.config.set(EMBEDDED_DASK_CONFIG):
            local = await LocalCluster(n_workers=1, threads_per_worker=settings.embedded_threads, processes=False,
                                       asynchronous=True, dashboard_address=None,
                                       scheduler_kwargs={"dashboard": False})
        client = await Client(local, asynchronous=True)
        # The client's view of the cluster, which sizes tiles (total_threads),
        # must include the worker before the first job.
        await client.wait_for_workers(1)
        cluster = cls(client, local)
        await cluster._set_up()
        log.info("embedded Dask cluster with %d threads", settings.embedded_threads)
        return cluster

    def subscribe_topic(self, topic: str, handler: Callable) -> None:
        """Events workers log on `topic` go to `handler`, from every scheduler joined."""
        self._topics[topic] = handler
        self.client.subscribe_topic(topic, handler)

    async def _set_up(self) -> None:
        """What a scheduler must know of this server: the worker plugin (which
        it hands every worker that joins), how many tiles a worker holds
        (tile_slots.py) and the topics it forwards here."""
        await self.client.register_plugin(RenderWorkerSetup())
        await tile_slots.set_up(self.client)
        for topic, handler in self._topics.items():
            self.client.subscribe_topic(topic, handler)
        self._scheduler_id = self.client.scheduler_info().get("id", "")

    async def _keep_connected(self) -> None:
        """Dask's client reconnects to a scheduler that went away for its
        timeout, then closes for good; and a restarted scheduler knows neither
        the plugin nor the topics. So a closed client is replaced, and a
        scheduler met for the first time is set up."""
        while True:
            await asyncio.sleep(RECONNECT_INTERVAL_SECONDS)
            try:
                if self.client.status in ("closing", "closed", "failed"):
                    old, self.client = self.client, await Client(self._address, asynchronous=True,
                                                                timeout=CONNECT_TIMEOUT)
                    await old.close()
                if self.client.status == "running" and self.client.scheduler_info().get("id") != self._scheduler_id:
                    await self._set_up()
                    log.info("set up the Dask scheduler at %s (%s)", self._address, self._scheduler_id)
            except (OSError, asyncio.TimeoutError) as e:
                log.warning("no Dask scheduler at %s yet: %r", self._address, e)
            except Exception:  # whatever a scheduler answers, the server keeps trying
                log.exception("setting up the Dask scheduler at %s failed; trying again", self._address)

    @property
    def connected(self) -> bool:
        """Whether the scheduler can take work now (a closed or reconnecting client cannot)."""
        return self.client.status == "running" and bool(self._scheduler_id)

    def lost(self, error: BaseException) -> bool:
        """Whether a run failed because its cluster went away (its futures
        cancelled by Dask for a lost scheduler, a result's worker gone with
        it, or no scheduler to send them to), rather than because of the job
        itself."""
        if isinstance(error, FutureCancelledError):
            return error.reason in (SCHEDULER_LOST, "scheduler-restart")
        # A result being fetched from a worker that ended with its scheduler,
        # before the client saw the scheduler go.
        return isinstance(error, CommClosedError) or not self.connected

    async def wait_connected(self) -> None:
        while not self.connected:
            await asyncio.sleep(RECONNECT_INTERVAL_SECONDS / 4)

    def submit(self, name: str, tasks: dict[str, tuple[Callable, ...]], priorities: dict[str, int]) -> list[Future]:
        """Futures of `tasks` ({key: (function, *arguments)}), sent to the
        scheduler as one graph: one message and one update for a job's tiles
        instead of one each (a third of Dask's cost per tile). Higher priority
        runs first; between equal priorities, the graph sent earlier. The
        scheduler queues them and hands each worker two at a time (tile_slots.py)."""
        layer = MaterializedLayer(queued_tasks(tasks), annotations={"priority": priorities.__getitem__})
        graph = HighLevelGraph({name: layer}, {name: set()})
        # fifo_timeout 0: every graph is a generation of its own, older first.
        return self.client.get(graph, list(tasks), sync=False, fifo_timeout="0ms")

    async def stop(self, run_id: str, futures: list[Future]) -> None:
        """Stops a run's tiles: cancelling their futures drops those not yet
        started, and tile_tasks.stop_run on every worker makes those running
        stop at their next pixel (and any still to come return at once)."""
        await self.client.cancel(futures)
        try:
            await asyncio.wait_for(self.client.run(stop_run, run_id, on_error="ignore"), STOP_TIMEOUT_SECONDS)
        except (asyncio.TimeoutError, OSError) as e:
            log.warning("could not reach every worker to stop %s: %r", run_id, e)

    @property
    def embedded(self) -> bool:
        return self._local is not None

    # The scheduler's own totals, which the client refreshes every few seconds.
    # On the event loop scheduler_info() answers that cache without I/O, and
    # its per-worker part is empty: summing the workers' threads there gave 1
    # and planned every job's tiles for one thread. (From another thread it
    # asks the scheduler, through the busy event loop.)
    def total_threads(self) -> int:
        return self.client.scheduler_info().get("total_threads", 0) or 1

    def worker_count(self) -> int:
        return self.client.scheduler_info().get("n_workers", 0)

    def health(self) -> job_pb2.Health:
        """Whether the cluster can take work: "degraded" without a worker."""
        workers = self.worker_count()
        return job_pb2.Health(status="ok" if workers else "degraded",
                              cluster="embedded" if self.embedded else self._address,
                              workers=workers, threads=self.total_threads() if workers else 0)

    async def close(self) -> None:
        if self._watch is not None:
            self._watch.cancel()
        await self.client.close()
        if self._local is not None:
            await self._local.close()
