"""Render jobs: from a request to Dask tile tasks, and from their results to the
job record, the tile stream and the finished images.

Each tile is one Dask task (tile_tasks.render_tile), which writes its pixels
into the job's layer files, or sends them back for the server to write when
its worker does not see the data folder. The server keeps the job's record, forwards each
tile to the job's viewers as it comes back, then the record it changed, and
persists the record at each change of state, so that a restart can pick the
job up again from the start.
"""

from __future__ import annotations

import asyncio
import logging
import secrets
import shutil
import time
from collections import Counter, OrderedDict
from dataclasses import dataclass, field
from pathlib import Path

from distributed import Future, as_completed
from rt import job_pb2, render_pb2

from ..core.config import Settings
from ..core.proto import normalize
from . import layer_files, references, retention, storage
from .cluster import RenderCluster
from .data_access import DataAccess
from .errors import Invalid, ServiceError
from .fair_share import FairShare
from .job_image import finish_layers
from .job_outputs import JobOutputs, final_image_stream, whole_image_tile  # noqa: F401 (tests import them here)
from .job_removal import JobRemoval
from .job_store import JobStore
from .ownership import scene_for
from .quotas import Quotas
from .scene_store import SceneStore, StoredScene
from .streams import TileStream
from .tile_results import RunProgress, store_tile
from .tile_plan import TileSpec, grid_size, plan_passes, rays_per_pixel
from .tile_tasks import TILE_STARTED_TOPIC, aux_names, render_tile

log = logging.getLogger("rt.jobs")

FINAL_STATES = (job_pb2.DONE, job_pb2.FAILED, job_pb2.CANCELLED)
# Runs of one job its cluster may lose (the scheduler went away) before it fails.
MAX_RUNS = 3
# What a new run starts without: the progress of the run lost.
RUN_FIELDS = ("progress", "tiles_done", "tiles_total", "passes", "started_at", "render_seconds", "rays",
              "mean_samples_per_pixel", "denoise_seconds", "tiles_via_shared_folder", "tiles_via_network", "error")


@dataclass
class RunningJob:
    record: job_pb2.Job
    scene: StoredScene
    stream: TileStream = field(default_factory=TileStream)
    task: asyncio.Task | None = None
    runs: int = 0


