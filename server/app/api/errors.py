"""The one place where the services' errors become HTTP answers: each kind of
services.errors.ServiceError has its status, and the answer's detail is the
error's message."""

from __future__ import annotations

from fastapi import FastAPI, Request
from fastapi.responses import JSONResponse

from ..services.errors import Conflict, Invalid, NotFound, Refused, ServiceError, TooLarge, UnsupportedType

HTTP_STATUS: dict[type[ServiceError], int] = {
    NotFound: 404,
    Conflict: 409,
    Invalid: 422,
    Refused: 400,
    TooLarge: 413,
    UnsupportedType: 415,
}


def http_status(error: ServiceError) -> int:
    """The status of the error's most specific kind."""
    for kind in type(error).__mro__:
        if kind in HTTP_STATUS:
            return HTTP_STATUS[kind]
    return 500


def add_error_handlers(app: FastAPI) -> None:
    @app.exception_handler(ServiceError)
    async def service_error(request: Request, exc: ServiceError):
        return JSONResponse({"detail": str(exc)}, status_code=http_status(exc))
