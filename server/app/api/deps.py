"""What routes need from the running service: the stores, the user a request
acts as, the records their paths name (each lookup of an id a path names
lives here, and answers another user's record as missing), and the JSON
answers they give."""

from __future__ import annotations


from fastapi import Request
from fastapi.responses import JSONResponse
from google.protobuf.message import Message
from rt import job_pb2

from ..core.proto import to_dict
from ..services import ownership
from ..services.errors import NotFound
from ..services.jobs import JobManager
from ..services.scene_store import SceneStore, StoredScene
from .guards import USER_KEY


# Dependencies are coroutines: FastAPI runs a plain function in its thread pool,
# a hand-off that cost more than the request itself.
async def scenes(request: Request) -> SceneStore:
    return request.app.state.scenes


async def jobs(request: Request) -> JobManager:
    return request.app.state.jobs


async def user(request: Request) -> str:
    """The owner name the request acts as (RequestGuards identified its token): "" without named users."""
    return request.scope.get(USER_KEY) or ""


def scene_or_404(store: SceneStore, scene_id: str, user: str) -> StoredScene:
    """A scene the user may see: theirs, or shared."""
    return ownership.scene_for(store, scene_id, user)


def job_or_404(manager: JobManager, job_id: str, user: str) -> job_pb2.Job:
    """One of the user's jobs."""
    job = manager.get(job_id)
    if not ownership.sees_job(job, user):
        raise NotFound(f"no job with id '{job_id}'")
    return job


def scene_info(manager: JobManager, info: job_pb2.SceneInfo, user: str) -> job_pb2.SceneInfo:
    """A scene as the user is shown it: of its references, theirs."""
    return ownership.shown(info, user, lambda job_id: (job.owner if (job := manager.get(job_id)) else None))


def proto_json(message: Message, status_code: int = 200, headers: dict[str, str] | None = None) -> JSONResponse:
    return JSONResponse(to_dict(message), status_code=status_code, headers=headers)
