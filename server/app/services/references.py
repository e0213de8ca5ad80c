"""References: a done job marked as the one its view (scene, camera and
image size) is measured against, and that view's done jobs as points of
render time against error, for the viewer's speed-against-error plot.

A scene keeps its references' ids (SceneInfo.reference_jobs), one per view
and user (a shared sample scene holds each user's own): marking a job
replaces the reference its owner had for its view, and a user's jobs are
measured against their own reference only.
"""

from __future__ import annotations

from google.protobuf.message import Message
from rt import job_pb2

from .errors import Conflict, NotFound
from .scene_store import SceneStore

# The jobs looked at for a view's plot: the newest this many of all jobs.
PLOT_JOBS = 500
# Points of a plot at most, the view's newest jobs: measuring a job the first
# time makes its HDR-FLIP map, about a second of a core for 640x480, so a
# long history must not hold one request for minutes.
PLOT_POINTS = 32


# Cameras this close are one view: the viewer's camera, sent back after
# three.js held it, differs from the job's it came from in the last bits.
CAMERA_TOLERANCE = 1e-4


def _close(a: Message, b: Message) -> bool:
    """Two messages equal field by field, floats within CAMERA_TOLERANCE (relative above 1)."""
    fields = {f.name for f, _ in a.ListFields()} | {f.name for f, _ in b.ListFields()}
    for name in fields:
        field = a.DESCRIPTOR.fields_by_name[name]
        repeated = field.label == field.LABEL_REPEATED
        x, y = getattr(a, name), getattr(b, name)
        if field.message_type is not None and not repeated:
            if not _close(x, y):
                return False
        elif field.type in (field.TYPE_FLOAT, field.TYPE_DOUBLE):
            xs, ys = (list(x), list(y)) if repeated else ([x], [y])
            if len(xs) != len(ys) or any(abs(u - v) > CAMERA_TOLERANCE * max(1.0, abs(u)) for u, v in zip(xs, ys)):
                return False
        elif x != y:
            return False
    return True


def same_view(a: job_pb2.Job, b: job_pb2.Job) -> bool:
    """Whether two jobs show one view: scene, image size and camera."""
    sa, sb = a.request.settings, b.request.settings
    return (a.request.scene_id == b.request.scene_id and (sa.width, sa.height) == (sb.width, sb.height)
            and _close(a.request.camera, b.request.camera))


def reference_ids(scenes: SceneStore) -> set[str]:
    """Every view's reference, over all scenes: jobs that deletion and retention keep."""
    return {r for stored in scenes.all() for r in stored.info.reference_jobs}


def reference_for(scenes: SceneStore, manager, job: job_pb2.Job) -> job_pb2.Job | None:
    """The reference of the job's view (its owner's), or None."""
    stored = scenes.get(job.request.scene_id)
    if stored is None:
        return None
    for reference_id in reversed(stored.info.reference_jobs):
        reference = manager.get(reference_id)
        if reference is not None and reference.state == job_pb2.DONE and reference.owner == job.owner \
                and same_view(reference, job):
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
    kept = [r for r in stored.info.reference_jobs if r != job.id and (other := manager.get(r)) is not None
            and not (other.owner == job.owner and same_view(other, job))]
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
    """The newest PLOT_POINTS done jobs of the job's view against its reference, oldest first;
    empty (no reference_id) while the view has no reference, a state every
    view starts in rather than an error."""
    reference = reference_for(scenes, manager, job)
    if reference is None:
        return job_pb2.AccuracyPlot()
    jobs, _ = manager.page(0, PLOT_JOBS, job.owner)  # newest first
    view = [other for other in jobs
            if other.id != reference.id and other.state == job_pb2.DONE and same_view(other, job)][:PLOT_POINTS]
    plot = job_pb2.AccuracyPlot(reference_id=reference.id)
    for other in reversed(view):
        error = await manager.compare(manager.side(other), manager.side(reference), None)
        plot.points.add(job_id=other.id, seconds=max(other.finished_at - other.started_at, 0.0), error=error,
                        settings=other.request.settings)
    return plot
