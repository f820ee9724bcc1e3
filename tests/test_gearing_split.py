"""Ratio splitting: geometric programs against the stationarity condition and brute-force scans, the handbook
rule, R20 snapping, the seed's total ratios and the problems a layout can raise."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

import synth
from synth.gearing.split import R20_BASE

from conftest import CASES

WIDE = synth.StageSpec("spur", ratio_min=1.0, ratio_max=20.0)


def wide(n: int) -> tuple[synth.Stage, ...]:
    return synth.make_stages([WIDE] * n, max_stages=6)


def inertia_two_stage(u1: np.ndarray, total: float, jp: float, load: float) -> np.ndarray:
    """Independent statement of the issue's model for two stages: J/J_p = 1 + (u1^4 + 1)/u1^2 + u2^4/U^2 + load."""
    u2 = total / u1
    return jp * (1 + (u1**4 + 1) / u1**2 + u2**4 / total**2) + load / total**2


@pytest.mark.parametrize("objective", ["min_inertia", "min_volume"])
def test_split_programs_are_dgp(objective: str) -> None:
    problem, _ = synth.build_split_program(20.0, synth.make_stages(3, max_stages=6), objective,
                                           synth.InertiaModel(load_inertia=0.5))
    assert problem.is_dgp()


@pytest.mark.parametrize("total", [6.0, 12.0, 20.0, 40.0])
def test_min_inertia_meets_the_stationarity_condition(total: float) -> None:
    # The condition u1^6 - u1^2 - 2 U^2 = 0 (no load, no shafts); its positive real root, by numpy.
    result = synth.split_ratio(total, wide(2), "min_inertia")
    u1 = result.stage_ratios[0]
    assert u1**6 - u1**2 - 2 * total**2 == pytest.approx(0.0, abs=1e-4 * 2 * total**2)
    roots = np.roots([1, 0, 0, 0, -1, 0, -2 * total**2])
    root = max(r.real for r in roots if abs(r.imag) < 1e-9 and r.real > 0)
    # The objective is flat at its minimum, so Clarabel's 1e-10 gap leaves the ratio accurate to ~1e-6.
    assert u1 == pytest.approx(root, rel=1e-5)
    assert result.stage_ratios[1] == pytest.approx(total / root, rel=1e-5)
    assert result.checks.kkt_residual is not None and result.checks.kkt_residual < 1e-4


@pytest.mark.parametrize(("total", "load"), [(12.0, 0.0), (25.0, 0.8), (8.0, 5.0)])
def test_min_inertia_equals_a_brute_force_scan(total: float, load: float) -> None:
    jp = 2e-3
    result = synth.split_ratio(total, wide(2), "min_inertia", inertia=synth.InertiaModel(jp, load))
    u1 = np.geomspace(max(1.0, total / 20), min(20.0, total), 200_001)   # every admissible first-stage ratio
    values = inertia_two_stage(u1, total, jp, load)
    best = int(np.argmin(values))
    assert result.objective_value == pytest.approx(values[best], rel=1e-7)
    assert result.stage_ratios[0] == pytest.approx(u1[best], rel=1e-4)
    assert result.checks.objective_model == pytest.approx(values[best], rel=1e-7)


def test_min_volume_equals_a_brute_force_scan_over_three_stages() -> None:
    # Independent statement of the sizing rule: V = sum c_k T_k (u_k + 1)(u_k^2 + 1)/u_k, T_k downstream.
    stages = synth.make_stages(["helical", "helical", "spur"], max_stages=6)
    total, torque = 60.0, 80.0
    result = synth.split_ratio(total, stages, "min_volume", input_torque=torque)
    g = np.geomspace(1.0, 6.3, 1201)
    u1, u2 = np.meshgrid(g, g, indexing="ij")
    u3 = total / (u1 * u2)
    ok = (u3 >= 1.0) & (u3 <= 6.3)
    c = [s.volume_coefficient for s in stages]
    eta = [s.efficiency for s in stages]
    shape = [(u + 1) * (u**2 + 1) / u for u in (u1, u2, u3)]
    vol = torque * (c[0] * shape[0] + c[1] * u1 * eta[0] * shape[1] + c[2] * u1 * eta[0] * u2 * eta[1] * shape[2])
    scan = float(vol[ok].min())
    assert result.objective_value <= scan * (1 + 1e-7)
    assert result.objective_value == pytest.approx(scan, rel=1e-4)   # grid spacing 0.15 % in each ratio
    assert math.prod(result.stage_ratios) == pytest.approx(total, rel=1e-8)


