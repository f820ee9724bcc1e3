"""Which table drives and which side the constant torque takes: an engine's torque over 720° drives, the constant
torque is then the consumer's resistance, and only a real sign mistake warns."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.flywheel import FlywheelIn

# A single-cylinder four-stroke engine: bore 0.08 m, crank r = 0.045 m, rod l = 0.15 m, 2000 rev/min.
R, L, BORE = 0.045, 0.15, 0.08
DEG = np.arange(0.0, 720.0, 5.0)


def _gas_torque(deg: np.ndarray) -> np.ndarray:
    """Crank torque of the gas force [N·m]: p(phi)·A·dx/dphi with the exact slider-crank velocity ratio."""
    phi = np.radians(deg)
    lam = R / L
    # piston displacement from top dead centre and its derivative, both exact for the slider-crank
    root = np.sqrt(1 - (lam * np.sin(phi)) ** 2)
    dxdphi = R * (np.sin(phi) + lam * np.sin(phi) * np.cos(phi) / root)
    # pressure above atmosphere [Pa]: a combustion pulse after TDC of the power stroke (at 360°), a small
    # compression rise before it and a small pumping loss during exhaust and intake
    burn = 5.0e6 * np.exp(-(((deg - 375.0) / 25.0) ** 2))
    compression = 1.2e6 * np.exp(-(((deg - 345.0) / 30.0) ** 2))
    pumping = np.where(deg < 180, -2.0e4, np.where(deg > 540, 1.5e4, 0.0))
    return (burn + compression + pumping) * (math.pi * BORE**2 / 4) * dxdphi


def _body(**tables: Any) -> FlywheelIn:
    return FlywheelIn.model_validate({
        "tables": {"crank_angle_deg": DEG.tolist(), **tables}, "cycle_deg": 720, "mean_speed_rpm": 2000.0,
        "delta": 1 / 80,
    })


def test_engine_torque_drives_and_the_constant_torque_resists(client: SynthClient) -> None:
    torque = _gas_torque(DEG)
    out = client.flywheel(_body(driving_torque_Nm=torque.tolist()))
    assert out.constant_torque_role == "resisting"
    assert not out.warnings, [w.code for w in out.warnings]
    # independent derivation: trapezoidal work of the closed table; the consumer's load is its mean torque
    phi = np.radians(np.append(DEG, 720.0))
    closed = np.append(torque, torque[0])
    work = np.concatenate(([0.0], np.cumsum(0.5 * (closed[1:] + closed[:-1]) * np.diff(phi))))
    assert work[-1] > 0
    assert out.cycle_work_J == pytest.approx(work[-1], rel=1e-12)
    assert out.constant_driving_torque_Nm == pytest.approx(-work[-1] / (4 * math.pi), rel=1e-12)
    # constant inertia (J_red = 0): J = (max - min of the excess work) / (delta w_m^2), the excess work being
    # the table's work less the load's; the extremes lie at the table's rows or where the net torque crosses zero
    w_m = 2000 * math.pi / 30
    fine = np.linspace(0, 4 * math.pi, 200_001)
    t_fine = np.interp(fine, phi, closed) - work[-1] / (4 * math.pi)
    excess = np.concatenate(([0.0], np.cumsum(0.5 * (t_fine[1:] + t_fine[:-1]) * np.diff(fine))))
    j = (excess.max() - excess.min()) / ((1 / 80) * w_m**2)
    assert out.required_constant_inertia_kgm2 == pytest.approx(j, rel=1e-6)
    assert out.achieved_delta == pytest.approx(1 / 80, rel=1e-6)


def test_the_same_table_summed_with_its_role_named_agrees(client: SynthClient) -> None:
    torque = _gas_torque(DEG).tolist()
    engine = client.flywheel(_body(driving_torque_Nm=torque))
    summed = client.flywheel(_body(reduced_torque_Nm=torque, constant_torque_role="resisting"))
    assert not summed.warnings
    assert summed.required_constant_inertia_kgm2 == pytest.approx(engine.required_constant_inertia_kgm2, rel=1e-12)
    # without the role a summed table is read as loads: the constant torque must drive, and here it cannot
    default = client.flywheel(_body(reduced_torque_Nm=torque))
    assert [w.code for w in default.warnings] == ["load_work_positive"]
    assert default.warnings[0].value == pytest.approx(engine.cycle_work_J, rel=1e-12)


def test_real_sign_mistakes_warn_on_their_table(client: SynthClient) -> None:
    torque = _gas_torque(DEG)
    # the engine's torque typed as resistance: the resisting table does positive work
    out = client.flywheel(_body(resisting_torque_Nm=torque.tolist()))
    assert [(w.code, w.field) for w in out.warnings] == [("load_work_positive", "tables.resisting_torque_Nm")]
    # the engine's torque typed with the wrong sign as the drive: the driving table does negative work
    out = client.flywheel(_body(driving_torque_Nm=(-torque).tolist()))
    assert [(w.code, w.field) for w in out.warnings] == [("drive_work_negative", "tables.driving_torque_Nm")]
    assert out.warnings[0].value == pytest.approx(-client.flywheel(_body(driving_torque_Nm=torque.tolist()))
                                                  .cycle_work_J, rel=1e-12)
