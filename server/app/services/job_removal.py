"""Jobs going away: deleted by their owner, with their files; let go by the
retention policy; cancelled with their scene. Pins keep a job whatever the
policy says. A part of JobManager (services/jobs.py), which keeps the running.
"""

from __future__ import annotations

import asyncio
import logging
import shutil
import time

from rt import job_pb2

from . import references, retention, storage
from .errors import Conflict

log = logging.getLogger("rt.jobs")


class JobRemoval:
    """JobManager's removing side, a base class of it: JobManager provides
    cancel(), folder(), _save_ended(), _running, _unsaved, _store, _scenes,
    _settings, _finished_streams and _output_lock."""

    async def delete(self, job: job_pb2.Job) -> job_pb2.Job | None:
        """DELETE /api/jobs/{id}: a queued or running job is cancelled, and its
        record answered (as ever); a job that has ended goes, with its files
        (None). A view's reference is refused until it is unmarked."""
        if job.id in self._running:
            return await self.cancel(job.id)
        if job.id in references.reference_ids(self._scenes):
            raise Conflict(f"job '{job.id}' is its view's reference: unmark it first "
                           f"(DELETE /api/scenes/{job.request.scene_id}/references/{job.id})")
        await self._remove(job.id)
        return None

    async def _remove(self, job_id: str) -> None:
        """A job that has ended, gone: its record, its stream, its files."""
        self._store.delete(job_id)
        self._finished_streams.pop(job_id, None)
        async with self._output_lock:  # not while one of its images is being made
            await asyncio.to_thread(shutil.rmtree, self.folder(job_id), True)
        storage.forget_size(self._settings.data_dir)

    def pin(self, job: job_pb2.Job, pinned: bool) -> job_pb2.Job:
        """Keeps a job (as get() answers it: a running one's live record) whatever
        the retention policy says, or lets it go again."""
        job.pinned = pinned
        self._store.save(job)
        return job

    async def apply_retention(self) -> None:
        """Removes the jobs the retention policy lets go (services/retention.py),
        after saving the records a full disk kept in memory."""
        for job in list(self._unsaved.values()):
            self._save_ended(job)
        if not retention.applies(self._settings):  # spares each job's end a thread's round trip
            return
        gone = await asyncio.to_thread(retention.expired, self._settings, self._store, self._scenes, time.time())
        for job_id in gone:
            if job_id not in self._running:  # none is, unless one was resumed meanwhile
                await self._remove(job_id)
        if gone:
            log.info("retention: removed %d jobs, %s", len(gone), retention.policy(self._settings))

    async def delete_scene(self, scene_id: str) -> None:
        """Cancels the scene's running jobs, then deletes the scene (its jobs'
        records stay). Only its owner deletes a scene: the jobs are theirs."""
        for job_id in [j for j, r in self._running.items() if r.record.request.scene_id == scene_id]:
            await self.cancel(job_id, "the scene was deleted")
        self._scenes.delete(scene_id)
        storage.forget_size(self._settings.data_dir)
