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


class Forbidden(ServiceError):
    """A thing the caller may see but not change (a shared sample scene)."""


class OverQuota(TooLarge):
    """Stored bytes past the user's quota (RT_QUOTA_MB): an upload, or a job's output."""


class TooManyJobs(ServiceError):
    """More queued jobs than the user's quota (RT_QUOTA_QUEUED_JOBS); worth
    trying again after `retry_after` seconds, as their jobs end."""

    def __init__(self, message: str, retry_after: int):
        super().__init__(message)
        self.retry_after = retry_after
