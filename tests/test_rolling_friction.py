"""A slide run on rollers: rolling friction k·N (seed 000 §13.3) in the friction block, against its closed form."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.analysis import AnalysisIn

PRESS = {"type": "slider_crank", "crank_length_m": 0.1, "rod_length_m": 0.35}
BODY = {"mechanism": PRESS, "speed_rpm": 120.0, "samples": 360, "loads": [{"type": "window", "force_N": 2000.0}]}
K, RHO, F = 5e-4, 0.02, 0.15  # rolling resistance [m], roller radius [m], adhesion [-]


def test_rolling_guide_matches_the_closed_form(client: SynthClient) -> None:
    out = client.analysis(AnalysisIn.model_validate({**BODY, "friction": {"guide": {
        "coefficient": F, "rolling_resistance_m": K, "roller_radius_m": RHO}}}))
    assert out.friction is not None
    # closed form for massless links (the slider-crank press): the rolling moment k·|N| over the roller's radius
    # resists the slide, so with mu = k/rho: |F_rod| = P/(cos b - mu|sin b|), N = |F_rod sin b|,
    # T = (P + mu·N)·|v|/w and the guide loses k·N·|v|/rho, the power of k·N at the roller's speed |v|/rho
    p, w, mu = 2000.0, 120.0 * math.pi / 30, K / RHO
    beta = np.radians(out.links["rod"].angle_deg)
    v = np.array(out.points["B"].velocity_m_s)[:, 0]
    normal = np.abs(p / (np.cos(beta) - mu * np.abs(np.sin(beta))) * np.sin(beta))
    moving = np.abs(v) > 1e-12
    torque = np.where(moving, (p + mu * normal) * np.abs(v) / w, 0.0)
    assert np.max(np.abs(np.array(out.friction.driving_torque_Nm) - torque)) <= 1e-9 * np.max(torque)
    loss = np.where(moving, K * normal * np.abs(v) / RHO, 0.0)
    guide = out.friction.pairs["guide"]
    assert guide.mean_power_loss_W == pytest.approx(np.mean(loss), rel=1e-9)
    # about f/(k/rho) = 6 times less than the same guide sliding with its adhesion coefficient
    sliding = client.analysis(AnalysisIn.model_validate({**BODY, "friction": {"guide": {"coefficient": F}}}))
    assert sliding.friction is not None
    assert sliding.friction.pairs["guide"].mean_power_loss_W > 5 * guide.mean_power_loss_W


def _problem(client: SynthClient, guide: dict, joint: str = "guide") -> dict:
    body = {**BODY, "friction": {joint: guide}}
    r = client.http.post("/v1/analysis", content=json.dumps(body), headers={"content-type": "application/json"})
    assert r.status_code == 422, r.text
    return dict(r.json())


def test_rolling_that_cannot_roll_is_refused_naming_the_field(client: SynthClient) -> None:
    # pure rolling needs f > k/rho (seed 000:549-577): here k/rho = 0.25 > f
    assert "coefficient" in json.dumps(_problem(client, {"coefficient": 0.15, "rolling_resistance_m": 5e-3,
                                                         "roller_radius_m": 0.02}))
    assert "roller_radius_m" in json.dumps(_problem(client, {"coefficient": 0.15, "rolling_resistance_m": 5e-4}))
    assert "rolling_resistance_m" in json.dumps(_problem(client, {"coefficient": 0.1, "journal_radius_m": 0.01,
                                                                  "rolling_resistance_m": 5e-4,
                                                                  "roller_radius_m": 0.02}, "O"))
