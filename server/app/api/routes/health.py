"""/api/health: whether the service and its cluster can take work."""

from __future__ import annotations

from fastapi import APIRouter, Request

router = APIRouter(prefix="/api", tags=["health"])


@router.get("/health")
def health(request: Request):
    cluster = request.app.state.cluster
    workers = cluster.worker_count()
    return {
        "status": "ok" if workers else "degraded",
        "cluster": "embedded" if cluster.embedded else request.app.state.settings.scheduler,
        "workers": workers,
        "threads": cluster.total_threads() if workers else 0,
    }
