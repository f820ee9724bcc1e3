"""Running a study: variants batched into tasks of a fraction of a second to two seconds, a bounded number of
tasks in flight on any executor, each finished batch handed to a sink (the store) at once, cancel between tasks.

A task is :func:`run_batch`, a module-level function of plain data, so it runs unchanged in this process, on a
local worker pool or on a Dask worker. Each variant's outcome is a :class:`VariantRow`: its metrics, or the
engine's problem type and message when it cannot be built, assembled or solved; the study goes on. An endpoint
with a batched path (``batch_fn``: many requests in, one answer or problem per request out, the same answers as
the variant function's) runs a task's variants through it in one call, which shares the fixed cost of each
array operation and solver set-up among them.

A batch whose worker died (:class:`~synth.errors.WorkerLost`) or that ran past its deadline as a whole
(:class:`~synth.errors.SolverTimeout`) is run again one variant per task, so that the one variant that crashes
or hangs is the only row with that problem. A variant is run again at most once: a task of one variant that is
lost is its row.
"""

from __future__ import annotations

import collections
import concurrent.futures as cf
import logging
import math
import threading
import time
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ..errors import InvalidInput, SolverTimeout, SynthError, WorkerLost
from ..execution import Executor
from .model import StudyConstraint, Scalar, Study
from .paths import get_path
from .sampling import Sampler, variant_request

log = logging.getLogger("synth.studies")

VariantFn = Callable[[dict[str, Any]], Mapping[str, Any]]
#: Many requests in one call: per request its answer, or the exception the variant function would raise.
BatchFn = Callable[[list[dict[str, Any]]], Sequence[Mapping[str, Any] | BaseException]]

# Aim of a task's duration [s]: long enough that dispatch costs little, short enough that a cancel takes effect
# and an interactive request sharing the workers waits little.
TASK_TARGET_S = 0.5
TASK_RANGE_S = (0.2, 2.0)
MAX_BATCH = 5_000


@dataclass(frozen=True, slots=True)
class VariantRow:
    """One variant's outcome.

    Parameters
    ----------
    index
        Variant index in the study [-].
    values
        The varied parameters' values, in parameter order [unit of each field].
    metrics
        The collected metrics in metric order, None for all of them when the variant failed [unit of each metric].
    feasible
        Within every constraint (True when there are none); None when the variant failed [-].
    problem_type
        The engine's problem slug (``not-assemblable``, ``infeasible``, ...) when the variant failed [-].
    detail
        The problem's message [-].
    """

    index: int
    values: tuple[Scalar, ...]
    metrics: tuple[float | None, ...] | None
    feasible: bool | None
    problem_type: str | None = None
    detail: str | None = None

    @property
    def ok(self) -> bool:
        """True when the variant gave its metrics."""
        return self.problem_type is None


@dataclass(frozen=True, slots=True)
class BatchSpec:
    """What every task of a study needs besides its variants: plain data, sent with each task; ``batch_fn`` the
    endpoint's batched path, None when it has none."""

    variant_fn: VariantFn
    base: Mapping[str, Any]
    paths: tuple[str, ...]
    metrics: tuple[str, ...]
    constraints: tuple[StudyConstraint, ...]
    batch_fn: BatchFn | None = None


@dataclass(frozen=True, slots=True)
class RunReport:
    """How a run of a study went.

    Parameters
    ----------
    finished
        Variants written by this run (failed ones included) [-].
    failed
        Variants of this run that ended as a problem [-].
    tasks
        Tasks run [-].
    cancelled
        The run stopped on a cancel before every variant was written [-].
    elapsed_s
        Wall time of the run [s].
    task_s
        Median task duration measured in the workers [s].
    busy_s
        Sum of the task durations measured in the workers [s].
    retried
        Variants run again alone because their batch's worker died or the batch ran past its deadline [-].
    """

    finished: int
    failed: int
    tasks: int
    cancelled: bool
    elapsed_s: float
    task_s: float
    busy_s: float
    retried: int = 0


def _metric(answer: Mapping[str, Any], path: str) -> float | None:
    value = get_path(answer, path)
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InvalidInput(f"metric {path!r} is a {type(value).__name__} in the answer, not a number", field=path)
    value = float(value)
    return value if math.isfinite(value) else None


def _feasible(metrics: Sequence[float | None], names: Sequence[str], constraints: Sequence[StudyConstraint]) -> bool:
    for c in constraints:
        v = metrics[names.index(c.metric)]
        if v is None or (c.minimum is not None and v < c.minimum) or (c.maximum is not None and v > c.maximum):
            return False
    return True


