"""The optional API token (RT_API_TOKEN).

Clients send it as `Authorization: Bearer <token>`. Browsers cannot set headers
on a WebSocket, an <img> or a download link, so `?token=<token>` is accepted too.
"""

from __future__ import annotations

import hmac

from starlette.requests import HTTPConnection


def presented_token(connection: HTTPConnection) -> str:
    header = connection.headers.get("authorization", "")
    scheme, _, credentials = header.partition(" ")
    if scheme.lower() == "bearer" and credentials:
        return credentials.strip()
    return connection.query_params.get("token", "")


def is_authorized(connection: HTTPConnection, token: str) -> bool:
    """Always, without a configured token; else only with the same one."""
    return not token or hmac.compare_digest(presented_token(connection).encode(), token.encode())
