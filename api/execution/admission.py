"""Where a request's solver work runs: submitted as a task to the executor, awaited without a server thread.

The web process only validates, submits and answers: the engine call *and* the conversion of its result into the
response bytes (JSON or a figure) run in the worker, so a large answer or a figure never holds the event loop and
``/health`` answers while every worker is busy. Admission is bounded: at most ``workers + queue_size`` requests
hold or wait for a worker; the next one gets 503 with ``Retry-After`` at once. Each request has one deadline for
all of its work; past it the task is cancelled, which stops its worker (a new one takes its place), and the answer
is 504.
"""

from __future__ import annotations

import asyncio
import math
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any, TypeVar

from fastapi import Request, Response

from synth.errors import SolverTimeout
from synth.execution import Executor, make_executor

from ..media import Render, file_headers, negotiate
from .plans import Limits, Plan
from ..settings import Settings

T = TypeVar("T")


class Overloaded(Exception):
    """Every worker is busy and the queue is full; try again after ``retry_after_s``."""

    def __init__(self, capacity: int, retry_after_s: int) -> None:
        super().__init__(f"all {capacity} solver slots (workers and queue) are taken; retry in {retry_after_s} s")
        self.capacity = capacity
        self.retry_after_s = retry_after_s


def render_task(render: Render, fn: Callable[..., Any], args: tuple[Any, ...], kwargs: dict[str, Any]
                ) -> tuple[bytes, str]:
    """Worker side of a request: the engine call and its answer's bytes with their media type."""
    return render(fn(*args, **kwargs))


# One executor per configuration and process: apps built alike (tests, a reload) share their workers, and the
# last app to shut down stops them.
_EXECUTORS: dict[tuple[str, int, int], tuple[Executor, int]] = {}
_EXECUTORS_LOCK = threading.Lock()


def _acquire_executor(kind: str, workers: int, memory_limit_mb: int) -> Executor:
    key = (kind, workers, memory_limit_mb)
    with _EXECUTORS_LOCK:
        # Workers import the plans (schemas, exports) once in the fork server, not on their first request.
        executor, users = _EXECUTORS.get(key) or (
            make_executor(kind, workers, memory_limit_mb=memory_limit_mb, preload=["api.execution.plans"]), 0)
        _EXECUTORS[key] = (executor, users + 1)
        return executor


def _release_executor(executor: Executor) -> None:
    with _EXECUTORS_LOCK:
        for key, (shared, users) in list(_EXECUTORS.items()):
            if shared is executor:
                if users > 1:
                    _EXECUTORS[key] = (shared, users - 1)
                    return
                del _EXECUTORS[key]
        executor.shutdown()


class Solvers:
    """The service's executor (started on first use) with its admission bound and counters."""

    def __init__(self, settings: Settings) -> None:
        self.settings = settings
        self._executor: Executor | None = None
        self.in_flight = 0
        self.completed = 0
        self.timed_out = 0
        self.rejected = 0

    @property
    def executor(self) -> Executor:
        """The executor, started on first use so that importing the app spawns no process."""
        if self._executor is None:
            s = self.settings
            self._executor = _acquire_executor(s.executor, s.workers, s.worker_memory_mb)
        return self._executor

    @property
    def workers(self) -> int:
        """Worker count the executor has or will have."""
        if self._executor is not None:
            return self._executor.workers
        import os

        return 1 if self.settings.executor == "serial" else (self.settings.workers or os.cpu_count() or 1)

    @property
    def capacity(self) -> int:
        """Requests that may hold or wait for a worker at once."""
        return self.workers + self.settings.queue_size

    def status(self) -> dict[str, Any]:
        """Workers, queue and counters for ``/ready``; reads counters only, never waits on a worker."""
        return {
            "executor": self.settings.executor,
            "started": self._executor is not None,
            "workers": self.workers,
            "running": min(self.in_flight, self.workers),
            "queued": max(0, self.in_flight - self.workers),
            "capacity": self.capacity,
            "completed": self.completed,
            "timed_out": self.timed_out,
            "rejected": self.rejected,
        }

    def start(self) -> None:
        """Start the workers and wait until one has run a task, so the first request does not pay for it."""
        self.executor.submit(abs, 0.0).result()

    def shutdown(self) -> None:
        """Let go of the executor; its workers stop when no other app of this process uses them."""
        if self._executor is not None:
            executor, self._executor = self._executor, None
            _release_executor(executor)

    async def run(self, deadline: float, fn: Callable[..., T], /, *args: Any, **kwargs: Any) -> T:
        """Run ``fn(*args, **kwargs)`` as a task that must finish by ``deadline`` (``time.monotonic()`` seconds)."""
        if self.in_flight >= self.capacity:
            self.rejected += 1
            raise Overloaded(self.capacity, max(1, math.ceil(self.settings.request_deadline_s / 4)))
        self.in_flight += 1
        started = time.monotonic()
        remaining = deadline - started
        try:
            if remaining <= 0:
                raise SolverTimeout(self.settings.request_deadline_s, "the request's deadline passed before its "
                                    "solver work could start", stage="queued", elapsed_s=0.0)
            executor = self._executor
            if executor is None:  # starting the workers takes a second or two: never on the event loop
                executor = await asyncio.to_thread(lambda: self.executor)
            future = executor.submit(fn, *args, timeout=remaining, **kwargs)
            try:
                return await asyncio.wait_for(asyncio.wrap_future(future), timeout=remaining)
            except asyncio.TimeoutError:
                # wait_for cancelled the wrapped future; that cancels the task and stops its worker.
                self.timed_out += 1
                elapsed = time.monotonic() - started
                raise SolverTimeout(
                    self.settings.request_deadline_s,
                    f"the request's work did not finish within its deadline of "
                    f"{self.settings.request_deadline_s:g} s; its worker was stopped and replaced",
                    stage="running" if future.running() or future.cancelled() else "queued",
                    elapsed_s=round(elapsed, 3),
                ) from None
        finally:
            self.in_flight -= 1
            self.completed += 1


@dataclass(frozen=True, slots=True)
class RequestSolvers:
    """The solvers as one request sees them: every call shares the request's deadline."""

    solvers: Solvers
    deadline: float

    @property
    def settings(self) -> Settings:
        """The service settings."""
        return self.solvers.settings

    @property
    def limits(self) -> Limits:
        """The limits the request's plan runs under."""
        return Limits.from_settings(self.solvers.settings)

    async def run(self, fn: Callable[..., T], /, *args: Any, **kwargs: Any) -> T:
        """Run engine work in a worker and return its result (an engine object)."""
        return await self.solvers.run(self.deadline, fn, *args, **kwargs)

    async def answer(self, render: Render, fn: Callable[..., Any], /, *args: Any,
                     headers: dict[str, str] | None = None, **kwargs: Any) -> Response:
        """Run engine work in a worker and answer with the bytes ``render`` made of its result there."""
        content, media_type = await self.solvers.run(self.deadline, render_task, render, fn, args, kwargs)
        return Response(content=content, media_type=media_type, headers=headers)

    async def answer_plan(self, plan: Plan, request: Request, fmt: str | None = None) -> Response:
        """Answer with ``plan`` in the format the request asks for among those the plan offers."""
        chosen = negotiate(request, fmt, plan.offered)
        render = replace(plan.render, fmt=chosen)
        return await self.answer(render, plan.fn, *plan.args, headers=file_headers(chosen, plan.stem),
                                 **plan.kwargs)
