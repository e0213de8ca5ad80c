"""The rt job service: REST and WebSocket API, tiles on Dask, the viewer at /."""

from __future__ import annotations

import asyncio
import logging
from contextlib import asynccontextmanager

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import FileResponse, JSONResponse
from fastapi.staticfiles import StaticFiles

from .api.errors import add_error_handlers
from .api.guards import RequestGuards
from .api.openapi import build_schema
from .api.routes import cluster, comparisons, health, jobs, references, scenes, users
from .core.allocator import keep_freed_memory
from .core.collector import settle_after_startup
from .core.config import Settings, load_settings
from .core.log_writer import write_logs_off_the_event_loop
from .core.security import keep_tokens_out_of_logs
from .services.cluster import RenderCluster
from .services.data_access import server_access
from .services.job_store import JobStore
from .services.jobs import JobManager
from .services.scene_store import SceneStore

log = logging.getLogger("rt")


def create_app(settings: Settings | None = None) -> FastAPI:
    settings = settings or load_settings()
    keep_tokens_out_of_logs()

    @asynccontextmanager
    async def lifespan(app: FastAPI):
        settings.data_dir.mkdir(parents=True, exist_ok=True)
        put_logs_back = write_logs_off_the_event_loop()
        keep_freed_memory()
        app.state.settings = settings
        app.state.data_access = server_access(settings)
        app.state.scenes = SceneStore(settings)
        if settings.samples_dir and settings.samples_dir.is_dir():
            added = await asyncio.to_thread(app.state.scenes.import_samples, settings.samples_dir)
            log.info("added %d sample scenes from %s", added, settings.samples_dir)
        if settings.users:  # their names, never their tokens
            log.info("%d named users: %s", len(settings.users), ", ".join(u.name for u in settings.users))
        app.state.cluster = await RenderCluster.start(settings)
        app.state.jobs = JobManager(settings, app.state.cluster, app.state.scenes, JobStore(settings.database),
                                    app.state.data_access)
        await app.state.jobs.resume()
        log.info("%d objects made at start-up left out of garbage collection", settle_after_startup())
        try:
            yield
        finally:
            await app.state.jobs.shutdown()
            await app.state.cluster.close()
            put_logs_back()

    app = FastAPI(title="rt", summary="Ray tracing render service", lifespan=lifespan)
    for router in (health.router, users.router, scenes.router, jobs.router, comparisons.router, references.router,
                   cluster.router):
        app.include_router(router)

    app.add_middleware(RequestGuards, settings=settings)
    add_error_handlers(app, settings.data_dir)

    @app.exception_handler(RequestValidationError)
    async def validation_error(request: Request, exc: RequestValidationError):
        problems = "; ".join(f"{'.'.join(str(p) for p in e['loc'])}: {e['msg']}" for e in exc.errors())
        return JSONResponse({"detail": problems}, status_code=422)

    def openapi():
        if app.openapi_schema is None:
            app.openapi_schema = build_schema(app)
        return app.openapi_schema

    app.openapi = openapi
    _serve_viewer(app, settings)
    return app


def _serve_viewer(app: FastAPI, settings: Settings) -> None:
    """The built viewer at /, its other pages without their .html (/charts),
    and index.html for the viewer's client-side routes (/jobs/<id>)."""
    index = settings.web_dir / "index.html"
    if not index.is_file():
        log.warning("no viewer at %s (build it with `make web`)", settings.web_dir)
        return
    if (settings.web_dir / "assets").is_dir():
        app.mount("/assets", StaticFiles(directory=settings.web_dir / "assets"), name="assets")

    @app.get("/{path:path}", include_in_schema=False)
    def viewer(path: str):
        file = (settings.web_dir / path).resolve()
        if path and file.is_file() and settings.web_dir.resolve() in file.parents:
            return FileResponse(file)
        page = (settings.web_dir / f"{path.rstrip('/')}.html").resolve()
        if path and page.is_file() and page.parent == settings.web_dir.resolve():
            return FileResponse(page)
        if path.startswith("api/"):
            return JSONResponse({"detail": f"no route /{path}"}, status_code=404)
        return FileResponse(index)


app = create_app()
