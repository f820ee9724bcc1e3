"""The store on both engines (a SQLite file and a throwaway PostgreSQL cluster): migrations at start, studies held
by leases (a live lease is never swept, a lapsed one is claimed exactly once), rows written once, users and
tokens kept as hashes; an unreachable store says why."""

from __future__ import annotations

import sqlite3
import threading
import time
from collections.abc import Callable
from pathlib import Path

import pytest
import sqlalchemy as sa

from store import LeaseLost, MigrationFailed, SqlStudyStore, Store, StoreUnavailable, Users, token_hash
from store_engines import open_store, pg_cluster, store_url  # noqa: F401  (fixtures)
from synth.studies.runner import VariantRow


def _rows(indices: range) -> list[VariantRow]:
    return [VariantRow(i, (0.1 * i,), (float(i), None) if i % 3 else None, True if i % 3 else None,
                       None if i % 3 else "infeasible", None if i % 3 else f"variant {i}") for i in indices]


def test_migrations_bring_an_empty_store_to_head_once(open_store: Callable[[], Store]) -> None:
    store = open_store()
    assert store.migrate() == ["0001", "0002", "0003", "0004"]
    assert open_store().migrate() == []        # a second process finds the schema current
    tables = set(sa.inspect(store.engine).get_table_names())
    assert {"studies", "study_rows", "users", "api_tokens", "projects", "designs", "revisions", "revision_comments",
            "alembic_version"} <= tables


