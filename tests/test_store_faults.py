"""A real service whose store misbehaves under a running design study: a SQLite file locked by another writer past
the store's busy wait, a PostgreSQL database turned read-only (ALTER DATABASE ... default_transaction_read_only,
its connections terminated), and PostgreSQL connections killed as they are made. Meanwhile reads answer, writes
answer 503 with Retry-After and the reason within a bounded time (never a 500, never the request's deadline), and
/ready says the store is degraded; afterwards the study is no longer running (its end recorded, or swept once its
lease lapsed), resuming it runs the rest once, and every variant has exactly one row. A service killed outright
is tests/test_store_processes.py's case."""

from __future__ import annotations

import sqlite3
import sys
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import httpx
import psycopg
import pytest
import sqlalchemy as sa

from mechsynth_client.schemas.library import SAVE_EXAMPLE
from service import running_process
from store import Store
from store.db import SQLITE_BUSY_S
from store_engines import Cluster, pg_cluster  # noqa: F401  (fixture)
from test_store_processes import SPEC, TOTAL, _wait

LEASE_S = 1.5
FAULT_S = SQLITE_BUSY_S + 2.0      # longer than a writer waits for the lock: the study's writes fail under it
DESIGN = "/v1/library/projects/faults/designs/crank/revisions"


def _command(port: int) -> list[str]:
    return [sys.executable, "-m", "uvicorn", "api.app:app", "--host", "127.0.0.1", "--port", str(port)]


@contextmanager
def _sqlite_locked(path: str) -> Iterator[None]:
    """Another process's writer holds the file's write lock."""
    holder = sqlite3.connect(path, isolation_level=None, timeout=30)
    holder.execute("BEGIN IMMEDIATE")
    try:
        yield
    finally:
        holder.execute("ROLLBACK")
        holder.close()


def _admin(cluster: Cluster) -> psycopg.Connection[Any]:
    return psycopg.connect(f"host=127.0.0.1 port={cluster.port} user=synth dbname=postgres", autocommit=True)


@contextmanager
def _pg_read_only(cluster: Cluster, database: str) -> Iterator[None]:
    """The database turned read-only and every connection to it terminated (so new ones are read-only)."""
    with _admin(cluster) as admin:
        admin.execute(f'ALTER DATABASE "{database}" SET default_transaction_read_only = on')
        admin.execute("SELECT pg_terminate_backend(pid) FROM pg_stat_activity WHERE datname = %s", (database,))
        try:
            yield
        finally:
            admin.execute(f'ALTER DATABASE "{database}" SET default_transaction_read_only = off')
            admin.execute("SELECT pg_terminate_backend(pid) FROM pg_stat_activity WHERE datname = %s", (database,))


@contextmanager
def _pg_connections_killed(cluster: Cluster, database: str) -> Iterator[None]:
    """Every connection to the database terminated as soon as it is seen, for as long as the block runs."""
    stop = threading.Event()

    def kill() -> None:
        with _admin(cluster) as admin:
            while not stop.is_set():
                admin.execute("SELECT pg_terminate_backend(pid) FROM pg_stat_activity WHERE datname = %s",
                              (database,))
                time.sleep(0.05)

    killer = threading.Thread(target=kill, daemon=True)
    killer.start()
    try:
        yield
    finally:
        stop.set()
        killer.join(timeout=10)


def _rows(url: str) -> tuple[int, int]:
    """The study's rows and distinct variant indices, read from the store itself."""
    store = Store(url)
    try:
        with store.read() as db:
            count, distinct = db.execute(sa.text("SELECT count(*), count(DISTINCT idx) FROM study_rows")).one()
        return int(count), int(distinct)
    finally:
        store.dispose()


def _during_fault(base: str, study: str, writes_fail: bool) -> None:
    """While the store misbehaves: a read answers (or says the store is unavailable), a write answers 503 with
    Retry-After and the reason well before the request's deadline, /ready names the store, no 500 anywhere."""
    started = time.monotonic()
    read = httpx.get(f"{base}{study}", timeout=60)
    assert read.status_code in (200, 503), read.text
    saved = httpx.post(f"{base}{DESIGN}", json=SAVE_EXAMPLE, timeout=60)
    took = time.monotonic() - started
    if writes_fail:
        assert saved.status_code == 503, saved.text
        assert saved.headers["retry-after"] and saved.json()["reason"], saved.text
        # the store's busy wait (5 s) plus the read, not the 30 s request deadline
        assert took < SQLITE_BUSY_S + 10, took
        ready = httpx.get(f"{base}/ready", timeout=30)
        assert ready.json()["store_ok"] is False or "store" in ready.json()["degraded"], ready.text
    else:
        assert saved.status_code in (201, 503), saved.text


