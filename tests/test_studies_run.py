"""Design studies run: the same rows on serial, local-pool and Dask execution; failing variants are rows; cancel
keeps what finished and a resume runs only the rest; the service answers a study as the endpoint would."""

from __future__ import annotations

import csv
import io
import json
import sqlite3
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from fastapi.testclient import TestClient

import synth
from api.app import create_app
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE
from mechsynth_client.schemas.studies import StudyIn
from api.settings import Settings
from api.execution.plans import Limits
from api.studies.tasks import run_endpoint, variant_function
from synth.execution import DaskExecutor, LocalPoolExecutor, SerialExecutor
from synth.studies import runner

ENDPOINT = "/v1/balancing/static"
# 10 crank lengths x 5 mass budgets = 50 variants. The longest crank makes a change-point four-bar
# (0.2 + 0.35 = 0.3 + 0.25) and small budgets are below the least static-balance mass: both must be rows.
SPEC: dict[str, Any] = {
    "endpoint": ENDPOINT,
    "base": {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 36,
             "max_radius_m": {"crank": 0.1, "rocker": 0.25}},
    "parameters": [{"path": "mechanism.crank_length_m", "range": [0.05, 0.2], "count": 10},
                   {"path": "mass_budget_kg", "values": [1.0, 2.0, 3.5, 5.0, 8.0]}],
    "metrics": ["summary_after.rms_shaking_force_N", "summary_after.rms_driving_torque_Nm", "total_added_mass_kg"],
    "objectives": {"summary_after.rms_driving_torque_Nm": "min", "total_added_mass_kg": "min"},
    "constraints": [{"metric": "summary_after.rms_driving_torque_Nm", "max": 30.0}],
}
LIMITS = Limits(max_samples=20_000, max_stages=6, solver_time_limit_s=20.0)


def _run(executor: synth.execution.Executor, **kw: Any) -> list[synth.VariantRow]:
    rows: list[synth.VariantRow] = []
    synth.run_study(synth.study_from_dict(SPEC), variant_function(ENDPOINT, LIMITS), executor, rows.extend, **kw)
    return sorted(rows, key=lambda r: r.index)


@pytest.fixture(scope="module")
def serial_rows() -> list[synth.VariantRow]:
    executor = SerialExecutor()
    try:
        return _run(executor)
    finally:
        executor.shutdown()


def test_every_variant_is_a_row_and_failures_carry_their_problem(serial_rows: list[synth.VariantRow]) -> None:
    assert [r.index for r in serial_rows] == list(range(50))
    by_type: dict[str | None, int] = {}
    for r in serial_rows:
        by_type[r.problem_type] = by_type.get(r.problem_type, 0) + 1
    assert by_type.get("invalid-input") == 5           # the five change-point variants (crank 0.2 m)
    assert all("change-point" in (r.detail or "") for r in serial_rows if r.values[0] == pytest.approx(0.2))
    assert by_type.get("infeasible", 0) > 0 and by_type.get(None, 0) > 0
    for r in serial_rows:
        if r.problem_type == "infeasible":
            # The engine's message names the least mass; the budget of the variant is below it.
            needed = float((r.detail or "").split("at least ")[1].split(" kg")[0])
            assert r.values[1] < needed
        if r.ok:
            assert r.metrics is not None and r.metrics[2] <= r.values[1] * (1 + 1e-6)   # within its budget
            assert r.feasible == (r.metrics[1] <= 30.0)


def test_rows_are_the_answers_the_endpoint_sends(serial_rows: list[synth.VariantRow], tmp_path: Path) -> None:
    # The study's metrics must be what POST /v1/balancing/static answers for the same body.
    app = create_app(Settings(executor="serial", studies_db=str(tmp_path / "s.sqlite")))
    with TestClient(app) as http:
        for row in (serial_rows[7], serial_rows[12]):
            body = json.loads(json.dumps(SPEC["base"]))
            body["mechanism"]["crank_length_m"], body["mass_budget_kg"] = row.values
            answer = http.post(ENDPOINT, json=body).json()
            assert row.metrics == (answer["summary_after"]["rms_shaking_force_N"],
                                   answer["summary_after"]["rms_driving_torque_Nm"], answer["total_added_mass_kg"])


