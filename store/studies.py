"""Studies and their variant rows in the store, each running study held by a lease.

A process running a study holds its lease (``lease_owner``, ``lease_expires``) and renews it while it runs; a
process that finds a lease lapsed knows the study's process stopped. Taking a study to run is one conditional
UPDATE whose row count says whether this process won it, so two processes never run one study at once, and a
batch of rows is written only while the lease is still this process's.
"""

from __future__ import annotations

import json
import os
import socket
import time
import uuid
from collections.abc import Collection, Iterator, Mapping, Sequence
from typing import Any

import numpy as np
import sqlalchemy as sa
from numpy.typing import NDArray

from synth.model import FloatArray
from synth.studies.runner import VariantRow
from synth.studies.store import STATES, StudyRecord

from .db import Store
from .schema import studies, study_rows

_ROW_COLUMNS = (study_rows.c.idx, study_rows.c.params, study_rows.c.metrics, study_rows.c.feasible,
                study_rows.c.problem_type, study_rows.c.detail)
# Rows per statement when fetching given indices: well under every engine's bound on parameters.
_IN_CHUNK = 500


class LeaseLost(Exception):
    """This process no longer holds the study's lease (it lapsed and another process took the study)."""

    def __init__(self, study_id: str) -> None:
        super().__init__(f"the lease on study {study_id} is no longer this process's; its rows are not written")
        self.study_id = study_id


def process_owner() -> str:
    """A lease owner name unique to this process: host, process id and a random part (process ids are reused)."""
    return f"{socket.gethostname()[:100]}:{os.getpid()}:{uuid.uuid4().hex[:8]}"


