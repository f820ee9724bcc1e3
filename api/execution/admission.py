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
import os
import tempfile
import threading
import time
from collections.abc import Awaitable, Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, replace
from typing import Any, TypeVar

from fastapi import Request, Response
from fastapi.responses import StreamingResponse

from synth.errors import SolverTimeout
from synth.execution import BATCH, Executor, LocalPoolExecutor, make_executor

from ..media import Precision, Render, file_headers, negotiate
from .held import HeldResults
from .plans import Limits, Plan
from .warm import warm_worker
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


@dataclass(frozen=True, slots=True)
class Spooled:
    """A large answer the worker wrote to a file instead of sending it through the pipe: its path, size [bytes]
    and media type. The web process streams it from the file and removes the file."""

    path: str
    size: int
    media_type: str


#: The formats written from a held result rather than by designing again.
DOCUMENTS = frozenset({"pdf", "png"})


def answer_task(render: Render, spool_above: int, fn: Callable[..., Any], args: tuple[Any, ...],
                kwargs: dict[str, Any]) -> tuple[bytes, str] | Spooled:
    """Worker side of a request whose answer may be large: beyond ``spool_above`` bytes it goes to a file."""
    return _spooled(render_task(render, fn, args, kwargs), spool_above)


def kept_answer_task(render: Render, spool_above: int, fn: Callable[..., Any], args: tuple[Any, ...],
                     kwargs: dict[str, Any]) -> tuple[tuple[bytes, str] | Spooled, Any]:
    """:func:`answer_task` that also sends the engine's result back, for the web process to hold."""
    result = fn(*args, **kwargs)
    return _spooled(render(result), spool_above), result


def given(result: T) -> T:
    """The engine's work already done: its result as it was held."""
    return result


def _spooled(answer: tuple[bytes, str], spool_above: int) -> tuple[bytes, str] | Spooled:
    content, media_type = answer
    if len(content) <= spool_above:
        return content, media_type
    fd, path = tempfile.mkstemp(prefix="synth-answer-", suffix=".part")
    with os.fdopen(fd, "wb") as f:
        f.write(content)
    return Spooled(path, len(content), media_type)


_CHUNK_BYTES = 256 * 1024


def _file_chunks(f: Any) -> Iterator[bytes]:
    with f:
        while chunk := f.read(_CHUNK_BYTES):
            yield chunk


def spooled_response(spooled: Spooled, headers: dict[str, str] | None) -> Response:
    """Stream a spooled answer a chunk at a time; the file is unlinked at once (the open file keeps its data
    until the answer is sent or the client goes away)."""
    f = open(spooled.path, "rb")
    os.unlink(spooled.path)
    return StreamingResponse(_file_chunks(f), media_type=spooled.media_type,
                             headers={**(headers or {}), "content-length": str(spooled.size)})



# One executor per configuration and process: apps built alike (tests, a reload) share their workers, and the
# last app to shut down stops them.
_EXECUTORS: dict[tuple[Any, ...], tuple[Executor, int]] = {}
_EXECUTORS_LOCK = threading.Lock()


def _batch_workers(settings: Settings, workers: int) -> int:
    """Workers of the study lane: none (shared with requests), the setting, or as many as the request workers."""
    if settings.study_lane == "shared":
        return 0
    return settings.study_workers or workers


