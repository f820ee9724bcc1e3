"""Drive design: the seed's worked example (motor, ratios, shaft torques), the motor choice, and the identities
every drive result satisfies."""

from __future__ import annotations

import math
from typing import Any, Literal

import pytest

import synth

from conftest import CASES


def seed_drive(torque_basis: Literal["load", "rated"] = "rated") -> tuple[synth.DriveResult, Any, Any, float]:
    case = CASES["drive_motor_selection_and_ratio_split"]
    inp = case["inputs"]
    stages = synth.make_stages([
        synth.StageSpec("bevel", ratio=inp["u_bevel"],
                        efficiency=inp["eta_coupling"] * inp["eta_bevel"] * inp["eta_bearing"]),
        synth.StageSpec("open_spur", efficiency=inp["eta_open_cyl_gear"] * inp["eta_bearing"]),
    ], max_stages=6)
    result = synth.design_drive(inp["P_out_kW"] * 1e3, inp["omega_out_rad_s"], stages,
                                reserve_factor=inp["reserve_factor"], drive_efficiency=inp["eta_drive_assumed"],
                                torque_basis=torque_basis)
    return result, inp, case["expected"], case["tolerance_rel"]


def test_seed_drive_motor_selection_and_ratio_split() -> None:
    # The case's notes: torques follow the motor's NOMINAL power, the doc uses pi = 3.14 and rounds (u = 17,
    # u_cyl = 5.7); the exact chain with pi lies within the case's 1 % of every printed value.
    result, inp, exp, rel = seed_drive()
    assert result.motor.name == inp["motor"]
    assert result.motor.rated_power == pytest.approx(inp["P_motor_nom_kW"] * 1e3)
    assert result.motor.rated_speed * 30 / math.pi == pytest.approx(inp["n_motor_rpm"])
    assert result.required_power / 1e3 == pytest.approx(exp["P_motor_req_kW"], rel=rel)
    assert result.output_speed * 30 / math.pi == pytest.approx(exp["n_out_rpm"], rel=rel)
    assert result.total_ratio == pytest.approx(exp["u_total"], rel=rel)
    assert result.split.stage_ratios[0] == inp["u_bevel"]
    assert result.split.stage_ratios[1] == pytest.approx(exp["u_cyl"], rel=rel)
    assert result.stage_efficiencies[0] == pytest.approx(exp["eta_1"], rel=rel)
    assert result.stage_efficiencies[1] == pytest.approx(exp["eta_2"], rel=rel)
    torques_kNm = [s.torque / 1e3 for s in result.shafts]
    assert torques_kNm[0] == pytest.approx(exp["T_I_kNm"], rel=rel)
    assert torques_kNm[1] == pytest.approx(exp["T_II_kNm"], rel=rel)
    assert torques_kNm[2] == pytest.approx(exp["T_III_kNm"], rel=rel)
    assert any(w.code == "rated_power_exceeds" for w in result.warnings)   # 24.9 kW reach the output, 20 kW are needed


def test_load_basis_delivers_the_output_power() -> None:
    # Identity: with torques from the load, the output shaft carries exactly the required output power.
    result, inp, _, _ = seed_drive("load")
    out = result.shafts[-1]
    assert out.torque * out.speed == pytest.approx(inp["P_out_kW"] * 1e3, rel=1e-12)
    assert result.shafts[0].power == pytest.approx(inp["P_out_kW"] * 1e3 / result.chain_efficiency, rel=1e-12)


def test_reduced_inertia_equals_kinetic_energy_on_the_shafts() -> None:
    stages = synth.make_stages(["helical", "helical"], max_stages=6)
    model = synth.InertiaModel(pinion_inertia=2e-3, load_inertia=3.0, shaft_inertias=(1e-3, 5e-3, 0.02))
    result = synth.design_drive(3000.0, 60 * math.pi / 30, stages, inertia=model)
    # Independent: sum of 1/2 J w^2 over the shafts at rated speed equals 1/2 J_red w_motor^2.
    ke = sum(0.5 * s.inertia * s.speed**2 for s in result.shafts)
    assert 0.5 * result.reduced_inertia * result.shafts[0].speed ** 2 == pytest.approx(ke, rel=1e-12)
    assert result.checks.kinetic_energy == pytest.approx(result.checks.reduced_kinetic_energy, rel=1e-12)
    rotor = result.motor.rotor_inertia or 0.0
    assert result.shafts[0].inertia == pytest.approx(2e-3 + 1e-3 + rotor, rel=1e-12)
    assert result.shafts[-1].inertia == pytest.approx(2e-3 * result.split.stage_ratios[1] ** 4 + 0.02 + 3.0)


@pytest.mark.parametrize("power", [400.0, 1100.0, 1500.1, 27_500.0, 60_000.0])
def test_motor_choice_is_the_smallest_covering_rating(power: float) -> None:
    motor = synth.select_motor(power)
    smallest = min(m.rated_power for m in synth.motor_catalogue() if m.rated_power >= power)
    assert motor.rated_power == smallest
    four_pole = synth.select_motor(power, synchronous_speed=1500 * math.pi / 30)
    assert four_pole.synchronous_speed == pytest.approx(1500 * math.pi / 30)
    assert four_pole.rated_power == min(m.rated_power for m in synth.motor_catalogue()
                                        if m.rated_power >= power and m.synchronous_speed == four_pole.synchronous_speed)


def test_drive_problems() -> None:
    stages = synth.make_stages(2, max_stages=6)
    with pytest.raises(synth.Infeasible) as err:
        synth.design_drive(500e3, 10.0, stages)
    assert err.value.constraint == "motor_power"
    with pytest.raises(synth.Infeasible) as err:
        synth.design_drive(1000.0, 10.0, stages, motor="4A71A4")
    assert err.value.constraint == "motor_power"
    with pytest.raises(synth.InvalidInput) as bad:
        synth.design_drive(1000.0, 10.0, stages, motor="no-such-motor")
    assert bad.value.field == "motor"
    with pytest.raises(synth.Infeasible) as far:
        synth.design_drive(1000.0, 1.0, stages, synchronous_speed=3000 * math.pi / 30)   # U ~ 290 > 6.3^2
    assert far.value.constraint == "stage_ratio_max"
