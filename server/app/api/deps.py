"""What routes need from the running service, and the JSON answers they give."""

from __future__ import annotations

from fastapi import HTTPException, Request
from fastapi.responses import JSONResponse
from google.protobuf.message import Message

from ..core.proto import to_dict
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
        raise HTTPException(404, f"no scene with id '{scene_id}'")
    return stored


def proto_json(message: Message, status_code: int = 200, headers: dict[str, str] | None = None) -> JSONResponse:
    return JSONResponse(to_dict(message), status_code=status_code, headers=headers)