def test_local_pool_and_dask_give_bit_identical_rows(serial_rows: list[synth.VariantRow]) -> None:
    from distributed import Client, LocalCluster

    pool = LocalPoolExecutor(2)
    try:
        assert _run(pool) == serial_rows
        _cancel_midway(pool, serial_rows)
    finally:
        pool.shutdown()
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=":0") as cluster, \
            Client(cluster, set_as_default=False) as client:
        dask = DaskExecutor(client=client)
        assert dask.workers == 2
        assert _run(dask) == serial_rows
        _service_on_dask(cluster.scheduler_address)
        _cancel_midway(dask, serial_rows)


def _service_on_dask(address: str) -> None:
    """A service with SYNTH_DASK_SCHEDULER set sends its studies there; the rows are the endpoint's answers.

    Driven below HTTP: FastAPI builds a route's validators on its first request under process-wide warning
    filters, which Dask's threads in this process would race with."""
    import tempfile

    from api.execution.admission import Solvers
    from api.studies.runs import StudyRuns

    with tempfile.TemporaryDirectory() as tmp:
        settings = Settings(executor="serial", dask_scheduler=address, studies_db=f"{tmp}/s.sqlite")
        runs = StudyRuns(settings, Solvers(settings))
        try:
            spec = StudyIn.model_validate({**SPEC, "parameters": [{"path": "mass_budget_kg", "values": [3.5, 5.0]}]})
            study_id = runs.create(spec.model_dump(mode="json")).id
            while runs.get(study_id).state == "running":
                time.sleep(0.05)
            assert isinstance(runs.executor(), DaskExecutor) and runs.get(study_id).state == "done"
            for row in runs.store.rows(study_id):
                answer = run_endpoint(ENDPOINT, LIMITS, {**SPEC["base"], "mass_budget_kg": row.values[0]})
                assert row.metrics is not None and row.metrics[2] == answer["total_added_mass_kg"]
        finally:
            runs.shutdown()


class _SlowSink:
    """Lets the test cancel after the first finished batches."""

    def __init__(self) -> None:
        self.rows: list[synth.VariantRow] = []
        self.first = threading.Event()

    def __call__(self, rows: list[synth.VariantRow]) -> None:
        self.rows.extend(rows)
        if len(self.rows) >= 3:
            self.first.set()


def _cancel_midway(executor: synth.execution.Executor, serial_rows: list[synth.VariantRow]) -> None:
    """Cancel after the first rows: the run stops early, and what it wrote is exactly what a full run writes."""
    cancel, sink = threading.Event(), _SlowSink()
    runner = threading.Thread(target=synth.run_study, args=(synth.study_from_dict(SPEC), variant_function(
        ENDPOINT, LIMITS), executor, sink), kwargs={"cancel": cancel})
    runner.start()
    assert sink.first.wait(60)
    cancel.set()
    runner.join(30)
    assert not runner.is_alive() and 3 <= len(sink.rows) < 50
    assert all(r == serial_rows[r.index] for r in sink.rows)
    _drain(executor)


def _drain(executor: synth.execution.Executor) -> None:
    """Wait until a cancelled task that runs on in a thread of this process (serial, Dask in-process) is over:
    solvers in it toggle process-wide warning filters, which an app built meanwhile would see."""
    if isinstance(executor, DaskExecutor):
        while any(executor.client.processing().values()):
            time.sleep(0.05)
    elif isinstance(executor, SerialExecutor):
        executor.submit(abs, 0.0).result()


