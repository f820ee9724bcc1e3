"""Flywheel sizing against the seeds' worked examples (read from seed_cases.json) and the energy relation."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import synth
from tests.conftest import CASES


def test_machine_type_table_equals_seed() -> None:
    # the package's admissible-delta table must be the seed's (003:443-453), row for row
    case = CASES["delta_admissible_ranges"]
    table = {row.name: (row.delta_min, row.delta_max) for row in synth.machine_types()}
    assert set(table) == set(case["expected"])
    for name, (lo, hi) in case["expected"].items():
        assert table[name] == pytest.approx((lo, hi), rel=case["tolerance_rel"])
        # a request naming the machine type gets the tightest value of its range
        assert synth.admissible_delta(name) == pytest.approx(lo, rel=case["tolerance_rel"])


def test_unknown_machine_type_names_the_field() -> None:
    with pytest.raises(synth.InvalidInput) as err:
        synth.admissible_delta("steam_hammers")
    assert err.value.field == "machine_type"


def test_delta_from_speed_table() -> None:
    # seed case: delta of the coursework's table of true crank speeds
    case = CASES["cw_delta_from_speed_table"]
    lo, hi, delta = synth.speed_fluctuation(np.array(case["inputs"]["omega_table_rad_s"]))
    rel = case["tolerance_rel"]
    assert lo == pytest.approx(case["inputs"]["omega_min_rad_s"], rel=rel)
    assert hi == pytest.approx(case["inputs"]["omega_max_rad_s"], rel=rel)
    assert 0.5 * (lo + hi) == pytest.approx(case["expected"]["omega_mean_rad_s"], rel=rel)
    assert delta == pytest.approx(case["expected"]["delta"], rel=rel)


def _shaper_cycle(case: dict) -> synth.ReducedCycle:
    resist = case["inputs"]["M_red_resist_Nm"]
    angles = np.radians(case["inputs"]["phi_step_deg"] * np.arange(len(resist)))
    return synth.cycle_from_tables(angles, driving_torque=np.zeros(len(resist)), resisting_torque=resist)


def test_energy_method_from_tables_regression() -> None:
    # seed case (an algorithm regression, LOW TRUST physically): constant driving torque from the balance of
    # work, excess work at the 7 nodes, J = swing/(delta w^2) with the mechanism's inertia ignored
    case = CASES["cw_flywheel_energy_method_from_tables"]
    inp, exp, rel = case["inputs"], case["expected"], case["tolerance_rel"]
    cycle = _shaper_cycle(case)
    assert cycle.cycle_work == pytest.approx(exp["A_resist_cycle_J"], rel=rel)
    balanced, driving = cycle.balanced()
    assert driving == pytest.approx(exp["M_drive_Nm"], rel=rel)
    swing = np.ptp(balanced.work_nodes())
    assert balanced.work_nodes() == pytest.approx(exp["dA_nodes_J"], rel=rel, abs=0.01)  # the seed rounds to 0.01 J
    assert swing == pytest.approx(exp["dA_range_J"], rel=rel)
    j = synth.energy_method_constant_inertia(balanced, inp["omega_mean_rad_s"], inp["delta"], samples_only=True)
    assert j == pytest.approx(exp["J_flywheel_kgm2"], rel=rel)
    # the service reports the same constant driving torque
    result = synth.size_flywheel(cycle, inp["omega_mean_rad_s"], inp["delta"])
    assert result.driving_torque == pytest.approx(exp["M_drive_Nm"], rel=rel)


def test_energy_method_between_samples_sees_more_swing() -> None:
    # identity: with linear torque between the samples the work is largest where the torque crosses zero,
    # between samples, so the continuous swing is at least the nodes' swing
    case = CASES["cw_flywheel_energy_method_from_tables"]
    balanced, _ = _shaper_cycle(case).balanced()
    hi, lo = synth.energy_extremes(balanced, 0.0)
    hi_n, lo_n = synth.energy_extremes(balanced, 0.0, samples_only=True)
    assert hi - lo >= hi_n - lo_n
    dense = balanced.evaluate(np.linspace(0, 2 * np.pi, 200_001))[2]  # brute force over the piecewise model
    assert hi - lo == pytest.approx(np.ptp(dense), rel=1e-9)


def test_flywheel_inertia_from_intercept() -> None:
    # seed case: J = AB*mu_T/(delta w^2). A cycle of constant inertia whose work swings by AB*mu_T: a triangle
    # of torque (0, m, 0, -m at 0, 90, 180, 270 deg) has a swing of m*pi/2
    case = CASES["cw_flywheel_inertia_from_AB"]
    inp, exp, rel = case["inputs"], case["expected"], case["tolerance_rel"]
    swing = inp["AB_mm"] * inp["mu_T_J_per_mm"]
    assert swing == pytest.approx(exp["energy_swing_J"], rel=rel)
    m = 2 * swing / math.pi
    cycle = synth.cycle_from_tables(np.radians([0, 90, 180, 270]), reduced_torque=[0, m, 0, -m])
    hi, lo = synth.energy_extremes(cycle, 0.0)
    assert hi - lo == pytest.approx(exp["energy_swing_J"], rel=1e-12)
    j = synth.exact_constant_inertia(cycle, inp["omega_mean_rad_s"], inp["delta"])
    assert j == pytest.approx(exp["J_M_kgm2"], rel=rel)


def test_wittenbauer_tangents_are_the_seed_tangents_to_first_order() -> None:
    # seed case: tan psi = w^2 (1 +/- delta) mu_J/(2 mu_T) uses (1 +/- delta) for (1 +/- delta/2)^2. The exact
    # slopes w_max^2/2, w_min^2/2 differ from the seed's by the factor 1 + delta^2/4/(1 +/- delta) exactly.
    case = CASES["cw_wittenbauer_tangents"]
    inp, exp, rel = case["inputs"], case["expected"], case["tolerance_rel"]
    w, d = inp["omega_mean_rad_s"], inp["delta"]
    cycle = synth.cycle_from_tables(np.radians([0, 120, 240]), reduced_torque=[1.0, -2.0, 1.0])
    tan = synth.wittenbauer_tangents(cycle, w, d)
    scale = inp["mu_J_kgm2_per_mm"] / inp["mu_T_J_per_mm"]
    for slope, key, omega_key, sign in ((tan.slope_max, "tan_psi_max", "omega_max_rad_s", 1),
                                        (tan.slope_min, "tan_psi_min", "omega_min_rad_s", -1)):
        second_order = 1 + d * d / 4 / (1 + sign * d)
        assert slope * scale == pytest.approx(exp[key] * second_order, rel=rel)
        assert math.degrees(math.atan(slope * scale / second_order)) == pytest.approx(exp[key.replace("tan", "").strip("_") + "_deg"], rel=rel)
        assert math.sqrt(2 * slope) == pytest.approx(exp[omega_key] * math.sqrt(second_order), rel=rel)
    # identity behind the closed form: w_max^2 - w_min^2 = 2 delta w_m^2
    assert tan.slope_max - tan.slope_min == pytest.approx(d * w * w, rel=1e-14)


@settings(max_examples=25, deadline=None)
@given(
    inertia=st.floats(0.05, 50.0),
    amplitudes=st.lists(st.floats(-100.0, 100.0), min_size=3, max_size=3),
    delta=st.floats(0.003, 0.2),
    speed=st.floats(2.0, 200.0),
)
def test_energy_relation_for_constant_inertia(inertia: float, amplitudes: list[float], delta: float, speed: float) -> None:
    # seeds (003:457-471): with constant J, delta = A_swing/(J w_m^2) exactly when w_m = (w_max + w_min)/2.
    # The simulated steady motion (work integral, no sizing formula) must give it, and the three methods agree.
    phi = np.linspace(0, 2 * np.pi, 180, endpoint=False)
    torque = sum(a * np.sin((k + 1) * phi + k) for k, a in enumerate(amplitudes))
    cycle, _ = synth.ReducedCycle(phi, np.full(phi.size, inertia), torque, 2 * np.pi).balanced()
    hi, lo = synth.energy_extremes(cycle, 0.0)
    if hi - lo < 1e-6:
        return
    profile = synth.steady_speed(cycle, 0.0, speed)
    expected = (hi - lo) / (inertia * speed**2)
    if expected < 1.0:
        assert profile.delta == pytest.approx(expected, rel=1e-6)
    exact = synth.exact_constant_inertia(cycle, speed, delta)
    assert synth.mertsalov_constant_inertia(cycle, speed, delta) == pytest.approx(exact, rel=1e-9, abs=1e-12 * inertia)
    assert synth.energy_method_constant_inertia(cycle, speed, delta) == pytest.approx(exact, rel=1e-9, abs=1e-9 * inertia)
