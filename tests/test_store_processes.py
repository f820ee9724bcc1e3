"""Two real service processes on one store (a SQLite file, and a PostgreSQL cluster): designs saved through one
are the other's (a stale save through either is refused); the second, sweeping for lapsed leases three times a
lease, never takes the first's running study, and after the first is killed (SIGKILL: no shutdown, its lease
just lapses) the study is resumed exactly once and every variant has exactly one row."""

from __future__ import annotations

import os
import signal
import sys
import threading
import time
from pathlib import Path
from typing import Any

import httpx
import pytest
import sqlalchemy as sa

from mechsynth_client.schemas.common import FOURBAR_EXAMPLE
from mechsynth_client.schemas.library import SAVE_EXAMPLE
from service import running_process
from store import Store
from store_engines import pg_cluster, store_url  # noqa: F401  (fixtures)

LEASE_S = 1.5
# 60 crank lengths x 10 mass budgets at 3600 samples: a study of some seconds even on a quiet machine (the static
# balancing of a batch of variants takes a few milliseconds each), so it is killed part-way.
SPEC: dict[str, Any] = {
    "endpoint": "/v1/balancing/static",
    "base": {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 3600,
             "max_radius_m": {"crank": 0.1, "rocker": 0.25}},
    "parameters": [{"path": "mechanism.crank_length_m", "range": [0.05, 0.15], "count": 60},
                   {"path": "mass_budget_kg", "range": [2.0, 8.0], "count": 10}],
    "metrics": ["total_added_mass_kg"],
}
TOTAL = 600


def _command(port: int) -> list[str]:
    return [sys.executable, "-m", "uvicorn", "api.app:app", "--host", "127.0.0.1", "--port", str(port)]


def _wait(predicate: Any, timeout_s: float, what: str) -> Any:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if value := predicate():
            return value
        time.sleep(0.1)
    pytest.fail(f"timed out waiting for {what}")


def _share_designs(first: str, second: str) -> None:
    design = "/v1/library/projects/shop/designs/crank/revisions"
    saved = httpx.post(f"{first}{design}", json=SAVE_EXAMPLE, timeout=60)
    assert saved.status_code == 201
    seen = httpx.get(f"{second}{design}/1").json()
    assert (seen["content_hash"], seen["author"]) == (saved.json()["content_hash"], "ann")
    newer = {**SAVE_EXAMPLE, "parent": 1, "author": "bob",
             "request": {**SAVE_EXAMPLE["request"], "speed_rpm": 320}}
    assert httpx.post(f"{second}{design}", json=newer, timeout=60).status_code == 201
    stale = httpx.post(f"{first}{design}", json={**newer, "author": "ann"}, timeout=60)
    assert stale.status_code == 409 and stale.json()["head_revision"] == 2


def test_a_killed_service_s_study_is_resumed_once_by_the_other(store_url: str, tmp_path: Path) -> None:
    env = {"SYNTH_EXECUTOR": "serial", "SYNTH_STUDY_LEASE_S": str(LEASE_S)}
    if store_url.startswith("postgresql"):
        env["SYNTH_DATABASE_URL"] = store_url
    else:
        env["SYNTH_STUDIES_DB"] = store_url.removeprefix("sqlite:///")
    with running_process(_command, tmp_path, env=env) as (first, first_proc), \
            running_process(_command, tmp_path, env=env) as (second, _):
        _share_designs(first, second)
        created = httpx.post(f"{first}/v1/studies", json=SPEC, timeout=30)
        assert created.status_code == 202
        study = f"/v1/studies/{created.json()['id']}"
        _wait(lambda: httpx.get(f"{first}{study}").json()["done"] >= 10, 60, "the first rows")
        # the second service neither marks the study interrupted nor takes it, however often it is asked to
        # resume it
        seen = httpx.get(f"{second}{study}").json()
        assert seen["state"] == "running" and seen["done"] < TOTAL
        assert httpx.post(f"{second}{study}/resume").json()["state"] == "running"
        assert httpx.get(f"{second}/ready").json()["studies_running"] == 0
        time.sleep(LEASE_S)               # past one lease: the first one's renewals keep it
        assert httpx.get(f"{second}{study}").json()["state"] == "running"

        os.killpg(first_proc.pid, signal.SIGKILL)
        first_proc.wait(timeout=30)
        stopped = _wait(lambda: (s := httpx.get(f"{second}{study}").json())["state"] == "interrupted" and s,
                        10 * LEASE_S, "the lapsed lease to show")
        assert 10 <= stopped["done"] < TOTAL
        # two resumes at once: one run
        answers: list[str] = []
        threads = [threading.Thread(target=lambda: answers.append(
            httpx.post(f"{second}{study}/resume", timeout=30).json()["state"])) for _ in range(2)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        assert answers == ["running", "running"]
        final = _wait(lambda: (s := httpx.get(f"{second}{study}").json())["state"] != "running" and s,
                      120, "the resumed study to end")
        assert (final["state"], final["done"], final["total"]) == ("done", TOTAL, TOTAL)
    store = Store(store_url)
    try:
        with store.read() as db:
            counts = db.execute(sa.text("SELECT idx, COUNT(*) FROM study_rows GROUP BY idx ORDER BY idx")).all()
    finally:
        store.dispose()
    assert [tuple(c) for c in counts] == [(i, 1) for i in range(TOTAL)]
