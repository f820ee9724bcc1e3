"""The store's two engines for the tests: a SQLite file in the test's directory, and a throwaway PostgreSQL
cluster (Debian's server binaries, initdb + pg_ctl) in a temporary directory on a free loopback port, one
database per test. The cluster runs as the ``postgres`` user when the tests run as root (the server refuses
root)."""

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


class Cluster:
    """A PostgreSQL server on 127.0.0.1:``port`` for user ``synth`` (trust authentication)."""

    def __init__(self) -> None:
        self.root = Path(tempfile.mkdtemp(prefix="synth-pg-"))
        self.port = free_port()
        self.as_user: list[str] = []
        if os.geteuid() == 0:
            account = pwd.getpwnam("postgres")
            os.chown(self.root, account.pw_uid, account.pw_gid)
            self.as_user = ["runuser", "-u", "postgres", "--"]
        data = self.root / "data"
        self._run(_bin("initdb"), "-D", str(data), "-U", "synth", "--auth=trust", "-E", "UTF8", "--no-locale",
                  "--no-sync")
        options = (f"-p {self.port} -k {self.root} -c listen_addresses=127.0.0.1 -c fsync=off "
                   "-c synchronous_commit=off -c full_page_writes=off -c max_connections=200")
        self._run(_bin("pg_ctl"), "-D", str(data), "-o", options, "-l", str(self.root / "log"), "-w", "start")

    def _run(self, *command: str) -> None:
        done = subprocess.run([*self.as_user, *command], capture_output=True, text=True)
        if done.returncode:
            log = self.root / "log"
            pytest.fail(f"{' '.join(command)} failed: {done.stderr[-2000:]}"
                        f"{log.read_text()[-2000:] if log.exists() else ''}")

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
