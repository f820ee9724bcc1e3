"""Inputs that used to answer 500, wrong-typed values, the OpenAPI document's problem responses, 405's Allow
header and settings validated at start."""

from __future__ import annotations

import os
import subprocess
import sys
from typing import Any

import pytest

from mechsynth_client.client import SynthClient
from api.problems import PROBLEM_STATUSES

FOURBAR = {"type": "fourbar", "ground_length_m": 0.3, "crank_length_m": 0.1, "coupler_length_m": 0.35,
           "rocker_length_m": 0.25}
TABLES = {"crank_angle_deg": [0, 120, 240, 360], "resisting_torque_Nm": [-10, -20, -5, -10],
          "driving_torque_Nm": [0, 0, 0, 0]}


@pytest.mark.parametrize(("path", "body", "field"), [
    ("/v1/gears/drive", {"output_power_W": 1e308, "reserve_factor": 1e308, "output_speed_rpm": 60},
     "output_power_W"),
    ("/v1/gears/teeth", {"total_ratio": 17.3, "stages": 2, "addendum_coefficient": 1e308}, "addendum_coefficient"),
    ("/v1/gears/teeth", {"total_ratio": 17.3, "stages": 2, "profile_shift": 1e308}, "profile_shift"),
    ("/v1/flywheel", {"tables": {**TABLES, "resisting_torque_Nm": [1e308, -1e308, 1e308, 1e308]},
                      "mean_speed_rad_s": 10, "delta": 0.1}, "tables.resisting_torque_Nm[0]"),
    ("/v1/flywheel", {"tables": TABLES, "mean_speed_rad_s": 1e308, "delta": 0.1}, "mean_speed_rad_s"),
    ("/v1/flywheel", {"tables": TABLES, "mean_speed_rad_s": 1e-300, "delta": 0.1}, "mean_speed_rad_s"),
    ("/v1/analysis", {"mechanism": FOURBAR, "speed_rpm": True}, "speed_rpm"),
    ("/v1/analysis", {"mechanism": FOURBAR, "speed_rpm": "60"}, "speed_rpm"),
    ("/v1/analysis", {"mechanism": FOURBAR, "samples": 36.5}, "samples"),
])
def test_out_of_range_and_wrong_typed_values_are_named(client: SynthClient, path: str, body: dict[str, Any],
                                                       field: str) -> None:
    r = client.http.post(path, json=body)
    assert r.status_code == 422, r.text
    assert r.headers["content-type"] == "application/problem+json" and r.json()["field"] == field


def test_a_change_point_four_bar_is_refused_with_its_collinear_angle(client: SynthClient) -> None:
    mechanism = {**FOURBAR, "rocker_length_m": 0.15}   # 0.1 + 0.35 = 0.3 + 0.15: Grashof neutral
    r = client.http.post("/v1/analysis", json={"mechanism": mechanism, "samples": 36})
    assert r.status_code == 422 and r.json()["field"] == "mechanism" and "[0.0] deg" in r.json()["detail"]


def test_a_result_beyond_the_answer_schema_is_a_named_problem(client: SynthClient) -> None:
    # A counterweight radius of 1 um for a 1000 kg crank at 0.5 m needs 5e8 kg: far past the answer's mass bound.
    body = {"mechanism": {"type": "slider_crank", "crank_length_m": 0.5, "rod_length_m": 2.0,
                          "links": {"crank": {"mass_kg": 1e6, "com_m": [0.5, 0]}}},
            "counterweight_radius_m": 1e-6, "speed_rpm": 60}
    r = client.http.post("/v1/balancing/slider-crank", json=body)
    assert r.status_code == 422, r.text
    assert r.headers["content-type"] == "application/problem+json" and r.json()["field"].endswith("mass_kg")


def test_every_post_operation_documents_its_problems(client: SynthClient) -> None:
    doc = client.http.get("/openapi.json").json()
    assert "HTTPValidationError" not in doc["components"]["schemas"]
    posts = [(path, op) for path, item in doc["paths"].items() for method, op in item.items() if method == "post"]
    assert posts
    for path, op in posts:
        for status in PROBLEM_STATUSES:
            content = op["responses"][str(status)]["content"]
            assert content == {"application/problem+json": {"schema": {"$ref": "#/components/schemas/Problem"}}}, path
        assert "Retry-After" in op["responses"]["503"]["headers"]


def test_405_names_the_allowed_methods(client: SynthClient) -> None:
    r = client.http.put("/v1/analysis", json={})
    assert r.status_code == 405 and r.headers["allow"] == "POST"
    assert r.headers["content-type"] == "application/problem+json"


def test_ready_reports_workers_without_waiting(client: SynthClient) -> None:
    ready = client.http.get("/ready").json()
    assert ready["workers"] >= 1 and ready["capacity"] == ready["workers"] + 16 and ready["queued"] == 0


def test_a_bad_setting_stops_the_service_naming_the_variable() -> None:
    env = {**os.environ, "SYNTH_WORKERS": "-3"}
    run = subprocess.run([sys.executable, "-c", "import api.app"], env=env, capture_output=True, text=True,
                         timeout=60)
    assert run.returncode != 0 and "SYNTH_WORKERS" in run.stderr and "greater than or equal to 0" in run.stderr