def run_variant(spec: BatchSpec, index: int, values: Sequence[Scalar]) -> VariantRow:
    """Build, run and measure one variant; an engine problem becomes the row's problem."""
    try:
        answer = spec.variant_fn(variant_request(spec.base, spec.paths, values))
    except Exception as exc:
        # One variant's problem is its row; the rest of the batch and the study go on.
        return _failed_row(index, values, exc)
    return _answered_row(spec, index, values, answer)


def _answered_row(spec: BatchSpec, index: int, values: Sequence[Scalar], answer: Mapping[str, Any]) -> VariantRow:
    try:
        metrics = tuple(_metric(answer, m) for m in spec.metrics)
    except Exception as exc:
        return _failed_row(index, values, exc)
    return VariantRow(index, tuple(values), metrics, _feasible(metrics, spec.metrics, spec.constraints))


def run_batch(spec: BatchSpec, items: Sequence[tuple[int, Sequence[Scalar]]]) -> tuple[list[VariantRow], float]:
    """Task body: the rows of a batch of (index, values) and the batch's wall time in the worker [s].

    Through the endpoint's batched path when it has one and the batch has more than one variant; should that
    path fail as a whole, each variant runs alone.
    """
    t0 = time.perf_counter()
    rows = None
    if spec.batch_fn is not None and len(items) > 1:
        rows = _run_batched(spec, spec.batch_fn, items)
    if rows is None:
        rows = [run_variant(spec, i, v) for i, v in items]
    return rows, time.perf_counter() - t0


def _run_batched(spec: BatchSpec, batch_fn: BatchFn, items: Sequence[tuple[int, Sequence[Scalar]]]
                 ) -> list[VariantRow] | None:
    """The rows of ``items`` from one call of ``batch_fn``; None when that call fails as a whole."""
    rows: dict[int, VariantRow] = {}
    sent: list[tuple[int, int, Sequence[Scalar]]] = []
    requests: list[dict[str, Any]] = []
    for k, (index, values) in enumerate(items):
        try:
            requests.append(variant_request(spec.base, spec.paths, values))
        except Exception as exc:
            rows[k] = _failed_row(index, values, exc)
            continue
        sent.append((k, index, values))
    try:
        answers = batch_fn(requests)
        if len(answers) != len(requests):
            raise ValueError(f"the batched path answered {len(answers)} of {len(requests)} requests")
    except Exception:
        log.warning("the batched path failed on %d variants; running each alone", len(requests), exc_info=True)
        return None
    for (k, index, values), answer in zip(sent, answers, strict=True):
        rows[k] = (_failed_row(index, values, answer) if isinstance(answer, BaseException)
                   else _answered_row(spec, index, values, answer))
    return [rows[k] for k in range(len(items))]


def _failed_row(index: int, values: Sequence[Scalar], exc: BaseException) -> VariantRow:
    if isinstance(exc, SynthError):
        return VariantRow(index, tuple(values), None, None, exc.slug, str(exc))
    # An error no engine check anticipated: the traceback goes to the log, never into the results.
    log.error("variant %d failed unexpectedly", index, exc_info=exc)
    return VariantRow(index, tuple(values), None, None, "internal-error",
                      f"the variant failed unexpectedly ({type(exc).__name__}); the error was logged")


class _Sizer:
    """Batch size from the latest measured task: about TASK_TARGET_S per task, growing at most 8-fold a step."""

    def __init__(self) -> None:
        self.size = 1
        self.durations: list[float] = []

    def measured(self, count: int, seconds: float) -> None:
        self.durations.append(seconds)
        per_variant = max(seconds / max(count, 1), 1e-6)
        wanted = max(1, int(TASK_TARGET_S / per_variant))
        self.size = min(wanted, 8 * max(self.size, count), MAX_BATCH)


