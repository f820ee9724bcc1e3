"""The store's two engines for the tests: a SQLite file in the test's directory, and a throwaway PostgreSQL
cluster in a temporary directory on a free loopback port, one database per test. The cluster is made and started
by ``deploy/postgres.sh``, the script docs/deployment.md's recipe follows (as the ``postgres`` user when the tests
run as root: the server refuses root)."""

from __future__ import annotations

import glob
import os
import pwd
import shutil
import subprocess
import tempfile
import uuid
from collections.abc import Callable, Iterator
from pathlib import Path

import psycopg
import pytest

from service import free_port
from store import Store


def _bin(name: str) -> str:
    found = sorted(glob.glob(f"/usr/lib/postgresql/*/bin/{name}"), key=lambda p: int(p.split("/")[4]))
    path = found[-1] if found else shutil.which(name)
    if path is None:
        pytest.fail(f"PostgreSQL's {name} is not installed: `make test` installs Debian's postgresql package")
    return path


SETUP = Path(__file__).resolve().parents[1] / "deploy" / "postgres.sh"


class Cluster:
    """A PostgreSQL server on 127.0.0.1:``port`` for user ``synth`` (trust authentication on loopback), made by
    ``deploy/postgres.sh`` (``password``: the role needs it over TCP); ``url`` is the URL the script prints."""

    def __init__(self, password: str | None = None) -> None:
        self.root = Path(tempfile.mkdtemp(prefix="synth-pg-"))
        self.port = free_port()
        self.as_user: list[str] = []
        _bin("initdb")
        if os.geteuid() == 0:
            account = pwd.getpwnam("postgres")
            os.chown(self.root, account.pw_uid, account.pw_gid)
            self.as_user = ["runuser", "-u", "postgres", "--"]
        # a throwaway server: no waiting on the disk
        env = {**os.environ, "SYNTH_INITDB_OPTIONS": "--no-sync", "SYNTH_DB_PASSWORD": password or ""}
        done = subprocess.run(["sh", str(SETUP), str(self.root), str(self.port), "-c", "fsync=off", "-c",
                               "synchronous_commit=off", "-c", "full_page_writes=off", "-c", "max_connections=200"],
                              capture_output=True, text=True, env=env)
        if done.returncode:
            log = self.root / "log"
            pytest.fail(f"{SETUP} failed: {done.stderr[-2000:]}{log.read_text()[-2000:] if log.exists() else ''}")
        self.url = done.stdout.strip().splitlines()[-1].partition("=")[2]

    def database(self) -> str:
        """A new empty database; its SQLAlchemy URL."""
        name = "t" + uuid.uuid4().hex[:12]
        with psycopg.connect(f"host=127.0.0.1 port={self.port} user=synth dbname=postgres", autocommit=True) as c:
            c.execute(f'CREATE DATABASE "{name}"')
        return f"postgresql+psycopg://synth@127.0.0.1:{self.port}/{name}"

    def stop(self) -> None:
        """Stop the server at once and remove its files."""
        subprocess.run([*self.as_user, _bin("pg_ctl"), "-D", str(self.root / "data"), "-m", "immediate", "stop"],
                       capture_output=True)
        shutil.rmtree(self.root, ignore_errors=True)


@pytest.fixture(scope="session")
def pg_cluster() -> Iterator[Cluster]:
    cluster = Cluster()
    try:
        yield cluster
    finally:
        cluster.stop()


@pytest.fixture(params=["sqlite", "postgresql"])
def store_url(request: pytest.FixtureRequest, tmp_path: Path) -> str:
    """The URL of an empty store on each engine."""
    if request.param == "sqlite":
        return f"sqlite:///{tmp_path / 'store.sqlite'}"
    cluster: Cluster = request.getfixturevalue("pg_cluster")
    return cluster.database()


@pytest.fixture()
def open_store(store_url: str) -> Iterator[Callable[[], Store]]:
    """Opens the test's store, as a new process would (its own connections); every one closed at the end."""
    opened: list[Store] = []

    def make() -> Store:
        opened.append(Store(store_url))
        return opened[-1]

    yield make
    for store in opened:
        store.dispose()