def _acquire_executor(settings: Settings) -> Executor:
    s = settings
    workers = s.workers or os.cpu_count() or 1
    warm = warm_worker if s.warm_workers else None
    key = (s.executor, workers, s.worker_memory_mb, _batch_workers(s, workers), s.study_nice, warm)
    with _EXECUTORS_LOCK:
        # Workers import the plans (schemas, exports) once in the fork server, not on their first request.
        executor, users = _EXECUTORS.get(key) or (
            make_executor(s.executor, workers, memory_limit_mb=s.worker_memory_mb, preload=["api.execution.plans"],
                          batch_workers=_batch_workers(s, workers), batch_nice=s.study_nice, warm=warm), 0)
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
        self.held = HeldResults()

    @property
    def executor(self) -> Executor:
        """The executor, started on first use so that importing the app spawns no process."""
        if self._executor is None:
            self._executor = _acquire_executor(self.settings)
        return self._executor

    def batch(self, owner: str) -> Executor:
        """Where one owner's study tasks run: the pool's study lane (owners taking turns), else the executor."""
        executor = self.executor
        if isinstance(executor, LocalPoolExecutor):
            return executor.lane(BATCH, owner)
        return executor

    @property
    def workers(self) -> int:
        """Worker count the executor has or will have."""
        if self._executor is not None:
            return self._executor.workers
        return 1 if self.settings.executor == "serial" else (self.settings.workers or os.cpu_count() or 1)

    @property
    def capacity(self) -> int:
        """Requests that may hold or wait for a worker at once."""
        return self.workers + self.settings.queue_size

    def status(self) -> dict[str, Any]:
        """Workers, queue and counters for ``/ready``; reads counters only, never waits on a worker."""
        serial = self.settings.executor == "serial"
        pool: dict[str, Any] = {"workers_alive": self.workers if serial else 0,
                                "workers_warm": self.workers if serial else 0, "worker_restarts": 0}
        if isinstance(self._executor, LocalPoolExecutor):
            pool = self._executor.status()
        return {**pool,
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
        """Start the workers and wait until every request worker is warm (bounded by ``warm_limit_s``) and one has
        run a task, so the first requests do not pay for imports and compiled programs."""
        executor = self.executor
        if isinstance(executor, LocalPoolExecutor) and self.settings.warm_workers:
            executor.wait_warm(self.settings.warm_limit_s)
        executor.submit(abs, 0.0).result()

    def shutdown(self) -> None:
        """Let go of the executor; its workers stop when no other app of this process uses them."""
        if self._executor is not None:
            executor, self._executor = self._executor, None
            _release_executor(executor)

    async def run(self, deadline: float, fn: Callable[..., T], /, *args: Any, **kwargs: Any) -> T:
        """Run ``fn(*args, **kwargs)`` as a task that must finish by ``deadline`` (``time.monotonic()`` seconds)."""
        return (await self.run_on(deadline, None, fn, *args, **kwargs))[0]

    async def run_on(self, deadline: float, prefer: str | None, fn: Callable[..., T], /, *args: Any,
                     **kwargs: Any) -> tuple[T, str | None]:
        """:meth:`run` on the worker named ``prefer`` rather than another when both could take it (None: any);
        the result and the name of the worker that ran it (None where workers have no names)."""
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
            future = executor.submit(fn, *args, timeout=remaining, prefer=prefer, **kwargs)
            waiter = asyncio.wrap_future(future)
            done, _ = await asyncio.wait({waiter}, timeout=remaining)
            if waiter in done:
                return waiter.result(), getattr(future, "worker", None)
            # Read before cancelling: a task that never left the queue is "queued", one a worker took "running".
            ran = future.running() or getattr(future, "started_at", None) is not None
            waiter.cancel()  # cancels the task; a running one has its worker stopped and replaced
            self.timed_out += 1
            elapsed = time.monotonic() - started
            raise SolverTimeout(
                self.settings.request_deadline_s,
                f"the request's work did not finish within its deadline of "
                f"{self.settings.request_deadline_s:g} s"
                + ("; its worker was stopped and replaced" if ran else "; it never reached a worker"),
                stage="running" if ran else "queued",
                elapsed_s=round(elapsed, 3),
            )
        finally:
            self.in_flight -= 1
            self.completed += 1


async def in_turn(calls: Sequence[Callable[[], Awaitable[T]]], at_once: int) -> list[T]:
    """Await the engine calls ``calls`` makes, at most ``at_once`` in flight, the next one started as soon as one
    ends, and return their results in order: the workers stay evenly busy whatever each call costs, and the
    request holds no more of the service's slots than that. A failure cancels the others, as :func:`together`."""
    pending = iter(enumerate(calls))
    results: dict[int, T] = {}

    async def lane() -> None:
        for i, call in pending:
            results[i] = await call()

    await together(lane() for _ in range(max(1, min(at_once, len(calls)))))
    return [results[i] for i in range(len(calls))]


async def together(calls: Iterable[Awaitable[T]]) -> list[T]:
    """Await engine calls side by side and return their results in order; when one fails (a timeout, a lost
    worker) the others' work is moot: they are cancelled and the failure raised."""
    tasks = [asyncio.ensure_future(c) for c in calls]
    try:
        return list(await asyncio.gather(*tasks))
    except BaseException:
        for task in tasks:
            task.cancel()
        raise


@dataclass(frozen=True, slots=True)
class RequestSolvers:
    """The solvers as one request sees them: every call shares the request's deadline, and every answer is
    written with the digits the request asks for."""

    solvers: Solvers
    deadline: float
    precision: Precision = "single"

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

    async def run_on(self, prefer: str | None, fn: Callable[..., T], /, *args: Any,
                     **kwargs: Any) -> tuple[T, str | None]:
        """:meth:`run` on the worker named ``prefer`` rather than another (one that kept what an earlier task of
        the same work computed); the result and the worker that ran it."""
        return await self.solvers.run_on(self.deadline, prefer, fn, *args, **kwargs)

    async def answer(self, render: Render, fn: Callable[..., Any], /, *args: Any,
                     headers: dict[str, str] | None = None, **kwargs: Any) -> Response:
        """Run engine work in a worker and answer with the bytes ``render`` made of its result there."""
        answer = await self.solvers.run(self.deadline, answer_task, render, self.settings.spool_above_bytes, fn,
                                        args, kwargs)
        if isinstance(answer, Spooled):
            return spooled_response(answer, headers)
        content, media_type = answer
        return Response(content=content, media_type=media_type, headers=headers)

    async def answer_plan(self, plan: Plan, request: Request, fmt: str | None = None) -> Response:
        """Answer with ``plan`` in the format the request asks for among those the plan offers."""
        chosen = negotiate(request, fmt, plan.offered)
        render = replace(plan.render, fmt=chosen, max_bytes=self.settings.max_answer_bytes, precision=self.precision)
        return await self.answer(render, plan.fn, *plan.args, headers=file_headers(chosen, plan.stem),
                                 **plan.kwargs)

    async def answer_held(self, plan: Plan, request: Request, fmt: str | None, key: tuple[str, str]) -> Response:
        """:meth:`answer_plan` for a plan whose result the process holds under ``key`` (the user and the hash of
        the canonical request): a document (PDF, PNG) of a result held is only rendered (no engine work); a JSON
        answer is always designed anew, so its time is the design's, and held."""
        chosen = negotiate(request, fmt, plan.offered)
        render = replace(plan.render, fmt=chosen, max_bytes=self.settings.max_answer_bytes, precision=self.precision)
        spool = self.settings.spool_above_bytes
        held = self.solvers.held.get(key) if chosen in DOCUMENTS else None
        if held is not None:
            answer = await self.solvers.run(self.deadline, answer_task, render, spool, given, (held,), {})
        else:
            answer, result = await self.solvers.run(self.deadline, kept_answer_task, render, spool, plan.fn,
                                                    plan.args, plan.kwargs)
            self.solvers.held.put(key, result)
        headers = file_headers(chosen, plan.stem)
        if isinstance(answer, Spooled):
            return spooled_response(answer, headers)
        content, media_type = answer
        return Response(content=content, media_type=media_type, headers=headers)
