"""/api/me: who the request's token belongs to, and their use of the server
against its per-user quotas (what the viewer's header shows)."""

from __future__ import annotations

from fastapi import APIRouter, Depends
from rt import job_pb2

from ...core.proto import json_response
from ...services.jobs import JobManager
from ..deps import jobs, proto_json, user

router = APIRouter(prefix="/api", tags=["users"])


@router.get("/me", responses={200: json_response(job_pb2.UserInfo, "The signed-in user: name, stored bytes and "
                                                                   "queued jobs against the quotas")})
async def me(manager: JobManager = Depends(jobs), owner: str = Depends(user)):
    return proto_json(await manager.user_info(owner))
