"""One store, two engines: SQLite in a file (the embedded default) or PostgreSQL (an office server, several service
processes), reached through one SQLAlchemy engine and brought to the latest schema by the migrations at start."""

from __future__ import annotations

import logging
import os
import sqlite3
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from importlib.resources import files
from typing import Any

import sqlalchemy as sa
from alembic import command
from alembic.config import Config
from alembic.runtime.migration import MigrationContext
from alembic.script import ScriptDirectory
from sqlalchemy import event
from sqlalchemy.engine import Connection, Engine

log = logging.getLogger("store")

# Seconds a SQLite writer waits for another process's write to end before the store counts as locked (a request
# then answers 503 at once instead of waiting for its deadline; the store's own writes take milliseconds).
SQLITE_BUSY_S = 5.0
# Seconds to reach a PostgreSQL server before the store counts as unreachable.
CONNECT_TIMEOUT_S = 5
# Milliseconds a PostgreSQL statement waits for another transaction's lock before the store counts as locked.
LOCK_TIMEOUT_MS = 5000
# What the drivers say when the store cannot take a write, or cannot be reached at all: a fault of the store, not
# of the request (SQLite: locked past its busy wait, a read-only file or disk; PostgreSQL: a read-only database,
# a lock wait past its bound, a connection lost).
_FAULTS = ("connection", "server closed", "terminating", "unable to open database", "database is locked",
           "readonly database", "read-only", "disk i/o error", "lock timeout", "database or disk is full",
           "could not receive data", "no connection to the server")


# Alembic's command context (alembic.op, alembic.context) is one per process, not per thread: two stores
# migrating at once in one process take turns.
_ALEMBIC = threading.Lock()


class StoreUnavailable(Exception):
    """The store cannot be reached (server down, file unreadable); ``reason`` says what the driver said."""

    def __init__(self, reason: str) -> None:
        super().__init__(f"the store cannot be reached: {reason}")
        self.reason = reason

    def __reduce__(self) -> tuple[type[StoreUnavailable], tuple[str]]:
        return type(self), (self.reason,)


class MigrationFailed(Exception):
    """The store was reached but its schema could not be brought up to date; the service must not start."""


def database_url(url: str | None, sqlite_path: str) -> str:
    """The SQLAlchemy URL of the store: ``url`` when given (``postgresql://`` is taken as psycopg 3), else the
    SQLite file at ``sqlite_path``."""
    if not url:
        return f"sqlite:///{sqlite_path}"
    for plain in ("postgresql://", "postgres://"):
        if url.startswith(plain):
            return "postgresql+psycopg://" + url[len(plain):]
    return url


def _unavailable(exc: BaseException) -> StoreUnavailable:
    # The driver's first line says what failed (connection refused, no such host); never the statement's text.
    reason = str(getattr(exc, "orig", None) or exc).strip().splitlines()
    return StoreUnavailable(reason[0] if reason else type(exc).__name__)


