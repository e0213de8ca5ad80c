"""/api/jobs: submit, list, show, cancel, the finished images and linear
layers, and the live tile stream over WebSocket."""

from __future__ import annotations

from fastapi import APIRouter, Depends, Query, Request, WebSocket, WebSocketDisconnect
from fastapi.responses import FileResponse, JSONResponse, Response
from rt import job_pb2

from ...core.proto import json_body, json_response, to_dict
from ...core.security import identify
from ...services import ownership
from ...services.errors import NotFound
from ...services.job_image import heat_ramp_png
from ...services.jobs import JobManager
from ...services.layer_files import AUX_CHANNELS, NOISY
from ..deps import job_or_404, jobs, proto_json, user

router = APIRouter(prefix="/api/jobs", tags=["jobs"])

# The largest index or pixel coordinate a query takes: SQLite's and numpy's
# integers are 64-bit, and a larger one was a 500.
MAX_INDEX = (1 << 31) - 1
IMAGE_NAMES = ("image", NOISY) + tuple(AUX_CHANNELS)
LAYER_NAMES = ("color", NOISY) + tuple(AUX_CHANNELS)
HEAT_RAMP_PNG = heat_ramp_png()


@router.post("", status_code=202, openapi_extra=json_body(job_pb2.JobRequest),
             responses={202: json_response(job_pb2.Job, "The queued job; Location is its address"),
                        404: {"description": "scene_id names no scene"},
                        413: {"description": "The job's output would take the user past their stored-bytes quota"},
                        429: {"description": "The user has as many jobs queued or running as their quota allows; "
                                             "Retry-After says when to try again",
                              "headers": {"Retry-After": {"description": "Seconds to wait",
                                                          "schema": {"type": "integer"}}}}})
async def submit_job(request: Request, manager: JobManager = Depends(jobs), owner: str = Depends(user)):
    job = await manager.submit(await request.body(), owner)
    return proto_json(job, 202, {"Location": f"/api/jobs/{job.id}"})


@router.get("", responses={200: json_response(job_pb2.JobList, "The caller's jobs, newest first")})
def list_jobs(offset: int = Query(0, ge=0, le=MAX_INDEX), limit: int = Query(20, ge=1, le=200),
              manager: JobManager = Depends(jobs), owner: str = Depends(user)):
    page, total = manager.page(offset, limit, owner)
    # Job by job, so that each record's JSON is the one answered before (core.proto.to_dict).
    return JSONResponse({**to_dict(job_pb2.JobList(total=total, offset=offset)), "jobs": [to_dict(j) for j in page]})


@router.get("/legends/bvh_cost.png", response_class=Response,
            responses={200: {"content": {"image/png": {}}, "description": "The colour ramp of bvh_cost.png, low to high"}})
def bvh_cost_legend():
    return Response(HEAT_RAMP_PNG, media_type="image/png", headers={"Cache-Control": "max-age=86400"})


@router.get("/{job_id}", responses={200: json_response(job_pb2.Job, "The job")})
async def get_job(job_id: str, manager: JobManager = Depends(jobs), owner: str = Depends(user)):
    return proto_json(job_or_404(manager, job_id, owner))


@router.delete("/{job_id}", status_code=200, responses={
    200: json_response(job_pb2.Job, "A queued or running job, cancelled: its record"),
    204: {"description": "A job that had ended, deleted with its images and layers"},
    409: {"description": "The job is its view's reference: unmark it first"}})
async def delete_job(job_id: str, manager: JobManager = Depends(jobs), owner: str = Depends(user)):
    cancelled = await manager.delete(job_or_404(manager, job_id, owner))
    return proto_json(cancelled) if cancelled is not None else Response(status_code=204)


@router.put("/{job_id}/pin", responses={200: json_response(job_pb2.Job, "The job, pinned")})
async def pin_job(job_id: str, manager: JobManager = Depends(jobs), owner: str = Depends(user)):
    """Keeps the job whatever the retention policy (RT_KEEP_JOBS, RT_KEEP_DAYS) says."""
    return proto_json(manager.pin(job_or_404(manager, job_id, owner), True))


@router.delete("/{job_id}/pin", responses={200: json_response(job_pb2.Job, "The job, no longer pinned")})
async def unpin_job(job_id: str, manager: JobManager = Depends(jobs), owner: str = Depends(user)):
    return proto_json(manager.pin(job_or_404(manager, job_id, owner), False))


@router.get("/{job_id}/image.exr", response_class=FileResponse,
            responses={200: {"content": {"image/x-exr": {}}, "description": "Linear colour and auxiliary layers"}})
async def job_exr(job_id: str, manager: JobManager = Depends(jobs), owner: str = Depends(user)):
    path = await manager.finished_file(job_or_404(manager, job_id, owner), "image.exr")
    return FileResponse(path, media_type="image/x-exr", filename=f"{job_id}.exr")


@router.get("/{job_id}/{name}.png", response_class=FileResponse,
            responses={200: {"content": {"image/png": {}}, "description": "sRGB colour, or an auxiliary layer"}})
async def job_png(job_id: str, name: str, manager: JobManager = Depends(jobs), owner: str = Depends(user)):
    if name not in IMAGE_NAMES:
        raise NotFound(f"no image named '{name}.png' (one of: {', '.join(IMAGE_NAMES)})")
    path = await manager.finished_file(job_or_404(manager, job_id, owner), f"{name}.png")
    return FileResponse(path, media_type="image/png")


@router.get("/{job_id}/layers/{name}", response_class=Response,
            responses={200: {"content": {"application/x-protobuf": {}},
                             "description": "A serialized rt.Layer: the layer's linear float32 values, whole"}})
async def job_layer(job_id: str, name: str, manager: JobManager = Depends(jobs), owner: str = Depends(user)):
    if name not in LAYER_NAMES:
        raise NotFound(f"no layer named '{name}' (one of: {', '.join(LAYER_NAMES)})")
    return Response(await manager.layer(job_or_404(manager, job_id, owner), name),
                    media_type="application/x-protobuf")


@router.websocket("/{job_id}/tiles")
async def tile_stream(websocket: WebSocket, job_id: str):
    """Binary rt.TileStreamMessage frames: every tile so far, then live ones,
    then the final job record; the server closes the socket after it."""
    manager: JobManager = websocket.app.state.jobs
    await websocket.accept()
    owner = identify(websocket, websocket.app.state.settings)
    if owner is None:
        await websocket.close(code=4401, reason="this server needs an API token: add ?token=<token>")
        return
    job = manager.get(job_id)
    if not ownership.sees_job(job, owner):
        await websocket.close(code=4404, reason=f"no job with id '{job_id}'")
        return
    try:
        async for message in manager.tile_messages(job):
            await websocket.send_bytes(message)
        await websocket.close()
    except WebSocketDisconnect:
        pass

