"""What routes need from the running service: the stores, the records their
paths name (each lookup of an id a path names lives here), and the JSON
answers they give."""

from __future__ import annotations


from fastapi import Request
from fastapi.responses import JSONResponse
from google.protobuf.message import Message
from rt import job_pb2

from ..core.proto import to_dict
from ..services.errors import NotFound
from ..services.jobs import JobManager
from ..services.scene_store import SceneStore, StoredScene



# Dependencies are coroutines: FastAPI runs a plain function in its thread pool,
# a hand-off that cost more than the request itself.
async def scenes(request: Request) -> SceneStore:
    return request.app.state.scenes


async def jobs(request: Request) -> JobManager:
    return request.app.state.jobs


def scene_or_404(store: SceneStore, scene_id: str) -> StoredScene:
    stored = store.get(scene_id)
    if stored is None:
        raise NotFound(f"no scene with id '{scene_id}'")
    return stored


def job_or_404(manager: JobManager, job_id: str) -> job_pb2.Job:
    job = manager.get(job_id)
    if job is None:
        raise NotFound(f"no job with id '{job_id}'")
    return job


def proto_json(message: Message, status_code: int = 200, headers: dict[str, str] | None = None) -> JSONResponse:
    return JSONResponse(to_dict(message), status_code=status_code, headers=headers)
