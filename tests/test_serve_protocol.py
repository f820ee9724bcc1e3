"""The service's connection protocol (api/serve.py) in one process: a connection refused for its address costs
no request state, and the kernel's accept queue is the service's own, not uvicorn's 2 048."""

from __future__ import annotations

import asyncio
from typing import Any

import pytest
import uvicorn
from uvicorn.protocols.http.h11_impl import H11Protocol
from uvicorn.server import ServerState

from api import serve
from api.settings import Settings


async def _app(scope: dict[str, Any], receive: Any, send: Any) -> None:
    await send({"type": "http.response.start", "status": 200, "headers": [(b"content-length", b"2")]})
    await send({"type": "http.response.body", "body": b"ok"})


def test_a_connection_refused_for_its_address_builds_no_request_state(monkeypatch: pytest.MonkeyPatch) -> None:
    built: list[H11Protocol] = []
    original = H11Protocol.__init__

    def counted(self: H11Protocol, *args: Any, **kwargs: Any) -> None:
        built.append(self)
        original(self, *args, **kwargs)

    monkeypatch.setattr(H11Protocol, "__init__", counted)
    config = uvicorn.Config(app=_app, log_level="warning")
    config.load()
    state = ServerState()
    cls = serve.protocol(30.0, per_client=1)

    async def run() -> tuple[bytes, bytes]:
        loop = asyncio.get_running_loop()
        server = await loop.create_server(lambda: cls(config=config, server_state=state, app_state={}),
                                          "127.0.0.1", 0)
        port = server.sockets[0].getsockname()[1]
        first = await asyncio.open_connection("127.0.0.1", port)
        await asyncio.sleep(0.05)
        # one that leaves before its answer (unread, its leaving is seen when the answer is written)
        leaving = await asyncio.open_connection("127.0.0.1", port)
        await asyncio.sleep(0.05)
        leaving[1].close()
        second = await asyncio.open_connection("127.0.0.1", port)
        opened = loop.time()
        await asyncio.sleep(0.05)
        assert cls.held == 2
        refused = await asyncio.wait_for(second[0].read(200), 5)
        # answered after the refusal's wait, and neither is held any more
        assert loop.time() - opened >= 0.9 * serve.REFUSAL_DELAY_S and cls.held == 0
        first[1].write(b"GET / HTTP/1.1\r\nHost: x\r\n\r\n")
        answered = await asyncio.wait_for(first[0].read(200), 5)
        for _, writer in (first, second):
            writer.close()
        server.close()
        await server.wait_closed()
        return refused, answered

    refused, answered = asyncio.run(run())
    assert refused.startswith(b"HTTP/1.1 503") and b"too many open connections" in refused
    assert answered.startswith(b"HTTP/1.1 200")
    # the admitted connection set up uvicorn's protocol; the refused one never did
    assert len(built) == 1


def test_past_the_held_bound_a_refusal_is_answered_at_once() -> None:
    cls = serve.protocol(30.0, per_client=0)
    cls.most_held = 0
    config = uvicorn.Config(app=_app, log_level="warning")
    config.load()

    async def run() -> tuple[bytes, float]:
        loop = asyncio.get_running_loop()
        server = await loop.create_server(lambda: cls(config=config, server_state=ServerState(), app_state={}),
                                          "127.0.0.1", 0)
        reader, writer = await asyncio.open_connection("127.0.0.1", server.sockets[0].getsockname()[1])
        opened = loop.time()
        answer = await asyncio.wait_for(reader.read(200), 5)
        waited = loop.time() - opened
        writer.close()
        server.close()
        await server.wait_closed()
        return answer, waited

    answer, waited = asyncio.run(run())
    assert answer.startswith(b"HTTP/1.1 503") and waited < serve.REFUSAL_DELAY_S


def test_the_accept_queue_is_the_services_setting() -> None:
    assert Settings().accept_backlog == 128
    assert serve.config("127.0.0.1", 0, Settings()).backlog == 128
    assert serve.config("127.0.0.1", 0, Settings(accept_backlog=64)).backlog == 64
