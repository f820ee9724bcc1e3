"""Design studies in the background of the service: one thread per running study drives the engine's runner,
so the event loop only reads the store; rows go to the store batch by batch.

Studies run on the service's own executor, or on a Dask cluster when ``SYNTH_DASK_SCHEDULER`` is set. Each
running study is held by this process's lease, renewed by a heartbeat thread; several service processes may
share one store. A study whose lease lapsed (its process stopped) is marked ``interrupted`` by whichever process
looks first; resuming one takes it with an atomic claim, so exactly one process runs the variants that have no
row yet.

Study tasks go to the executor's study lane, beside the requests' admission bound (a study never gets 503):
each running study keeps at most one task more than there are study workers in flight, and ``/ready`` counts
them. At most ``max_running_studies`` run at once; the others wait as ``queued``, and owners take turns for the
places that free up (the owner with the fewest running studies first, then the one served longest ago), so one
owner's many studies cannot keep another's waiting. A study's estimated work (its variants times the estimated
work of one, :mod:`api.execution.work`) is bounded, and so is the sum over one owner's queued and running ones.
"""

from __future__ import annotations

import collections
import concurrent.futures as cf
import dataclasses
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
import sqlalchemy as sa
from numpy.typing import NDArray
from starlette.exceptions import HTTPException

import synth
from synth.errors import InvalidInput, SynthError, TooLarge
from synth.model import FloatArray
from synth.execution import DaskExecutor, Executor

from store import LeaseLost, SqlStudyStore, Store, StoreUnavailable

from ..settings import Settings
from ..storage import open_store
from ..execution.admission import Solvers
from ..execution.plans import Limits
from ..execution.work import describe_s, estimate_s, finite
from .paths import check_metrics
from .tasks import batch_function, validate_request, variant_function

log = logging.getLogger("api.studies")

T = TypeVar("T")


class StudyFinished(Exception):
    """A finished study has nothing left to run: a 409 problem response."""

    def __init__(self, study_id: str) -> None:
        super().__init__(f"study {study_id} is done: every variant has its row, there is nothing to resume")
        self.study_id = study_id


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
        self.spare_tasks = executor.spare_tasks
        self._executor = executor
        self._in_flight = in_flight

    def submit(self, fn: Callable[..., T], /, *args: Any, timeout: float | None = None, prefer: str | None = None,
               **kwargs: Any) -> cf.Future[T]:
        """Submit to the executor and count the task."""
        future = self._executor.submit(fn, *args, timeout=timeout, prefer=prefer, **kwargs)
        self._in_flight.add(future)
        return future

    def share(self, value: Any) -> Any:
        """``value`` as the executor shares it."""
        return self._executor.share(value)

    def shutdown(self) -> None:
        """Nothing to stop: the executor is the service's (or the Dask connection's), not one study's."""


@dataclass
class _Run:
    thread: threading.Thread
    owner: str
    cancel: threading.Event = field(default_factory=threading.Event)
    reason: str = "cancelled"
    # when this process's claim on the study was taken (monotonic clock); None until then
    claimed_at: float | None = None


@dataclass(frozen=True, slots=True)
class _Waiting:
    study_id: str
    owner: str
    study: synth.Study
    indices: list[int] | None