def _tail_size(size: int, unsent: int, in_flight: int) -> int:
    """The next task's size when ``unsent`` variants are left to send with ``in_flight`` tasks at a time: the
    measured ``size`` until the end is near, then a share of what is left (guided self-scheduling), so that the
    workers finish together instead of one running the last full task alone; never below an eighth of ``size``,
    where each task's fixed cost would start to tell."""
    share = math.ceil(unsent / (2 * in_flight))
    return max(1, min(size, max(share, size // 8)))


def run_study(study: Study, variant_fn: VariantFn, executor: Executor, sink: Callable[[list[VariantRow]], None], *,
              indices: Iterable[int] | None = None, cancel: threading.Event | None = None,
              in_flight: int | None = None, variant_timeout_s: float | None = None,
              progress: Callable[[int], None] | None = None, batch_fn: BatchFn | None = None) -> RunReport:
    """Run the variants of ``study`` (all, or only ``indices``) on ``executor``, writing rows through ``sink``.

    Parameters
    ----------
    study
        The study [-].
    variant_fn
        Module-level function of one request (a plain dict) returning the answer as a plain dict [-].
    executor
        Where tasks run (:mod:`synth.execution`) [-].
    sink
        Called in this thread with each finished batch's rows, in completion order [-].
    indices
        Variants to run, default all; a resumed study passes the missing ones [-].
    cancel
        When set, no further task is submitted and the tasks in flight are cancelled [-].
    in_flight
        Most tasks submitted at once, default the executor's workers and its spare tasks (one more on a local
        pool, twice as many on Dask): a worker that finishes starts the next batch without waiting for this
        thread, and requests sharing a pool's workers wait behind one batch at most [-].
    variant_timeout_s
        Time allowed per variant; a task may run its variant count times this [s].
    progress
        Called with the number of variants written so far by this run [-].
    batch_fn
        The endpoint's batched path: module-level, many requests (plain dicts) in, per request the answer or the
        exception ``variant_fn`` would give; a task's variants then run through it in one call [-].
    """
    t0 = time.perf_counter()
    sampler = Sampler(study)
    spec = BatchSpec(variant_fn, dict(study.base), study.parameter_paths, study.metrics, study.constraints,
                     batch_fn)
    order = range(sampler.count) if indices is None else list(indices)
    pending: Iterator[int] = iter(order)
    unsent = len(order)
    limit = max(1, in_flight or executor.workers + executor.spare_tasks)
    # what every task takes, sent to a cluster's workers once instead of with each task
    shared = executor.share(spec)
    sizer = _Sizer()
    futures: dict[cf.Future[tuple[list[VariantRow], float]], list[tuple[int, list[Scalar]]]] = {}
    # Variants of a lost batch, each to run again in a task of its own before any new batch.
    alone: collections.deque[tuple[int, list[Scalar]]] = collections.deque()
    finished = failed = tasks = retried = 0
    exhausted = cancelled = False
    stop = cancel or threading.Event()

    def submit() -> bool:
        nonlocal unsent
        if alone:
            items = [alone.popleft()]
        else:
            # The first task is sized 1 and measured before any other is sent, so a study of slow variants never
            # starts with long tasks.
            size = sizer.size if sizer.durations else 1
            if sizer.durations:
                size = _tail_size(size, unsent, limit)
            items = []
            for index in pending:
                items.append((index, sampler.values(index)))
                if len(items) >= size:
                    break
            if not items:
                return False
            unsent -= len(items)
        timeout = None if variant_timeout_s is None else variant_timeout_s * len(items)
        futures[executor.submit(run_batch, shared, items, timeout=timeout)] = items
        return True

    try:
        while True:
            if stop.is_set():
                cancelled = True
                break
            while (alone or not exhausted) and len(futures) < (limit if sizer.durations else 1):
                exhausted = not submit() or exhausted
            if not futures:
                break
            done, _ = cf.wait(list(futures), timeout=0.1, return_when=cf.FIRST_COMPLETED)
            for future in done:
                items = futures.pop(future)
                tasks += 1
                try:
                    rows, seconds = future.result()
                    sizer.measured(len(items), seconds)
                except cf.CancelledError:
                    continue
                except Exception as exc:
                    if isinstance(exc, (WorkerLost, SolverTimeout)) and len(items) > 1:
                        # One variant that crashes its worker or hangs must not take its batch with it.
                        log.warning("a batch of %d variants was lost (%s); running each alone", len(items), exc)
                        alone.extend(items)
                        retried += len(items)
                        continue
                    # A task of one variant lost, or failed as a whole otherwise: the cause is each variant's row.
                    rows = [_failed_row(i, v, exc) for i, v in items]
                sink(rows)
                finished += len(rows)
                failed += sum(not r.ok for r in rows)
                if progress is not None:
                    progress(finished)
    finally:
        for future in futures:
            future.cancel()
    durations = sorted(sizer.durations)
    median = durations[len(durations) // 2] if durations else 0.0
    return RunReport(finished, failed, tasks, cancelled, time.perf_counter() - t0, median, sum(durations), retried)