def _run_through(store_url: str, env: dict[str, str], tmp_path: Path, fault: Callable[[], Any],
                 writes_fail: bool) -> None:
    with running_process(_command, tmp_path, env=env) as (base, _):
        created = httpx.post(f"{base}/v1/studies", json=SPEC, timeout=30)
        assert created.status_code == 202, created.text
        study = f"/v1/studies/{created.json()['id']}"
        _wait(lambda: httpx.get(f"{base}{study}").json()["done"] >= 10, 60, "the first rows")
        with fault():
            _during_fault(base, study, writes_fail)
            time.sleep(max(0.0, FAULT_S - SQLITE_BUSY_S))
        # the run stopped under the fault is recorded (or swept) once the store answers: never running for good
        record = _wait(lambda: (r := httpx.get(f"{base}{study}").json())["state"] != "running" and r, 60,
                       "the study to stop running")
        if record["state"] != "done":
            assert record["state"] in ("interrupted", "failed"), record
            resumed = httpx.post(f"{base}{study}/resume", timeout=30)
            assert resumed.status_code == 202, resumed.text
            record = _wait(lambda: (r := httpx.get(f"{base}{study}").json())["state"] in ("done", "failed")
                           and r, 300, "the resumed study to finish")
        assert record["state"] == "done" and record["done"] == TOTAL, record
        again = httpx.post(f"{base}{study}/resume", timeout=30)
        assert again.status_code == 409 and again.json()["type"] == "/problems/study-finished", again.text
        ready = httpx.get(f"{base}/ready", timeout=30).json()
        assert ready["store_ok"] and ready["store_writable"] and ready["studies_running"] == 0, ready
    assert _rows(store_url) == (TOTAL, TOTAL)      # every variant exactly once


def test_a_locked_sqlite_store_answers_503_and_the_study_finishes_once(tmp_path: Path) -> None:
    path = str(tmp_path / "store.sqlite")
    env = {"SYNTH_EXECUTOR": "serial", "SYNTH_STUDY_LEASE_S": str(LEASE_S), "SYNTH_STUDIES_DB": path}
    _run_through(f"sqlite:///{path}", env, tmp_path, lambda: _sqlite_locked(path), writes_fail=True)


@pytest.mark.parametrize("fault", ["read-only", "connections-killed"])
def test_a_faulty_postgresql_store_answers_503_and_the_study_finishes_once(
        pg_cluster: Cluster, tmp_path: Path, fault: str) -> None:  # noqa: F811
    url = pg_cluster.database()
    database = url.rsplit("/", 1)[1]
    env = {"SYNTH_EXECUTOR": "serial", "SYNTH_STUDY_LEASE_S": str(LEASE_S), "SYNTH_DATABASE_URL": url}
    make = ((lambda: _pg_read_only(pg_cluster, database)) if fault == "read-only"
            else (lambda: _pg_connections_killed(pg_cluster, database)))
    _run_through(url, env, tmp_path, make, writes_fail=fault == "read-only")


def test_a_read_only_sqlite_store_at_start_is_served_and_reported(tmp_path: Path) -> None:
    path = tmp_path / "store.sqlite"
    store = Store(f"sqlite:///{path}")
    store.migrate()
    store.dispose()
    path.chmod(0o444)
    immutable = _immutable(path, True)   # root writes through file modes: the immutable flag stops it too
    try:
        env = {"SYNTH_EXECUTOR": "serial", "SYNTH_STUDIES_DB": str(path)}
        with running_process(_command, tmp_path, env=env) as (base, _):
            ready = httpx.get(f"{base}/ready", timeout=30).json()
            assert ready["status"] == "degraded" and ready["degraded"] == ["store"], ready
            assert "readonly" in ready["store_problem"], ready
            assert httpx.get(f"{base}/v1/studies", timeout=30).status_code == 200
            saved = httpx.post(f"{base}{DESIGN}", json=SAVE_EXAMPLE, timeout=60)
            assert saved.status_code == 503 and "readonly" in saved.json()["reason"], saved.text
    finally:
        if immutable:
            _immutable(path, False)
        path.chmod(0o644)


def _immutable(path: Path, on: bool) -> bool:
    import os
    import subprocess

    if os.geteuid() != 0:
        return False
    return subprocess.run(["chattr", "+i" if on else "-i", str(path)], capture_output=True).returncode == 0
