"""References: mark a done job as the one its view (scene, camera, size) is
measured against, unmark it, and the view's jobs as render time against
error (/api/jobs/{id}/accuracy) for the speed-against-error plot."""

from __future__ import annotations

from fastapi import APIRouter, Depends
from rt import job_pb2

from ...core.proto import json_response
from ...services import ownership, references
from ...services.errors import NotFound
from ...services.jobs import JobManager
from ...services.scene_store import SceneStore
from ..deps import job_or_404, jobs, proto_json, scene_info, scene_or_404, scenes, user

router = APIRouter(tags=["references"])


@router.put("/api/scenes/{scene_id}/references/{job_id}",
            responses={200: json_response(job_pb2.SceneInfo, "The scene, the job its view's reference")})
async def mark_reference(scene_id: str, job_id: str, store: SceneStore = Depends(scenes),
                         manager: JobManager = Depends(jobs), owner: str = Depends(user)):
    scene_or_404(store, scene_id, owner)
    info = references.mark(store, manager, scene_id, job_or_404(manager, job_id, owner))
    return proto_json(scene_info(manager, info, owner))


@router.delete("/api/scenes/{scene_id}/references/{job_id}",
               responses={200: json_response(job_pb2.SceneInfo, "The scene, without that reference")})
async def unmark_reference(scene_id: str, job_id: str, store: SceneStore = Depends(scenes),
                           manager: JobManager = Depends(jobs), owner: str = Depends(user)):
    scene_or_404(store, scene_id, owner)
    job = manager.get(job_id)
    if job is not None and not ownership.sees_job(job, owner):  # another user's reference on a shared scene
        raise NotFound(f"job '{job_id}' is no reference of scene '{scene_id}'")
    return proto_json(scene_info(manager, references.unmark(store, scene_id, job_id), owner))


@router.get("/api/jobs/{job_id}/accuracy",
            responses={200: json_response(job_pb2.AccuracyPlot,
                                                "The view's done jobs against its reference; empty without one")})
async def accuracy(job_id: str, store: SceneStore = Depends(scenes), manager: JobManager = Depends(jobs),
                   owner: str = Depends(user)):
    return proto_json(await references.accuracy(store, manager, job_or_404(manager, job_id, owner)))
