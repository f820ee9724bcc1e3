"""Rolling friction of a cam's roller (seed 000 §13.3): the couple k·N on the roller, its contact force and the
cam's driving torque, against the closed form of a dwell and the power balance with the rolling loss."""

from __future__ import annotations

import numpy as np
import pytest

from mechsynth_client.client import InvalidInputError, SynthClient
from mechsynth_client.schemas.cams import CamAnalysisIn

BASE, ROLLER, LIFT, K = 0.04, 0.01, 0.02, 0.0005   # [m]


def _body(k: float, **follower: object) -> CamAnalysisIn:
    return CamAnalysisIn.model_validate({
        "segments": [{"kind": "rise", "angle_deg": 120, "lift_m": LIFT, "law": "cycloidal"},
                     {"kind": "dwell", "angle_deg": 60},
                     {"kind": "return", "angle_deg": 120, "lift_m": LIFT, "law": "polynomial_345"},
                     {"kind": "dwell", "angle_deg": 60}],
        "follower": {"contact": "roller", "roller_radius_m": ROLLER, **follower},
        "base_radius_m": BASE, "speed_rpm": 300, "samples": 720,
        "loads": {"mass_kg": 2.0, "spring_stiffness_N_m": 2000.0, "spring_preload_N": 50.0,
                  "process": [{"from_deg": 0, "to_deg": 120, "force_N": 30}], "rolling_resistance_m": k}})


def test_cam_roller_rolling_friction_in_a_dwell(client: SynthClient) -> None:
    out = client.cam_analysis(_body(K))
    f = out.forces
    assert f is not None
    theta = np.radians(out.cam_angle_deg)
    assert out.motion.follower_motion == "translating"
    lift = np.array(out.motion.s_m)
    n, torque = np.array(f.contact_force_N), np.array(f.driving_torque_Nm)
    # Closed form in a dwell: the roller centre stands still at radius R = base + r + s straight above the cam
    # centre, the normal is vertical so N = spring + process, and the cam surface runs under the roller at
    # omega·R: the roller turns at omega·R/r relative to the cam, the couple k·N absorbs k·N·omega·R/r, so
    # T = k·N·(base + r + s)/r.
    for lo, hi, s in ((120.0, 180.0, LIFT), (300.0, 360.0, 0.0)):
        inside = (np.degrees(theta) > lo + 1) & (np.degrees(theta) < hi - 1)
        assert np.abs(lift[inside] - s).max() < 1e-12
        expected_n = 2000.0 * s + 50.0
        assert np.abs(n[inside] - expected_n).max() < 1e-9 * expected_n
        assert np.abs(torque[inside] - K * n[inside] * (BASE + ROLLER + s) / ROLLER).max() < 1e-9 * np.abs(torque).max()
    # Everywhere: the torque from the contact geometry equals virtual power with the rolling loss counted.
    assert out.checks.torque_virtual_power_error is not None and out.checks.torque_virtual_power_error < 1e-9
    loss = np.array(f.rolling_loss_torque_Nm)
    assert loss.min() >= 0.0 and np.mean(loss) > 0.0
    # Without rolling resistance the dwell costs nothing.
    plain = client.cam_analysis(_body(0.0)).forces
    assert plain is not None and not any(plain.rolling_loss_torque_Nm)
    dwell = (np.degrees(theta) > 121) & (np.degrees(theta) < 179)
    assert np.abs(np.array(plain.driving_torque_Nm)[dwell]).max() < 1e-9


def test_offset_follower_power_balance_with_rolling(client: SynthClient) -> None:
    # An offset axis tilts the normal (pressure angle), so the tangential force enters N and the lever: the
    # contact geometry's torque still equals virtual power with the rolling loss, and the loss never drives.
    out = client.cam_analysis(_body(K, offset_m=0.005)).forces
    plain = client.cam_analysis(_body(0.0, offset_m=0.005)).forces
    assert out is not None and plain is not None
    check = client.cam_analysis(_body(K, offset_m=0.005)).checks.torque_virtual_power_error
    assert check is not None and check < 1e-9
    # Over a turn the spring and mass give back what they take; the process load takes 30 N over the rise, so the
    # mean torque is 30·lift/(2 pi), plus the mean rolling loss.
    process_work = 30.0 * LIFT / (2 * np.pi)
    assert np.mean(plain.driving_torque_Nm) == pytest.approx(process_work, rel=1e-6)
    assert np.mean(out.driving_torque_Nm) == pytest.approx(process_work + np.mean(out.rolling_loss_torque_Nm),
                                                           rel=1e-6)


def test_rolling_resistance_needs_a_roller_larger_than_it(client: SynthClient) -> None:
    with pytest.raises(InvalidInputError, match="roller") as err:
        client.cam_analysis(_body(0.02))
    assert err.value.problem.get("field") == "loads.rolling_resistance_m"