def test_cancel_keeps_finished_rows_and_resume_runs_only_the_rest(serial_rows: list[synth.VariantRow]) -> None:
    executor = SerialExecutor()
    try:
        cancel, sink = threading.Event(), _SlowSink()
        study = synth.study_from_dict(SPEC)
        runner = threading.Thread(target=synth.run_study, args=(study, variant_function(ENDPOINT, LIMITS), executor,
                                                                sink), kwargs={"cancel": cancel})
        runner.start()
        assert sink.first.wait(60)
        cancel.set()
        runner.join(30)
        _drain(executor)
        first = {r.index: r for r in sink.rows}
        assert 3 <= len(first) < 50
        missing = sorted(set(range(50)) - set(first))
        rest: list[synth.VariantRow] = []
        report = synth.run_study(study, variant_function(ENDPOINT, LIMITS), executor, rest.extend, indices=missing)
        assert sorted(r.index for r in rest) == missing and report.finished == len(missing)
        assert sorted([*first.values(), *rest], key=lambda r: r.index) == serial_rows
    finally:
        executor.shutdown()


# --- the service ---------------------------------------------------------------------------------------------

@pytest.fixture()
def service(tmp_path: Path) -> Iterator[SynthClient]:
    app = create_app(Settings(executor="serial", studies_db=str(tmp_path / "studies.sqlite"),
                              max_study_variants=1000))
    with TestClient(app) as http:
        yield SynthClient(http=http)


def test_study_endpoints_from_start_to_front(service: SynthClient, serial_rows: list[synth.VariantRow]) -> None:
    http = service.http
    created = http.post("/v1/studies", json=SPEC)
    assert created.status_code == 202 and created.headers["location"] == f"/v1/studies/{created.json()['id']}"
    handle = service.study_handle(created.json()["id"])
    out = io.StringIO()
    final = handle.wait(progress=True, timeout=120, poll_s=0.2, out=out)
    assert (final.state, final.done, final.total) == ("done", 50, 50)
    assert final.failed == sum(not r.ok for r in serial_rows) and final.eta_s is None
    assert "50/50 [" in out.getvalue()

    rows = handle.results(page_size=20)                       # three pages
    assert [r["index"] for r in rows] == list(range(50))
    for got, want in zip(rows, serial_rows):
        metrics = [got[m] for m in SPEC["metrics"]]
        assert metrics == (list(want.metrics) if want.metrics else [None] * 3)
        assert got["problem_type"] == (None if want.ok else f"/problems/{want.problem_type}")
    table = list(csv.DictReader(io.StringIO(handle.csv())))
    assert len(table) == 50 and float(table[7]["total_added_mass_kg"]) == rows[7]["total_added_mass_kg"]

    # Front: the feasible rows no other feasible row beats, each objective counted in units of its ninth
    # significant digit (of its largest value), by brute force over all pairs.
    feasible = [r for r in serial_rows if r.feasible]
    raw = np.array([[r.metrics[1], r.metrics[2]] for r in feasible])  # type: ignore[index]
    cost = np.round(raw / 10.0 ** (np.floor(np.log10(np.abs(raw).max(axis=0))) - 8))
    expected = {r.index for r, p in zip(feasible, cost) if not any(np.all(q <= p) and np.any(q < p) for q in cost)}
    front = handle.pareto()
    assert front.candidates == len(feasible)
    assert {v.index for v in front.front} == expected
    figure = handle.pareto_png()
    assert figure[:8] == b"\x89PNG\r\n\x1a\n"


