"""Loads of fixed direction: along the output (signed) or fixed in the frame, beside the resistance against motion.

Independent derivations written here: the in-line slider-crank's slide position s(phi) = r·cos phi +
sqrt(l² - r²·sin² phi) differentiated by hand; a four-bar's rocker point by intersecting two circles and central
differences. With massless links the driving torque balances the load's virtual power: T·w + F·v_P = 0, so
T = -F·dP/dphi.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from mechsynth_client.client import InvalidInputError, SynthClient
from mechsynth_client.schemas.analysis import AnalysisIn

R, L = 0.1, 0.35
F = 500.0


def _slider(**load: Any) -> dict[str, Any]:
    return {"mechanism": {"type": "slider_crank", "crank_length_m": R, "rod_length_m": L},
            "speed_rpm": 60, "samples": 72, "loads": [{"type": "window", **load}]}


def _ds_dphi(phi: np.ndarray) -> np.ndarray:
    root = np.sqrt(L * L - (R * np.sin(phi)) ** 2)
    return -R * np.sin(phi) - R * R * np.sin(phi) * np.cos(phi) / root


@pytest.mark.parametrize("load", [
    {"force_N": -F, "direction": "output"},                                   # a thrust toward the crank
    {"force_N": F, "direction": "frame", "frame_angle_deg": 180.0},           # the same force, given in the frame
    {"force_N": -F, "direction": "frame", "frame_angle_deg": 0.0},
], ids=["along the slide", "frame 180°", "frame 0° negative"])
def test_a_constant_force_on_a_slider_costs_F_ds_dphi(client: SynthClient, load: dict[str, Any]) -> None:
    answer = client.analysis(AnalysisIn.model_validate(_slider(**load)))
    phi = np.radians(answer.crank_angle_deg)
    expected = F * _ds_dphi(phi)          # the force -F along x: T = -(-F)·ds/dphi
    assert np.allclose(answer.driving_torque_Nm, expected, rtol=1e-9, atol=1e-9 * F * R)
    assert np.allclose(answer.virtual_power_torque_Nm, expected, rtol=1e-9, atol=1e-9 * F * R)
    # it works one way over half the revolution and the other way over the other: no net work
    assert abs(np.mean(answer.driving_torque_Nm)) < 1e-9 * F * R


def test_the_old_way_two_window_loads_gives_the_same(client: SynthClient) -> None:
    # before: a force of fixed direction took two resistances, one per stroke, with opposite signs
    two = client.analysis(AnalysisIn.model_validate({**_slider(force_N=F, stroke=1), "loads": [
        {"type": "window", "force_N": F, "stroke": 1}, {"type": "window", "force_N": -F, "stroke": -1}]}))
    one = client.analysis(AnalysisIn.model_validate(_slider(force_N=-F, direction="output")))
    # the strokes change at the dead centres, where ds/dphi is zero either way
    assert np.allclose(one.driving_torque_Nm, two.driving_torque_Nm, atol=1e-9 * F * R)


def test_a_weight_across_the_slide_does_no_work_but_loads_the_guide(client: SynthClient) -> None:
    answer = client.analysis(AnalysisIn.model_validate(_slider(force_N=F, direction="frame", frame_angle_deg=-90)))
    assert np.max(np.abs(answer.driving_torque_Nm)) < 1e-9 * F * R
    guide = [k for k in answer.joint_reactions_N if k not in ("O", "A", "B")]
    assert guide
    # the guide holds the weight: its reaction on the slider is F upward
    assert np.allclose(np.array(answer.joint_reactions_N[guide[0]])[:, 1], F, rtol=1e-9)


def _rocker_point(phi: np.ndarray, a: float, b: float, c: float, d: float, u: float) -> np.ndarray:
    """The rocker point at distance u from Q along the rocker, branch +1 (B left of A->Q), by circle intersection."""
    ax, ay = a * np.cos(phi), a * np.sin(phi)
    qx, qy = d, 0.0
    dx, dy = qx - ax, qy - ay
    e = np.hypot(dx, dy)
    along = (b * b - c * c + e * e) / (2 * e)
    h = np.sqrt(b * b - along * along)
    bx = ax + along * dx / e - h * dy / e
    by = ay + along * dy / e + h * dx / e
    return np.stack([qx + u * (bx - qx) / c, qy + u * (by - qy) / c], axis=1)


def test_a_weight_on_a_rocker_costs_its_virtual_power(client: SynthClient) -> None:
    a, b, c, d = 0.1, 0.35, 0.3, 0.3
    weight = 80.0
    body = {"mechanism": {"type": "fourbar", "ground_length_m": d, "crank_length_m": a, "coupler_length_m": b,
                          "rocker_length_m": c},
            "speed_rpm": 60, "samples": 72,
            "loads": [{"type": "window", "force_N": weight, "direction": "frame", "frame_angle_deg": -90,
                       "point_m": [0.6 * c, 0.0]}]}
    answer = client.analysis(AnalysisIn.model_validate(body))
    phi = np.radians(answer.crank_angle_deg)
    h = 1e-6
    dp = (_rocker_point(phi + h, a, b, c, d, 0.6 * c) - _rocker_point(phi - h, a, b, c, d, 0.6 * c)) / (2 * h)
    expected = -np.array([0.0, -weight]) @ dp.T
    assert np.allclose(answer.driving_torque_Nm, expected, rtol=1e-6, atol=1e-7 * weight * c)
    assert np.allclose(answer.virtual_power_torque_Nm, expected, rtol=1e-6, atol=1e-7 * weight * c)


def test_a_frame_force_is_a_force(client: SynthClient) -> None:
    body = {"mechanism": {"type": "fourbar", "ground_length_m": 0.3, "crank_length_m": 0.1,
                          "coupler_length_m": 0.35, "rocker_length_m": 0.3},
            "speed_rpm": 60, "loads": [{"type": "window", "torque_Nm": 5, "direction": "frame"}]}
    with pytest.raises(InvalidInputError) as err:
        client.analysis(AnalysisIn.model_validate(body))
    assert err.value.problem["field"] == "loads.force_N"
