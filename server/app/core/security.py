"""API tokens: the optional one of a server with one local user
(RT_API_TOKEN), or one per named user (RT_USERS, RT_USERS_FILE: core/users.py).

Clients send it as `Authorization: Bearer <token>`. Browsers cannot set headers
on a WebSocket, an <img> or a download link, so `?token=<token>` is accepted too,
and kept out of the access log.
"""

from __future__ import annotations

import hmac
import logging
import re

from starlette.requests import HTTPConnection


def presented_token(connection: HTTPConnection) -> str:
    header = connection.headers.get("authorization", "")
    scheme, _, credentials = header.partition(" ")
    if scheme.lower() == "bearer" and credentials:
        return credentials.strip()
    return connection.query_params.get("token", "")


_TOKEN_IN_QUERY = re.compile(r"(?<=[?&])token=[^&\s]*")


def redact(path: str) -> str:
    """A request path with any `token=` query value replaced."""
    return _TOKEN_IN_QUERY.sub("token=[redacted]", path)


class TokenRedaction(logging.Filter):
    """Keeps `?token=` values out of uvicorn's access log (its record's args are
    client, method, path with query, HTTP version, status)."""

    def filter(self, record: logging.LogRecord) -> bool:
        args = record.args
        if isinstance(args, tuple) and len(args) >= 3 and isinstance(args[2], str) and "token=" in args[2]:
            record.args = (*args[:2], redact(args[2]), *args[3:])
        return True


def keep_tokens_out_of_logs() -> None:
    access = logging.getLogger("uvicorn.access")
    if not any(isinstance(f, TokenRedaction) for f in access.filters):
        access.addFilter(TokenRedaction())


def is_authorized(connection: HTTPConnection, token: str) -> bool:
    """Always, without a configured token; else only with the same one."""
    return not token or hmac.compare_digest(presented_token(connection).encode(), token.encode())


# The one user of a server without named users owns records as "".
LOCAL_OWNER = ""


def identify(connection: HTTPConnection, settings) -> str | None:
    """The owner name the request acts as: LOCAL_OWNER on a server without
    named users (given RT_API_TOKEN when it is set), a user's name when the
    token is theirs, None when it is no one's. The presented token is compared
    with every user's, each in constant time and without stopping at a match,
    so the time taken tells nothing of which token matched or how much of it."""
    if not settings.users:
        return LOCAL_OWNER if is_authorized(connection, settings.api_token) else None
    presented = presented_token(connection).encode()
    found = None
    for user in settings.users:
        if hmac.compare_digest(presented, user.token.encode()) and found is None:
            found = user.name
    return found
