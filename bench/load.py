"""Load on a real server over loopback: fairness between studies and requests, memory under large answers,
and (``--classic``) latency percentiles, throughput, errors and memory, alone and mixed.

``python -m bench.load`` starts ``uvicorn api.app:app`` on a free loopback port with 2 workers and measures, each
scenario bounded in count and time:

- fairness: a 90-sample analysis (one client, 0.1 s between requests) and ``/health`` (every 20 ms) on an idle
  service; then 12 design studies of static balancing (2 000 variants each) alone, timed from submission to the
  last one done; then the same 12 studies again with the analysis and health clients running beside them. It
  prints analysis p50/p95 and health p99 idle and beside the studies, and the studies' time beside the requests
  over their time alone;
- large answers: 16 clients each asking for a 20 000-sample analysis (about 22 MB of JSON) and reading it
  slowly (64 kB every 20 ms); it prints the web process's own peak RSS (VmHWM, the workers not counted).

- abuse (a third server, authentication on): 120 sign-ins with fresh names from one address, 30 at once, while a
  viewer's token reads ``GET /v1/studies?limit=1`` every 50 ms from another (goal: its p95 <= 100 ms); a 100 MB
  library import (one revision holding 50 million zeros) while ``/health`` is asked every 20 ms (goals: the web
  process's peak RSS grows <= 100 MB, ``/health`` p99 <= 50 ms); one address holding as many slow-header sockets
  as it may (up to 1 050, each reopened as the server closes it) for 20 s while another asks ``/health`` every
  50 ms (goal: p99 <= 50 ms, no 503). Every client is on loopback (127.0.0.x), each bounded in count and time.
  ``--abuse-only`` runs these alone.

``--baseline DIR`` runs the same scenarios on another checkout of the service (say ``git archive main`` unpacked
in a temporary directory) in the same run and prints both side by side; ``--shared`` adds this checkout with
``SYNTH_STUDY_LANE=shared`` (studies on the request workers, requests first at task boundaries). ``--classic`` runs the former
scenarios on 1 and 2 workers; ``--soak N`` adds N analysis requests of 3600 samples (4 MB answers) to them.
"""

from __future__ import annotations

import argparse
import asyncio
import math
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import httpx
import numpy as np

REPO = Path(__file__).resolve().parents[1]
FOURBAR = {"type": "fourbar", "ground_length_m": 0.3, "crank_length_m": 0.1, "coupler_length_m": 0.35,
           "rocker_length_m": 0.25,
           "links": {"crank": {"mass_kg": 1.0, "com_m": [0.05, 0.0], "inertia_kgm2": 0.001},
                     "coupler": {"mass_kg": 2.0, "com_m": [0.175, 0.0], "inertia_kgm2": 0.02},
                     "rocker": {"mass_kg": 1.5, "com_m": [0.125, 0.0], "inertia_kgm2": 0.008}}}
REQUESTS: dict[str, tuple[str, str, dict[str, Any] | None]] = {
    "health": ("GET", "/health", None),
    "analysis_360": ("POST", "/v1/analysis", {"mechanism": FOURBAR, "speed_rpm": 300, "samples": 360}),
    # 4 MB answers: what a leak or a cycle holding answers in the web process shows on
    "analysis_3600": ("POST", "/v1/analysis", {"mechanism": FOURBAR, "speed_rpm": 300, "samples": 3600}),
    "optimal_balancing": ("POST", "/v1/balancing/optimal", {
        "mechanism": FOURBAR, "speed_rpm": 300, "samples": 360, "mass_budget_kg": 4.0,
        "weights": {"shaking_force": 1.0, "shaking_moment": 1.0, "driving_torque": 1.0}}),
    "motor_flywheel": ("POST", "/v1/flywheel", {
        "mechanism": {"type": "slider_crank", "crank_length_m": 0.06, "rod_length_m": 0.24,
                      "links": {"rod": {"mass_kg": 4, "com_m": [0.08, 0], "inertia_kgm2": 0.03},
                                "slider": {"mass_kg": 9}}},
        "loads": [{"type": "window", "force_N": 2500, "start_deg": 0, "end_deg": 180}],
        "mean_speed_rpm": 480, "delta": 0.02, "samples": 360,
        "motor": {"synchronous_speed_rpm": 1500, "rated_speed_rpm": 1440, "rated_torque_Nm": 20, "gear_ratio": 3}}),
}


