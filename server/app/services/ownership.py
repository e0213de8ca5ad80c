"""Who sees what: each user sees and changes only their own scenes and jobs.

A scene's or job's owner is the name of the user who made it (Job.owner,
SceneInfo.owner). Records without one (owner "") are, on a server without
named users, the one local user's, as they always were; once users are
named, such scenes (the samples of RT_SAMPLES_DIR, and uploads from before)
are shared read-only with everyone, and such jobs are no one's.

Another user's scene or job is answered as missing (NotFound, 404), not as
forbidden: whether it exists is theirs to know. A shared scene that a user
may see but not delete is refused as Forbidden (403), naming why.
"""

from __future__ import annotations

from collections.abc import Callable

from rt import job_pb2

from .errors import Forbidden, NotFound
from .scene_store import SceneStore, StoredScene

SHARED = ""


def sees_scene(info: job_pb2.SceneInfo, user: str) -> bool:
    return info.owner in (user, SHARED)


def sees_job(job: job_pb2.Job | None, user: str) -> bool:
    return job is not None and job.owner == user


def scene_for(store: SceneStore, scene_id: str, user: str, what: str = "") -> StoredScene:
    """The scene `user` may use; NotFound (prefixed by `what`, a field's
    name) for a scene that is missing or another user's."""
    stored = store.get(scene_id)
    if stored is None or not sees_scene(stored.info, user):
        raise NotFound(f"{what}no scene with id '{scene_id}'")
    return stored


def check_deletable(stored: StoredScene, user: str, users_named: bool) -> None:
    """Forbidden for a shared scene on a server with named users."""
    if users_named and stored.info.owner != user:
        raise Forbidden(f"scene '{stored.info.id}' ({stored.info.name}) is a sample shared with every user: "
                        "it cannot be deleted")


def shown(info: job_pb2.SceneInfo, user: str, owner_of: Callable[[str], str | None]) -> job_pb2.SceneInfo:
    """The scene as `user` sees it: of a shared scene's references (one per
    user and view), theirs only. `owner_of(job_id)`: a job's owner, None when
    the job is gone (a reference left dangling shows as before)."""
    refs = [r for r in info.reference_jobs if owner_of(r) in (user, None)]
    if len(refs) == len(info.reference_jobs):
        return info
    mine = job_pb2.SceneInfo()
    mine.CopyFrom(info)
    del mine.reference_jobs[:]
    mine.reference_jobs.extend(refs)
    return mine
