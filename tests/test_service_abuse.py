"""A real service (``python -m api.serve``, authentication on) against a caller who tries to wear it down: a spray
of sign-ins with fresh names is refused per client address with 429 and Retry-After, while a token's requests
keep answering; one address holding many sockets gets 503 for those beyond its share, while another address's
/health and /ready answer; an API token's use is recorded off the request's path."""

from __future__ import annotations

import socket
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from api.serve import REFUSAL_DELAY_S
from service import running_process
from store import Store
from store.schema import api_tokens

ADMIN, PASSWORD = "root", "first admin password"
PER_MINUTE = 5
PER_CLIENT = 8


@pytest.fixture(scope="module")
def service(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[str, Path]]:
    directory = tmp_path_factory.mktemp("abuse")
    env = {"SYNTH_AUTH": "on", "SYNTH_ADMIN_NAME": ADMIN, "SYNTH_ADMIN_PASSWORD": PASSWORD,
           "SYNTH_EXECUTOR": "serial", "SYNTH_SIGN_INS_PER_MINUTE": str(PER_MINUTE),
           "SYNTH_MAX_CONNECTIONS_PER_CLIENT": str(PER_CLIENT), "SYNTH_HEADER_TIMEOUT_S": "30"}
    with running_process(lambda port: [sys.executable, "-m", "api.serve", "--host", "127.0.0.1", "--port",
                                       str(port), "--log-level", "warning"], directory, env=env) as (url, _):
        yield url, directory / "studies.sqlite"


def _token(url: str) -> str:
    """A viewer's API token, made by the admin signed in from another loopback address."""
    with httpx.Client(base_url=url, transport=httpx.HTTPTransport(local_address="127.0.0.3"), timeout=30) as admin:
        signed = admin.post("/v1/auth/signin", json={"name": ADMIN, "password": PASSWORD})
        assert signed.status_code == 200, signed.text
        csrf = {"x-csrf-token": signed.json()["csrf_token"]}
        made = admin.post("/v1/users", json={"name": "vera", "password": "a viewer password", "roles": ["viewer"]},
                          headers=csrf)
        assert made.status_code in (201, 409), made.text
        token = admin.post("/v1/users/vera/tokens", json={"label": "probe"}, headers=csrf)
        assert token.status_code == 201, token.text
        return str(token.json()["token"])


def test_a_sign_in_spray_meets_429_per_address_while_a_token_keeps_working(service: tuple[str, Path]) -> None:
    url, db = service
    bearer = {"authorization": f"Bearer {_token(url)}"}
    answers: list[httpx.Response] = []

    def spray(n: int) -> None:
        with httpx.Client(base_url=url, timeout=60) as c:
            for k in range(n):
                answers.append(c.post("/v1/auth/signin", json={"name": f"fresh-{n}-{k}", "password": "guess it"}))

    sprayers = [threading.Thread(target=spray, args=(10,)) for _ in range(3)]
    for t in sprayers:
        t.start()
    with httpx.Client(base_url=url, transport=httpx.HTTPTransport(local_address="127.0.0.2"), timeout=60) as c:
        reads = [c.get("/v1/studies?limit=1", headers=bearer) for _ in range(10)]
    for t in sprayers:
        t.join()
    assert all(r.status_code == 200 for r in reads), [r.text for r in reads if r.status_code != 200]
    statuses = sorted(r.status_code for r in answers)
    # fresh names never reach the per-name bound: only the per-address one stops them, after PER_MINUTE tries
    assert statuses.count(401) == PER_MINUTE and statuses.count(429) == 30 - PER_MINUTE, statuses
    refused = next(r for r in answers if r.status_code == 429)
    assert 1 <= int(refused.headers["retry-after"]) <= 60 and refused.json()["type"] == "/problems/too-many-sign-ins"
    # the token's uses are written by the service's own thread within its period, never by the reads themselves
    store = Store(f"sqlite:///{db}")
    try:
        deadline = time.monotonic() + 40
        while True:
            with store.read() as conn:
                used = conn.execute(api_tokens.select().where(api_tokens.c.label == "probe")).one()
            if used.last_used_at is not None or time.monotonic() > deadline:
                break
            time.sleep(1)
        assert used.last_used_at is not None
    finally:
        store.dispose()


def test_one_address_holding_sockets_leaves_health_to_the_others(service: tuple[str, Path]) -> None:
    url, _ = service
    port = int(url.rsplit(":", 1)[1])
    held: list[socket.socket] = []
    refused = 0
    try:
        for _ in range(PER_CLIENT + 6):
            s = socket.socket()
            s.bind(("127.0.0.4", 0))
            s.connect(("127.0.0.1", port))
            s.sendall(b"GET /health HTTP/1.1\r\nHost: 127.0.0.1\r\n")   # a head never finished
            held.append(s)
        time.sleep(REFUSAL_DELAY_S + 0.5)  # the refused ones wait that long, unread, for their 503
        for s in held:
            s.settimeout(0.2)
            try:
                head = s.recv(200)
            except TimeoutError:
                continue
            refused += head.startswith(b"HTTP/1.1 503")
        assert refused == 6, refused
        with httpx.Client(base_url=url, timeout=10) as c:
            assert c.get("/health").status_code == 200
            assert c.get("/ready").status_code == 200
    finally:
        for s in held:
            s.close()


def _peak_rss_mb(pid: int) -> float:
    """A process's own peak resident memory since it started (VmHWM) [MiB]."""
    line = next(x for x in Path(f"/proc/{pid}/status").read_text().splitlines() if x.startswith("VmHWM:"))
    return int(line.split()[1]) / 1024


def test_a_large_import_is_parsed_off_the_web_process(tmp_path: Path) -> None:
    from bench.load import _export_of_zeros

    body = _export_of_zeros(30)   # 30 MB: 15 million zeros, about 0.5 GB once parsed into Python objects
    env = {"SYNTH_WORKERS": "1", "SYNTH_MAX_IMPORT_BYTES": str(64_000_000)}
    with running_process(lambda port: [sys.executable, "-m", "api.serve", "--host", "127.0.0.1", "--port",
                                       str(port), "--log-level", "warning"], tmp_path, env=env) as (url, proc):
        with httpx.Client(base_url=url, timeout=120) as c:
            assert c.get("/ready").status_code == 200
            before = _peak_rss_mb(proc.pid)
            answer: list[httpx.Response] = []
            sender = threading.Thread(target=lambda: answer.append(c.post(
                "/v1/library/import", content=body, headers={"content-type": "application/json"})))
            sender.start()
            health = 0
            while sender.is_alive():
                assert httpx.get(f"{url}/health", timeout=30).status_code == 200
                health += 1
                time.sleep(0.05)
            sender.join()
        # the export is refused for its content hash (zeros hash to something else) only once a worker parsed it
        assert answer[0].status_code == 422, answer[0].text[:300]
        assert "content_hash" in answer[0].json()["field"], answer[0].text[:300]
        # the web process holds the body's chunks on their way to a file, not the document: a few MB, where
        # parsing it there took hundreds
        assert _peak_rss_mb(proc.pid) - before < 60, (before, _peak_rss_mb(proc.pid))
        assert health > 0     # /health answered meanwhile (its times are bench.load's to measure)
