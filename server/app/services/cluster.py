"""The Dask cluster the tiles run on.

Without RT_SCHEDULER the server embeds a local cluster whose worker threads
live in the server process: no serialization on the way back and one scene
cache shared with the API (rendering releases the GIL, so the threads render in
parallel). With RT_SCHEDULER=tcp://host:8786 it joins a real cluster, whose
workers import app.services.tile_tasks and read scenes from the shared data
folder.
"""

from __future__ import annotations

import logging

import dask
from distributed import Client, LocalCluster

from ..core.config import Settings

log = logging.getLogger("rt.cluster")

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


class RenderCluster:
    def __init__(self, client: Client, local: LocalCluster | None):
        self.client = client
        self._local = local

    @classmethod
    async def start(cls, settings: Settings) -> "RenderCluster":
        if settings.scheduler:
            client = await Client(settings.scheduler, asynchronous=True, timeout="20s")
            log.info("joined the Dask scheduler at %s", settings.scheduler)
            return cls(client, None)
        # Read as the scheduler and worker start, so the rest of the process keeps Dask's defaults.
        with dask.config.set(EMBEDDED_DASK_CONFIG):
            local = await LocalCluster(n_workers=1, threads_per_worker=settings.embedded_threads, processes=False,
                                       asynchronous=True, dashboard_address=None,
                                       scheduler_kwargs={"dashboard": False})
        client = await Client(local, asynchronous=True)
        log.info("embedded Dask cluster with %d threads", settings.embedded_threads)
        return cls(client, local)

    @property
    def embedded(self) -> bool:
        return self._local is not None

    def total_threads(self) -> int:
        workers = self.client.scheduler_info().get("workers", {})
        return sum(w.get("nthreads", 1) for w in workers.values()) or 1

    def worker_count(self) -> int:
        return len(self.client.scheduler_info().get("workers", {}))

    async def close(self) -> None:
        await self.client.close()
        if self._local is not None:
            await self._local.close()
