"""Checks every HTTP request passes before any route sees it: the API token, and
the size of a scene upload.

A plain ASGI middleware rather than FastAPI's @app.middleware("http"): that
wraps each request in a task group and a stream of its own, which took 7% of
the event loop's time when a batch client checked on its jobs while they
rendered. WebSockets pass through; the tile stream checks the token itself,
as a browser cannot send it in a header.
"""

from __future__ import annotations

from starlette.requests import HTTPConnection
from starlette.responses import JSONResponse
from starlette.types import ASGIApp, Receive, Scope, Send

from ..core.config import Settings
from ..core.security import is_authorized

# Multipart framing around an upload's file, allowed over the upload limit.
UPLOAD_FRAMING_BYTES = 1 << 20


class RequestGuards:
    def __init__(self, app: ASGIApp, settings: Settings):
        self.app = app
        self.settings = settings

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] == "http":
            refusal = self._refusal(HTTPConnection(scope), scope["method"])
            if refusal is not None:
                await refusal(scope, receive, send)
                return
        await self.app(scope, receive, send)

    def _refusal(self, request: HTTPConnection, method: str) -> JSONResponse | None:
        path = request.url.path
        if path.startswith("/api/") and not is_authorized(request, self.settings.api_token):
            return JSONResponse({"detail": "this server needs an API token: send 'Authorization: Bearer <token>'"},
                                status_code=401, headers={"WWW-Authenticate": "Bearer"})
        # The multipart parser would spool the whole body before the route can count it.
        length = request.headers.get("content-length", "")
        if method == "POST" and path == "/api/scenes" and length.isdigit() \
                and int(length) > self.settings.max_upload_bytes + UPLOAD_FRAMING_BYTES:
            return JSONResponse({"detail": f"upload of {int(length)} bytes is over this server's limit of "
                                           f"{self.settings.max_upload_bytes} bytes"}, status_code=413)
        return None
