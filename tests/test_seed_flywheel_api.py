"""The course work's flywheel cases through POST /v1/flywheel: inertia from the energy swing, placement on the
motor shaft, rim dimensions."""

from __future__ import annotations

import math

import pytest

from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.flywheel import FlywheelIn
from conftest import CASES


def _swing_cycle(swing: float) -> dict:
    # A reduced torque whose energy swings by exactly ``swing`` over the cycle: +m over a quarter turn and -m
    # over another, with m = 2·swing/pi (linear between the tabulated points).
    m = 2 * swing / math.pi
    return {"crank_angle_deg": [0, 90, 180, 270], "reduced_torque_Nm": [0, m, 0, -m]}


def test_inertia_placement_and_rim_of_the_course_work(client: SynthClient) -> None:
    ab = CASES["cw_flywheel_inertia_from_AB"]
    inp, exp, rel = ab["inputs"], ab["expected"], ab["tolerance_rel"]
    swing = inp["AB_mm"] * inp["mu_T_J_per_mm"]  # the intercept AB at the energy scale
    assert swing == pytest.approx(exp["energy_swing_J"], rel=rel)
    motor = CASES["cw_flywheel_to_motor_shaft"]
    rim = CASES["cw_flywheel_rim_diameter"]
    w_crank = motor["inputs"]["omega_crank_rad_s"]
    w_motor = motor["inputs"]["n_motor_rpm"] * math.pi / 30
    k1, k2 = rim["inputs"]["k1"], rim["inputs"]["k2"]
    body = {"tables": _swing_cycle(swing), "mean_speed_rad_s": inp["omega_mean_rad_s"], "delta": inp["delta"],
            "geometry": {"shape": "rim", "density_kg_m3": rim["inputs"]["gamma_N_m3"] / rim["inputs"]["g_m_s2"],
                         "max_rim_speed_m_s": None, "max_diameter_m": rim["inputs"]["D_max_m"],
                         "thickness_ratio": [k1, k1], "width_ratio": [k2, k2],
                         "shafts": [{"name": "motor", "speed_ratio": w_motor / w_crank}]}}
    out = client.flywheel(FlywheelIn.model_validate(body))
    # J = swing/(delta·w²) (seed: J_M = AB·mu_T/(delta·omega²)); exact method with J_red = 0.
    assert out.flywheel_inertia_kgm2 == pytest.approx(exp["J_M_kgm2"], rel=rel)
    assert out.geometry is not None
    placed = {p.shaft: p for p in out.geometry.placements}
    # J' = J·(w_crank/w_motor)²; the case's J and speeds agree with the AB case to 0.2 %.
    assert w_motor == pytest.approx(motor["expected"]["omega_motor_rad_s"], rel=motor["tolerance_rel"])
    assert placed["motor"].inertia_kgm2 == pytest.approx(motor["expected"]["J_M_motor_shaft_kgm2"],
                                                         rel=motor["tolerance_rel"])
    # Rim a = k1·D, b = k2·D: the seed's thin rim J = m·D²/4 gives D = (4 g J/(pi gamma k1 k2))^(1/5) for its
    # J = 0.47; ours is 1.3 % larger, so D a fifth of that. The service takes the whole annulus,
    # J = m·(D² + a²)/4 = m·D²·(1 + k1²)/4, which makes D smaller by (1 + k1²)^(1/5).
    d_case = rim["expected"]["D_m"] * (placed["motor"].inertia_kgm2 / rim["inputs"]["J_M_kgm2"]) ** 0.2
    assert placed["motor"].diameter_m * (1 + k1**2) ** 0.2 == pytest.approx(d_case, rel=rim["tolerance_rel"])
    assert placed["motor"].width_m == pytest.approx(k2 * placed["motor"].diameter_m, rel=1e-6)  # solver tolerance
    # On the crank shaft it would need D = 0.937 m > 0.75 m: the seed's reason to move it.
    assert [(m.shaft, m.constraint) for m in out.geometry.misses] == [("crank", "max_diameter_m")]
    assert out.geometry.best.shaft == "motor"


def test_wittenbauer_tangents_of_the_course_work(client: SynthClient) -> None:
    # The seed's tan psi = w²(1 ± delta)·mu_J/(2 mu_T) takes (1 ± delta) for (1 ± delta/2)²; the service's exact
    # slopes w_max²/2, w_min²/2 differ from it by the factor 1 + delta²/4/(1 ± delta) exactly (written here).
    case = CASES["cw_wittenbauer_tangents"]
    inp, exp, rel = case["inputs"], case["expected"], case["tolerance_rel"]
    w, d = inp["omega_mean_rad_s"], inp["delta"]
    body = {"tables": {"crank_angle_deg": [0, 120, 240], "reduced_torque_Nm": [1.0, -2.0, 1.0]},
            "mean_speed_rad_s": w, "delta": d}
    em = client.flywheel(FlywheelIn.model_validate(body)).energy_mass
    scale = inp["mu_J_kgm2_per_mm"] / inp["mu_T_J_per_mm"]
    for slope, key, omega_key, sign in ((em.tangent_max_slope_J_per_kgm2, "tan_psi_max", "omega_max_rad_s", 1),
                                        (em.tangent_min_slope_J_per_kgm2, "tan_psi_min", "omega_min_rad_s", -1)):
        second_order = 1 + d * d / 4 / (1 + sign * d)
        assert slope * scale == pytest.approx(exp[key] * second_order, rel=rel)
        assert math.degrees(math.atan(slope * scale / second_order)) == pytest.approx(
            exp[key.replace("tan_", "") + "_deg"], rel=rel)
        assert math.sqrt(2 * slope) == pytest.approx(exp[omega_key] * math.sqrt(second_order), rel=rel)