@dataclass
class Tally:
    """Latencies [s] and statuses of one kind of request in one scenario."""

    latencies: list[float] = field(default_factory=list)
    errors: int = 0
    statuses: dict[int, int] = field(default_factory=dict)

    def line(self, name: str, seconds: float) -> str:
        if not self.latencies:
            return f"  {name:18s} no answers, errors {self.errors}"
        p50, p95, p99 = np.percentile(np.array(self.latencies) * 1e3, [50, 95, 99])
        return (f"  {name:18s} n {len(self.latencies):5d}  p50 {p50:8.1f} ms  p95 {p95:8.1f} ms  p99 {p99:8.1f} ms"
                f"  {len(self.latencies) / seconds:7.1f} rps  errors {self.errors}  statuses {self.statuses}")


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _rss_mb(pid: int) -> float:
    """Resident memory of a process and all its descendants [MiB]."""
    out = subprocess.run(["ps", "-eo", "pid=,ppid=,rss="], capture_output=True, text=True, check=True).stdout
    rows = [tuple(int(v) for v in line.split()) for line in out.splitlines() if line.strip()]
    children: dict[int, list[int]] = {}
    rss = {}
    for p, parent, kb in rows:
        children.setdefault(parent, []).append(p)
        rss[p] = kb
    total, stack = 0, [pid]
    while stack:
        p = stack.pop()
        total += rss.get(p, 0)
        stack += children.get(p, [])
    return total / 1024


@contextmanager
def server(workers: int, queue_size: int = 64, repo: Path = REPO,
           extra_env: dict[str, str] | None = None, module: str = "uvicorn") -> Iterator[tuple[str, int]]:
    """A uvicorn server on loopback with ``workers`` worker processes, run from the checkout ``repo`` (``module``
    ``api.serve``: as the service is deployed, with its connection limits); yields its URL and pid."""
    port = _free_port()
    env = {**os.environ, "SYNTH_WORKERS": str(workers), "SYNTH_QUEUE_SIZE": str(queue_size), **(extra_env or {})}
    command = (["uvicorn", "api.app:app"] if module == "uvicorn" else [module]) + [
        "--host", "127.0.0.1", "--port", str(port), "--log-level", "warning"]
    proc = subprocess.Popen([sys.executable, "-m", *command], cwd=repo, env=env, start_new_session=True)
    url = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + 240   # a busy machine starts the workers slowly
        while True:
            try:
                if httpx.get(f"{url}/ready", timeout=1).json()["started"]:
                    break
            except (httpx.TransportError, ValueError):
                pass
            if proc.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError("server did not start")
            time.sleep(0.2)
        yield url, proc.pid
    finally:
        os.killpg(proc.pid, signal.SIGTERM)
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)   # never hide the scenario's own error behind a slow stop
            proc.wait(timeout=30)


async def _client(http: httpx.AsyncClient, kind: str, tally: Tally, count: int, stop_at: float) -> None:
    method, path, body = REQUESTS[kind]
    for _ in range(count):
        if time.monotonic() > stop_at:
            return
        start = time.perf_counter()
        try:
            r = await http.request(method, path, json=body)
            status = r.status_code
        except httpx.HTTPError:
            status = 0
        tally.latencies.append(time.perf_counter() - start)
        tally.statuses[status] = tally.statuses.get(status, 0) + 1
        if not 200 <= status < 300:
            tally.errors += 1


async def scenario(url: str, mix: dict[str, int], per_client: int, limit_s: float) -> tuple[dict[str, Tally], float]:
    """Run ``mix`` (kind -> concurrent clients), each client sending up to ``per_client`` requests within ``limit_s``."""
    tallies = {kind: Tally() for kind in mix}
    stop_at = time.monotonic() + limit_s
    limits = httpx.Limits(max_connections=sum(mix.values()) + 4)
    async with httpx.AsyncClient(base_url=url, timeout=120, limits=limits) as http:
        start = time.perf_counter()
        await asyncio.gather(*(_client(http, kind, tallies[kind], per_client, stop_at)
                               for kind, clients in mix.items() for _ in range(clients)))
        elapsed = time.perf_counter() - start
    return tallies, elapsed