def test_study_problems(service: SynthClient) -> None:
    http = service.http
    missing = http.get("/v1/studies/0123456789abcdef")
    assert missing.status_code == 404 and missing.headers["content-type"] == "application/problem+json"
    too_many = http.post("/v1/studies", json={**SPEC, "sampling": "lhs", "samples": 5000})
    assert too_many.status_code == 413 and too_many.json()["limit"] == 1000
    bad_base = http.post("/v1/studies", json={**SPEC, "base": {**SPEC["base"], "speed_rpm": -1}})
    assert bad_base.status_code == 422 and bad_base.json()["field"] == "base.speed_rpm"
    bad_endpoint = http.post("/v1/studies", json={**SPEC, "endpoint": "/v1/nowhere"})
    assert bad_endpoint.status_code == 422 and bad_endpoint.json()["field"] == "endpoint"
    bad_metric = http.post("/v1/studies", json={**SPEC, "objectives": {"nothing": "min"}})
    assert bad_metric.status_code == 422
    deep = '{"endpoint": "/v1/analysis", "base": ' + '{"a": ' * 300 + '1' + '}' * 300 + \
        ', "parameters": [{"path": "a", "values": [1]}], "metrics": ["m"]}'
    too_deep = http.post("/v1/studies", content=deep, headers={"content-type": "application/json"})
    assert too_deep.status_code == 422 and too_deep.json()["field"] == "base"
    assert http.get(f"/v1/studies/{'0' * 32}/pareto", params={"x": "nope"}).status_code == 404


def test_cancel_then_restart_then_resume(tmp_path: Path, serial_rows: list[synth.VariantRow],
                                        monkeypatch: pytest.MonkeyPatch) -> None:
    # Each variant made to last 20 ms, so the batches after the first two (1 and 8 variants) take long enough for
    # the cancel to land before the study ends, however fast the machine.
    original = runner.run_batch

    def slow_batch(spec: runner.BatchSpec, items: Any) -> tuple[list[synth.VariantRow], float]:
        time.sleep(0.02 * len(items))
        return original(spec, items)

    monkeypatch.setattr(runner, "run_batch", slow_batch)
    db = tmp_path / "studies.sqlite"
    settings = Settings(executor="serial", studies_db=str(db))
    with TestClient(create_app(settings)) as http:
        study_id = http.post("/v1/studies", json=SPEC).json()["id"]
        while http.get(f"/v1/studies/{study_id}").json()["done"] < 3:
            time.sleep(0.05)
        cancelled = http.delete(f"/v1/studies/{study_id}").json()
        assert cancelled["state"] == "cancelled" and 3 <= cancelled["done"] < 50
        _drain(http.app.state.solvers.executor)  # type: ignore[attr-defined]
        assert http.get(f"/v1/studies/{study_id}").json()["done"] == cancelled["done"]   # nothing runs on
        kept = http.get(f"/v1/studies/{study_id}/results").json()["variants"]
    # A crash leaves the study marked running; a new service on the same file finds it interrupted.
    with sqlite3.connect(db) as conn:
        conn.execute("UPDATE studies SET state = 'running', run_started_at = 0 WHERE id = ?", (study_id,))
    with TestClient(create_app(settings)) as http:
        client = SynthClient(http=http)
        handle = client.study_handle(study_id)
        assert handle.last.state == "interrupted"
        assert handle.resume().state == "running"
        final = handle.wait(timeout=120, poll_s=0.1)
        assert (final.state, final.done) == ("done", 50)
        rows = http.get(f"/v1/studies/{study_id}/results").json()["variants"]
    assert [v["index"] for v in rows] == list(range(50))
    assert all(rows[v["index"]] == v for v in kept)     # the rows finished before the cancel are unchanged
    assert [v["metrics"] and list(v["metrics"].values()) for v in rows] == \
        [list(r.metrics) if r.metrics else None for r in serial_rows]


def test_client_study_round_trip(service: SynthClient) -> None:
    spec = {**SPEC, "parameters": [{"path": "mass_budget_kg", "values": [4.0, 6.0]}], "name": "budget"}
    handle = service.study(StudyIn.model_validate(spec))
    status = handle.wait(timeout=60, poll_s=0.1)
    assert status.state == "done" and status.name == "budget"
    assert "mass_budget_kg" in handle.table().splitlines()[0]
    assert handle.cancel().state == "done"                # cancelling a finished study changes nothing
    listed = service.http.get("/v1/studies", params={"limit": 5}).json()
    assert listed[0]["id"] == handle.id and listed[0]["done"] == 2
    document = service.http.get("/openapi.json").json()["paths"]["/v1/studies/{study_id}"]["get"]
    assert "application/problem+json" in document["responses"]["404"]["content"]
