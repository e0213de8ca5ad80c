"""/api/health: whether the service and its cluster can take work, and how
full its data folder is."""

from __future__ import annotations

import asyncio

from fastapi import APIRouter, Request
from rt import job_pb2

from ...core.proto import json_response
from ...services import storage
from ..deps import proto_json

router = APIRouter(prefix="/api", tags=["health"])


@router.get("/health", responses={200: json_response(job_pb2.Health,
                                                     "The cluster's workers and threads; the data folder's use")})
async def health(request: Request):
    # On the event loop, where the cluster's totals are the client's cache (no
    # round trip to the scheduler through the loop under load); the data
    # folder's size on a thread when it must be walked again.
    answer = request.app.state.cluster.health()
    data_dir = request.app.state.settings.data_dir
    answer.data_bytes, answer.free_bytes = storage.fresh_usage(data_dir) or \
        await asyncio.to_thread(storage.usage, data_dir)
    return proto_json(answer)
