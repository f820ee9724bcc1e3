"""State-changing requests from another site's page are refused, with or without sign-in.

A browser names the page a request comes from in ``Origin`` (else ``Referer``); a POST, PUT, PATCH or DELETE is
refused (403) unless that origin is this service's own (the scheme's host and port of the request itself) or one
of the origins allowed to call from another site. A request naming no page (the Python client, curl) is allowed,
unless the browser says in ``Sec-Fetch-Site`` that it came from another site. Without this, a form on any page
could make a visitor's browser start, cancel or resume studies.
"""

from __future__ import annotations

from collections.abc import Sequence
from urllib.parse import urlsplit

from starlette.datastructures import Headers
from starlette.types import ASGIApp, Receive, Scope, Send

from ..problems import problem
from .roles import SAFE_METHODS

_DEFAULT_PORTS = {"http": 80, "https": 443}


def origin_of(url: str) -> str | None:
    """``scheme://host[:port]`` of a URL, the port left out when it is the scheme's default; None when the URL has
    no scheme and host."""
    try:
        parts = urlsplit(url)
        port = parts.port
    except ValueError:
        return None
    if parts.scheme not in _DEFAULT_PORTS or not parts.hostname:
        return None
    host = f"[{parts.hostname}]" if ":" in parts.hostname else parts.hostname
    return f"{parts.scheme}://{host}" + (f":{port}" if port and port != _DEFAULT_PORTS[parts.scheme] else "")


def own_origin(scope: Scope, headers: Headers) -> str | None:
    """The origin the request was sent to: its scheme (as the server saw it) and its Host header."""
    scheme = "https" if scope.get("scheme") in ("https", "wss") else "http"
    host = headers.get("host")
    return origin_of(f"{scheme}://{host}") if host else None


class SameOrigin:
    """ASGI middleware refusing state-changing requests whose page is on another origin."""

    def __init__(self, app: ASGIApp, trusted_origins: Sequence[str], behind_tls: bool) -> None:
        self.app = app
        self.trusted = {o for o in (origin_of(t) for t in trusted_origins) if o}
        # behind a TLS proxy the service itself is spoken to over http: the page's origin is https
        self.behind_tls = behind_tls

    def _allowed(self, scope: Scope, headers: Headers, page: str | None) -> bool:
        if page is None:
            return False
        own = own_origin(scope, headers)
        if page == own or page in self.trusted:
            return True
        return own is not None and self.behind_tls and page == origin_of("https" + own[own.index("://"):])

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http" or scope["method"] in SAFE_METHODS:
            await self.app(scope, receive, send)
            return
        headers = Headers(scope=scope)
        origin, referer = headers.get("origin"), headers.get("referer")
        reason: str | None = None
        if origin is not None:
            if not self._allowed(scope, headers, origin_of(origin)):
                reason = f"the request comes from a page of {origin[:200]!r} (Origin), another site"
        elif referer is not None:
            if not self._allowed(scope, headers, origin_of(referer)):
                page = origin_of(referer) or "an unknown page"
                reason = f"the request comes from a page of {page[:200]!r} (Referer), another site"
        elif headers.get("sec-fetch-site") in ("cross-site", "same-site"):
            reason = "the browser says the request comes from another site (Sec-Fetch-Site)"
        if reason is None:
            await self.app(scope, receive, send)
            return
        response = problem(403, "cross-origin-request", "Request from another site refused",
                           f"{reason}: this service accepts changes only from its own pages, or from "
                           f"origins set in SYNTH_CORS_ORIGINS", origin=origin, referer=origin_of(referer or ""))
        await response(scope, receive, send)
