"""Design studies in the background of the service: one thread per running study drives the engine's runner,
so the event loop only reads the store; rows go to the store batch by batch.

Studies run on the service's own executor, or on a Dask cluster when ``SYNTH_DASK_SCHEDULER`` is set. Each
running study is held by this process's lease, renewed by a heartbeat thread; several service processes may
share one store. A study whose lease lapsed (its process stopped) is marked ``interrupted`` by whichever process
looks first; resuming one takes it with an atomic claim, so exactly one process runs the variants that have no
row yet.

Study tasks go to the executor directly, beside the requests' admission bound (a study never gets 503): each
running study keeps at most one task more than there are workers in flight, and ``/ready`` counts them.
"""

from __future__ import annotations

import concurrent.futures as cf
import csv
import io
import logging
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from functools import partial
from typing import Any, TypeVar

import numpy as np
from numpy.typing import NDArray
from starlette.exceptions import HTTPException

import synth
from synth.errors import InvalidInput, SynthError
from synth.model import FloatArray
from synth.execution import DaskExecutor, Executor

from store import LeaseLost, SqlStudyStore, Store, StoreUnavailable

from ..settings import Settings
from ..storage import open_store
from ..execution.admission import Solvers
from ..execution.plans import Limits
from .paths import check_metrics
from .tasks import batch_function, validate_request, variant_function

log = logging.getLogger("api.studies")

T = TypeVar("T")


class StudyNotFound(HTTPException):
    """No study has this id: a 404 problem response."""

    def __init__(self, study_id: str) -> None:
        super().__init__(404, f"no study with id {study_id!r}")
        self.study_id = study_id


@dataclass(frozen=True, slots=True)
class Front:
    """A study's Pareto front: the stored study, its feasible candidates and the rows on the front."""

    record: synth.StudyRecord
    candidates: int
    rows: list[synth.VariantRow]


@dataclass(frozen=True, slots=True)
class Scatter:
    """What the scatter figure of two metrics needs, as plain arrays for a worker."""

    x: FloatArray
    y: FloatArray
    feasible: NDArray[np.bool_]
    front: NDArray[np.bool_]
    x_label: str
    y_label: str
    title: str
    staircase: str | None


class _InFlight:
    """Study tasks submitted and not yet finished, over every running study."""

    def __init__(self) -> None:
        self.count = 0
        self._lock = threading.Lock()

    def add(self, future: cf.Future[Any]) -> None:
        with self._lock:
            self.count += 1
        future.add_done_callback(self._finished)

    def _finished(self, _: cf.Future[Any]) -> None:
        with self._lock:
            self.count -= 1


class _Counted:
    """``executor`` with every task it is given counted in ``in_flight`` until the task finishes."""

    def __init__(self, executor: Executor, in_flight: _InFlight) -> None:
        self.workers = executor.workers
        self._executor = executor
        self._in_flight = in_flight

    def submit(self, fn: Callable[..., T], /, *args: Any, timeout: float | None = None,
               **kwargs: Any) -> cf.Future[T]:
        """Submit to the executor and count the task."""
        future = self._executor.submit(fn, *args, timeout=timeout, **kwargs)
        self._in_flight.add(future)
        return future

    def shutdown(self) -> None:
        """Nothing to stop: the executor is the service's (or the Dask connection's), not one study's."""


@dataclass
class _Run:
    thread: threading.Thread
    cancel: threading.Event = field(default_factory=threading.Event)
    reason: str = "cancelled"
    # when this process's claim on the study was taken (monotonic clock); None until then
    claimed_at: float | None = None


