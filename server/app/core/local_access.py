"""Who may drive this server from a browser: the checks that keep web pages
from using a server on the user's machine, as Jupyter and other local servers
added after the same reports.

- Host: a page on evil.example can point its own name at 127.0.0.1 (DNS
  rebinding) and then read the API as same-origin. A server bound to a
  loopback address answers only Host names that are loopback ones, its bound
  address, or RT_ALLOWED_HOSTS; one bound to all interfaces answers any Host
  unless RT_ALLOWED_HOSTS lists them. The name workers reach it by
  (RT_SERVER_URL) is answered too.
- Origin: any page can send a form post (a multipart upload) or open a
  WebSocket without a preflight. State-changing requests and WebSocket
  handshakes from a browser are refused unless their Origin is the server's
  own (the Host they were sent to) or listed in RT_ALLOWED_ORIGINS. Clients
  that are not browsers send no Origin and pass.
- Response headers that a served web app should send (SECURITY_HEADERS).
"""

from __future__ import annotations

import ipaddress
from urllib.parse import urlsplit

from .config import Settings

STATE_CHANGING = frozenset({"POST", "PUT", "PATCH", "DELETE"})

SECURITY_HEADERS = [
    (b"x-content-type-options", b"nosniff"),
    (b"referrer-policy", b"no-referrer"),  # a ?token= in a URL goes nowhere else
    (b"x-frame-options", b"DENY"),
    (b"cross-origin-opener-policy", b"same-origin"),
    (b"cross-origin-resource-policy", b"same-origin"),
]
# The viewer loads nothing from elsewhere; FastAPI's /docs and /redoc load
# Swagger UI and ReDoc from a CDN, so they go without it.
CONTENT_SECURITY_POLICY = (b"default-src 'self'; img-src 'self' data: blob:; style-src 'self' 'unsafe-inline'; "
                           b"connect-src 'self'; worker-src 'self' blob:; object-src 'none'; base-uri 'none'; "
                           b"frame-ancestors 'none'; form-action 'self'")
CDN_PAGES = ("/docs", "/redoc")


def _hostname(authority: str) -> str:
    """The host of a Host header or an origin's netloc, without its port, in lower case."""
    try:
        return (urlsplit(f"//{authority}").hostname or "").lower()
    except ValueError:
        return ""


def _is_loopback(name: str) -> bool:
    if name == "localhost" or name.endswith(".localhost"):
        return True
    try:
        return ipaddress.ip_address(name).is_loopback
    except ValueError:
        return False


def _all_interfaces(name: str) -> bool:
    return name in ("0.0.0.0", "::", "")


def host_refusal(settings: Settings, host_header: str) -> str | None:
    """Why a request's Host is refused, or None."""
    name = _hostname(host_header)
    if name and (_is_loopback(name) or name in settings.allowed_hosts or name == settings.host.lower()
                 or name == _hostname(urlsplit(settings.server_url).netloc)):
        return None
    if _all_interfaces(settings.host) and not settings.allowed_hosts:
        return None
    return (f"Host '{host_header}' is not this server's name: it answers {_names(settings)} "
            f"(add yours to RT_ALLOWED_HOSTS)")


def _names(settings: Settings) -> str:
    names = ["localhost", "127.0.0.1", "[::1]"]
    if not _is_loopback(settings.host) and not _all_interfaces(settings.host):
        names.append(settings.host)
    return ", ".join(names + list(settings.allowed_hosts))


def origin_refusal(settings: Settings, method: str, headers) -> str | None:
    """Why a browser's state-changing request or WebSocket handshake is refused, or None."""
    if method not in STATE_CHANGING:
        return None
    origin = headers.get("origin")
    if origin is None:
        # Sent by browsers with every request; a cross-site one without an Origin is still cross-site.
        if headers.get("sec-fetch-site", "") == "cross-site":
            return "a cross-site request is refused: send it from this server's own pages"
        return None
    if origin.rstrip("/") in settings.allowed_origins:
        return None
    own = headers.get("host", "")
    parts = urlsplit(origin)
    if parts.scheme in ("http", "https") and own and parts.netloc.lower() == own.lower():
        return None
    return (f"a request from Origin '{origin}' is refused: it is not this server's own ({own or 'no Host'}); "
            f"allow it with RT_ALLOWED_ORIGINS")
