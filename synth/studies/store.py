"""Studies and their rows in SQLite (the standard library's sqlite3, WAL mode): a restart loses nothing that
finished, and rows go to disk batch by batch instead of piling up in memory.

Each call opens its own short connection, so the store is used safely from the web process's threads and from
the thread that drives a study; WAL lets readers page through results while a study writes.
"""

from __future__ import annotations

import json
import sqlite3
import time
import uuid
from collections.abc import Iterator, Mapping, Sequence
from contextlib import closing, contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..model import FloatArray
from .runner import VariantRow

STATES = ("queued", "running", "done", "cancelled", "interrupted", "failed")
ACTIVE = ("queued", "running")

_SCHEMA = """
CREATE TABLE IF NOT EXISTS studies (
    id TEXT PRIMARY KEY,
    spec TEXT NOT NULL,
    total INTEGER NOT NULL,
    state TEXT NOT NULL,
    created_at REAL NOT NULL,
    run_started_at REAL,
    run_start_done INTEGER NOT NULL DEFAULT 0,
    elapsed_s REAL NOT NULL DEFAULT 0,
    message TEXT
);
CREATE TABLE IF NOT EXISTS rows (
    study_id TEXT NOT NULL REFERENCES studies(id),
    idx INTEGER NOT NULL,
    params TEXT NOT NULL,
    metrics TEXT,
    feasible INTEGER,
    problem_type TEXT,
    detail TEXT,
    PRIMARY KEY (study_id, idx)
) WITHOUT ROWID;
"""


@dataclass(frozen=True, slots=True)
class StudyRecord:
    """A stored study and its progress.

    Parameters
    ----------
    id
        The study's id [-].
    spec
        The study as submitted (plain JSON-like data) [-].
    total
        Variants in the study [-].
    state
        ``queued``, ``running``, ``done``, ``cancelled``, ``interrupted`` or ``failed`` [-].
    done
        Variants with a row (failed ones included) [-].
    failed
        Variants whose row is a problem [-].
    created_at
        Creation time, seconds since the epoch [s].
    elapsed_s
        Running time over all runs so far [s].
    eta_s
        Estimated time to finish the current run, None when not running or not yet measurable [s].
    message
        Why a study failed or stopped, when it did [-].
    """

    id: str
    spec: Mapping[str, Any]
    total: int
    state: str
    done: int
    failed: int
    created_at: float
    elapsed_s: float
    eta_s: float | None
    message: str | None