class SqlStudyStore:
    """Studies in ``store``; ``owner`` names this process's leases, which last ``lease_s`` from each renewal."""

    def __init__(self, store: Store, owner: str | None = None, lease_s: float = 30.0) -> None:
        self.store = store
        self.owner = owner or process_owner()
        self.lease_s = lease_s

    def create(self, spec: Mapping[str, Any], total: int) -> str:
        """Store a new study, queued and held by this process; its id."""
        study_id = uuid.uuid4().hex
        now = time.time()
        with self.store.write() as db:
            db.execute(studies.insert().values(id=study_id, spec=json.dumps(spec), total=total, state="queued",
                                               created_at=now, lease_owner=self.owner,
                                               lease_expires=now + self.lease_s))
        return study_id

    def get(self, study_id: str) -> StudyRecord | None:
        """The study with its progress, or None when there is no such study."""
        with self.store.read() as db:
            return self._get(db, study_id)

    def _get(self, db: sa.Connection, study_id: str) -> StudyRecord | None:
        s = studies.c
        row = db.execute(sa.select(s.spec, s.total, s.state, s.created_at, s.run_started_at, s.run_start_done,
                                   s.elapsed_s, s.message).where(s.id == study_id)).one_or_none()
        if row is None:
            return None
        done, failed = db.execute(sa.select(sa.func.count(), sa.func.count(study_rows.c.problem_type))
                                  .where(study_rows.c.study_id == study_id)).one()
        spec, total, state, created, started, start_done, elapsed, message = row
        eta = None
        if state == "running" and started is not None:
            run_s = max(time.time() - started, 0.0)
            elapsed += run_s
            if done > start_done and done < total:
                eta = run_s / (done - start_done) * (total - done)
        return StudyRecord(study_id, json.loads(spec), total, state, done, failed, created, elapsed, eta, message)

    def recent(self, limit: int = 100, offset: int = 0) -> list[StudyRecord]:
        """The latest studies first, with their progress."""
        with self.store.read() as db:
            ids = db.scalars(sa.select(studies.c.id).order_by(studies.c.created_at.desc(), studies.c.id)
                             .limit(limit).offset(offset)).all()
            return [r for r in (self._get(db, i) for i in ids) if r is not None]

    def claim(self, study_id: str) -> bool:
        """Mark a study running from now under this process's lease; False when another process's lease on it is
        live or the study is done (then nothing changes)."""
        s = studies.c
        now = time.time()
        with self.store.write() as db:
            done = db.execute(sa.select(sa.func.count()).where(study_rows.c.study_id == study_id)).scalar_one()
            taken = db.execute(
                studies.update()
                .where(s.id == study_id, s.state != "done",
                       sa.or_(s.lease_owner.is_(None), s.lease_owner == self.owner, s.lease_expires < now))
                .values(state="running", run_started_at=now, run_start_done=done, message=None,
                        lease_owner=self.owner, lease_expires=now + self.lease_s))
            return taken.rowcount == 1

    def renew(self, ids: Collection[str] | None = None) -> set[str]:
        """Extend this process's leases on its queued and running studies (only those of ``ids`` when given: a run
        that died without recording its end is not kept alive, so its lease lapses and it is swept as
        interrupted); the ids still held."""
        s = studies.c
        mine = sa.and_(s.lease_owner == self.owner, s.state.in_(("queued", "running")))
        wanted = None if ids is None else sorted(ids)
        chunks = [mine] if wanted is None else [sa.and_(mine, s.id.in_(wanted[k:k + _IN_CHUNK]))
                                                for k in range(0, len(wanted), _IN_CHUNK)]
        held: set[str] = set()
        with self.store.write() as db:
            for where in chunks:
                db.execute(studies.update().where(where).values(lease_expires=time.time() + self.lease_s))
                held |= set(db.scalars(sa.select(s.id).where(where)).all())
        return held

    def stopped(self, study_id: str, state: str, message: str | None = None) -> None:
        """End a run in ``state``, adding its running time to the study's and releasing the lease.

        A study another process holds now (this process's lease lapsed and it was taken) is left as that process
        has it.
        """
        if state not in STATES:
            raise ValueError(f"unknown study state {state!r}")
        s = studies.c
        now = time.time()
        with self.store.write() as db:
            db.execute(studies.update()
                       .where(s.id == study_id, sa.or_(s.lease_owner.is_(None), s.lease_owner == self.owner))
                       .values(state=state, message=message,
                               elapsed_s=s.elapsed_s + sa.func.coalesce(now - s.run_started_at, 0.0),
                               run_started_at=None, lease_owner=None, lease_expires=None))

    def cancel(self, study_id: str) -> bool:
        """Cancel a queued or running study whichever process runs it: its rows are refused from now on and its
        process stops the run when it next renews its lease. False when it was not queued or running."""
        with self.store.write() as db:
            return db.execute(studies.update().where(studies.c.id == study_id,
                                                     studies.c.state.in_(("queued", "running")))
                              .values(state="cancelled", message="cancelled; finished variants are kept")
                              ).rowcount == 1

    def sweep(self) -> int:
        """Studies queued or running whose lease lapsed (their process stopped) become ``interrupted``; how many.
        A study whose lease is live is another process's, running: it is left alone."""
        s = studies.c
        now = time.time()
        # the smaller of two values: SQLite's two-argument min(), PostgreSQL's least()
        least = sa.func.min if self.store.dialect == "sqlite" else sa.func.least
        greatest = sa.func.max if self.store.dialect == "sqlite" else sa.func.greatest
        with self.store.write() as db:
            swept = db.execute(
                studies.update()
                .where(s.state.in_(("queued", "running")),
                       sa.or_(s.lease_expires.is_(None), s.lease_expires < now))
                .values(state="interrupted", message="the service stopped while it ran",
                        # the run is known to have gone on until its lease was last renewed (a batch written, a
                        # heartbeat): neither the rest of the lease nor the time the service was down is running
                        elapsed_s=s.elapsed_s + greatest(0.0, sa.func.coalesce(
                            least(now, sa.func.coalesce(s.lease_expires - self.lease_s, now)) - s.run_started_at,
                            0.0)),
                        run_started_at=None, lease_owner=None, lease_expires=None))
            return swept.rowcount

    def write_rows(self, study_id: str, rows: Sequence[VariantRow]) -> None:
        """Store a batch of rows in one transaction, renewing this process's lease on the study;
        :class:`LeaseLost` (and nothing written) when the study is no longer this process's."""
        s = studies.c
        with self.store.write() as db:
            held = db.execute(studies.update()
                              .where(s.id == study_id, s.lease_owner == self.owner, s.state == "running")
                              .values(lease_expires=time.time() + self.lease_s))
            if held.rowcount != 1:
                raise LeaseLost(study_id)
            if rows:
                db.execute(study_rows.insert(), [
                    {"study_id": study_id, "idx": r.index, "params": json.dumps(list(r.values)),
                     "metrics": None if r.metrics is None else json.dumps(list(r.metrics)),
                     "feasible": r.feasible, "problem_type": r.problem_type, "detail": r.detail} for r in rows])

    def missing(self, study_id: str, total: int) -> list[int]:
        """Indices of the variants that have no row yet, ascending."""
        with self.store.read() as db:
            have = np.fromiter(db.scalars(sa.select(study_rows.c.idx).where(study_rows.c.study_id == study_id)),
                               dtype=np.int64)
        mask = np.ones(total, dtype=bool)
        mask[have[(have >= 0) & (have < total)]] = False
        return [int(i) for i in np.flatnonzero(mask)]

    def rows(self, study_id: str, offset: int = 0, limit: int | None = None) -> list[VariantRow]:
        """Rows in index order, from ``offset``, at most ``limit``."""
        query = (sa.select(*_ROW_COLUMNS).where(study_rows.c.study_id == study_id).order_by(study_rows.c.idx)
                 .offset(offset))
        if limit is not None:
            query = query.limit(limit)
        with self.store.read() as db:
            return [_row(r) for r in db.execute(query)]

    def iter_rows(self, study_id: str, chunk: int = 2_000) -> Iterator[VariantRow]:
        """Every row in index order, read ``chunk`` at a time, each chunk in its own short transaction (keyset
        paging: no transaction is held open while the consumer is slow)."""
        last = -1
        while True:
            with self.store.read() as db:
                batch = [_row(r) for r in db.execute(
                    sa.select(*_ROW_COLUMNS).where(study_rows.c.study_id == study_id, study_rows.c.idx > last)
                    .order_by(study_rows.c.idx).limit(chunk))]
            if not batch:
                return
            yield from batch
            last = batch[-1].index

    def metric_table(self, study_id: str, width: int) -> tuple[NDArray[np.int64], FloatArray, NDArray[np.bool_]]:
        """Index, metrics (NaN where missing; ``width`` columns) and feasibility of every variant that gave its
        metrics, in index order: the arrays a front or a figure needs, without the rest of the rows."""
        r = study_rows.c
        with self.store.read() as db:
            table = db.execute(sa.select(r.idx, r.metrics, r.feasible)
                               .where(r.study_id == study_id, r.metrics.is_not(None)).order_by(r.idx)).all()
        index = np.array([t[0] for t in table], dtype=np.int64)
        values = np.array([[np.nan if v is None else v for v in json.loads(t[1])] for t in table],
                          dtype=float).reshape(len(table), width)
        return index, values, np.array([bool(t[2]) for t in table], dtype=bool)

    def rows_at(self, study_id: str, indices: Sequence[int]) -> list[VariantRow]:
        """The rows of the given variant indices, in index order."""
        out: list[VariantRow] = []
        with self.store.read() as db:
            for start in range(0, len(indices), _IN_CHUNK):
                chunk = [int(i) for i in indices[start:start + _IN_CHUNK]]
                out += [_row(r) for r in db.execute(
                    sa.select(*_ROW_COLUMNS).where(study_rows.c.study_id == study_id, study_rows.c.idx.in_(chunk)))]
        return sorted(out, key=lambda r: r.index)


def _row(r: Sequence[Any]) -> VariantRow:
    idx, params, metrics, feasible, problem_type, detail = r
    return VariantRow(int(idx), tuple(json.loads(params)), None if metrics is None else tuple(json.loads(metrics)),
                      None if feasible is None else bool(feasible), problem_type, detail)