def run(mix: dict[str, int], url: str, pid: int, per_client: int, limit_s: float, title: str) -> dict[str, Tally]:
    before = _rss_mb(pid)
    tallies, elapsed = asyncio.run(scenario(url, mix, per_client, limit_s))
    after = _rss_mb(pid)
    print(f" {title} ({elapsed:.1f} s, RSS {before:.0f} -> {after:.0f} MiB)")
    for kind, tally in tallies.items():
        print(tally.line(kind, elapsed))
    return tallies


STUDY = {
    "endpoint": "/v1/balancing/static",
    "base": {"mechanism": FOURBAR, "speed_rpm": 300, "samples": 90, "max_radius_m": {"crank": 0.1, "rocker": 0.25}},
    "parameters": [{"path": "mechanism.crank_length_m", "range": [0.05, 0.12]},
                   {"path": "mechanism.coupler_length_m", "range": [0.30, 0.40]},
                   {"path": "mechanism.rocker_length_m", "range": [0.20, 0.30]},
                   {"path": "mass_budget_kg", "range": [2.0, 6.0]}],
    "sampling": "lhs", "samples": 2000, "seed": 1,
    "metrics": ["summary_after.rms_shaking_force_N", "total_added_mass_kg"],
}
ANALYSIS_90 = {"mechanism": FOURBAR, "speed_rpm": 300, "samples": 90}
LARGE = {"mechanism": FOURBAR, "speed_rpm": 300, "samples": 20000}


async def _probe(http: httpx.AsyncClient, method: str, path: str, body: dict[str, Any] | None, pause_s: float,
                 stop: asyncio.Event, tally: Tally) -> None:
    """One client sending the same request with a pause between answers until ``stop``."""
    while not stop.is_set():
        start = time.perf_counter()
        try:
            status = (await http.request(method, path, json=body)).status_code
        except httpx.HTTPError:
            status = 0
        tally.latencies.append(time.perf_counter() - start)
        tally.statuses[status] = tally.statuses.get(status, 0) + 1
        tally.errors += not 200 <= status < 300
        try:
            await asyncio.wait_for(stop.wait(), pause_s)
        except asyncio.TimeoutError:
            pass


async def _studies(http: httpx.AsyncClient, count: int, variants: int, limit_s: float) -> tuple[float, int]:
    """Submit ``count`` studies and wait for all to end; their time from the first submission [s] and how many
    ended done."""
    start = time.perf_counter()
    ids = []
    for k in range(count):
        r = await http.post("/v1/studies", json={**STUDY, "samples": variants, "seed": k + 1})
        r.raise_for_status()
        ids.append(r.json()["id"])
    while time.perf_counter() - start < limit_s:
        states = [(await http.get(f"/v1/studies/{i}")).json()["state"] for i in ids]
        if all(s not in ("queued", "running") for s in states):
            return time.perf_counter() - start, states.count("done")
        await asyncio.sleep(0.25)
    return math.inf, 0


async def _fairness(url: str, args: argparse.Namespace) -> dict[str, float]:
    out: dict[str, float] = {}
    async with httpx.AsyncClient(base_url=url, timeout=120) as http:
        for _ in range(5):
            (await http.post("/v1/analysis", json=ANALYSIS_90)).raise_for_status()
        for phase in ("idle", "studies"):
            stop = asyncio.Event()
            analysis, health = Tally(), Tally()
            probes = [asyncio.create_task(_probe(http, "POST", "/v1/analysis", ANALYSIS_90, 0.1, stop, analysis)),
                      asyncio.create_task(_probe(http, "GET", "/health", None, 0.02, stop, health))]
            if phase == "idle":
                await asyncio.sleep(args.idle_s)
            else:
                out["studies_beside_s"], out["done_beside"] = await _studies(http, args.studies, args.variants,
                                                                             args.limit_s)
            stop.set()
            await asyncio.gather(*probes)
            a = np.percentile(np.array(analysis.latencies) * 1e3, [50, 95])
            out[f"analysis_p50_{phase}_ms"], out[f"analysis_p95_{phase}_ms"] = float(a[0]), float(a[1])
            out[f"health_p99_{phase}_ms"] = float(np.percentile(np.array(health.latencies) * 1e3, 99))
            out[f"errors_{phase}"] = analysis.errors + health.errors
            if phase == "idle":
                out["studies_alone_s"], out["done_alone"] = await _studies(http, args.studies, args.variants,
                                                                           args.limit_s)
    return out