class StudyRuns:
    """The studies of one service: the store (opened at start or on first use), the running studies and where
    their tasks run."""

    def __init__(self, settings: Settings, solvers: Solvers, store: Store | None = None) -> None:
        self.settings = settings
        self.solvers = solvers
        self._db = store or open_store(settings)
        self._store: SqlStudyStore | None = None
        self._heartbeat: threading.Thread | None = None
        self._stopping = threading.Event()
        self._dask: Executor | None = None
        self._runs: dict[str, _Run] = {}
        self._tasks = _InFlight()
        self._lock = threading.Lock()
        # Connecting to a scheduler can take its whole timeout; the store stays reachable meanwhile.
        self._dask_lock = threading.Lock()

    @property
    def store(self) -> SqlStudyStore:
        """The studies in the store; the first use marks studies whose process stopped as interrupted."""
        with self._lock:
            if self._store is None:
                store = SqlStudyStore(self._db, lease_s=self.settings.study_lease_s)
                self._sweep(store)
                self._store = store
            return self._store

    @staticmethod
    def _sweep(store: SqlStudyStore) -> None:
        if count := store.sweep():
            log.warning("%d design studies were interrupted by a stopped service; resume them with "
                        "POST /v1/studies/{id}/resume", count)

    def open(self) -> None:
        """At start: show studies a stopped service left running as interrupted (when the store answers), and
        start the heartbeat that renews this process's leases."""
        try:
            _ = self.store
        except StoreUnavailable as exc:
            log.error("design studies wait for the store: %s", exc)
        self._heartbeat = threading.Thread(target=self._beat, daemon=True, name="study-leases")
        self._heartbeat.start()

    def _beat(self) -> None:
        """Every third of the lease: renew this process's leases, stop a run whose lease another process took,
        and mark studies whose process stopped as interrupted."""
        while not self._stopping.wait(self.settings.study_lease_s / 3):
            try:
                asked = time.monotonic()
                held = self.store.renew()
                with self._lock:
                    lost = [run for study_id, run in self._runs.items() if study_id not in held
                            and run.claimed_at is not None and run.claimed_at < asked]
                for run in lost:
                    run.reason = "lost"
                    run.cancel.set()
                self._sweep(self.store)
            except StoreUnavailable as exc:
                log.warning("the study leases were not renewed: %s", exc)
            except Exception:
                log.exception("the study leases were not renewed")

    def executor(self) -> Executor:
        """Where study tasks run: the Dask cluster when one is configured, else the service's workers."""
        if self.settings.dask_scheduler is None:
            return self.solvers.executor
        with self._dask_lock:
            if self._dask is None:
                self._dask = DaskExecutor(self.settings.dask_scheduler)
            return self._dask

    def status(self) -> dict[str, Any]:
        """Running studies, their tasks in flight and where those run, for ``/ready``; never waits on a study."""
        with self._lock:
            running = len(self._runs)
        return {"studies_running": running, "study_tasks_in_flight": self._tasks.count,
                "study_tasks_on": "workers" if self.settings.dask_scheduler is None else "dask"}

    def create(self, spec: dict[str, Any]) -> synth.StudyRecord:
        """Check a study (its metrics against the endpoint's answer, its size before anything is generated, its
        base request against the endpoint), store it and start it."""
        study = synth.study_from_dict(spec)
        check_metrics(spec["endpoint"], study.metrics)
        total = study.check_size(self.settings.max_study_variants)
        validate_request(spec["endpoint"], _first_variant(study), field="base")
        study_id = self.store.create(spec, total)
        self._start(study_id, study, None)
        return self.get(study_id)

    def get(self, study_id: str) -> synth.StudyRecord:
        """The stored study with its progress; :class:`StudyNotFound` when there is none."""
        record = self.store.get(study_id)
        if record is None:
            raise StudyNotFound(study_id)
        return record

    def recent(self, limit: int, offset: int) -> list[synth.StudyRecord]:
        """The latest studies first."""
        return self.store.recent(limit, offset)

    def cancel(self, study_id: str) -> synth.StudyRecord:
        """Stop a study: no new task is sent, tasks in flight are cancelled, finished rows stay."""
        record = self.get(study_id)
        with self._lock:
            run = self._runs.get(study_id)
        if run is not None:
            run.reason = "cancelled"
            run.cancel.set()
            run.thread.join(timeout=10.0)
        elif record.state in ("queued", "interrupted"):
            self.store.stopped(study_id, "cancelled", "cancelled before it finished")
        return self.get(study_id)

    def resume(self, study_id: str) -> synth.StudyRecord:
        """Run the variants of a stopped study that have no row yet; a running or finished study is left as is."""
        self._sweep(self.store)
        record = self.get(study_id)
        if record.state in ("cancelled", "interrupted", "failed"):
            study = synth.study_from_dict(record.spec)
            self._start(study_id, study, self.store.missing(study_id, record.total))
        return self.get(study_id)

    def page(self, study_id: str, offset: int, limit: int) -> tuple[synth.StudyRecord, list[synth.VariantRow]]:
        """The study and ``limit`` of its rows from ``offset``, in index order."""
        record = self.get(study_id)
        return record, self.store.rows(study_id, offset, limit)

    def csv(self, study_id: str) -> Iterator[str]:
        """The study's rows as CSV text, a chunk of rows at a time (never all of them in memory)."""
        spec = self.get(study_id).spec
        paths, metrics = [p["path"] for p in spec["parameters"]], list(spec["metrics"])

        def chunks() -> Iterator[str]:
            buffer = io.StringIO()
            writer = csv.writer(buffer, lineterminator="\n")
            writer.writerow(["index", *paths, *metrics, "feasible", "problem_type", "detail"])
            for n, row in enumerate(self.store.iter_rows(study_id), start=1):
                values = row.metrics if row.metrics is not None else [None] * len(metrics)
                writer.writerow([row.index, *row.values, *("" if v is None else repr(v) for v in values),
                                 "" if row.feasible is None else int(row.feasible),
                                 "" if row.ok else f"/problems/{row.problem_type}", row.detail or ""])
                if n % 1000 == 0:
                    yield buffer.getvalue()
                    buffer.seek(0)
                    buffer.truncate()
            yield buffer.getvalue()

        return chunks()

    def pareto(self, study_id: str) -> Front:
        """The feasible variants that no other feasible variant beats in every objective, in index order."""
        record = self.get(study_id)
        study = synth.study_from_dict(record.spec)
        if not study.objectives:
            raise InvalidInput("the study has no objectives, so it has no Pareto front; give objectives "
                               "(metric -> min or max) when creating it", field="objectives")
        index, values, feasible = self.store.metric_table(study_id, len(study.metrics))
        on_front, candidates = _front(study, values, feasible)
        return Front(record, int(candidates.sum()), self.store.rows_at(study_id, index[on_front].tolist()))

    def scatter(self, study_id: str, x: str | None, y: str | None) -> Scatter:
        """Two metrics of every variant that gave both, whether it is feasible and on the front."""
        record = self.get(study_id)
        study = synth.study_from_dict(record.spec)
        defaults = list(study.objectives) + [m for m in study.metrics if m not in study.objectives]
        x = x or defaults[0]
        y = y or next((m for m in defaults if m != x), x)
        for axis, name in (("x", x), ("y", y)):
            if name not in study.metrics:
                raise InvalidInput(f"{axis}={name!r} is not one of the study's metrics {list(study.metrics)}",
                                   field=axis)
        _, values, feasible = self.store.metric_table(study_id, len(study.metrics))
        on_front = _front(study, values, feasible)[0] if study.objectives else np.zeros(len(values), dtype=bool)
        xs, ys = values[:, study.metrics.index(x)], values[:, study.metrics.index(y)]
        shown = ~(np.isnan(xs) | np.isnan(ys))
        senses = dict(study.objectives)
        staircase = f"{senses[x]}{senses[y]}" if set(senses) == {x, y} and x != y else None
        done = f"{record.done} of {record.total} variants" + (f", {record.failed} failed" if record.failed else "")
        return Scatter(xs[shown], ys[shown], feasible[shown], on_front[shown], x, y,
                       f"{record.spec.get('name') or record.spec['endpoint']}: {done}", staircase)

    def shutdown(self) -> None:
        """Stop every running study (they become interrupted and can be resumed) before the workers stop."""
        self._stopping.set()
        with self._lock:
            runs = list(self._runs.values())
        for run in runs:
            run.reason = "interrupted"
            run.cancel.set()
        for run in runs:
            run.thread.join(timeout=10.0)
        if self._heartbeat is not None:
            self._heartbeat.join(timeout=10.0)
        if self._dask is not None:
            self._dask.shutdown()
            self._dask = None

    def _start(self, study_id: str, study: synth.Study, indices: list[int] | None) -> None:
        thread = threading.Thread(target=self._drive, args=(study_id, study, indices), daemon=True,
                                  name=f"study-{study_id[:8]}")
        with self._lock:
            if study_id in self._runs:
                return  # two resumes at once start one run
            self._runs[study_id] = _Run(thread)
        try:
            claimed = self.store.claim(study_id)
        except BaseException:
            with self._lock:
                self._runs.pop(study_id, None)
            raise
        if not claimed:
            # another process holds the study (its lease is live) or it is done: that process's run goes on
            with self._lock:
                self._runs.pop(study_id, None)
            return
        with self._lock:
            self._runs[study_id].claimed_at = time.monotonic()
        if indices is not None:
            # rows written between the look and the claim (a process that stopped while writing) are not redone
            indices = self.store.missing(study_id, study.variant_count)
        thread.start()

    def _drive(self, study_id: str, study: synth.Study, indices: list[int] | None) -> None:
        with self._lock:
            run = self._runs[study_id]
        endpoint = self.store.get(study_id).spec["endpoint"]  # type: ignore[union-attr]
        state, message, release = "failed", None, True
        try:
            report = synth.run_study(
                study, variant_function(endpoint, Limits.from_settings(self.settings)),
                _Counted(self.executor(), self._tasks),
                partial(self.store.write_rows, study_id), indices=indices, cancel=run.cancel,
                variant_timeout_s=self.settings.request_deadline_s,
                batch_fn=batch_function(endpoint, Limits.from_settings(self.settings)),
            )
            record = self.store.get(study_id)
            if report.cancelled and record is not None and record.done < record.total:
                state = run.reason
                message = ("cancelled; finished variants are kept" if run.reason == "cancelled"
                           else "the service stopped while it ran")
            else:
                state = "done"
        except SynthError as exc:
            message = str(exc)
        except LeaseLost:
            # the lease lapsed (this process stalled past it) and another process took the study: it is theirs
            log.warning("design study %s was taken over by another process; this run stops", study_id)
            release = False
        except Exception as exc:
            # A study-wide failure (the Dask scheduler unreachable, the store's disk full) ends this study only.
            log.exception("design study %s failed", study_id)
            message = f"the study stopped on an unexpected error ({type(exc).__name__}); the error was logged"
        finally:
            if release and run.reason != "lost":
                self.store.stopped(study_id, state, message)
            with self._lock:
                self._runs.pop(study_id, None)


def _front(study: synth.Study, values: FloatArray, feasible: NDArray[np.bool_]
           ) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """Per variant of a metric table: on the front, and a candidate (feasible, every objective present)."""
    columns = [i for i, _ in study.senses]
    candidates = feasible & ~np.isnan(values[:, columns]).any(axis=1)
    on_front = np.zeros(len(values), dtype=bool)
    on_front[candidates] = synth.pareto_mask(values[candidates][:, columns], [s for _, s in study.senses],
                                             study.objective_digits)
    return on_front, candidates


def scatter_png(s: Scatter) -> bytes:
    """Worker side of the study figure."""
    from synth.studies.plots import pareto_png

    return pareto_png(s.x, s.y, s.feasible, s.front, s.x_label, s.y_label, s.title, s.staircase)


def _first_variant(study: synth.Study) -> dict[str, Any]:
    return synth.studies.variant_request(study.base, study.parameter_paths, synth.Sampler(study).values(0))
