"""Timing shared by the benchmarks: medians of several runs, and the best run where a value is wanted."""

from __future__ import annotations

import asyncio
import statistics
import time
from collections.abc import Callable
from typing import Any


def compute_unit() -> float:
    """The machine's compute unit [s]: the median of 30 runs of a fixed numpy-and-JSON task (2 000 stacked 9x9
    solves and 50 000 floats written as JSON), about 20 ms on a quiet 2-core machine of the project's kind. Speed
    figures are printed in these units, timed in the same run, so they hold where absolute times do not."""
    import json

    import numpy as np

    rng = np.random.default_rng(0)
    a = rng.random((2000, 9, 9)) + 9 * np.eye(9)
    b = rng.random((2000, 9))
    values = rng.random(50000).tolist()
    times = []
    for _ in range(30):
        t0 = time.perf_counter()
        np.linalg.solve(a, b[..., None])
        json.dumps(values)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def timed(fn: Callable[..., Any], args: tuple[Any, ...]) -> tuple[Any, float]:
    """``fn(*args)`` and its wall time [s] where it ran (a worker process, when submitted as a task)."""
    t0 = time.perf_counter()
    out = fn(*args)
    return out, time.perf_counter() - t0


def best_of(fn: Callable[[], object], repeat: int) -> float:
    """Shortest wall time of ``repeat`` calls of ``fn`` [s]."""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def median_of(fn: Callable[[], object], repeat: int) -> float:
    """Median wall time of ``repeat`` calls of ``fn`` after one warm-up call [s]."""
    fn()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def asgi_medians(requests: dict[str, tuple[str, str, object]], repeat: int) -> dict[str, float]:
    """Median wall time [s] of each named request (method, path, JSON body) sent to a fresh in-process app over
    ASGI from one event loop: the service's own work, without the thread hand-offs of the synchronous test
    client (about 2 ms per request on this machine)."""
    from mechsynth_client.client import AsyncSynthClient

    async def run() -> dict[str, float]:
        client = AsyncSynthClient.in_process()
        out = {}
        try:
            for name, (method, path, body) in requests.items():
                async def send(method: str = method, path: str = path, body: object = body) -> None:
                    (await client.http.request(method, path, json=body)).raise_for_status()

                await send()
                times = []
                for _ in range(repeat):
                    t0 = time.perf_counter()
                    await send()
                    times.append(time.perf_counter() - t0)
                out[name] = statistics.median(times)
        finally:
            await client.aclose()
        return out

    return asyncio.run(run())


def interleaved(fns: dict[str, Callable[[], object]], repeat: int) -> dict[str, tuple[float, float]]:
    """Minimum and median wall time [s] of each named call over ``repeat`` rounds that call every one in turn,
    after one warm-up round: a burst of load from other work on the machine falls on all of them alike."""
    for fn in fns.values():
        fn()
    times: dict[str, list[float]] = {name: [] for name in fns}
    for _ in range(repeat):
        for name, fn in fns.items():
            t0 = time.perf_counter()
            fn()
            times[name].append(time.perf_counter() - t0)
    return {name: (min(t), statistics.median(t)) for name, t in times.items()}
