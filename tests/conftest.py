"""Shared test fixtures: the seed cases (read from ../shared, never copied by hand) and the in-process client."""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path
from typing import Any

import pytest
from hypothesis import settings
from hypothesis.configuration import set_hypothesis_home_dir

# The same examples on every run: a commit that is green stays green. Set SYNTH_HYPOTHESIS_RANDOM=1 to explore.
# Tests leave no files in the repository: no example database, and hypothesis's own cache (constants of the code
# under test) in a scratch directory instead of .hypothesis/ in the working directory.
set_hypothesis_home_dir(tempfile.mkdtemp(prefix="synth-hypothesis-"))
settings.register_profile("repeatable", derandomize=True, deadline=None, database=None)
settings.register_profile("explore", deadline=None, database=None)
settings.load_profile("explore" if os.environ.get("SYNTH_HYPOTHESIS_RANDOM") else "repeatable")

# Studies started by tests (fuzzing included) go to a scratch database, never into the working directory.
os.environ.setdefault("SYNTH_STUDIES_DB", str(Path(tempfile.mkdtemp(prefix="synth-tests-")) / "studies.sqlite"))
# Services started by the tests skip the workers' warm-up (seconds per pool); tests/test_execution.py warms one.
os.environ.setdefault("SYNTH_WARM_WORKERS", "0")
# Starlette's TestClient (and schemathesis in-process) speak to the app as host "testserver".
os.environ.setdefault("SYNTH_ALLOWED_HOSTS", "localhost,127.0.0.1,::1,testserver")

REPO = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("SYNTH_SHARED_DIR", REPO.parent / "shared"))
SEED_CASES_PATH = SHARED / "reference" / "seed_cases.json"


def load_cases() -> dict[str, dict[str, Any]]:
    """Seed cases by id."""
    return {c["id"]: c for c in json.loads(SEED_CASES_PATH.read_text())}


CASES = load_cases()


@pytest.fixture(scope="session", autouse=True)
def _repository_root_stays_clean():  # type: ignore[no-untyped-def]
    """The whole run leaves no new file or directory in the repository root (databases, caches, figures)."""
    before = set(os.listdir(REPO))
    yield
    left = sorted(set(os.listdir(REPO)) - before)
    assert not left, f"the tests left these in the repository root: {left}"


@pytest.fixture(scope="session")
def client():  # type: ignore[no-untyped-def]
    """In-process client of a fresh app, its methods asking every answer for full precision: the tests hold
    answers to the engine's values and identities at its own round-off (a raw ``client.http`` call that does
    so asks with ``?precision=full``). ``tests/test_answer_precision.py`` holds the service's default, single
    precision, to the full answers."""
    from mechsynth_client.client import SynthClient

    with SynthClient.in_process(precision="full") as c:
        yield c


def pytest_unconfigure(config: pytest.Config) -> None:
    """Whatever a test left running (a pool, a server, a thread) may not hold the run's exit: if the interpreter
    is still alive three minutes after the last test, every thread's stack is printed and the run fails."""
    import faulthandler
    import sys

    faulthandler.dump_traceback_later(180, exit=True, file=sys.__stderr__ or sys.stderr)