def _hwm_mb(pid: int) -> float:
    """Peak resident memory of one process since it started (VmHWM) [MiB]."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) / 1024
    return math.nan


async def _slow_reader(http: httpx.AsyncClient, tally: Tally) -> int:
    start = time.perf_counter()
    size = 0
    async with http.stream("POST", "/v1/analysis", json=LARGE) as r:
        async for chunk in r.aiter_raw(65536):
            size += len(chunk)
            await asyncio.sleep(0.02)
    tally.latencies.append(time.perf_counter() - start)
    tally.statuses[r.status_code] = tally.statuses.get(r.status_code, 0) + 1
    return size


async def _large_answers(url: str, pid: int, clients: int) -> dict[str, float]:
    tally = Tally()
    before = _hwm_mb(pid)
    async with httpx.AsyncClient(base_url=url, timeout=600, limits=httpx.Limits(max_connections=clients + 2)) as http:
        sizes = await asyncio.gather(*(_slow_reader(http, tally) for _ in range(clients)))
    return {"rss_peak_before_mb": before, "rss_peak_mb": _hwm_mb(pid), "answer_mb": max(sizes) / 1e6,
            "large_s": max(tally.latencies), "large_ok": tally.statuses.get(200, 0)}


ADMIN = ("root", "bench admin password")


def _token(url: str, name: str, role: str) -> str:
    """An API token of a new user ``name`` with ``role``, made by the admin signed in from its own address."""
    with httpx.Client(base_url=url, transport=httpx.HTTPTransport(local_address="127.0.0.9"), timeout=60) as c:
        signed = c.post("/v1/auth/signin", json={"name": ADMIN[0], "password": ADMIN[1]})
        signed.raise_for_status()
        csrf = {"x-csrf-token": signed.json()["csrf_token"]}
        c.post("/v1/users", json={"name": name, "password": f"a {role} password", "roles": [role]},
               headers=csrf).raise_for_status()
        made = c.post(f"/v1/users/{name}/tokens", json={"label": "bench"}, headers=csrf)
        made.raise_for_status()
        return str(made.json()["token"])


async def _spray(url: str, token: str, attempts: int = 120, at_once: int = 30) -> dict[str, float]:
    """``attempts`` sign-ins with fresh names, ``at_once`` at a time, from 127.0.0.1, while a viewer reads."""
    reads, signs = Tally(), Tally()
    stop = asyncio.Event()
    viewer = httpx.AsyncClient(base_url=url, timeout=120, headers={"authorization": f"Bearer {token}"},
                               transport=httpx.AsyncHTTPTransport(local_address="127.0.0.2"))
    sprayer = httpx.AsyncClient(base_url=url, timeout=120, limits=httpx.Limits(max_connections=at_once))
    queue = list(range(attempts))

    async def one_client() -> None:
        while queue:
            k = queue.pop()
            start = time.perf_counter()
            try:
                status = (await sprayer.post("/v1/auth/signin", json={"name": f"fresh{k}",
                                                                      "password": "a guess"})).status_code
            except httpx.HTTPError:
                status = 0
            signs.latencies.append(time.perf_counter() - start)
            signs.statuses[status] = signs.statuses.get(status, 0) + 1

    async with viewer, sprayer:
        probe = asyncio.create_task(_probe(viewer, "GET", "/v1/studies?limit=1", None, 0.05, stop, reads))
        await asyncio.sleep(0.5)
        start = time.perf_counter()
        await asyncio.wait_for(asyncio.gather(*(one_client() for _ in range(at_once))), 240)
        spray_s = time.perf_counter() - start
        stop.set()
        await probe
    return {"spray_viewer_p95_ms": float(np.percentile(np.array(reads.latencies) * 1e3, 95)),
            "spray_viewer_errors": reads.errors, "spray_s": spray_s,
            "spray_401": signs.statuses.get(401, 0), "spray_429": signs.statuses.get(429, 0)}


def _export_of_zeros(megabytes: int) -> bytes:
    """A library export of one revision whose request holds ``megabytes`` MB of zeros (about half a million zeros
    per MB): what a careless or hostile import sends."""
    head = (b'{"format":"mechsynth-library/1","project":"bulk","created_at":1.7e9,"created_by":"ann",'
            b'"exported_at":1.7e9,"designs":[{"name":"d","endpoint":"/v1/analysis","created_at":1.7e9,'
            b'"created_by":"ann","revisions":[{"number":1,"parent":null,"request":{"zeros":[')
    tail = (b'0]},"content_hash":"' + b"0" * 64 + b'","author":"ann","created_at":1.7e9,"message":"m",'
            b'"answer":null,"passed":null,"state":"draft","checked_by":null,"checked_at":null,"approved_by":null,'
            b'"approved_at":null,"superseded_by":null,"record_pdf_base64":null}]}]}')
    return head + b"0," * (megabytes * 500_000) + tail


async def _large_import(url: str, pid: int, token: str, megabytes: int = 100) -> dict[str, float]:
    """A ``megabytes`` MB import while /health is asked every 20 ms: the web process's peak RSS and /health."""
    body = _export_of_zeros(megabytes)
    health = Tally()
    stop = asyncio.Event()
    before = _hwm_mb(pid)
    async with httpx.AsyncClient(base_url=url, timeout=600) as http:
        probe = asyncio.create_task(_probe(http, "GET", "/health", None, 0.02, stop, health))
        await asyncio.sleep(0.5)
        start = time.perf_counter()
        r = await http.post("/v1/library/import", content=body, headers={
            "content-type": "application/json", "authorization": f"Bearer {token}"})
        took = time.perf_counter() - start
        stop.set()
        await probe
    return {"import_status": r.status_code, "import_s": took, "import_rss_growth_mb": _hwm_mb(pid) - before,
            "import_health_p99_ms": float(np.percentile(np.array(health.latencies) * 1e3, 99)),
            "import_health_errors": health.errors}


