"""What the services refuse, by kind; str(e) names the problem in plain words
for the user. The API layer answers each kind with its HTTP status
(api/errors.py); services never name one."""

from __future__ import annotations


class ServiceError(Exception):
    """A request the service refuses."""


class NotFound(ServiceError):
    """No such scene, job or output."""


class Conflict(ServiceError):
    """The thing exists but not in the state asked for (a job's image before it is done)."""


class Invalid(ServiceError):
    """A request whose values the service cannot run: outside the schema's
    limits, refused by the renderer, or beyond this server's limits."""


class Refused(ServiceError):
    """Content that is not what it claims to be (a damaged upload)."""


class TooLarge(Refused):
    """Content over one of the server's size limits."""


class UnsupportedType(Refused):
    """Content of a type the service does not take."""
