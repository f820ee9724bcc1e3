"""The Host header must name this service: Starlette's TrustedHostMiddleware, answering a problem response.

A page on another site whose name an attacker points at 127.0.0.1 (DNS rebinding) reaches a laptop's service
with its own name in the Host header; refusing unknown hosts stops it.
"""

from __future__ import annotations

from collections.abc import Sequence

from starlette.datastructures import Headers
from starlette.middleware.trustedhost import TrustedHostMiddleware
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from ..problems import problem

_PASSED = "synth.allowed_host"


class AllowedHosts(TrustedHostMiddleware):
    """TrustedHostMiddleware whose refusal is a 400 problem naming the host and the setting."""

    def __init__(self, app: ASGIApp, allowed_hosts: Sequence[str]) -> None:
        super().__init__(self._passed, allowed_hosts=allowed_hosts, www_redirect=False)
        self.inner = app

    async def _passed(self, scope: Scope, receive: Receive, send: Send) -> None:
        scope[_PASSED] = True
        await self.inner(scope, receive, send)

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] not in ("http", "websocket") or self.allow_any:
            await self.inner(scope, receive, send)
            return
        refused = False

        async def answer(message: Message) -> None:
            nonlocal refused
            if scope.get(_PASSED):
                await send(message)
                return
            if message["type"] == "http.response.start":
                refused = True
                host = Headers(scope=scope).get("host", "")
                response = problem(400, "host-not-allowed", "Host not allowed",
                                   f"this service does not answer to the host {host[:200]!r}; the hosts it answers "
                                   f"to are set with SYNTH_ALLOWED_HOSTS", host=host[:200])
                await response(scope, receive, send)
            # the refusal's own body is dropped: the problem above has been sent in its place
            elif not refused:
                await send(message)

        await super().__call__(scope, receive, answer)