async def _crowd(host: str, port: int, sockets: int, hold_s: float) -> tuple[int, int]:
    """Up to ``sockets`` connections from 127.0.0.4 that never finish their headers, each opened again as the
    server closes it, for ``hold_s``: the counts opened and refused 503."""
    stop = asyncio.Event()
    opened = refused = 0

    async def hold() -> None:
        nonlocal opened, refused
        while not stop.is_set():
            try:
                reader, writer = await asyncio.open_connection(host, port, local_addr=("127.0.0.4", 0))
            except OSError:
                await asyncio.sleep(0.1)
                continue
            opened += 1
            writer.write(b"GET /health HTTP/1.1\r\nHost: 127.0.0.1\r\n")
            try:
                while not stop.is_set():
                    try:
                        head = await asyncio.wait_for(reader.read(100), 1.0)
                    except asyncio.TimeoutError:
                        writer.write(b"X-Slow: 1\r\n")    # one header line now and then: never a whole head
                        continue
                    refused += head.startswith(b"HTTP/1.1 503")
                    break
            except OSError:
                pass
            writer.close()

    crowd = [asyncio.create_task(hold()) for _ in range(sockets)]
    await asyncio.sleep(hold_s)
    stop.set()
    await asyncio.gather(*crowd, return_exceptions=True)
    return opened, refused


def _crowd_process(url: str, sockets: int, hold_s: float, out: Any) -> None:
    host, port = url.removeprefix("http://").split(":")
    out.put(asyncio.run(_crowd(host, int(port), sockets, hold_s)))


async def _slow_crowd(url: str, sockets: int = 1050, hold_s: float = 20.0) -> dict[str, float]:
    """One address (127.0.0.4) holding up to ``sockets`` connections that never finish their headers, while another
    asks /health every 50 ms. The crowd runs in a process of its own: on one event loop with the probe, its
    thousands of reconnections a second would delay the probe's own reads and be counted as the server's."""
    import multiprocessing

    context = multiprocessing.get_context("spawn")
    out = context.Queue()
    crowd = context.Process(target=_crowd_process, args=(url, sockets, hold_s + 2.0, out), daemon=True)
    crowd.start()
    stop = asyncio.Event()
    health = Tally()
    async with httpx.AsyncClient(base_url=url, timeout=60) as http:
        await asyncio.sleep(2.0)
        probe = asyncio.create_task(_probe(http, "GET", "/health", None, 0.05, stop, health))
        await asyncio.sleep(hold_s)
        stop.set()
        await probe
    opened, refused = await asyncio.to_thread(out.get, True, 60.0)
    crowd.join(10)
    return {"crowd_health_p99_ms": float(np.percentile(np.array(health.latencies) * 1e3, 99)),
            "crowd_health_not_200": health.errors, "crowd_health_n": len(health.latencies),
            "crowd_opened": opened, "crowd_refused_503": refused}