class JobManager(JobOutputs, JobRemoval):
    def __init__(self, settings: Settings, cluster: RenderCluster, scenes: SceneStore, store: JobStore,
                 access: DataAccess):
        self._settings = settings
        self._access = access
        self._cluster = cluster
        self._scenes = scenes
        self._store = store
        self.quotas = Quotas(settings, scenes, store)
        self._fair = FairShare(enabled=bool(settings.users))
        self._preparing: Counter[str] = Counter()  # jobs being prepared, by owner: queued by the quota's count
        self._running: dict[str, RunningJob] = {}
        self._unsaved: dict[str, job_pb2.Job] = {}  # ended, not saved for want of room (_save_ended)
        self._finished_streams: OrderedDict[str, TileStream] = OrderedDict()
        self._tiles: dict[str, tuple[RunningJob, TileSpec]] = {}  # Dask key -> its job and tile
        self._output_lock = asyncio.Lock()
        self._retention: asyncio.Task | None = None
        cluster.subscribe_topic(TILE_STARTED_TOPIC, self._tile_started)

    async def _tile_started(self, event: tuple[float, str]) -> None:
        found = self._tiles.get(event[1])
        if found is not None:  # not when the tile's result came first
            running, spec = found
            self._fair.started(spec, running.record.request.interactive)
            await running.stream.publish(job_pb2.TileStreamMessage(started=spec.region()).SerializeToString())

    # --- requests -----------------------------------------------------------

    def scene(self, scene_id: str, owner: str) -> StoredScene:
        """The stored scene a request of `owner` names (theirs or shared); NotFound naming the field."""
        return scene_for(self._scenes, scene_id, owner, "scene_id: ")

    def prepare(self, body: bytes, owner: str) -> tuple[job_pb2.Job, StoredScene]:
        """A queued job record of `owner` for a JSON rt.JobRequest, completed
        and checked for its scene (core.proto.normalize) so that the renderer's
        own checks answer now rather than inside a worker, and saved; blocking
        (run it off the event loop). Raises NotFound, Invalid or OverQuota
        naming the problem."""
        try:
            request = normalize(job_pb2.JobRequest, body, lambda r: self.scene(r.scene_id, owner).load())
        except ValueError as e:
            raise Invalid(str(e)) from None
        pixels = request.settings.width * request.settings.height
        if pixels > self._settings.max_job_pixels:
            raise Invalid(f"settings: {request.settings.width}x{request.settings.height} is {pixels} pixels, "
                          f"above this server's limit of {self._settings.max_job_pixels}")
        self.quotas.check_job(owner, request)
        job = job_pb2.Job(id=secrets.token_hex(8), state=job_pb2.QUEUED, created_at=time.time(), request=request,
                          owner=owner)
        self._store.save(job)
        return job, self.scene(request.scene_id, owner)

    def queued(self, owner: str) -> int:
        """The owner's jobs queued or running."""
        return sum(1 for r in self._running.values() if r.record.owner == owner)

    async def user_info(self, owner: str) -> job_pb2.UserInfo:
        """The owner's name and use of the server against its quotas (GET /api/me)."""
        return await asyncio.to_thread(self.quotas.user_info, owner, self.queued(owner))

    async def submit(self, body: bytes, owner: str = "") -> job_pb2.Job:
        """Queues a JSON rt.JobRequest as a new job of `owner` and starts it.
        Raises NotFound (no such scene), Invalid, OverQuota or TooManyJobs
        naming the problem."""
        # Counted on the event loop, with the jobs still being prepared, so
        # that a burst of posts cannot slip past the limit together.
        if self.quotas.quota_queued_jobs:  # counting walks the running jobs
            self.quotas.check_queued(self.queued(owner) + self._preparing[owner])
        self._preparing[owner] += 1
        try:
            job, stored = await asyncio.to_thread(self.prepare, body, owner)
        finally:
            self._preparing[owner] -= 1
            if not self._preparing[owner]:
                del self._preparing[owner]
        self.start(job, stored)
        return job

    def start(self, job: job_pb2.Job, stored: StoredScene) -> None:
        running = RunningJob(job, stored)
        self._running[job.id] = running
        running.task = asyncio.create_task(self._run_when_connected(running), name=f"job-{job.id}")

    def get(self, job_id: str) -> job_pb2.Job | None:
        running = self._running.get(job_id)
        return running.record if running else self._unsaved.get(job_id) or self._store.get(job_id)

    def page(self, offset: int, limit: int, owner: str) -> tuple[list[job_pb2.Job], int]:
        """The owner's jobs, newest first, and how many they have."""
        jobs, total = self._store.page(offset, limit, owner)
        return [self._running[j.id].record if j.id in self._running else self._unsaved.get(j.id, j)
                for j in jobs], total

    async def cancel(self, job_id: str, reason: str = "cancelled by request") -> job_pb2.Job | None:
        running = self._running.get(job_id)
        if running is None:
            return self._store.get(job_id)
        running.record.error = reason
        if running.task is not None:
            running.task.cancel()
            await asyncio.gather(running.task, return_exceptions=True)
        return running.record

    def stream(self, job_id: str) -> TileStream | None:
        running = self._running.get(job_id)
        if running is not None:
            return running.stream
        return self._finished_streams.get(job_id)

    def folder(self, job_id: str) -> Path:
        return self._settings.jobs_dir / job_id

    # --- lifecycle ----------------------------------------------------------

    async def resume(self) -> None:
        """Jobs that were queued or running when the server stopped start again;
        those whose scene is gone fail with the reason."""
        for job in self._store.active():
            stored = self._scenes.get(job.request.scene_id)
            if stored is None:
                self._end(job, job_pb2.FAILED, "the server restarted and the job's scene is gone")
                continue
            log.info("resuming job %s", job.id)
            fresh = job_pb2.Job(id=job.id, state=job_pb2.QUEUED, created_at=job.created_at, pinned=job.pinned,
                                owner=job.owner)
            fresh.request.CopyFrom(job.request)
            self._store.save(fresh)
            self.start(fresh, stored)
        self._retention = asyncio.create_task(retention.keep_applying(self.apply_retention), name="retention")

    async def shutdown(self) -> None:
        """Leaves running jobs as they are in the store, to be resumed."""
        if self._retention is not None:
            self._retention.cancel()
        for running in list(self._running.values()):
            if running.task is not None:
                running.task.cancel("shutdown")
        await asyncio.gather(*(r.task for r in self._running.values() if r.task), return_exceptions=True)

    def _end(self, job: job_pb2.Job, state: int, error: str = "") -> None:
        job.state = state
        if error and not job.error:
            job.error = error
        job.finished_at = time.time()
        self._save_ended(job)

    def _save_ended(self, job: job_pb2.Job) -> None:
        """Saves a job that has ended. A full disk must not leave it queued or
        running in the store for everyone to wait on: its record is answered
        from memory meanwhile, and saved at the next job's end or retention
        pass with room (a restart before that runs it again)."""
        try:
            self._store.save(job)
            self._unsaved.pop(job.id, None)
        except Exception as e:
            if not storage.is_full(e):
                raise
            log.error("job %s ended %s, but the data folder is full to record it: %s", job.id,
                      job_pb2.JobState.Name(job.state), e)
            self._unsaved[job.id] = job

    def _mark_reference(self, job: job_pb2.Job) -> None:
        """A done "Render reference" job becomes its view's reference, unless its scene went meanwhile."""
        try:
            references.mark(self._scenes, self, job.request.scene_id, job)
        except ServiceError as e:
            log.warning("job %s: not marked as a reference: %s", job.id, e)

    # --- running ------------------------------------------------------------

    async def _run(self, running: RunningJob) -> None:
        job, request = running.record, running.record.request
        running.runs += 1
        passes = plan_passes(request.settings.width, request.settings.height, self._cluster.total_threads(),
                             request.interactive, rays_per_pixel(request.settings, running.scene.info.lights))
        specs = self._fair.order(job.id, request.interactive, [spec for tiles in passes for spec in tiles],
                                 (j for j, r in self._running.items() if r.record.owner == job.owner), self._running)
        denoise = request.settings.denoise != render_pb2.NO_DENOISER
        last_pass = denoise or request.settings.bloom_strength > 0
        job.passes = len(passes) + last_pass
        job.tiles_total = len(specs) + last_pass
        folder = self.folder(job.id)
        run_id = f"{job.id}-{secrets.token_hex(3)}"  # a resumed job is a new run, with keys of its own
        futures: dict[str, TileSpec] = {}
        submitted: set[Future] = set()  # not handled yet: a handled tile's result may leave the workers' memory
        lost = shutdown = False
        try:
            layers_dir = await asyncio.to_thread(layer_files.create, folder, request.settings.width,
                                                 request.settings.height, grid_size(passes[-1]), aux_names(request),
                                                 noisy=denoise)
            futures, submitted = self._submit(running, run_id, layers_dir, specs)
            progress = RunProgress(job, specs)
            async for future in as_completed(list(submitted)):
                await self._take(running, progress, layers_dir, futures[future.key], await future)
                self._tiles.pop(future.key, None)
                submitted.discard(future)
            if last_pass:
                await self._last_pass(running, folder, len(passes))
            layer_files.complete(folder)
            self._end(job, job_pb2.DONE)
            if request.reference:
                self._mark_reference(job)
        except asyncio.CancelledError as e:
            await self._cluster.stop(run_id, list(submitted))
            shutdown = "shutdown" in e.args
            if not shutdown:
                shutil.rmtree(folder, ignore_errors=True)
                self._end(job, job_pb2.CANCELLED, "cancelled by request")
        except Exception as e:  # a tile failed (or its files could not be made): the job fails with the reason
            await self._cluster.stop(run_id, list(submitted))
            shutil.rmtree(folder, ignore_errors=True)
            lost = self._failed(running, e)
        finally:
            for key in futures:
                self._tiles.pop(key, None)
            if lost:
                await self._requeue(running)
            elif not shutdown:
                await self._finish(running)
            else:
                self._running.pop(job.id, None)

    def _submit(self, running: RunningJob, run_id: str, layers_dir: Path,
                specs: list[TileSpec]) -> tuple[dict[str, TileSpec], set[Future]]:
        """The run's tiles as one Dask graph: each tile's key and spec, and their futures."""
        job, scene = running.record, running.scene
        args = (self._access, scene.sha256, str(scene.scene_file), job.request.SerializeToString(), job.id, run_id,
                str(layers_dir))
        futures: dict[str, TileSpec] = {}
        keys: dict[TileSpec, str] = {}
        tasks, priorities = {}, {}
        for spec in specs:  # previews first: a tile's task names its preview's key, whose result it takes
            key = keys[spec] = f"tile-{run_id}-{spec.pass_index}-{spec.x}-{spec.y}"
            tasks[key] = (render_tile, *args, spec) + ((keys[spec.preview],) if spec.preview else ())
            priorities[key] = spec.priority
            futures[key] = spec
            self._tiles[key] = (running, spec)
        return futures, set(self._cluster.submit(f"job-{run_id}", tasks, priorities))

    async def _take(self, running: RunningJob, progress: RunProgress, layers_dir: Path, spec: TileSpec,
                    result: job_pb2.TileResult) -> None:
        """A tile's result: its layers stored when its worker sent them, its
        pixels to the job's viewers, its counts into the record."""
        job = running.record
        if spec.scale == 1:
            await store_tile(job, layers_dir, spec, result)
        if job.state == job_pb2.QUEUED:
            job.state = job_pb2.RUNNING
            job.started_at = result.started
            # The store keeps states, not progress: a restart runs a job again from the start.
            self._store.save(job)
        await running.stream.publish(result.message)
        progress.add(spec, result)
        await running.stream.update(job)  # its new state (the first tile's) and progress

    def _failed(self, running: RunningJob, error: Exception) -> bool:
        """Ends a run that failed, with the reason; True when its cluster lost
        it instead (the scheduler went away) and it should run again."""
        job = running.record
        lost = self._cluster.lost(error)
        log.log(logging.WARNING if lost else logging.ERROR, "job %s failed", job.id, exc_info=not lost)
        if lost and running.runs < MAX_RUNS:
            return True
        if lost:
            self._end(job, job_pb2.FAILED, f"its cluster lost its Dask scheduler {running.runs} times: {error}")
        elif storage.is_full(error):
            self._end(job, job_pb2.FAILED, storage.full_message(self._settings.data_dir, error))
        else:
            self._end(job, job_pb2.FAILED, f"{type(error).__name__}: {error}")
        return False

    async def _requeue(self, running: RunningJob) -> None:
        """A run its cluster lost starts again from scratch, as a restart of
        the server would resume it, once a scheduler is there to take it."""
        job = running.record
        for name in RUN_FIELDS:
            job.ClearField(name)
        job.state = job_pb2.QUEUED
        self._store.save(job)
        await running.stream.update(job)
        log.warning("job %s: its cluster lost the run; run %d starts once a scheduler is back", job.id, running.runs + 1)
        running.task = asyncio.create_task(self._run_when_connected(running), name=f"job-{job.id}")

    async def _run_when_connected(self, running: RunningJob) -> None:
        try:
            await self._cluster.wait_connected()
        except asyncio.CancelledError as e:
            if "shutdown" in e.args:  # left queued in the store, resumed at the next start
                self._running.pop(running.record.id, None)
            else:
                self._end(running.record, job_pb2.CANCELLED, "cancelled by request")
                await self._finish(running)
            raise
        await self._run(running)

    async def _finish(self, running: RunningJob) -> None:
        """A job that has ended: its stream ends and is kept for late viewers; the retention policy applies."""
        job = running.record
        self._running.pop(job.id, None)
        await running.stream.finish(job)
        self._finished_streams[job.id] = running.stream
        while len(self._finished_streams) > self._settings.kept_streams:
            self._finished_streams.popitem(last=False)
        try:
            await self.apply_retention()
        except Exception:
            log.exception("retention failed after job %s", job.id)


    @staticmethod
    async def _last_pass(running: RunningJob, folder: Path, pass_index: int) -> None:
        """The denoiser and bloom read and spread light across tile borders, so
        they run on the whole image once every tile is in; viewers receive the
        result as one last tile."""
        job = running.record
        settings = job.request.settings
        rgba, job.denoise_seconds = await asyncio.to_thread(finish_layers, folder, settings)
        await running.stream.publish(whole_image_tile(job.id, pass_index, settings.width, settings.height, rgba))
        job.tiles_done += 1
        await running.stream.update(job)

