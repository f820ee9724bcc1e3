"""Protective headers on every answer: a Content-Security-Policy without ``unsafe-inline``, nosniff, no framing,
same-origin referrers, and HSTS behind TLS.

The workbench loads only its own files, so its policy allows ``'self'`` alone. The API manual (Swagger UI, ReDoc,
pages FastAPI writes) starts its bundle with an inline script: an HTML answer's inline scripts are allowed by
their SHA-256 in that answer's policy, never by ``unsafe-inline``; the manual's widgets also set inline styles
and Swagger UI runs a worker from a blob, which its pages alone allow.
"""

from __future__ import annotations

import base64
import hashlib
import re

from starlette.datastructures import MutableHeaders
from starlette.types import ASGIApp, Message, Receive, Scope, Send

POLICY = {
    "default-src": "'self'",
    "script-src": "'self'",
    "style-src": "'self'",
    # figures the page fetches arrive as blobs; the page's empty favicon is a data: URL
    "img-src": "'self' data: blob:",
    "connect-src": "'self'",
    "object-src": "'none'",
    "frame-ancestors": "'none'",
    "base-uri": "'none'",
    "form-action": "'self'",
}
MANUAL_PATHS = ("/docs", "/redoc")
_INLINE_SCRIPT = re.compile(rb"<script>(.*?)</script>", re.S)
_HTML_LIMIT = 1_000_000


def policy(script_hashes: list[str] | None = None, manual: bool = False) -> str:
    """The Content-Security-Policy header's value, allowing the inline scripts of these hashes; the manual's
    pages also set inline styles and run a worker from a blob."""
    parts = dict(POLICY)
    if script_hashes:
        parts["script-src"] += "".join(f" 'sha256-{h}'" for h in script_hashes)
    if manual:
        parts["style-src"] += " 'unsafe-inline'"
        parts["worker-src"] = "'self' blob:"
    return "; ".join(f"{k} {v}" for k, v in parts.items())


def script_hashes(html: bytes) -> list[str]:
    """SHA-256 (base64) of every inline script of an HTML page, as a CSP source expression needs them."""
    return [base64.b64encode(hashlib.sha256(m).digest()).decode() for m in _INLINE_SCRIPT.findall(html)]


class SecurityHeaders:
    """ASGI middleware adding the protective headers to every HTTP answer."""

    def __init__(self, app: ASGIApp, hsts: bool) -> None:
        self.app = app
        self.fixed = {
            "x-content-type-options": "nosniff",
            "x-frame-options": "DENY",
            "referrer-policy": "same-origin",
            "cross-origin-opener-policy": "same-origin",
            **({"strict-transport-security": "max-age=31536000"} if hsts else {}),
        }
        self.strict = policy()

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        manual = str(scope.get("path", "")).startswith(MANUAL_PATHS)
        start: Message | None = None
        held: list[bytes] = []

        async def protected(message: Message) -> None:
            nonlocal start
            if message["type"] == "http.response.start":
                headers = MutableHeaders(scope=message)
                for name, value in self.fixed.items():
                    headers[name] = value
                if not (manual and headers.get("content-type", "").startswith("text/html")):
                    headers["content-security-policy"] = self.strict
                    await send(message)
                    return
                start = message          # the manual's page: its policy depends on its inline scripts
                return
            if start is None or message["type"] != "http.response.body":
                await send(message)
                return
            held.append(message.get("body", b""))
            if message.get("more_body", False) and sum(map(len, held)) < _HTML_LIMIT:
                return
            body = b"".join(held)
            headers = MutableHeaders(scope=start)
            headers["content-security-policy"] = policy(script_hashes(body), manual=True)
            await send(start)
            await send({"type": "http.response.body", "body": body, "more_body": message.get("more_body", False)})
            start = None

        await self.app(scope, receive, protected)
