"""The fixed cost of a small request between the web process and a worker, taken apart.

One worker process (the service's pool, forked from the server that preloads the engine and the plans). Timed in
alternation, minimum and median of each:
- the raw pool round trip of a task that does nothing (``abs(0.0)``);
- a small analysis (four-bar, 36 angles) with its JSON answer made in the worker: its time in this process, and
  its round trip through the pool split into the time the worker spends on it (measured in the worker) and the
  rest (submission, pickling both ways, the pipes, the pool's threads and the wake-ups);
- the same request over ASGI from an event loop against an app on that pool (validation, plan, the HTTP stack),
  and ``GET /health``, which never reaches a worker.
"""

from __future__ import annotations

import asyncio
import pickle
import statistics
import time
from typing import Any

from api.execution import plans
from api.execution.admission import render_task
from bench._timing import timed
from mechsynth_client.schemas.analysis import AnalysisIn
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE
from synth.execution import LocalPoolExecutor

REPEAT = 300
BODY = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 36}


def _stats(values: list[float]) -> str:
    return f"{min(values) * 1e3:6.3f} / {statistics.median(values) * 1e3:6.3f} ms"


def pool_round_trips(executor: LocalPoolExecutor, args: tuple[Any, ...]) -> dict[str, list[float]]:
    """Raw round trip, the task here, its round trip, its time in the worker, and the difference [s] each."""
    out: dict[str, list[float]] = {"raw": [], "here": [], "trip": [], "worker": [], "overhead": []}
    executor.submit(timed, render_task, args).result()
    for _ in range(REPEAT):
        t0 = time.perf_counter()
        executor.submit(abs, 0.0).result()
        out["raw"].append(time.perf_counter() - t0)
        out["here"].append(timed(render_task, args)[1])
        t0 = time.perf_counter()
        _, inside = executor.submit(timed, render_task, args).result()
        trip = time.perf_counter() - t0
        out["trip"].append(trip)
        out["worker"].append(inside)
        out["overhead"].append(trip - inside)
    return out


def over_asgi() -> dict[str, list[float]]:
    """POST /v1/analysis (small) and GET /health over ASGI against an app with one pool worker [s]."""
    import httpx

    from api.app import create_app
    from api.settings import Settings

    async def run() -> dict[str, list[float]]:
        app = create_app(Settings(executor="pool", workers=1))
        out: dict[str, list[float]] = {"analysis": [], "health": []}
        try:
            async with httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url="http://localhost") as client:
                (await client.post("/v1/analysis", json=BODY)).raise_for_status()
                for _ in range(REPEAT):
                    t0 = time.perf_counter()
                    (await client.post("/v1/analysis", json=BODY)).raise_for_status()
                    out["analysis"].append(time.perf_counter() - t0)
                    t0 = time.perf_counter()
                    (await client.get("/health")).raise_for_status()
                    out["health"].append(time.perf_counter() - t0)
        finally:
            app.state.solvers.shutdown()
        return out

    return asyncio.run(run())


def main() -> None:
    """Print the round trips and where their time goes."""
    body = AnalysisIn.model_validate(BODY)
    plan = plans.analysis(body, plans.Limits(100_000, 8, 10.0))
    args = (plan.render, plan.fn, plan.args, plan.kwargs)
    executor = LocalPoolExecutor(1, preload=["api.execution.plans", "bench._timing"])
    try:
        trips = pool_round_trips(executor, args)
    finally:
        executor.shutdown()
    answer = render_task(*args)[0]
    print(f"one pool worker, small analysis (four-bar, 36 angles, {len(answer)} bytes of JSON), min / median over "
          f"{REPEAT} alternated runs:")
    print(f"  raw pool round trip (abs(0.0)):            {_stats(trips['raw'])}")
    print(f"  the task in this process:                  {_stats(trips['here'])}")
    print(f"  the task through the pool:                 {_stats(trips['trip'])}")
    print(f"    of which in the worker:                  {_stats(trips['worker'])}")
    print(f"    the rest (submit, pickle, pipes, wake):  {_stats(trips['overhead'])}   goal <= 1 ms at the median")
    print(f"  pickling the task's arguments: {len(pickle.dumps((render_task, args, {})))} bytes")
    asgi = over_asgi()
    print(f"  POST /v1/analysis over ASGI, app on the pool: {_stats(asgi['analysis'])}; GET /health "
          f"{_stats(asgi['health'])}")


if __name__ == "__main__":
    main()
