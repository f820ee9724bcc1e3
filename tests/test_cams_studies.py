"""Cams in design studies: a study varies a cam request like any design endpoint's, and each of its rows is what
the endpoint answers for that variant; the least cam grows with the lift it must give (a cam scaled with its lift
keeps every pressure angle, so the least base radius is proportional to the lift at a fixed roller)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient

import synth
from api.app import create_app
from api.execution.plans import PLANS, Limits
from api.settings import Settings
from api.studies.tasks import variant_function
from mechsynth_client.schemas.cams import CamAnalysisIn, CamSynthesisIn
from synth.execution import SerialExecutor

LIMITS = Limits(max_samples=20_000, max_stages=6, solver_time_limit_s=20.0)
LIFTS = [0.01, 0.02, 0.03]


def _example(model: type[Any]) -> dict[str, Any]:
    return json.loads(json.dumps(model.model_config["json_schema_extra"]["examples"][0]))


def _study(endpoint: str, base: dict[str, Any], metrics: list[str]) -> dict[str, Any]:
    return {"endpoint": endpoint, "base": base, "metrics": metrics,
            "parameters": [{"path": "segments.0.lift_m", "values": LIFTS},
                           {"path": "segments.2.lift_m", "values": LIFTS}],
            "sampling": "grid"}


def _rows(spec: dict[str, Any]) -> list[synth.VariantRow]:
    rows: list[synth.VariantRow] = []
    executor = SerialExecutor()
    try:
        synth.run_study(synth.study_from_dict(spec), variant_function(spec["endpoint"], LIMITS), executor,
                        rows.extend)
    finally:
        executor.shutdown()
    return sorted(rows, key=lambda r: r.index)


def test_the_cam_endpoints_are_design_endpoints_a_study_may_vary() -> None:
    assert PLANS["/v1/cams/analysis"][0] is CamAnalysisIn
    assert PLANS["/v1/cams/synthesis"][0] is CamSynthesisIn


def test_a_cam_analysis_study_row_is_the_endpoints_answer(tmp_path: Path) -> None:
    base = _example(CamAnalysisIn)
    metrics = ["profile.max_pressure_angle_rise_deg", "profile.max_pressure_angle_return_deg"]
    spec = _study("/v1/cams/analysis", base, metrics)
    rows = _rows(spec)
    # a cam must bring its follower back: only equal rise and return close the turn, the others are rows that
    # carry the endpoint's problem
    assert len(rows) == len(LIFTS) ** 2
    for r in rows:
        rise, fall = r.values
        assert r.ok == (rise == fall), r.detail
        if rise < fall:
            assert (r.problem_type, r.detail) == ("invalid-input", "a return takes the follower below its lowest position")
        elif rise > fall:
            assert r.problem_type == "invalid-input" and "do not bring the follower back" in (r.detail or "")
    closed = [r for r in rows if r.ok]
    app = create_app(Settings(executor="serial", studies_db=str(tmp_path / "s.sqlite")))
    with TestClient(app) as http:
        for row in closed:
            body = json.loads(json.dumps(base))
            body["segments"][0]["lift_m"], body["segments"][2]["lift_m"] = row.values
            answer = http.post("/v1/cams/analysis", json=body).json()
            assert row.metrics == (answer["profile"]["max_pressure_angle_rise_deg"],
                                   answer["profile"]["max_pressure_angle_return_deg"])
    # a larger rise on the same base circle, a steeper cam: the rise's pressure angle grows with its lift
    rise_angle = [r.metrics[0] for r in closed]  # type: ignore[index]
    assert rise_angle[0] < rise_angle[1] < rise_angle[2]


def test_the_least_cam_of_a_study_scales_with_the_lift() -> None:
    base = _example(CamSynthesisIn)
    base["follower"] = {k: v for k, v in base["follower"].items() if k != "roller_radius_m"} | {"contact": "knife_edge"}
    base.pop("min_curvature_radius_m", None)
    rows = [r for r in _rows(_study("/v1/cams/synthesis", base, ["base_radius_m"])) if r.values[0] == r.values[1]]
    assert len(rows) == len(LIFTS) and all(r.ok for r in rows), [r.detail for r in rows]
    # a knife-edge cam limited by pressure angles alone is similar to itself at any scale: the least base
    # radius is proportional to the lift (measured: equal to 1e-10)
    per_lift = [r.metrics[0] / r.values[0] for r in rows]  # type: ignore[index]
    assert per_lift == pytest.approx([per_lift[0]] * len(LIFTS), rel=1e-6)
