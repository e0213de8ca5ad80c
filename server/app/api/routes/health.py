"""/api/health: whether the service and its cluster can take work, and how
full its data folder is."""

from __future__ import annotations

from fastapi import APIRouter, Request
from rt import job_pb2

from ...core.proto import json_response
from ...services import storage
from ..deps import proto_json

router = APIRouter(prefix="/api", tags=["health"])


@router.get("/health", responses={200: json_response(job_pb2.Health,
                                                     "The cluster's workers and threads; the data folder's use")})
def health(request: Request):
    # A plain def: FastAPI runs it on its thread pool, where the Dask client's
    # blocking scheduler_info() works (called on the event loop it saw no
    # workers) and walking the data folder holds up nothing else.
    answer = request.app.state.cluster.health()
    answer.data_bytes, answer.free_bytes = storage.usage(request.app.state.settings.data_dir)
    return proto_json(answer)