def test_handbook_rule_and_the_seed_fixed_first_stage() -> None:
    # Handbook rule for a developed two-stage reducer: slow stage 0.88 sqrt(U).
    result = synth.split_ratio(20.0, synth.make_stages(["helical", "helical"], max_stages=6), "handbook")
    assert result.stage_ratios[1] == pytest.approx(0.88 * math.sqrt(20.0), rel=1e-12)
    assert math.prod(result.stage_ratios) == pytest.approx(20.0, rel=1e-12)
    # Seed rule [004:790-800]: a standard first stage, the remainder to the second; u = 17 as the doc rounds it.
    case = CASES["drive_motor_selection_and_ratio_split"]
    inp, exp = case["inputs"], case["expected"]
    stages = synth.make_stages([synth.StageSpec("bevel", ratio=inp["u_bevel"]), "open_spur"], max_stages=6)
    for objective in ("handbook", "min_inertia", "min_volume"):
        split = synth.split_ratio(exp["u_total"], stages, objective)
        assert split.stage_ratios[0] == inp["u_bevel"]
        assert split.stage_ratios[1] == pytest.approx(exp["u_cyl"], rel=case["tolerance_rel"])


def test_case_task1_total_ratios_and_splits() -> None:
    case = CASES["case_task1_total_ratios"]
    inp = case["inputs"]
    for n_out, n_motor, expected in zip(inp["n_out_rpm"], inp["n_motor_rpm"], case["expected"]["u_total"],
                                        strict=True):
        total = synth.total_ratio(n_motor * math.pi / 30, n_out * math.pi / 30)
        assert total == pytest.approx(expected, abs=5e-7)   # the case prints six decimals; its 1e-9 is relative
        assert total == pytest.approx(n_motor / n_out, rel=case["tolerance_rel"])
        n = math.ceil(math.log(total) / math.log(6.3))   # fewest spur stages that reach it
        split = synth.split_ratio(total, synth.make_stages(n, max_stages=6), "min_inertia")
        assert math.prod(split.stage_ratios) == pytest.approx(total, rel=1e-8)
        assert all(1.0 <= u <= 6.3 for u in split.stage_ratios)
        if n > 1:
            with pytest.raises(synth.Infeasible) as err:
                synth.split_ratio(total, synth.make_stages(n - 1, max_stages=6), "min_inertia")
            assert err.value.constraint == "stage_ratio_max"
            assert err.value.details["reachable_max"] == pytest.approx(6.3 ** (n - 1))


@pytest.mark.parametrize(("total", "objective"), [(12.5, "min_inertia"), (20.0, "min_inertia"), (20.0, "min_volume"),
                                                  (4.0, "min_inertia")])
def test_r20_snapping_is_the_best_admissible_r20_pair(total: float, objective: str) -> None:
    stages = synth.make_stages(2, max_stages=6)
    result = synth.split_ratio(total, stages, objective, snap_r20=True)
    tol = 0.025 if total <= 4.5 else 0.04
    assert result.snap_tolerance == tol
    r20 = [b * 10.0**d for d in (0, 1) for b in R20_BASE if 1.0 <= b * 10.0**d <= 6.3]
    assert all(any(math.isclose(u, v) for v in r20) for u in result.stage_ratios)
    assert abs(math.prod(result.stage_ratios) / total - 1) <= tol
    # Independent: every admissible pair of R20 values, scored with the plain models.
    model = synth.InertiaModel()
    pairs = [p for p in itertools.product(r20, r20) if abs(p[0] * p[1] / total - 1) <= tol]
    score = [synth.reduced_train_inertia(p, model) if objective == "min_inertia" else synth.gear_volume(p, stages)
             for p in pairs]
    assert result.objective_value == pytest.approx(min(s for s in score if s is not None), rel=1e-12)


