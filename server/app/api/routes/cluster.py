"""/cluster: what the render workers ask of the server, not clients. A worker
that does not see the data folder fetches a scene's files here by the
upload's content hash (services/data_access.py). The routes take the server's
cluster secret, which reaches workers inside their tasks, and stay out of the
public API's schema."""

from __future__ import annotations

import hmac

from fastapi import APIRouter, Depends, HTTPException, Request
from fastapi.responses import FileResponse, Response

from ...core.security import presented_token
from ...services import scene_files
from ...services.scene_store import SceneStore
from ..deps import scenes

PROTOBUF = "application/x-protobuf"


async def worker_only(request: Request) -> None:
    secret = request.app.state.data_access.secret
    if not hmac.compare_digest(presented_token(request).encode(), secret.encode()):
        raise HTTPException(401, "only the render workers of this server's cluster may ask this",
                            headers={"WWW-Authenticate": "Bearer"})


router = APIRouter(prefix="/cluster", include_in_schema=False, dependencies=[Depends(worker_only)])


@router.get("/scenes/{sha256}")
def scene_listing(sha256: str, store: SceneStore = Depends(scenes)):
    return Response(scene_files.listing(store, sha256).SerializeToString(), media_type=PROTOBUF)


@router.get("/scenes/{sha256}/files/{path:path}")
def scene_file(sha256: str, path: str, store: SceneStore = Depends(scenes)):
    return FileResponse(scene_files.file_path(store, sha256, path), media_type="application/octet-stream")