class Store:
    """The service's store at ``url`` (a SQLAlchemy URL: ``sqlite:///path`` or ``postgresql+psycopg://...``).

    Nothing is connected until first use; :meth:`migrate` brings the schema to the latest revision.
    """

    def __init__(self, url: str) -> None:
        self.url = url
        self.dialect = sa.make_url(url).get_backend_name()
        if self.dialect == "sqlite":
            self.engine: Engine = sa.create_engine(url, connect_args={"timeout": SQLITE_BUSY_S})
            _sqlite_setup(self.engine)
        else:
            self.engine = sa.create_engine(url, pool_pre_ping=True, pool_size=5, max_overflow=10, pool_timeout=5,
                                           connect_args={"connect_timeout": CONNECT_TIMEOUT_S,
                                                         "options": f"-c lock_timeout={LOCK_TIMEOUT_MS}"})

        self._migrated = False

    def __repr__(self) -> str:
        return f"Store({sa.make_url(self.url).render_as_string(hide_password=True)!r})"

    @contextmanager
    def read(self) -> Iterator[Connection]:
        """A connection in a transaction for reading; :class:`StoreUnavailable` when the store cannot be reached."""
        with self._begin(write=False) as conn:
            yield conn

    @contextmanager
    def write(self) -> Iterator[Connection]:
        """A connection in a transaction that writes, committed at the end; SQLite takes its write lock at once,
        so two processes' writers queue instead of failing on a stale read."""
        with self._begin(write=True) as conn:
            yield conn

    @contextmanager
    def _begin(self, write: bool) -> Iterator[Connection]:
        if not self._migrated:
            self.migrate()
        try:
            conn = self.engine.connect()
        except (sa.exc.DBAPIError, sa.exc.TimeoutError) as exc:
            raise _unavailable(exc) from exc
        try:
            conn.execution_options(store_write=write)
            with conn.begin():
                yield conn
        except sa.exc.DBAPIError as exc:
            if exc.connection_invalidated or _store_fault(exc):
                raise _unavailable(exc) from exc
            raise
        finally:
            conn.close()

    def ping(self) -> None:
        """Reach the store; :class:`StoreUnavailable` with the reason when it cannot be reached."""
        with self.read() as conn:
            conn.execute(sa.text("SELECT 1"))

    def write_problem(self) -> str | None:
        """Why the store cannot take a write now (locked by another writer, a read-only file or database), or
        None when it can; asked without writing and without waiting for a lock."""
        try:
            if self.dialect == "sqlite":
                path = self.engine.url.database
                if path and path != ":memory:" and os.path.exists(path) and not os.access(path, os.W_OK):
                    return "attempt to write a readonly database (the file is read-only)"
                raw = sqlite3.connect(path or ":memory:", timeout=0.05, isolation_level=None)
                try:
                    raw.execute("BEGIN IMMEDIATE")
                    raw.execute("ROLLBACK")
                finally:
                    raw.close()
                return None
            with self.read() as conn:
                if conn.execute(sa.text("SELECT current_setting('transaction_read_only')")).scalar() == "on":
                    return "the database is read-only (transaction_read_only is on)"
            return None
        except sqlite3.Error as exc:
            return str(exc) or type(exc).__name__
        except StoreUnavailable as exc:
            return exc.reason

    def migrate(self) -> list[str]:
        """Bring the schema to the latest revision; the revisions applied, oldest first.

        :class:`StoreUnavailable` when the store cannot be reached, :class:`MigrationFailed` with the reason when a
        migration fails (the schema is left at the last revision that succeeded).
        """
        with _ALEMBIC:
            if self._migrated:
                return []
            done = self._upgrade()
            self._migrated = True
            return done

    def _upgrade(self) -> list[str]:
        config = Config()
        config.set_main_option("script_location", str(files("store") / "migrations"))
        script = ScriptDirectory.from_config(config)
        try:
            conn = self.engine.connect()
        except (sa.exc.OperationalError, sa.exc.InterfaceError) as exc:
            raise _unavailable(exc) from exc
        try:
            with conn:
                if self.dialect == "postgresql":
                    # Two services starting at once on one server: the second waits for the first's migrations.
                    conn.execute(sa.text("SELECT pg_advisory_lock(734001)"))
                    conn.commit()
                before = MigrationContext.configure(conn).get_current_revision()
                conn.commit()
                config.attributes["connection"] = conn
                command.upgrade(config, "head")
                conn.commit()
                if self.dialect == "postgresql":
                    conn.execute(sa.text("SELECT pg_advisory_unlock(734001)"))
                    conn.commit()
        except StoreUnavailable:
            raise
        except sa.exc.DBAPIError as exc:
            if exc.connection_invalidated or _store_fault(exc):
                raise _unavailable(exc) from exc   # tried again at the next use, once the store takes writes
            raise MigrationFailed(f"migrating the store {self!r} failed: {type(exc).__name__}: "
                                  f"{str(exc).strip().splitlines()[0] if str(exc).strip() else ''}") from exc
        except Exception as exc:
            raise MigrationFailed(f"migrating the store {self!r} failed: {type(exc).__name__}: "
                                  f"{str(exc).strip().splitlines()[0] if str(exc).strip() else ''}") from exc
        applied = [s.revision for s in reversed(list(script.walk_revisions("base", "head")))]
        done = applied[applied.index(before) + 1:] if before in applied else applied
        if done:
            log.info("store %r migrated: %s", self, ", ".join(done))
        return done

    def head(self) -> str | None:
        """The schema revision the store is at (None before any migration)."""
        with self.read() as conn:
            revision: str | None = MigrationContext.configure(conn).get_current_revision()
            return revision

    def dispose(self) -> None:
        """Close every pooled connection."""
        self.engine.dispose()


def _store_fault(exc: sa.exc.DBAPIError) -> bool:
    text = str(exc.orig).lower()
    return any(s in text for s in _FAULTS)


def _sqlite_setup(engine: Engine) -> None:
    """WAL (readers never wait for the writer), a busy wait instead of an error, foreign keys on, and transactions
    begun by us (IMMEDIATE for writers) instead of by the driver."""

    @event.listens_for(engine, "connect")
    def _connect(dbapi: Any, _: Any) -> None:
        dbapi.isolation_level = None
        cursor = dbapi.cursor()
        cursor.execute("PRAGMA journal_mode=WAL")
        cursor.execute("PRAGMA synchronous=NORMAL")
        cursor.execute(f"PRAGMA busy_timeout={int(SQLITE_BUSY_S * 1000)}")
        cursor.execute("PRAGMA foreign_keys=ON")
        cursor.close()

    @event.listens_for(engine, "begin")
    def _begin(conn: Connection) -> None:
        immediate = conn.get_execution_options().get("store_write", True)
        conn.exec_driver_sql("BEGIN IMMEDIATE" if immediate else "BEGIN")
