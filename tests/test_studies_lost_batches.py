"""A batch lost to a dead worker or to its deadline is run again one variant per task: the variant that crashes or
hangs is the only row with that problem, the others are the rows a serial run gives, and /ready shows the study's
work while it runs."""

from __future__ import annotations

import os
import signal
import time
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient

import synth
from api.studies import runs as study_runs
from api.app import create_app
from api.execution.plans import Limits
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE
from api.settings import Settings
from api.studies.tasks import run_endpoint
from synth.execution import LocalPoolExecutor, SerialExecutor

ENDPOINT = "/v1/analysis"
LIMITS = Limits(max_samples=20_000, max_stages=6, solver_time_limit_s=20.0)
# Crank speeds that mark a variant; every other speed is an ordinary analysis of a few milliseconds.
CRASH_RPM, HANG_RPM, SLOW_RPM = 333.0, 444.0, 555.0


def crash_or_hang(request: dict[str, Any]) -> dict[str, Any]:
    """The analysis endpoint, except at the marked speeds: one kills its own worker, one never ends, one takes 2 s."""
    rpm = request["speed_rpm"]
    if rpm == CRASH_RPM:
        os.kill(os.getpid(), signal.SIGKILL)
    if rpm == HANG_RPM:
        time.sleep(600)
    if rpm == SLOW_RPM:
        time.sleep(2)
    return run_endpoint(ENDPOINT, LIMITS, request)


def _spec(speeds: list[float]) -> dict[str, Any]:
    return {"endpoint": ENDPOINT, "base": {"mechanism": FOURBAR_EXAMPLE, "samples": 36},
            "parameters": [{"path": "speed_rpm", "values": speeds}],
            "metrics": ["summary.rms_shaking_force_N", "summary.max_driving_torque_Nm"]}


def _speeds(marks: dict[int, float]) -> list[float]:
    return [marks.get(i, 100.0 + 20.0 * i) for i in range(12)]


def test_a_lost_batch_is_run_again_variant_by_variant() -> None:
    crash, hang = 4, 10
    study = synth.study_from_dict(_spec(_speeds({crash: CRASH_RPM, hang: HANG_RPM})))
    rows: list[synth.VariantRow] = []
    pool = LocalPoolExecutor(2)
    batches: list[list[int]] = []   # the variants of each task, as sent
    submit = pool.submit

    def recorded(fn: Any, *args: Any, **kwargs: Any) -> Any:
        batches.append([index for index, _ in args[1]])
        return submit(fn, *args, **kwargs)

    pool.submit = recorded  # type: ignore[method-assign]
    try:
        report = synth.run_study(study, crash_or_hang, pool, rows.extend, variant_timeout_s=1.0)
    finally:
        pool.shutdown()
    expected: list[synth.VariantRow] = []
    serial = SerialExecutor()
    try:   # the same variants in this process, the marked two left out
        synth.run_study(study, crash_or_hang, serial, expected.extend,
                        indices=[i for i in range(12) if i not in (crash, hang)])
    finally:
        serial.shutdown()

    by_index = {r.index: r for r in rows}
    assert len(rows) == 12 and sorted(by_index) == list(range(12))      # each variant written once
    assert {i: r for i, r in by_index.items() if i not in (crash, hang)} == {r.index: r for r in expected}
    assert all(r.ok for r in expected)
    assert by_index[crash].problem_type == "worker-lost" and by_index[crash].metrics is None
    assert "died" in (by_index[crash].detail or "") and f"exit code {-signal.SIGKILL}" in (by_index[crash].detail or "")
    assert by_index[hang].problem_type == "solver-timeout"
    assert "deadline of 1 s" in (by_index[hang].detail or "")              # its own timeout, not its batch's 3 s
    assert (report.finished, report.failed, report.cancelled) == (12, 2, False)
    # The first task holds variant 0 alone. A batch of several that held one of the two is lost, and each of its
    # variants runs again once, alone; every other variant runs once.
    lost = [b for b in batches if len(b) > 1 and (crash in b or hang in b)]
    assert batches[0] == [0] and lost
    assert report.retried == sum(len(b) for b in lost)
    assert sorted(i for b in batches for i in b) == sorted([*range(12), *(i for b in lost for i in b)])
    assert report.tasks == len(batches)


def test_a_study_whose_variant_kills_its_worker_ends_done_and_ready_shows_its_work(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(study_runs, "variant_function", lambda endpoint, limits: crash_or_hang)
    crash, slow = 4, 10
    settings = Settings(executor="pool", workers=2, studies_db=str(tmp_path / "s.sqlite"))
    with TestClient(create_app(settings)) as http:
        idle = http.get("/ready").json()
        assert (idle["studies_running"], idle["study_tasks_in_flight"], idle["study_tasks_on"]) == (0, 0, "workers")
        study_id = http.post("/v1/studies", json=_spec(_speeds({crash: CRASH_RPM, slow: SLOW_RPM}))).json()["id"]
        seen = []
        deadline = time.monotonic() + 120
        while http.get(f"/v1/studies/{study_id}").json()["state"] == "running" and time.monotonic() < deadline:
            seen.append(http.get("/ready").json())
            time.sleep(0.05)
        final = http.get(f"/v1/studies/{study_id}").json()
        variants = http.get(f"/v1/studies/{study_id}/results").json()["variants"]
        while http.get("/ready").json()["studies_running"] and time.monotonic() < deadline:
            time.sleep(0.01)   # the study's thread ends just after it stores the final state
        after = http.get("/ready").json()

    assert (final["state"], final["done"], final["failed"]) == ("done", 12, 1)
    assert [v["index"] for v in variants if v["problem_type"]] == [crash]
    assert variants[crash]["problem_type"] == "/problems/worker-lost"
    # The 2-s variant keeps one task in flight long enough to be seen; a study keeps at most workers + 1 tasks,
    # and its tasks never count as requests.
    assert any(r["studies_running"] == 1 and r["study_tasks_in_flight"] >= 1 for r in seen)
    assert all(r["study_tasks_in_flight"] <= r["workers"] + 1 for r in seen)
    assert all(r["running"] == r["queued"] == 0 for r in seen)
    assert (after["studies_running"], after["study_tasks_in_flight"]) == (0, 0)