def test_r20_snapping_out_of_tolerance_is_infeasible() -> None:
    # R20 pairs multiply to R20-spaced totals (12 % apart): 12 lies 4.2 % from the nearest (11.2, 12.5).
    with pytest.raises(synth.Infeasible) as err:
        synth.split_ratio(12.0, synth.make_stages(2, max_stages=6), "min_inertia", snap_r20=True)
    assert err.value.constraint == "snap_tolerance"


def test_layout_problems() -> None:
    with pytest.raises(synth.InvalidInput) as err:
        synth.make_stages(["spur", "harmonic"], max_stages=6)
    assert err.value.field == "stages[1].type" and "helical" in str(err.value) and "worm" in str(err.value)
    with pytest.raises(synth.TooLarge) as big:
        synth.make_stages(7, max_stages=6)
    assert (big.value.limit, big.value.got) == (6, 7)
    with pytest.raises(synth.Infeasible) as low:
        synth.split_ratio(5.0, synth.make_stages(["worm"], max_stages=6), "min_inertia")
    assert low.value.constraint == "stage_ratio_min" and low.value.details["reachable_min"] == 8.0
    with pytest.raises(synth.InvalidInput) as vol:
        synth.split_ratio(40.0, synth.make_stages(["belt", "spur", "spur"], max_stages=6), "min_volume")
    assert vol.value.field == "stages[0].type"
    with pytest.raises(synth.InvalidInput) as hb:
        synth.split_ratio(40.0, synth.make_stages(3, max_stages=6), "handbook")
    assert hb.value.field == "objective"


@pytest.mark.parametrize(("objective", "total", "layout", "model"), [
    ("min_inertia", 12.0, ["spur", "spur"], synth.InertiaModel()),
    ("min_inertia", 300.0, ["helical", "helical", {"type": "bevel", "ratio": 3.0}, "spur"],
     synth.InertiaModel(2e-3, 0.4, (1e-3, 0.0, 2e-3, 0.0, 0.1), 5e-3)),
    ("min_volume", 60.0, ["helical", "helical", "spur"], synth.InertiaModel()),
])
def test_log_space_solve_equals_the_cvxpy_geometric_program(objective: str, total: float, layout: list[object],
                                                            model: synth.InertiaModel) -> None:
    # The same GP stated independently in cvxpy's DGP form and canonicalised by cvxpy: same optimum.
    import cvxpy as cp

    specs = [synth.StageSpec(**s) if isinstance(s, dict) else s for s in layout]
    stages = synth.make_stages(specs, max_stages=6)
    problem, u = synth.build_split_program(total, stages, objective, model, 25.0)
    problem.solve(gp=True, solver=cp.CLARABEL, tol_gap_abs=1e-10, tol_gap_rel=1e-10, tol_feas=1e-10)
    result = synth.split_ratio(total, stages, objective, inertia=model, input_torque=25.0)
    assert result.objective_value == pytest.approx(problem.value, rel=1e-9)
    # The optimum is flat: the ratios agree to the square root of the solvers' gap.
    assert np.asarray(result.stage_ratios) == pytest.approx(np.asarray(u.value), rel=1e-5)


def test_a_split_held_by_a_stage_bound_says_which_stage_and_which_bound() -> None:
    # Independent derivation: without bounds the two-stage optimum solves u1^6 - u1^2 - 2 U^2 = 0 (numpy's root);
    # the objective is convex in log u1 along prod(u) = U, so a bound below that root holds the split on it.
    total, bound = 20.0, 2.5
    roots = np.roots([1, 0, 0, 0, -1, 0, -2 * total**2])
    free_optimum = max(r.real for r in roots if abs(r.imag) < 1e-9 and r.real > 0)
    assert free_optimum > bound
    stages = synth.make_stages([synth.StageSpec("spur", ratio_min=1.0, ratio_max=bound), WIDE], max_stages=6)
    result = synth.split_ratio(total, stages, "min_inertia")
    assert result.stage_ratios[0] == pytest.approx(bound, rel=1e-9)
    (note,) = [w for w in result.warnings if w.code == "stage_ratio_at_limit"]
    assert note.field == "stages[0]" and note.value == pytest.approx(bound, rel=1e-9)
    assert "upper limit 2.5" in note.message
    # the unbounded split carries no such note
    assert not [w for w in synth.split_ratio(total, wide(2), "min_inertia").warnings
                if w.code == "stage_ratio_at_limit"]
