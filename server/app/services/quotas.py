"""Per-user quotas (RT_QUOTA_MB, RT_QUOTA_QUEUED_JOBS) and what a user uses.

Stored bytes are what the user's scene folders and job folders take on disk
(as /api/health counts the data folder), measured when asked: an upload or a
job is refused (OverQuota, 413) when it would take the user past the quota,
naming the limit and their use. An upload streams no further than what is
left of the quota; a job's output is estimated from its size and layers before
it is queued (its layer files, then image.png; image.exr, made on request,
comes on top). Queued jobs are those queued or running: past the limit a job
is refused (TooManyJobs, 429) with a time to try again after.

Two uploads at the same moment may both fit alone and not together: the
quota bounds a user's use to about one upload past it, not to the byte.
"""

from __future__ import annotations

from pathlib import Path
from typing import BinaryIO

from rt import job_pb2, render_pb2

from ..core.config import Settings
from ..core.users import LOCAL_NAME
from .errors import OverQuota, TooManyJobs
from .job_store import JobStore
from .layer_files import AUX_CHANNELS
from .scene_store import SceneStore, StoredScene
from .storage import folder_bytes
from .uploads import UploadTooLarge

# What a client is told to wait before posting again once at the queued-jobs
# limit: a small job's time; the next refusal says so again.
RETRY_AFTER_SECONDS = 5


def megabytes(size: int) -> str:
    return f"{size / (1 << 20):.1f} MB"


def output_bytes(request: job_pb2.JobRequest) -> int:
    """About what a job leaves on disk: its linear layers (float32: colour,
    each output asked for, the colour before denoising) and its image.png."""
    channels = 3 + sum(AUX_CHANNELS[job_pb2.AuxOutput.Name(o).lower()] for o in request.outputs)
    if request.settings.denoise != render_pb2.NO_DENOISER:
        channels += 3
    pixels = request.settings.width * request.settings.height
    return pixels * (4 * channels + 4)


class Quotas:
    def __init__(self, settings: Settings, scenes: SceneStore, jobs: JobStore):
        self._settings = settings
        self._scenes = scenes
        self._jobs = jobs

    @property
    def quota_bytes(self) -> int:
        return self._settings.quota_bytes

    @property
    def quota_queued_jobs(self) -> int:
        return self._settings.quota_queued_jobs

    def stored_bytes(self, owner: str) -> int:
        """The owner's scene and job folders on disk (blocking: run it off the event loop)."""
        scenes = sum(folder_bytes(self._settings.scenes_dir / s.info.id)
                     for s in self._scenes.all() if s.info.owner == owner)
        return scenes + sum(folder_bytes(self._settings.jobs_dir / j) for j in self._jobs.ids(owner))

    def user_info(self, owner: str, queued: int) -> job_pb2.UserInfo:
        """GET /api/me: the owner's name and use against the quotas (blocking)."""
        s = self._settings
        return job_pb2.UserInfo(
            name=owner or LOCAL_NAME, stored_bytes=self.stored_bytes(owner), quota_bytes=s.quota_bytes,
            queued_jobs=queued, quota_queued_jobs=s.quota_queued_jobs,
            scenes=sum(1 for x in self._scenes.all() if x.info.owner == owner), jobs=len(self._jobs.ids(owner)),
            keep_jobs=s.keep_jobs, keep_days=s.keep_days)

    def _refusal(self, stored: int, adding: str) -> OverQuota:
        return OverQuota(f"{adding} would take you past your quota of {megabytes(self.quota_bytes)} stored "
                         f"(RT_QUOTA_MB): you store {megabytes(stored)}; delete scenes or jobs to make room")

    def check_job(self, owner: str, request: job_pb2.JobRequest) -> None:
        """OverQuota when the job's output would not fit in the owner's quota."""
        if not self.quota_bytes:
            return
        stored, adding = self.stored_bytes(owner), output_bytes(request)
        if stored + adding > self.quota_bytes:
            raise self._refusal(stored, f"this job's output (about {megabytes(adding)})")

    def check_queued(self, queued: int) -> None:
        """TooManyJobs when a user with `queued` jobs queued or running may not queue one more."""
        if self.quota_queued_jobs and queued >= self.quota_queued_jobs:
            raise TooManyJobs(f"you have {queued} jobs queued or running, this server's limit per user "
                              f"(RT_QUOTA_QUEUED_JOBS={self.quota_queued_jobs}): post again once one has ended, "
                              "or cancel one", RETRY_AFTER_SECONDS)

    def upload(self, owner: str, filename: str, stream: BinaryIO) -> StoredScene:
        """An upload stored for `owner` within their quota (blocking). The
        upload streams no further than the quota leaves; past it, or past it
        once unpacked, OverQuota and nothing is kept."""
        if not self.quota_bytes:
            return self._scenes.create(filename, stream, owner=owner)
        stored = self.stored_bytes(owner)
        left = self.quota_bytes - stored
        if left <= 0:
            raise self._refusal(stored, "another upload")
        try:
            scene = self._scenes.create(filename, stream, owner=owner, max_bytes=left)
        except UploadTooLarge as e:
            if f"limit of {left}" in str(e):  # the quota's limit, not the server's
                raise self._refusal(stored, f"{Path(filename).name or 'this upload'} (over {megabytes(left)})") \
                    from None
            raise
        size = folder_bytes(self._settings.scenes_dir / scene.info.id)
        if size > left:
            self._scenes.delete(scene.info.id)
            raise self._refusal(stored, f"{scene.info.name} ({megabytes(size)} on disk)")
        return scene
