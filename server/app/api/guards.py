"""Checks every request passes before any route sees it: its Host and Origin
(core/local_access.py), the API token (whose user the request then acts as:
scope["rt.user"], read by deps.user), and the size of a scene upload; and the
security headers every response carries.

A plain ASGI middleware rather than FastAPI's @app.middleware("http"): that
wraps each request in a task group and a stream of its own, which took 7% of
the event loop's time when a batch client checked on its jobs while they
rendered. WebSockets are checked for Host and Origin only; the tile stream
checks the token itself, as a browser cannot send it in a header.
"""

from __future__ import annotations

from starlette.requests import HTTPConnection
from starlette.responses import JSONResponse
from starlette.types import ASGIApp, Receive, Scope, Send

from ..core.config import Settings
from ..core.local_access import CDN_PAGES, CONTENT_SECURITY_POLICY, SECURITY_HEADERS, host_refusal, origin_refusal
from ..core.security import identify

USER_KEY = "rt.user"  # the scope's entry naming the owner the request acts as

# What every answer carries; pages but Swagger's and ReDoc's, the CSP too.
WITH_CSP = [*SECURITY_HEADERS, (b"content-security-policy", CONTENT_SECURITY_POLICY)]
# Multipart framing around an upload's file, allowed over the upload limit.
UPLOAD_FRAMING_BYTES = 1 << 20


class RequestGuards:
    def __init__(self, app: ASGIApp, settings: Settings):
        self.app = app
        self.settings = settings

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] not in ("http", "websocket"):
            await self.app(scope, receive, send)
            return
        connection = HTTPConnection(scope)
        if scope["type"] == "websocket":
            why = host_refusal(self.settings, connection.headers.get("host", "")) or \
                origin_refusal(self.settings, "POST", connection.headers)  # a handshake acts as one
            if why is not None:
                await send({"type": "websocket.close", "code": 1008, "reason": why[:120]})
                return
            await self.app(scope, receive, send)
            return
        refusal = self._refusal(connection, scope["method"], scope)
        headers = SECURITY_HEADERS if connection.url.path.startswith(CDN_PAGES) else WITH_CSP

        async def send_with_headers(message) -> None:
            if message["type"] == "http.response.start":
                message = {**message, "headers": [*message.get("headers", []), *headers]}
            await send(message)

        await (refusal or self.app)(scope, receive, send_with_headers)

    def _refusal(self, request: HTTPConnection, method: str, scope: Scope) -> JSONResponse | None:
        path = request.url.path
        if why := host_refusal(self.settings, request.headers.get("host", "")):
            return JSONResponse({"detail": why}, status_code=400)
        if why := origin_refusal(self.settings, method, request.headers):
            return JSONResponse({"detail": why}, status_code=403)
        user = identify(request, self.settings) if path.startswith("/api/") else None
        scope[USER_KEY] = user
        if path.startswith("/api/") and user is None:
            return JSONResponse({"detail": "this server needs an API token: send 'Authorization: Bearer <token>'"},
                                status_code=401, headers={"WWW-Authenticate": "Bearer"})
        # The multipart parser would spool the whole body before the route can count it.
        length = request.headers.get("content-length", "")
        if method == "POST" and path == "/api/scenes" and length.isdigit() \
                and int(length) > self.settings.max_upload_bytes + UPLOAD_FRAMING_BYTES:
            return JSONResponse({"detail": f"upload of {int(length)} bytes is over this server's limit of "
                                           f"{self.settings.max_upload_bytes} bytes"}, status_code=413)
        return None
