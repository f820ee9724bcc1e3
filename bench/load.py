"""Load on a real server over loopback: latency percentiles, throughput, errors and memory, alone and mixed.

``python -m bench.load`` starts ``uvicorn api.app:app`` on a free loopback port with 1 and then 2 workers and
drives it with concurrent clients, each scenario bounded in request count and in time. It reports, per scenario,
p50/p95/p99 latency, requests per second, non-2xx answers and the server's RSS (all its processes) before and
after; then the solver throughput ratio from 1 to 2 workers and /health's p99 while every worker is busy.
``--soak N`` adds N analysis requests of 3600 samples (4 MB answers) to check that memory stays flat.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import signal
import socket
import subprocess
import sys
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
def server(workers: int, queue_size: int = 64) -> Iterator[tuple[str, int]]:
    """A uvicorn server on loopback with ``workers`` worker processes; yields its URL and pid."""
    port = _free_port()
    env = {**os.environ, "SYNTH_WORKERS": str(workers), "SYNTH_QUEUE_SIZE": str(queue_size)}
    proc = subprocess.Popen([sys.executable, "-m", "uvicorn", "api.app:app", "--host", "127.0.0.1", "--port",
                             str(port), "--log-level", "warning"], cwd=REPO, env=env, start_new_session=True)
    url = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + 60
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


def main(argv: list[str] | None = None) -> None:
    """Scenarios on 1 and 2 workers, bounded in count and time."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--per-client", type=int, default=40, help="requests per client per scenario")
    parser.add_argument("--limit-s", type=float, default=20.0, help="time bound per scenario [s]")
    parser.add_argument("--soak", type=int, default=0, help="extra analysis requests for the memory check")
    args = parser.parse_args(argv)
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
