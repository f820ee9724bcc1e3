"""Serve the app with uvicorn under the service's connection limits: ``python -m api.serve --host H --port P``.

Uvicorn bounds connections (``limit_concurrency``: beyond ``SYNTH_MAX_CONNECTIONS`` open connections or
requests, a new request is answered 503 at once) and the idle time of a kept-alive connection
(``timeout_keep_alive``: ``SYNTH_KEEP_ALIVE_S``), and h11 bounds the size of a request's head (16 kB). It has no
bound on the time a client may take to send that head, so a client that sends a header line every few seconds
would hold its connection for ever: :class:`HeaderTimeout` adds one. A connection whose request head is not
complete ``SYNTH_HEADER_TIMEOUT_S`` after it opened (or after its previous answer) is answered 408 and closed.

One client could still take every one of the ``SYNTH_MAX_CONNECTIONS`` by holding slow sockets open (each closed
after the head timeout and opened again at once): the protocol also counts open connections per client address,
and a connection beyond ``SYNTH_MAX_CONNECTIONS_PER_CLIENT`` from one address is answered 503 and closed, before
it costs a request, so the other clients (and ``/health``) keep their places. That answer comes after
:data:`REFUSAL_DELAY_S` unread (for at most :func:`_most_held` connections at once, beyond at once), so a client
reopening every refused socket at once makes the service refuse hundreds a second, not thousands. A flood of new
connections waits in the kernel's queue of ``SYNTH_ACCEPT_BACKLOG`` (uvicorn's 2 048 would let one turn of the
event loop accept, and refuse, thousands while the requests in progress wait).
"""

from __future__ import annotations

import argparse
import asyncio
import resource
from typing import Any

import h11
import uvicorn
from uvicorn.protocols.http.h11_impl import H11Protocol

from .settings import Settings

_CROWDED = (b"HTTP/1.1 503 Service Unavailable\r\ncontent-type: text/plain\r\nconnection: close\r\n"
            b"retry-after: 5\r\ncontent-length: 46\r\n\r\ntoo many open connections from this address\r\n\r\n")
_TIMED_OUT = (b"HTTP/1.1 408 Request Timeout\r\ncontent-type: text/plain\r\nconnection: close\r\n"
              b"content-length: 41\r\n\r\nthe request's headers came too slowly\r\n\r\n")


#: How long a connection refused for its address waits, unread, before its 503: a crowd that reopens each
#: refused socket at once would otherwise make the service accept and refuse thousands a second.
REFUSAL_DELAY_S = 1.0


def _most_held() -> int:
    """Refused connections held waiting at once: a quarter of the process's file descriptors, at most 1 000
    (beyond, a refused connection is answered at once), so the wait never starves the service of descriptors."""
    try:
        soft, _ = resource.getrlimit(resource.RLIMIT_NOFILE)
    except (OSError, ValueError):
        return 0
    return max(0, min(1000, (soft if soft != resource.RLIM_INFINITY else 4000) // 4))


class HeaderTimeout(H11Protocol):
    """uvicorn's h11 protocol with a bound on the time to receive a request's head."""

    header_timeout_s = 10.0
    per_client = 1_000_000
    # open connections per client address, over every connection of this process (one event loop)
    open_from: dict[str, int] = {}
    # refused connections waiting for their 503, over every connection of this process, and the most of them
    held = 0
    most_held = _most_held()

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        # uvicorn's own set-up (its h11 connection, its state) waits until the connection is admitted: a
        # connection refused for its address costs only its refusal
        self._setup = (args, kwargs)

    def connection_made(self, transport: asyncio.Transport) -> None:  # type: ignore[override]
        self._header_timer: asyncio.TimerHandle | None = None
        peer = transport.get_extra_info("peername")
        self._address: str | None = str(peer[0]) if isinstance(peer, tuple) and peer else None
        self._refused = False
        if self._address is not None:
            count = self.open_from.get(self._address, 0)
            if count >= self.per_client:
                # uvicorn's protocol is never set up for it: no request, no slot of SYNTH_MAX_CONNECTIONS
                self._refused = True
                self._refusal: asyncio.TimerHandle | None = None
                cls = type(self)
                if cls.held < cls.most_held:
                    cls.held += 1
                    transport.pause_reading()
                    self._refusal = asyncio.get_running_loop().call_later(REFUSAL_DELAY_S, self._refuse, transport)
                else:
                    self._refuse(transport)
                return
            self.open_from[self._address] = count + 1
        args, kwargs = self._setup
        super().__init__(*args, **kwargs)
        super().connection_made(transport)
        self._arm()

    def _arm(self) -> None:
        self._disarm()
        self._header_timer = self.loop.call_later(self.header_timeout_s, self._too_slow)

    def _disarm(self) -> None:
        if self._header_timer is not None:
            self._header_timer.cancel()
            self._header_timer = None

    def data_received(self, data: bytes) -> None:
        super().data_received(data)
        if self.conn.their_state is not h11.IDLE:
            self._disarm()  # the head is in: the body has its own timeout (SYNTH_BODY_TIMEOUT_S)

    def on_response_complete(self) -> None:
        super().on_response_complete()
        if not self.transport.is_closing():
            self._arm()  # the next request's head on a kept-alive connection

    def _refuse(self, transport: asyncio.Transport) -> None:
        if self._refusal is not None:
            self._refusal = None
            type(self).held -= 1
        if not transport.is_closing():
            transport.write(_CROWDED)
            transport.close()

    def connection_lost(self, exc: Exception | None) -> None:
        if self._refused:
            if self._refusal is not None:  # the client left before its answer
                self._refusal.cancel()
                self._refusal = None
                type(self).held -= 1
            return
        if self._address is not None:
            left = self.open_from.get(self._address, 1) - 1
            if left > 0:
                self.open_from[self._address] = left
            else:
                self.open_from.pop(self._address, None)
        self._disarm()
        super().connection_lost(exc)

    def _too_slow(self) -> None:
        self._header_timer = None
        if self.conn.their_state is h11.IDLE and not self.transport.is_closing():
            self.transport.write(_TIMED_OUT)
            self.transport.close()


def protocol(header_timeout_s: float, per_client: int = 1_000_000) -> type[HeaderTimeout]:
    """The protocol class with the given head timeout [s] and bound on one client address's open connections."""
    return type("HeaderTimeoutProtocol", (HeaderTimeout,), {"header_timeout_s": header_timeout_s,
                                                             "per_client": per_client, "open_from": {},
                                                             "held": 0})


def config(host: str, port: int, settings: Settings, **extra: Any) -> uvicorn.Config:
    """uvicorn's configuration of the service under ``settings``' connection limits."""
    return uvicorn.Config("api.app:app", host=host, port=port, http=protocol(settings.header_timeout_s,
                                                                     settings.max_connections_per_client),
                          limit_concurrency=settings.max_connections,
                          timeout_keep_alive=settings.keep_alive_s,  # type: ignore[arg-type]
                          backlog=settings.accept_backlog, **extra)


def main(argv: list[str] | None = None) -> None:
    """Run the service on ``--host``/``--port`` until stopped."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=8000)
    parser.add_argument("--log-level", default="info")
    args = parser.parse_args(argv)
    uvicorn.Server(config(args.host, args.port, Settings.from_env(), log_level=args.log_level)).run()


if __name__ == "__main__":
    main()
