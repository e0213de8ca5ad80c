"""/api/jobs/{id}/compare/{reference}: a done job's image measured against
another done job's of the same size (RMSE, relative MSE, mean HDR-FLIP, as
`make charts` measures them), over the whole image or a rectangle; and the
per-pixel HDR-FLIP map the viewer shows. Either side may be a denoised job's
image before denoising (layer, reference_layer "noisy"), so a job compares
with its own noisy image too."""

from __future__ import annotations

from typing import Literal

from fastapi import APIRouter, Depends, Query
from fastapi.responses import Response
from rt import job_pb2

from ...core.proto import json_response
from ...services.errors import Invalid
from ...services.jobs import JobManager
from ..deps import job_or_404, jobs, proto_json, user
from .jobs import MAX_INDEX

router = APIRouter(prefix="/api/jobs", tags=["comparisons"])


Layer = Literal["color", "noisy"]
LAYER = Query("color", description="the job's colour, or its image before denoising (noisy)")
REFERENCE_LAYER = Query("color", description="the reference's colour, or its image before denoising (noisy)")


@router.get("/{job_id}/compare/{reference_id}",
            responses={200: json_response(job_pb2.ImageComparison, "The job's image measured against the reference's")})
async def compare(job_id: str, reference_id: str,
                  x: int | None = Query(None, ge=0, le=MAX_INDEX,
                                        description="a rectangle's left column (with y, w and h)"),
                  y: int | None = Query(None, ge=0, le=MAX_INDEX), w: int | None = Query(None, ge=1, le=MAX_INDEX),
                  h: int | None = Query(None, ge=1, le=MAX_INDEX), layer: Layer = LAYER, reference_layer: Layer = REFERENCE_LAYER,
                  manager: JobManager = Depends(jobs), owner: str = Depends(user)):
    given = [v is not None for v in (x, y, w, h)]
    if any(given) and not all(given):
        raise Invalid("a region needs all of x, y, w and h")
    mine = manager.side(job_or_404(manager, job_id, owner), layer)
    theirs = manager.side(job_or_404(manager, reference_id, owner), reference_layer)
    return proto_json(await manager.compare(mine, theirs, (x, y, w, h) if all(given) else None))


@router.get("/{job_id}/compare/{reference_id}/flip", response_class=Response,
            responses={200: {"content": {"application/x-protobuf": {}},
                             "description": "A serialized rt.Layer: the HDR-FLIP error of each pixel"}})
async def flip_map(job_id: str, reference_id: str, layer: Layer = LAYER, reference_layer: Layer = REFERENCE_LAYER,
                   manager: JobManager = Depends(jobs), owner: str = Depends(user)):
    mine = manager.side(job_or_404(manager, job_id, owner), layer)
    theirs = manager.side(job_or_404(manager, reference_id, owner), reference_layer)
    return Response(await manager.flip_layer(mine, theirs), media_type="application/x-protobuf")