def abuse(repo: Path, extra_env: dict[str, str] | None = None) -> dict[str, float]:
    """The sign-in spray, the large import and the slow-socket crowd on a server with authentication on."""
    with tempfile.TemporaryDirectory() as tmp:
        env = {"SYNTH_STUDIES_DB": str(Path(tmp) / "studies.sqlite"), "SYNTH_AUTH": "on",
               "SYNTH_ADMIN_NAME": ADMIN[0], "SYNTH_ADMIN_PASSWORD": ADMIN[1],
               # the 100 MB import is parsed, not refused for its size (the default bound is 50 MB)
               "SYNTH_MAX_IMPORT_BYTES": "150000000", **(extra_env or {})}
        with server(2, repo=repo, extra_env=env, module="api.serve") as (url, pid):
            figures = asyncio.run(_spray(url, _token(url, "vera", "viewer")))
            figures |= asyncio.run(_slow_crowd(url))
            figures |= asyncio.run(_large_import(url, pid, _token(url, "erin", "engineer")))
    return figures


def measure(repo: Path, args: argparse.Namespace, extra_env: dict[str, str] | None = None) -> dict[str, float]:
    """The fairness, large-answer and abuse figures of the service in ``repo`` (with ``extra_env`` set)."""
    figures: dict[str, float] = {}
    if not args.abuse_only:
        with tempfile.TemporaryDirectory() as tmp:
            env = {"SYNTH_STUDIES_DB": str(Path(tmp) / "studies.sqlite"), **(extra_env or {})}
            with server(2, repo=repo, extra_env=env) as (url, pid):
                figures = asyncio.run(_fairness(url, args))
            with server(2, repo=repo, extra_env=env) as (url, pid):
                figures |= asyncio.run(_large_answers(url, pid, args.large_clients))
    return figures | abuse(repo, extra_env)


ROWS = [
    ("analysis_p50_idle_ms", "analysis 90 samples p50, idle [ms]"),
    ("analysis_p95_idle_ms", "analysis 90 samples p95, idle [ms]"),
    ("health_p99_idle_ms", "/health p99, idle [ms]"),
    ("analysis_p50_studies_ms", "analysis p50 beside 12 studies [ms]"),
    ("analysis_p95_studies_ms", "analysis p95 beside 12 studies [ms] (goal <= 150)"),
    ("health_p99_studies_ms", "/health p99 beside 12 studies [ms] (goal <= 50)"),
    ("studies_alone_s", "12 studies alone [s]"),
    ("studies_beside_s", "12 studies beside the requests [s]"),
    ("studies_ratio", "studies beside / alone (goal <= 1.15)"),
    ("errors_studies", "analysis and health errors beside studies"),
    ("answer_mb", "large answer size [MB]"),
    ("large_s", "slowest large answer read [s]"),
    ("rss_peak_before_mb", "web process peak RSS before them [MiB]"),
    ("rss_peak_mb", "web process peak RSS, 16 large answers, slow readers [MiB]"),
    ("spray_viewer_p95_ms", "viewer p95 during 120 sign-ins, 30 at once [ms] (goal <= 100)"),
    ("spray_viewer_errors", "viewer errors during the sign-ins"),
    ("spray_401", "sign-ins answered 401"),
    ("spray_429", "sign-ins answered 429"),
    ("spray_s", "the 120 sign-ins took [s]"),
    ("crowd_health_p99_ms", "/health p99, one address holding slow sockets [ms] (goal <= 50)"),
    ("crowd_health_not_200", "/health not 200 meanwhile"),
    ("crowd_health_n", "/health answers meanwhile"),
    ("crowd_opened", "slow sockets opened (each reopened when closed)"),
    ("crowd_refused_503", "slow sockets answered 503 (past the per-address cap)"),
    ("import_status", "100 MB import: status"),
    ("import_s", "100 MB import: time [s]"),
    ("import_rss_growth_mb", "web process peak RSS growth [MiB] (goal <= 100)"),
    ("import_health_p99_ms", "/health p99 during the import [ms] (goal <= 50)"),
]


