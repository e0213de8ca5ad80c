"""The one place where the services' errors become HTTP answers: each kind of
services.errors.ServiceError has its status, and the answer's detail is the
error's message."""

from __future__ import annotations

import re
import sqlite3
from pathlib import Path

from fastapi import FastAPI, Request
from fastapi.responses import JSONResponse
from starlette.exceptions import HTTPException

from ..services import storage
from ..services.errors import (Conflict, Forbidden, Invalid, NotFound, Refused, ServiceError, TooLarge, TooManyJobs,
                               UnsupportedType)

HTTP_STATUS: dict[type[ServiceError], int] = {
    NotFound: 404,
    Conflict: 409,
    Invalid: 422,
    Refused: 400,
    TooLarge: 413,
    UnsupportedType: 415,
    Forbidden: 403,
    TooManyJobs: 429,
}


def http_status(error: ServiceError) -> int:
    """The status of the error's most specific kind."""
    for kind in type(error).__mro__:
        if kind in HTTP_STATUS:
            return HTTP_STATUS[kind]
    return 500


def allowed_methods(app: FastAPI, path: str) -> list[str]:
    """Every method the OpenAPI document gives `path` (HEAD with GET): a
    resource's GET and DELETE are two routes, and Starlette's 405 names only
    the first's."""
    methods = set()
    for template, operations in app.openapi()["paths"].items():
        if re.fullmatch(re.sub(r"\\{[^}]+\\}", "[^/]+", re.escape(template)), path):
            methods |= {m.upper() for m in operations}
    if "GET" in methods:
        methods.add("HEAD")
    return sorted(methods)


def add_error_handlers(app: FastAPI, data_dir: Path) -> None:
    # A write into a full data folder can happen in any route that stores
    # something (an upload, a job record, an image made when first asked for):
    # 507 Insufficient Storage, naming it, instead of a 500.
    async def storage_full(request: Request, exc: Exception):
        if not storage.is_full(exc):
            raise exc
        return JSONResponse({"detail": storage.full_message(data_dir, exc)}, status_code=507)

    app.add_exception_handler(OSError, storage_full)
    app.add_exception_handler(sqlite3.OperationalError, storage_full)

    @app.exception_handler(ServiceError)
    async def service_error(request: Request, exc: ServiceError):
        headers = {"Retry-After": str(exc.retry_after)} if isinstance(exc, TooManyJobs) else None
        return JSONResponse({"detail": str(exc)}, status_code=http_status(exc), headers=headers)

    @app.exception_handler(HTTPException)
    async def http_error(request: Request, exc: HTTPException):
        headers = dict(exc.headers or {})
        if exc.status_code == 405:
            headers["Allow"] = ", ".join(allowed_methods(app, request.url.path))
        return JSONResponse({"detail": exc.detail}, status_code=exc.status_code, headers=headers)