# Variants whose requests are estimated to find a study's most expensive one (evenly spread, ends included).
_ESTIMATE_PROBES = 16


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
        self._waiting: list[_Waiting] = []
        self._served: dict[str, int] = {}  # owner -> turn at which one of its studies last started
        self._turn = 0
        self._work: dict[str, tuple[str, float]] = {}  # queued or running study -> (owner, estimated work [s])
        self._closing = False
        self._tasks = _InFlight()
        # runs that ended while the store could not record their end: recorded when it answers again
        self._unrecorded: dict[str, tuple[str, str | None]] = {}
        self._lock = threading.RLock()
        # Connecting to a scheduler can take its whole timeout; the store stays reachable meanwhile.
        self._dask_lock = threading.Lock()

    @property
    def store(self) -> SqlStudyStore:
        """The studies in the store; the first use marks studies whose process stopped as interrupted."""
        with self._lock:
            if self._store is None:
                store = SqlStudyStore(self._db, lease_s=self.settings.study_lease_s)
                try:
                    self._sweep(store)
                except StoreUnavailable as exc:
                    # a store that answers reads but takes no writes (read-only, locked) still shows its studies;
                    # the heartbeat sweeps once it takes writes again
                    log.error("studies left running by a stopped service are not swept yet: %s", exc)
                    self._db.ping()
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
                self._record_ends()
                asked = time.monotonic()
                with self._lock:
                    ours = set(self._runs) | {w.study_id for w in self._waiting}
                held = self.store.renew(ours)
                with self._lock:
                    lost = [run for study_id, run in self._runs.items() if study_id not in held
                            and run.claimed_at is not None and run.claimed_at < asked]
                for run in lost:
                    # cancelled through another process, or taken by one after this process stalled past its
                    # lease: either way this run stops (and its end is recorded only if the study is still ours)
                    run.reason = "cancelled"
                    run.cancel.set()
                self._sweep(self.store)
                with self._lock:
                    self._dispatch()
            except (StoreUnavailable, sa.exc.DBAPIError) as exc:
                log.warning("the study leases were not renewed: %s", exc)
            except Exception:
                log.exception("the study leases were not renewed")

    def _record_ends(self) -> None:
        """Record the ends of runs that stopped while the store could not take them (the oldest first)."""
        with self._lock:
            pending = list(self._unrecorded.items())
        for study_id, (state, message) in pending:
            self.store.stopped(study_id, state, message)
            with self._lock:
                self._unrecorded.pop(study_id, None)
            log.warning("design study %s: its end (%s) is recorded now that the store answers", study_id, state)

    def executor(self, owner: str = "anonymous") -> Executor:
        """Where study tasks run: the Dask cluster when one is configured, else the service's study lane."""
        if self.settings.dask_scheduler is None:
            return self.solvers.batch(owner)
        with self._dask_lock:
            if self._dask is None:
                self._dask = DaskExecutor(self.settings.dask_scheduler)
            return self._dask

    def status(self) -> dict[str, Any]:
        """Running studies, their tasks in flight and where those run, for ``/ready``; never waits on a study."""
        # Read without the lock (one length each): /ready never waits behind a study being stored or started.
        running, queued = len(self._runs), len(self._waiting)
        return {"studies_running": running, "studies_queued": queued, "study_tasks_in_flight": self._tasks.count,
                "study_tasks_on": "workers" if self.settings.dask_scheduler is None else "dask"}

    def create(self, spec: dict[str, Any], owner: str | None = None) -> synth.StudyRecord:
        """Check a study (its metrics against the endpoint's answer, its size before anything is generated, its
        base request against the endpoint, its estimated work and its owner's), store it and queue it; it starts
        at once when a running place is free."""
        owner = owner or str(spec.get("owner") or "anonymous")
        spec = {**spec, "owner": owner}
        study = synth.study_from_dict(spec)
        check_metrics(spec["endpoint"], study.metrics)
        total = study.check_size(self.settings.max_study_variants)
        validate_request(spec["endpoint"], _first_variant(study), field="base")
        work = self._estimate(spec["endpoint"], study, total)
        with self._lock:
            owned = sum(w for o, w in self._work.values() if o == owner)
            if owned + work > self.settings.max_owner_work_s:
                raise TooLarge("owner's estimated study work [s]", int(self.settings.max_owner_work_s),
                               int(owned + work),
                               f"this study's estimated work ({describe_s(work)}) and that of {owner!r}'s queued "
                               f"and running studies ({describe_s(owned)}) pass the bound of "
                               f"{describe_s(self.settings.max_owner_work_s)} per owner: wait for them to finish "
                               "or cancel one", field="owner")
            study_id = self.store.create(spec, total)
            self._work[study_id] = (owner, work)
            self._waiting.append(_Waiting(study_id, owner, study, None))
            self._dispatch()
        return self.get(study_id)

    def _estimate(self, endpoint: str, study: synth.Study, total: int) -> float:
        """The study's estimated work [s]: its variant count times the costliest of a few spread variants;
        TooLarge beyond the bound of one study."""
        sampler = synth.Sampler(study)
        probes = sorted({round(k * (total - 1) / max(1, _ESTIMATE_PROBES - 1)) for k in range(_ESTIMATE_PROBES)})
        per_variant = 0.0
        for index in probes:
            request = synth.studies.variant_request(study.base, study.parameter_paths, sampler.values(index))
            try:
                body = validate_request(endpoint, request)
            except InvalidInput:
                continue  # a variant the endpoint refuses costs nothing: it becomes a problem row
            per_variant = max(per_variant, finite(estimate_s(endpoint, body)))
        work = finite(per_variant * total)
        if work > self.settings.max_study_work_s:
            raise TooLarge("study estimated work [s]", int(self.settings.max_study_work_s), int(min(work, 2**62)),
                           f"{total} variants of {endpoint} at up to {describe_s(per_variant)} each: about "
                           f"{describe_s(work)} of work, beyond the bound of "
                           f"{describe_s(self.settings.max_study_work_s)} per study: fewer variants (samples, "
                           "counts or values) or cheaper variants (fewer crank angles, smaller searches)",
                           field="parameters")
        return work

    def position(self, study_id: str) -> int | None:
        """A queued study's place in the queue (1: the next to start); None when it is not waiting."""
        with self._lock:
            for place, waiting in enumerate(self._order(), start=1):
                if waiting.study_id == study_id:
                    return place
        return None

    def positions(self) -> dict[str, int]:
        """Every queued study's place in the queue."""
        with self._lock:
            return {w.study_id: place for place, w in enumerate(self._order(), start=1)}

    def _order(self) -> list[_Waiting]:
        """The waiting studies in the order they will start: owners take turns (fewest running studies first,
        then the one served longest ago), each owner's studies first in, first out."""
        running = collections.Counter(run.owner for run in self._runs.values())
        served = dict(self._served)
        queues: dict[str, collections.deque[_Waiting]] = {}
        for waiting in self._waiting:
            queues.setdefault(waiting.owner, collections.deque()).append(waiting)
        out: list[_Waiting] = []
        turn = self._turn
        while queues:
            owner = min(queues, key=lambda o: (running[o], served.get(o, -1)))
            out.append(queues[owner].popleft())
            running[owner] += 1
            served[owner] = turn = turn + 1
            if not queues[owner]:
                del queues[owner]
        return out

    def _dispatch(self) -> None:
        """Start waiting studies while running places are free (called with the lock held)."""
        while not self._closing and self._waiting and len(self._runs) < self.settings.max_running_studies:
            nxt = self._order()[0]
            self._waiting.remove(nxt)
            try:
                self._start(nxt.study_id, nxt.study, nxt.indices, nxt.owner)
            except (StoreUnavailable, sa.exc.DBAPIError) as exc:
                # the claim could not be written: the study keeps its place, the heartbeat tries again
                self._waiting.insert(0, nxt)
                log.warning("design study %s waits for the store to start: %s", nxt.study_id, exc)
                return
            self._turn += 1
            self._served[nxt.owner] = self._turn

    def get(self, study_id: str) -> synth.StudyRecord:
        """The stored study with its progress; :class:`StudyNotFound` when there is none."""
        record = self.store.get(study_id)
        if record is None:
            raise StudyNotFound(study_id)
        return self._queued(record)

    def recent(self, limit: int, offset: int) -> list[synth.StudyRecord]:
        """The latest studies first."""
        return [self._queued(r) for r in self.store.recent(limit, offset)]

    def _queued(self, record: synth.StudyRecord) -> synth.StudyRecord:
        """A resumed study waiting for its turn is queued, whatever its stored state until its run starts."""
        if record.state != "queued" and any(w.study_id == record.id for w in list(self._waiting)):
            return dataclasses.replace(record, state="queued", message=None)
        return record

    def cancel(self, study_id: str) -> synth.StudyRecord:
        """Stop a study: no new task is sent, tasks in flight are cancelled, finished rows stay."""
        record = self.get(study_id)
        with self._lock:
            run = self._runs.get(study_id)
            waiting = next((w for w in self._waiting if w.study_id == study_id), None)
            if waiting is not None:
                self._waiting.remove(waiting)
                self._work.pop(study_id, None)
                self.store.stopped(study_id, "cancelled", "cancelled before it started")
                return self.get(study_id)
        if run is not None:
            run.reason = "cancelled"
            run.cancel.set()
            run.thread.join(timeout=10.0)
        elif record.state in ("queued", "running"):
            # run by another process sharing the store: it stops when it next renews its lease
            self.store.cancel(study_id)
        elif record.state == "interrupted":
            self.store.stopped(study_id, "cancelled", "cancelled before it finished")
        return self.get(study_id)

    def resume(self, study_id: str) -> synth.StudyRecord:
        """Run the variants of a stopped study that have no row yet; a running study is left as is,
        :class:`StudyFinished` for a finished one."""
        self._record_ends()
        self._sweep(self.store)
        record = self.get(study_id)
        if record.state == "done":
            raise StudyFinished(study_id)
        if record.state in ("cancelled", "interrupted", "failed"):
            study = synth.study_from_dict(record.spec)
            owner = str(record.spec.get("owner") or "anonymous")
            missing = self.store.missing(study_id, record.total)
            work = self._estimate(record.spec["endpoint"], study, record.total) * len(missing) / max(1, record.total)
            with self._lock:
                if study_id in self._runs or any(w.study_id == study_id for w in self._waiting):
                    return self.get(study_id)  # two resumes at once queue one run
                # The store keeps its stopped state until the run claims it: shown as queued meanwhile.
                self._work[study_id] = (owner, work)
                self._waiting.append(_Waiting(study_id, owner, study, missing))
                self._dispatch()
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
            self._closing = True
            runs = list(self._runs.values())
            self._waiting.clear()  # stored as queued: the next start marks them interrupted
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

    def _start(self, study_id: str, study: synth.Study, indices: list[int] | None, owner: str) -> None:
        """Start a study's run (called with the lock held)."""
        thread = threading.Thread(target=self._drive, args=(study_id, study, indices, owner), daemon=True,
                                  name=f"study-{study_id[:8]}")
        if study_id in self._runs:
            return  # two resumes at once start one run
        self._runs[study_id] = _Run(thread, owner)
        try:
            claimed = self.store.claim(study_id)
        except BaseException:
            self._runs.pop(study_id, None)
            raise
        if not claimed:
            # another process holds the study (its lease is live) or it is done: that process's run goes on
            self._runs.pop(study_id, None)
            return
        self._runs[study_id].claimed_at = time.monotonic()
        if indices is not None:
            # rows written between the look and the claim (a process that stopped while writing) are not redone
            indices = self.store.missing(study_id, study.variant_count)
        thread = threading.Thread(target=self._drive, args=(study_id, study, indices, owner), daemon=True,
                                  name=f"study-{study_id[:8]}")
        self._runs[study_id].thread = thread
        thread.start()

    def _drive(self, study_id: str, study: synth.Study, indices: list[int] | None, owner: str) -> None:
        with self._lock:
            run = self._runs[study_id]
        state, message = "failed", None
        try:
            endpoint = self.store.get(study_id).spec["endpoint"]  # type: ignore[union-attr]
            report = synth.run_study(
                study, variant_function(endpoint, Limits.from_settings(self.settings)),
                _Counted(self.executor(owner), self._tasks),
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
            # cancelled through another process, or taken by one after this process stalled past its lease
            log.warning("design study %s was cancelled or taken over elsewhere; this run stops", study_id)
            state, message = "cancelled", "cancelled; finished variants are kept"
        except (StoreUnavailable, sa.exc.DBAPIError) as exc:
            # the store failed under the run (locked, read-only, unreachable): its rows so far are kept and
            # resuming runs the rest
            log.warning("design study %s stopped: the store failed while it ran: %s", study_id, exc)
            state, message = "interrupted", "the store failed while it ran; resume it to run the rest"
        except Exception as exc:
            # A study-wide failure (the Dask scheduler unreachable, the store's disk full) ends this study only.
            log.exception("design study %s failed", study_id)
            message = f"the study stopped on an unexpected error ({type(exc).__name__}); the error was logged"
        finally:
            try:
                # a no-op when another process holds the study now
                self.store.stopped(study_id, state, message)
            except Exception as exc:
                # recorded by the heartbeat once the store answers; until then its lease is no longer renewed,
                # so it is swept as interrupted if this process stops first
                log.warning("design study %s: its end (%s) waits for the store: %s", study_id, state, exc)
                with self._lock:
                    self._unrecorded[study_id] = (state, message)
            with self._lock:
                self._runs.pop(study_id, None)
                self._work.pop(study_id, None)
                self._dispatch()


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