class StudyStore:
    """Studies and rows in the SQLite file at ``path`` (created when missing)."""

    def __init__(self, path: str | Path) -> None:
        self.path = str(path)
        with closing(self._connect()) as db:
            db.execute("PRAGMA journal_mode=WAL")
            db.executescript(_SCHEMA)

    def _connect(self) -> sqlite3.Connection:
        db = sqlite3.connect(self.path, timeout=30.0)
        db.execute("PRAGMA synchronous=NORMAL")
        return db

    @contextmanager
    def _tx(self) -> Iterator[sqlite3.Connection]:
        with closing(self._connect()) as db, db:
            yield db

    def create(self, spec: Mapping[str, Any], total: int) -> str:
        """Store a new study, queued; its id."""
        study_id = uuid.uuid4().hex
        with self._tx() as db:
            db.execute("INSERT INTO studies (id, spec, total, state, created_at) VALUES (?, ?, ?, 'queued', ?)",
                       (study_id, json.dumps(spec), total, time.time()))
        return study_id

    def get(self, study_id: str) -> StudyRecord | None:
        """The study with its progress, or None when there is no such study."""
        with self._tx() as db:
            row = db.execute("SELECT spec, total, state, created_at, run_started_at, run_start_done, elapsed_s, "
                             "message FROM studies WHERE id = ?", (study_id,)).fetchone()
            if row is None:
                return None
            done, failed = db.execute("SELECT COUNT(*), COUNT(problem_type) FROM rows WHERE study_id = ?",
                                      (study_id,)).fetchone()
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
        with self._tx() as db:
            ids = [i for (i,) in db.execute("SELECT id FROM studies ORDER BY created_at DESC, id LIMIT ? OFFSET ?",
                                            (limit, offset))]
        return [r for r in (self.get(i) for i in ids) if r is not None]

    def started(self, study_id: str) -> None:
        """Mark a study running from now."""
        with self._tx() as db:
            (done,) = db.execute("SELECT COUNT(*) FROM rows WHERE study_id = ?", (study_id,)).fetchone()
            db.execute("UPDATE studies SET state = 'running', run_started_at = ?, run_start_done = ?, message = NULL "
                       "WHERE id = ?", (time.time(), done, study_id))

    def stopped(self, study_id: str, state: str, message: str | None = None) -> None:
        """End a run in ``state``, adding its running time to the study's."""
        if state not in STATES:
            raise ValueError(f"unknown study state {state!r}")
        with self._tx() as db:
            db.execute("UPDATE studies SET state = ?, message = ?, "
                       "elapsed_s = elapsed_s + COALESCE(? - run_started_at, 0), run_started_at = NULL "
                       "WHERE id = ?", (state, message, time.time(), study_id))

    def checkpoint(self, study_id: str) -> None:
        """Add a running study's time since its start or last checkpoint to its elapsed time."""
        with self._tx() as db:
            now = time.time()
            db.execute("UPDATE studies SET elapsed_s = elapsed_s + (? - run_started_at), run_started_at = ? "
                       "WHERE id = ? AND run_started_at IS NOT NULL", (now, now, study_id))

    def mark_interrupted(self) -> int:
        """Studies left running or queued by a stopped service become ``interrupted``; how many. Their elapsed
        time keeps what the last checkpoint counted: the time since, the service's down time with it, is not
        running time."""
        with self._tx() as db:
            cursor = db.execute(
                "UPDATE studies SET state = 'interrupted', message = 'the service stopped while it ran', "
                "run_started_at = NULL WHERE state IN ('queued', 'running')")
            return cursor.rowcount

    def write_rows(self, study_id: str, rows: Sequence[VariantRow]) -> None:
        """Store a batch of rows in one transaction; a row already there is replaced."""
        with self._tx() as db:
            db.executemany(
                "INSERT OR REPLACE INTO rows (study_id, idx, params, metrics, feasible, problem_type, detail) "
                "VALUES (?, ?, ?, ?, ?, ?, ?)",
                [(study_id, r.index, json.dumps(list(r.values)),
                  None if r.metrics is None else json.dumps(list(r.metrics)),
                  None if r.feasible is None else int(r.feasible), r.problem_type, r.detail) for r in rows])

    def missing(self, study_id: str, total: int) -> list[int]:
        """Indices of the variants that have no row yet, ascending."""
        with self._tx() as db:
            have = np.fromiter((i for (i,) in db.execute("SELECT idx FROM rows WHERE study_id = ?", (study_id,))),
                               dtype=np.int64)
        mask = np.ones(total, dtype=bool)
        mask[have[(have >= 0) & (have < total)]] = False
        return [int(i) for i in np.flatnonzero(mask)]

    def rows(self, study_id: str, offset: int = 0, limit: int | None = None) -> list[VariantRow]:
        """Rows in index order, from ``offset``, at most ``limit``."""
        with self._tx() as db:
            cursor = db.execute("SELECT idx, params, metrics, feasible, problem_type, detail FROM rows "
                                "WHERE study_id = ? ORDER BY idx LIMIT ? OFFSET ?",
                                (study_id, -1 if limit is None else limit, offset))
            return [_row(r) for r in cursor]

    def iter_rows(self, study_id: str, chunk: int = 2_000) -> Iterator[VariantRow]:
        """Every row in index order, read ``chunk`` at a time (for exports that must not hold them all)."""
        last = -1
        while True:
            with self._tx() as db:
                batch = [_row(r) for r in db.execute(
                    "SELECT idx, params, metrics, feasible, problem_type, detail FROM rows "
                    "WHERE study_id = ? AND idx > ? ORDER BY idx LIMIT ?", (study_id, last, chunk))]
            if not batch:
                return
            yield from batch
            last = batch[-1].index

    def metric_table(self, study_id: str, width: int) -> tuple[NDArray[np.int64], FloatArray, NDArray[np.bool_]]:
        """Index, metrics (NaN where missing; ``width`` columns) and feasibility of every variant that gave its
        metrics, in index order: the arrays a front or a figure needs, without the rest of the rows."""
        with self._tx() as db:
            table = db.execute("SELECT idx, metrics, feasible FROM rows WHERE study_id = ? AND metrics IS NOT NULL "
                               "ORDER BY idx", (study_id,)).fetchall()
        index = np.array([r[0] for r in table], dtype=np.int64)
        values = np.array([[np.nan if v is None else v for v in json.loads(r[1])] for r in table],
                          dtype=float).reshape(len(table), width)
        return index, values, np.array([bool(r[2]) for r in table], dtype=bool)

    def rows_at(self, study_id: str, indices: Sequence[int]) -> list[VariantRow]:
        """The rows of the given variant indices, in index order."""
        out: list[VariantRow] = []
        with self._tx() as db:
            for start in range(0, len(indices), 500):
                chunk = [int(i) for i in indices[start:start + 500]]
                out += [_row(r) for r in db.execute(
                    "SELECT idx, params, metrics, feasible, problem_type, detail FROM rows WHERE study_id = ? "
                    f"AND idx IN ({','.join('?' * len(chunk))})", (study_id, *chunk))]
        return sorted(out, key=lambda r: r.index)


def _row(r: tuple[Any, ...]) -> VariantRow:
    idx, params, metrics, feasible, problem_type, detail = r
    return VariantRow(int(idx), tuple(json.loads(params)), None if metrics is None else tuple(json.loads(metrics)),
                      None if feasible is None else bool(feasible), problem_type, detail)