def test_a_lease_keeps_a_running_study_from_other_processes(open_store: Callable[[], Store]) -> None:
    store = open_store()
    first, second = SqlStudyStore(store, lease_s=1.0), SqlStudyStore(store, lease_s=1.0)
    study_id = first.create({"endpoint": "/v1/analysis"}, 10)
    assert first.claim(study_id)
    first.write_rows(study_id, _rows(range(0, 4)))
    # the second process starts: the study is running under a live lease, so it is neither swept nor taken
    assert second.sweep() == 0 and not second.claim(study_id)
    assert second.get(study_id).state == "running"  # type: ignore[union-attr]
    assert first.renew() == {study_id}
    time.sleep(1.1)                                   # the first process stops renewing: its lease lapses
    assert second.sweep() == 1 and second.get(study_id).state == "interrupted"  # type: ignore[union-attr]
    assert first.renew() == set()
    # both processes resume at once: one claim wins
    results: list[bool] = []
    barrier = threading.Barrier(2)

    def resume(s: SqlStudyStore) -> None:
        barrier.wait()
        results.append(s.claim(study_id))

    threads = [threading.Thread(target=resume, args=(s,)) for s in (first, second)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert sorted(results) == [False, True]
    winner, loser = (first, second) if first.claim(study_id) else (second, first)
    with pytest.raises(LeaseLost):
        loser.write_rows(study_id, _rows(range(4, 10)))
    assert winner.missing(study_id, 10) == [4, 5, 6, 7, 8, 9]
    winner.write_rows(study_id, _rows(range(4, 10)))
    winner.stopped(study_id, "done")
    record = winner.get(study_id)
    assert record is not None and (record.state, record.done, record.failed) == ("done", 10, 4)
    assert winner.rows(study_id) == _rows(range(10))
    assert list(winner.iter_rows(study_id, chunk=3)) == _rows(range(10))
    assert winner.rows_at(study_id, [9, 2]) == [_rows(range(10))[2], _rows(range(10))[9]]
    index, values, feasible = winner.metric_table(study_id, 2)
    assert index.tolist() == [1, 2, 4, 5, 7, 8] and values[0, 0] == 1.0 and feasible.all()
    assert not winner.claim(study_id)                 # a finished study is never taken again


def test_a_row_is_stored_once(open_store: Callable[[], Store]) -> None:
    studies = SqlStudyStore(open_store())
    study_id = studies.create({}, 3)
    studies.claim(study_id)
    studies.write_rows(study_id, _rows(range(2)))
    with pytest.raises(sa.exc.IntegrityError):
        studies.write_rows(study_id, _rows(range(1, 3)))
    assert studies.missing(study_id, 3) == [2]       # the failed batch left nothing behind


def test_users_and_tokens_keep_only_hashes(open_store: Callable[[], Store]) -> None:
    users = Users(open_store())
    ann = users.create("ann", {"engineer", "checker"}, password_hash="scrypt$...")
    assert users.by_name("ann") == ann and users.get(ann.id) == ann and ann.has("checker")
    with pytest.raises(ValueError, match="unknown roles"):
        users.create("bob", {"wizard"})
    with pytest.raises(sa.exc.IntegrityError):
        users.create("ann", {"viewer"})
    token_id = users.add_token(ann.id, "secret-token", label="laptop")
    with users.store.read() as db:
        stored = db.execute(sa.text("SELECT token_hash, last_used_at FROM api_tokens")).one()
    assert stored == (token_hash("secret-token"), None) and "secret-token" not in stored[0]
    assert users.by_token("secret-token") == ann and users.by_token("other") is None
    assert users.revoke_token(token_id) and users.by_token("secret-token") is None


def test_a_study_file_from_before_migrations_is_taken_over(tmp_path: Path) -> None:
    # the schema the service kept before it had migrations, with one finished row
    path = tmp_path / "old.sqlite"
    with sqlite3.connect(path) as db:
        db.executescript("""
            CREATE TABLE studies (id TEXT PRIMARY KEY, spec TEXT NOT NULL, total INTEGER NOT NULL,
                state TEXT NOT NULL, created_at REAL NOT NULL, run_started_at REAL,
                run_start_done INTEGER NOT NULL DEFAULT 0, elapsed_s REAL NOT NULL DEFAULT 0, message TEXT);
            CREATE TABLE rows (study_id TEXT NOT NULL REFERENCES studies(id), idx INTEGER NOT NULL,
                params TEXT NOT NULL, metrics TEXT, feasible INTEGER, problem_type TEXT, detail TEXT,
                PRIMARY KEY (study_id, idx)) WITHOUT ROWID;
            INSERT INTO studies VALUES ('s1', '{}', 2, 'running', 1.0, 1.0, 0, 0, NULL);
            INSERT INTO rows VALUES ('s1', 0, '[0.5]', '[2.0]', 1, NULL, NULL);
        """)
    store = Store(f"sqlite:///{path}")
    try:
        assert store.migrate() == ["0001", "0002", "0003", "0004"]
        studies = SqlStudyStore(store)
        assert studies.sweep() == 1 and studies.missing("s1", 2) == [1]
        assert studies.rows("s1") == [VariantRow(0, (0.5,), (2.0,), True)]
    finally:
        store.dispose()


def test_an_unreachable_store_says_why(tmp_path: Path) -> None:
    from service import free_port

    down = Store(f"postgresql+psycopg://synth@127.0.0.1:{free_port()}/nothing")
    with pytest.raises(StoreUnavailable) as caught:
        down.ping()
    assert "refused" in caught.value.reason.lower() or "connect" in caught.value.reason.lower()
    with pytest.raises(StoreUnavailable):
        down.migrate()


def test_a_failing_migration_stops_with_its_reason(tmp_path: Path) -> None:
    path = tmp_path / "taken.sqlite"
    with sqlite3.connect(path) as db:          # a table in the way of the first migration
        db.execute("CREATE TABLE users (something TEXT)")
    store = Store(f"sqlite:///{path}")
    with pytest.raises(MigrationFailed, match="users"):
        store.migrate()
    store.dispose()


def test_a_service_whose_store_fails_to_migrate_does_not_start(tmp_path: Path) -> None:
    from fastapi.testclient import TestClient

    from api.app import create_app
    from api.settings import Settings

    path = tmp_path / "taken.sqlite"
    with sqlite3.connect(path) as db:
        db.execute("CREATE TABLE users (something TEXT)")
    # the start-up fails with the reason (uvicorn logs it and exits)
    with pytest.raises(MigrationFailed, match="table users already exists"):
        with TestClient(create_app(Settings(executor="serial", studies_db=str(path)))):
            pass


def test_a_study_cancelled_through_another_process_takes_no_more_rows(open_store: Callable[[], Store]) -> None:
    store = open_store()
    owner, other = SqlStudyStore(store), SqlStudyStore(store)
    study_id = owner.create({}, 10)
    owner.claim(study_id)
    owner.write_rows(study_id, _rows(range(3)))
    assert other.cancel(study_id) and not other.cancel(study_id)
    with pytest.raises(LeaseLost):
        owner.write_rows(study_id, _rows(range(3, 6)))
    assert owner.renew() == set()                     # the owner's heartbeat sees it is no longer running it
    owner.stopped(study_id, "cancelled", "cancelled; finished variants are kept")
    record = owner.get(study_id)
    assert record is not None and (record.state, record.done) == ("cancelled", 3)
    assert other.claim(study_id)                      # resumed anywhere: the lease was released


def test_two_first_saves_of_one_new_design_at_once_store_one(open_store: Callable[[], Store]) -> None:
    from store.library import Library, StaleParent

    store = open_store()
    store.migrate()
    outcomes: list[str] = []
    barrier = threading.Barrier(2)

    def save(author: str) -> None:
        library = Library(open_store())
        barrier.wait()
        try:
            library.save("new", "design", "/v1/analysis", {"by": author}, author=author, message="", parent=None)
            outcomes.append("saved")
        except StaleParent as exc:
            outcomes.append(f"stale {exc.head}")

    threads = [threading.Thread(target=save, args=(name,)) for name in ("ann", "bob")]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert sorted(outcomes) == ["saved", "stale 1"]
    assert [r.number for r in Library(store).history("new", "design")] == [1]
