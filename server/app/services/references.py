"""References: a done job marked as the one its view (scene, camera and
image size) is measured against, and that view's done jobs as points of
render time against error, for the viewer's speed-against-error plot.

A scene keeps its references' ids (SceneInfo.reference_jobs), one per view:
marking a job replaces the reference its view had.
"""

from __future__ import annotations

from rt import job_pb2

from .errors import Conflict, NotFound
from .scene_store import SceneStore

# The jobs of a view looked at for its plot: the newest this many of all jobs.
PLOT_JOBS = 500


def view_of(job: job_pb2.Job) -> bytes:
    """What a job and its reference share: scene, camera and image size."""
    request = job.request
    size = f"|{request.settings.width}x{request.settings.height}|".encode()
    return request.scene_id.encode() + size + request.camera.SerializeToString(deterministic=True)


def reference_for(scenes: SceneStore, manager, job: job_pb2.Job) -> job_pb2.Job | None:
    """The reference of the job's view, or None."""
    stored = scenes.get(job.request.scene_id)
    if stored is None:
        return None
    for reference_id in reversed(stored.info.reference_jobs):
        reference = manager.get(reference_id)
        if reference is not None and reference.state == job_pb2.DONE and view_of(reference) == view_of(job):
            return reference
    return None


def mark(scenes: SceneStore, manager, scene_id: str, job: job_pb2.Job) -> job_pb2.SceneInfo:
    """Makes a done job of the scene the reference of its view."""
    if job.request.scene_id != scene_id:
        raise Conflict(f"job '{job.id}' renders scene '{job.request.scene_id}', not '{scene_id}'")
    if job.state != job_pb2.DONE:
        raise Conflict(f"job '{job.id}' is {job_pb2.JobState.Name(job.state).lower()}: only a done job can be a reference")
    stored = scenes.get(scene_id)
    if stored is None:
        raise NotFound(f"no scene with id '{scene_id}'")
    view = view_of(job)
    kept = [r for r in stored.info.reference_jobs
            if r != job.id and (other := manager.get(r)) is not None and view_of(other) != view]
    updated = scenes.set_references(scene_id, kept + [job.id])
    if updated is None:
        raise NotFound(f"no scene with id '{scene_id}'")
    return updated.info


def unmark(scenes: SceneStore, scene_id: str, job_id: str) -> job_pb2.SceneInfo:
    stored = scenes.get(scene_id)
    if stored is None:
        raise NotFound(f"no scene with id '{scene_id}'")
    if job_id not in stored.info.reference_jobs:
        raise NotFound(f"job '{job_id}' is no reference of scene '{scene_id}'")
    updated = scenes.set_references(scene_id, [r for r in stored.info.reference_jobs if r != job_id])
    if updated is None:
        raise NotFound(f"no scene with id '{scene_id}'")
    return updated.info


async def accuracy(scenes: SceneStore, manager, job: job_pb2.Job) -> job_pb2.AccuracyPlot:
    """The done jobs of the job's view against its reference, oldest first."""
    reference = reference_for(scenes, manager, job)
    if reference is None:
        raise NotFound(f"job '{job.id}''s view (its scene, camera and size) has no reference: "
                       "mark a done job of it as the reference, or render one")
    view = view_of(job)
    jobs, _ = manager.page(0, PLOT_JOBS)
    plot = job_pb2.AccuracyPlot(reference_id=reference.id)
    for other in reversed(jobs):
        if other.id == reference.id or other.state != job_pb2.DONE or view_of(other) != view:
            continue
        error = await manager.compare(other, reference, None)
        plot.points.add(job_id=other.id, seconds=max(other.finished_at - other.started_at, 0.0), error=error,
                        settings=other.request.settings)
    return plot
