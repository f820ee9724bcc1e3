"""POST /v1/analysis with a friction block per pair: the answer's friction against a closed form, and problems."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.analysis import AnalysisIn

PRESS = {"type": "slider_crank", "crank_length_m": 0.1, "rod_length_m": 0.35}
BODY = {"mechanism": PRESS, "speed_rpm": 120.0, "samples": 360,
        "loads": [{"type": "window", "force_N": 2000.0}]}


def _post(client: SynthClient, body: dict) -> tuple[int, dict]:
    r = client.http.post("/v1/analysis", content=json.dumps(body), headers={"content-type": "application/json"})
    return r.status_code, r.json()


def test_guide_friction_answer_matches_the_closed_form(client: SynthClient) -> None:
    # closed form (issue 25) for massless links: T = (P + mu |F sin b|) |v| / w, |F| = P/(cos b - mu |sin b|)
    mu, p = 0.12, 2000.0
    out = client.analysis(AnalysisIn.model_validate({**BODY, "friction": {"guide": {"coefficient": mu}}}))
    assert out.friction is not None
    w = 120.0 * math.pi / 30
    beta = np.radians(out.links["rod"].angle_deg)
    v = np.array(out.points["B"].velocity_m_s)[:, 0]
    force = p / (np.cos(beta) - mu * np.abs(np.sin(beta)))
    torque = np.where(np.abs(v) > 1e-12, (p + mu * np.abs(force * np.sin(beta))) * np.abs(v) / w, 0.0)
    assert np.max(np.abs(np.array(out.friction.driving_torque_Nm) - torque)) <= 1e-9 * np.max(torque)
    # the frictionless answer is unchanged, and the loss torque is the difference of the two torques
    assert np.allclose(np.array(out.friction.driving_torque_Nm) - np.array(out.driving_torque_Nm),
                       out.friction.loss_torque_Nm, rtol=0, atol=1e-9 * np.max(torque))
    guide = out.friction.pairs["guide"]
    assert guide.kind == "prismatic" and guide.friction_moment_Nm is None and guide.friction_force_N is not None
    # the cycle's efficiency: useful work over driving work, both from the closed form above
    useful = np.mean(np.where(np.abs(v) > 1e-12, p * np.abs(v), 0.0))
    assert out.friction.cycle_efficiency == pytest.approx(useful / np.mean(torque * w), rel=1e-9)
    assert out.friction.checks.newton_residual <= 1e-12
    assert out.friction.mean_power_loss_W == pytest.approx(guide.mean_power_loss_W, rel=1e-12)


def test_no_friction_block_answers_as_before(client: SynthClient) -> None:
    out = client.analysis(AnalysisIn.model_validate(BODY))
    assert out.friction is None


def test_large_coefficient_is_warned(client: SynthClient) -> None:
    status, out = _post(client, {**BODY, "friction": {"O": {"coefficient": 1.2, "journal_radius_m": 0.01}}})
    assert status == 200
    assert "friction.O.coefficient" in [w["field"] for w in out["warnings"]]


@pytest.mark.parametrize(("friction", "field"), [
    ({"guide": {"coefficient": -0.1}}, "coefficient"),
    ({"guide": {"coefficient": 4.0}}, "coefficient"),
    ({"A": {"coefficient": 0.1, "journal_radius_m": 0.5}}, "friction.A.journal_radius_m"),
    ({"C": {"coefficient": 0.1}}, "friction.C"),
    ({"guide": {"coefficient": 0.2, "static_coefficient": 0.1}}, "friction.guide.static_coefficient"),
])
def test_bad_friction_is_a_problem_naming_the_pair(client: SynthClient, friction: dict, field: str) -> None:
    status, problem = _post(client, {**BODY, "friction": friction})
    assert status == 422 and problem["type"] == "/problems/invalid-input"
    assert field in problem["field"]


def test_self_locking_is_a_problem(client: SynthClient) -> None:
    body = {**BODY, "mechanism": dict(PRESS, rod_length_m=0.12), "friction": {"guide": {"coefficient": 3.0}}}
    status, problem = _post(client, body)
    assert status == 422 and problem["type"] == "/problems/infeasible"
    assert problem["constraint"] == "friction" and problem["phi_deg"]


def test_flywheel_is_sized_with_the_friction_losses(client: SynthClient) -> None:
    # the cycle's work with friction is the frictionless one less the lost work, 2 pi times the mean loss torque
    # that /v1/analysis reports for the same linkage and friction (an independent request)
    friction = {"guide": {"coefficient": 0.15}, "O": {"coefficient": 0.1, "journal_radius_m": 0.03}}
    body = {"mechanism": PRESS, "mean_speed_rpm": 120.0, "delta": 0.05,
            "loads": [{"type": "window", "force_N": 2000.0, "start_deg": 0, "end_deg": 180}]}
    plain = client.http.post("/v1/flywheel", json=body).json()
    with_friction = client.http.post("/v1/flywheel", json={**body, "friction": friction}).json()
    an = client.analysis(AnalysisIn.model_validate({"mechanism": PRESS, "speed_rpm": 120.0, "loads": body["loads"],
                                                    "friction": friction}))
    assert an.friction is not None
    lost = 2 * math.pi * float(np.mean(an.friction.loss_torque_Nm))
    assert with_friction["cycle_work_J"] == pytest.approx(plain["cycle_work_J"] - lost, rel=1e-9)
    assert with_friction["constant_driving_torque_Nm"] > plain["constant_driving_torque_Nm"]


def test_csv_carries_the_friction_columns(client: SynthClient) -> None:
    # the CSV's driving torque with friction is the JSON answer's, column for column
    body = {**BODY, "samples": 36, "friction": {"guide": {"coefficient": 0.12}, "O": {"coefficient": 0.1,
                                                                                      "journal_radius_m": 0.02}}}
    r = client.http.post("/v1/analysis?format=csv", json=body)
    assert r.status_code == 200
    lines = r.text.strip().splitlines()
    header = lines[0].split(",")
    rows = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    out = client.analysis(AnalysisIn.model_validate(body))
    assert out.friction is not None
    col = header.index("driving_torque_with_friction_Nm")
    assert np.allclose(rows[:, col], out.friction.driving_torque_Nm, rtol=1e-9, atol=1e-9)
    assert {"guide_friction_force_N", "O_friction_moment_Nm", "O_friction_power_loss_W"} <= set(header)


def test_figure_with_friction_is_a_png(client: SynthClient) -> None:
    r = client.http.post("/v1/analysis?format=png", json={**BODY, "samples": 36,
                                                          "friction": {"guide": {"coefficient": 0.12}}})
    assert r.status_code == 200 and r.content[:8] == b"\x89PNG\r\n\x1a\n"
