"""The balancing cone programs written straight for Clarabel, against the same programs modelled in cvxpy."""

from __future__ import annotations

import math

import cvxpy as cp
import numpy as np
import pytest

import synth
from synth.balancing.program import counterweight_layout, realisability_block

SPEED = 20.0
SAMPLES = 90


def _linkage() -> synth.Linkage:
    fb = synth.FourBar(0.3, 0.1, 0.35, 0.25)
    return synth.Linkage(fb, {
        "crank": synth.MassProps(1.0, (0.05, 0.01), 0.001),
        "coupler": synth.MassProps(2.0, (0.175, 0.0), 0.02),
        "rocker": synth.MassProps(1.5, (0.125, 0.01), 0.008),
    })


def _map_objective(lm: synth.LinearMap, p0: np.ndarray, cols: list[int], weights: synth.Weights,
                   x: cp.Expression | np.ndarray, lengths: np.ndarray) -> cp.Expression:
    """The weighted RMS objective on the linear map, written plainly over all angles (no compression); each
    counterweight's inertia costs as mass at its link's length (``lengths`` [m], per counterweight)."""
    n = lm.y.shape[0]
    force = [lm.force_rows.start, lm.force_rows.start + 1]
    bearings = list(range(lm.torque_row))
    terms = {"shaking_force": (force, n), "shaking_moment": ([lm.moment_row], n),
             "driving_torque": ([lm.torque_row], n), "bearing_forces": (bearings, n * len(lm.joints))}
    goal: cp.Expression = 0
    for key, (rows, count) in terms.items():
        y = lm.y[:, rows, :].reshape(-1, lm.y.shape[2])
        c = y @ p0 + lm.y0[:, rows].reshape(-1)
        goal = goal + getattr(weights, key) * cp.norm(y[:, cols] @ x + c, 2) / math.sqrt(count)
    masses, inertias = x[0::4], x[3::4]
    return goal + weights.added_mass * (cp.sum(masses) + cp.sum(cp.multiply(inertias, 1 / lengths**2)))


def test_optimal_program_matches_a_cvxpy_model_of_the_same_problem() -> None:
    # Independent modelling of the same SOCP (cvxpy canonicalises it, uncompressed rows): same optimum.
    linkage = _linkage()
    weights = synth.Weights(shaking_force=1.0, shaking_moment=2.0, driving_torque=1.0, bearing_forces=0.1)
    budget = 4.0
    ours = synth.balance_optimal(linkage, SPEED, weights=weights, mass_budget=budget, samples=SAMPLES,
                                 weight_scale="absolute")
    an = synth.analyse(linkage, SPEED, samples=SAMPLES)
    lm = synth.linear_map(an.motion, linkage)
    cols = [c for link in ("crank", "rocker") for c in range(lm.columns(link).start, lm.columns(link).stop)]
    x = cp.Variable(8)
    r_max = np.array([0.1, 0.25])  # the crank's and rocker's lengths: the default limits
    cons = [cp.sum(x[0::4]) <= budget, x[0::4] >= 0, x[3::4] >= 0]
    for i in range(2):
        h = cp.hstack([x[4 * i + 1], x[4 * i + 2]])
        cons += [cp.norm(h, 2) <= r_max[i] * x[4 * i], cp.quad_over_lin(h, x[4 * i]) <= x[4 * i + 3]]
    problem = cp.Problem(cp.Minimize(_map_objective(lm, linkage.params(), cols, weights, x, r_max)), cons)
    problem.solve(solver=cp.CLARABEL)
    got = np.concatenate([c.params() for c in sorted(ours.counterweights, key=lambda c: c.link)])
    ours_on_map = float(_map_objective(lm, linkage.params(), cols, weights, got, r_max).value)
    # Both solvers stop at a relative gap near 1e-8; the radius margin of 1e-7 costs less than that here.
    assert ours_on_map == pytest.approx(problem.value, rel=1e-6)
    # And the reported objective (from the plain re-analysis) is that value too.
    assert ours.objective == pytest.approx(ours_on_map, rel=1e-9)


def test_a_sweep_reuses_one_solver_and_gives_the_single_answers() -> None:
    # Three weight sets with the same weighted terms share one program; each must equal a fresh single solve.
    linkage = _linkage()
    sets = [synth.Weights(shaking_force=1.0, driving_torque=k) for k in (0.5, 2.0, 8.0)]
    points = synth.tradeoff(linkage, SPEED, None, sets, mass_budget=4.0, samples=SAMPLES)
    for weights, point in zip(sets, points, strict=True):
        single = synth.balance_optimal(linkage, SPEED, weights=weights, mass_budget=4.0, samples=SAMPLES)
        assert point.objective == pytest.approx(single.objective, rel=1e-7)
        assert point.total_added_mass == pytest.approx(single.total_added_mass, rel=1e-5, abs=1e-7)
    # More torque weight never buys a larger RMS driving torque (each point re-analysed with the plain model).
    torques = [p.after.rms_driving_torque for p in points]
    assert torques[0] >= torques[1] - 1e-9 >= torques[2] - 2e-9


def test_realisability_rows_are_built_once_per_layout() -> None:
    linkage = _linkage()
    layout = counterweight_layout(synth.CounterweightSpec(("crank", "rocker"), angle={"crank": math.pi}), linkage)
    first = realisability_block(layout)
    assert realisability_block(layout) is first
    # Per counterweight: 2 signs, a 3-row and a 4-row cone; a fixed angle adds an equality and a sign.
    assert first[0].shape == (2 * (2 + 3 + 4) + 2, 8)


def test_an_iteration_limit_is_a_failure_not_a_timeout(monkeypatch: pytest.MonkeyPatch) -> None:
    # Clarabel stopped after two iterations reports MaxIterations: a SolverFailed naming it (422), not a 504.
    from synth.balancing import program

    monkeypatch.setitem(program._TOLERANCES, "max_iter", 2)
    with pytest.raises(synth.SolverFailed) as err:
        synth.balance_optimal(_linkage(), SPEED, weights=synth.Weights(1.0, 1.0, 1.0, 1.0), samples=SAMPLES)
    assert err.value.status == "iteration_limit"
