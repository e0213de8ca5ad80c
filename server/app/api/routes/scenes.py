"""/api/scenes: upload, list, show, delete, the scene as GLB, and the debugger's
views of it (one pixel's ray tree, the BVH boxes of one level)."""

from __future__ import annotations

import asyncio

from fastapi import APIRouter, Depends, File, Query, Request, UploadFile
from fastapi.responses import FileResponse, Response
from rt import debug_pb2, job_pb2

from ...core.proto import json_body, json_response
from ...services import debugger, ownership
from ...services.jobs import JobManager
from ...services.scene_store import SceneStore
from ..deps import jobs, proto_json, scene_info, scene_or_404, scenes, user

router = APIRouter(prefix="/api/scenes", tags=["scenes"])


@router.post("", status_code=201, responses={201: json_response(job_pb2.SceneInfo, "The stored scene")})
async def upload_scene(file: UploadFile = File(..., description=".glb, .gltf, .obj, or a .zip of a scene with its files"),
                       manager: JobManager = Depends(jobs), owner: str = Depends(user)):
    stored = await asyncio.to_thread(manager.quotas.upload, owner, file.filename or "", file.file)
    return proto_json(stored.info, 201, {"Location": f"/api/scenes/{stored.info.id}"})


@router.get("", responses={200: json_response(job_pb2.SceneList, "The caller's scenes and the shared samples, "
                                                                  "newest first")})
def list_scenes(store: SceneStore = Depends(scenes), manager: JobManager = Depends(jobs), owner: str = Depends(user)):
    return proto_json(job_pb2.SceneList(scenes=[scene_info(manager, s.info, owner) for s in store.all()
                                                if ownership.sees_scene(s.info, owner)]))


@router.get("/{scene_id}", responses={200: json_response(job_pb2.SceneInfo, "The scene")})
def get_scene(scene_id: str, store: SceneStore = Depends(scenes), manager: JobManager = Depends(jobs),
              owner: str = Depends(user)):
    return proto_json(scene_info(manager, scene_or_404(store, scene_id, owner).info, owner))


@router.delete("/{scene_id}", status_code=204,
               responses={403: {"description": "A sample scene shared with every user (it stays), or a browser's "
                                               "request from another site's page"}})
async def delete_scene(scene_id: str, request: Request, store: SceneStore = Depends(scenes),
                       manager: JobManager = Depends(jobs), owner: str = Depends(user)):
    stored = scene_or_404(store, scene_id, owner)
    ownership.check_deletable(stored, owner, bool(request.app.state.settings.users))
    await manager.delete_scene(scene_id)
    return Response(status_code=204)


@router.get("/{scene_id}/model.glb", response_class=FileResponse,
            responses={200: {"content": {"model/gltf-binary": {}}, "description": "The scene as the renderer sees it"}})
async def scene_model(scene_id: str, store: SceneStore = Depends(scenes), owner: str = Depends(user)):
    stored = scene_or_404(store, scene_id, owner)
    path = await asyncio.to_thread(store.model_glb, stored)
    return FileResponse(path, media_type="model/gltf-binary", filename=f"{stored.info.id}.glb")


@router.post("/{scene_id}/debug-ray", openapi_extra=json_body(job_pb2.DebugRayRequest),
             responses={200: json_response(debug_pb2.DebugPath, "Every ray traced for the pixel")})
async def debug_ray(scene_id: str, request: Request, store: SceneStore = Depends(scenes),
                    owner: str = Depends(user)):
    stored = scene_or_404(store, scene_id, owner)
    return proto_json(await debugger.debug_ray(stored, await request.body()))


@router.get("/{scene_id}/bvh", responses={200: json_response(
    debug_pb2.BvhBoxes, "The boxes of one level of the wide BVH the renderer traverses")})
async def bvh_boxes(scene_id: str,
                    level: int = Query(0, ge=0, le=1024, description="0 is the root; a node's children (nodes, leaves) below it"),
                    leaves: bool = Query(False, description="all leaf boxes instead of one level"),
                    tree: str = Query("top", max_length=10, description=(
                        "top: the top level over the instances (the only tree of a scene without any); "
                        "world: the tree of the triangles placed once; or an instance number: its mesh's tree, "
                        "with the instance's transform as to_world")),
                    store: SceneStore = Depends(scenes), owner: str = Depends(user)):
    return proto_json(await debugger.bvh_boxes(scene_or_404(store, scene_id, owner), level, leaves, tree))
