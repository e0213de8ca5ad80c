"""/api/health: whether the service and its cluster can take work."""

from __future__ import annotations

from fastapi import APIRouter, Request
from rt import job_pb2

from ...core.proto import json_response
from ..deps import proto_json

router = APIRouter(prefix="/api", tags=["health"])


@router.get("/health", responses={200: json_response(job_pb2.Health, "The cluster's workers and threads")})
def health(request: Request):
    return proto_json(request.app.state.cluster.health())
