"""/api/jobs/{id}/compare/{reference}: a done job's image measured against
another done job's of the same size (RMSE, relative MSE, mean HDR-FLIP, as
`make charts` measures them), over the whole image or a rectangle; and the
per-pixel HDR-FLIP map the viewer shows."""

from __future__ import annotations

from fastapi import APIRouter, Depends, Query
from fastapi.responses import Response
from rt import job_pb2

from ...core.proto import json_response
from ...services.errors import Invalid
from ...services.jobs import JobManager
from ..deps import job_or_404, jobs, proto_json

router = APIRouter(prefix="/api/jobs", tags=["comparisons"])


@router.get("/{job_id}/compare/{reference_id}",
            responses={200: json_response(job_pb2.ImageComparison, "The job's image measured against the reference's")})
async def compare(job_id: str, reference_id: str,
                  x: int | None = Query(None, ge=0, description="a rectangle's left column (with y, w and h)"),
                  y: int | None = Query(None, ge=0), w: int | None = Query(None, ge=1),
                  h: int | None = Query(None, ge=1), manager: JobManager = Depends(jobs)):
    given = [v is not None for v in (x, y, w, h)]
    if any(given) and not all(given):
        raise Invalid("a region needs all of x, y, w and h")
    job, reference = job_or_404(manager, job_id), job_or_404(manager, reference_id)
    return proto_json(await manager.compare(job, reference, (x, y, w, h) if all(given) else None))


@router.get("/{job_id}/compare/{reference_id}/flip", response_class=Response,
            responses={200: {"content": {"application/x-protobuf": {}},
                             "description": "A serialized rt.Layer: the HDR-FLIP error of each pixel"}})
async def flip_map(job_id: str, reference_id: str, manager: JobManager = Depends(jobs)):
    job, reference = job_or_404(manager, job_id), job_or_404(manager, reference_id)
    return Response(await manager.flip_layer(job, reference), media_type="application/x-protobuf")