def fairness_main(args: argparse.Namespace) -> None:
    """The fairness and memory figures, for this checkout and the baseline when one is given."""
    trees: list[tuple[str, Path, dict[str, str]]] = [("this", REPO, {})]
    if args.shared:
        trees.append(("shared", REPO, {"SYNTH_STUDY_LANE": "shared"}))
    if args.baseline:
        trees.append(("baseline", Path(args.baseline), {}))
    results = {}
    for name, repo, env in trees:
        print(f"== {name}: {repo} {env or ''}", flush=True)
        figures = measure(repo, args, env)
        if "studies_alone_s" in figures:
            figures["studies_ratio"] = figures["studies_beside_s"] / figures["studies_alone_s"]
        results[name] = figures
        for key, label in ROWS:
            if key in figures:
                print(f"  {label:62s} {figures[key]:10.2f}", flush=True)
        print(f"  {'load average over the last minute (2 cores)':62s} {os.getloadavg()[0]:10.2f}", flush=True)
    if len(results) > 1:
        names = [n for n in ("baseline", "shared", "this") if n in results]
        print(f"{'':64s} " + " ".join(f"{n:>10s}" for n in names))
        for key, label in ROWS:
            if any(key in results[n] for n in names):
                print(f"  {label:62s} " + " ".join(f"{results[n].get(key, math.nan):10.2f}" for n in names))


def main(argv: list[str] | None = None) -> None:
    """The fairness and memory scenarios (or the classic ones on 1 and 2 workers), bounded in count and time."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--per-client", type=int, default=40, help="requests per client per scenario")
    parser.add_argument("--limit-s", type=float, default=240.0, help="time bound per scenario [s]")
    parser.add_argument("--soak", type=int, default=0, help="extra analysis requests for the memory check")
    parser.add_argument("--classic", action="store_true", help="the former scenarios on 1 and 2 workers")
    parser.add_argument("--baseline", help="another checkout of the service to measure in the same run")
    parser.add_argument("--shared", action="store_true",
                        help="also measure this checkout with SYNTH_STUDY_LANE=shared (one lane, requests first)")
    parser.add_argument("--studies", type=int, default=12, help="studies submitted at once")
    parser.add_argument("--variants", type=int, default=2000, help="variants per study")
    parser.add_argument("--idle-s", type=float, default=8.0, help="time of the idle measurement [s]")
    parser.add_argument("--large-clients", type=int, default=16, help="slow readers of large answers")
    parser.add_argument("--abuse-only", action="store_true",
                        help="only the sign-in spray, the slow-socket crowd and the large import")
    args = parser.parse_args(argv)
    if not args.classic:
        fairness_main(args)
        return
    args.limit_s = min(args.limit_s, 20.0)
    throughput: dict[tuple[str, int], float] = {}
    for workers in (1, 2):
        print(f"== {workers} worker(s)")
        with server(workers) as (url, pid):
            asyncio.run(scenario(url, {"analysis_360": 2, "optimal_balancing": 2, "motor_flywheel": 2}, 3, 30))
            for kind in REQUESTS:
                run({kind: 4}, url, pid, args.per_client, args.limit_s, f"{kind} alone, 4 clients")
            for kind in ("optimal_balancing", "motor_flywheel"):
                start = time.perf_counter()
                t = run({kind: 4}, url, pid, args.per_client, args.limit_s, f"solver throughput, {kind}")
                throughput[kind, workers] = len(t[kind].latencies) / (time.perf_counter() - start)
            run({"health": 2, "analysis_360": 8, "optimal_balancing": 1, "motor_flywheel": 1}, url, pid,
                args.per_client, args.limit_s, "mixed: /health beside busy workers")
            if args.soak:
                # In quarters, so that a plateau (warm-up) tells itself from a leak (growth in every quarter).
                for quarter in range(4):
                    run({"analysis_3600": 4}, url, pid, args.soak // 16, 3600,
                        f"soak, 3600-sample analyses {quarter * args.soak // 4 + 1}-{(quarter + 1) * args.soak // 4}")
    for kind in ("optimal_balancing", "motor_flywheel"):
        print(f"{kind} throughput, 2 workers / 1 worker: {throughput[kind, 2] / throughput[kind, 1]:.2f}x")


if __name__ == "__main__":
    main()
