"""Pareto fronts immune to solver noise: rows that differ only by noise are one design, and the README's study
(crank length x mass budget, optimal balancing) keeps no design another beats beyond noise."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import synth
from api.execution.plans import Limits
from api.studies.tasks import variant_function
from synth.execution import SerialExecutor
from synth.studies.pareto import SOLVER_NOISE, tolerances


def _beats(q: np.ndarray, p: np.ndarray, tol: np.ndarray) -> bool:
    """Written apart from the engine: q no worse than p beyond tol anywhere and better beyond it somewhere."""
    return bool(all(q[j] <= p[j] + tol[j] for j in range(len(p))) and any(q[j] < p[j] - tol[j] for j in range(len(p))))


def _brute_force(points: np.ndarray, senses: list[str], tol: np.ndarray) -> np.ndarray:
    cost = points * np.array([1.0 if s == "min" else -1.0 for s in senses])
    return np.array([not any(_beats(q, p, tol) for q in cost) for p in cost])


@pytest.mark.parametrize("seed,senses", [(0, ["min", "min"]), (1, ["min", "max"]), (2, ["max", "min", "min"])])
def test_rows_that_differ_only_by_noise_make_the_clean_front(seed: int, senses: list[str]) -> None:
    rng = np.random.default_rng(seed)
    # Small integers make ties; each copy then gets noise of up to 1e-7 of its column's scale, a hundred times
    # what beats a nine-digit comparison and the size of the mass-budget residuals the solvers leave.
    clean = rng.integers(1, 12, size=(120, len(senses))).astype(float)
    scale = np.abs(clean).max(axis=0)
    noisy = clean + rng.uniform(-1e-7, 1e-7, size=clean.shape) * scale
    exact_clean = _brute_force(clean, senses, np.zeros(len(senses)))
    assert np.array_equal(synth.pareto_mask(noisy, senses), exact_clean)
    # the noise alone splits designs under an exact comparison: the tolerance is what keeps the front whole
    assert not np.array_equal(synth.pareto_mask(noisy, senses, noise=0.0), exact_clean)


@pytest.mark.parametrize("seed", [3, 4])
def test_front_equals_a_pairwise_check_with_the_same_tolerance(seed: int) -> None:
    # Continuous values a few tolerances apart, where beating is not transitive: every row against every row.
    rng = np.random.default_rng(seed)
    points = 1.0 + rng.integers(0, 6, size=(200, 2)) * 0.7e-6 + rng.uniform(0, 1e-7, size=(200, 2))
    tol = tolerances(points)
    assert tol == pytest.approx(SOLVER_NOISE * points.max(axis=0), rel=1e-15)
    assert np.array_equal(synth.pareto_mask(points, ["min", "min"]), _brute_force(points, ["min", "min"], tol))


README_STUDY: dict[str, Any] = {
    # The README's "Design studies" example: four crank lengths x three mass budgets, optimal balancing.
    "endpoint": "/v1/balancing/optimal",
    "base": {"mechanism": {"type": "fourbar", "ground_length_m": 0.30, "crank_length_m": 0.10,
                           "coupler_length_m": 0.35, "rocker_length_m": 0.25,
                           "links": {"crank": {"mass_kg": 1.0, "com_m": [0.05, 0.0], "inertia_kgm2": 0.001},
                                     "coupler": {"mass_kg": 2.0, "com_m": [0.175, 0.0], "inertia_kgm2": 0.02},
                                     "rocker": {"mass_kg": 1.5, "com_m": [0.125, 0.0], "inertia_kgm2": 0.008}}},
             "speed_rpm": 300, "samples": 90, "max_radius_m": {"crank": 0.1, "rocker": 0.25},
             "weights": {"shaking_force": 1.0, "driving_torque": 0.5}},
    "parameters": [{"path": "mechanism.crank_length_m", "range": [0.06, 0.12], "count": 4},
                   {"path": "mass_budget_kg", "values": [1.0, 2.0, 4.0]}],
    "metrics": ["summary_after.rms_shaking_force_N", "summary_after.rms_driving_torque_Nm", "total_added_mass_kg"],
    "objectives": {"summary_after.rms_shaking_force_N": "min", "total_added_mass_kg": "min"},
    "constraints": [{"metric": "summary_after.rms_driving_torque_Nm", "max": 40.0}],
}


def test_readme_study_front_holds_no_design_beaten_beyond_noise() -> None:
    study = synth.study_from_dict(README_STUDY)
    rows: list[synth.VariantRow] = []
    executor = SerialExecutor()
    try:
        synth.run_study(study, variant_function(README_STUDY["endpoint"], Limits(20_000, 6, 20.0)), executor,
                        rows.extend)
    finally:
        executor.shutdown()
    ok = sorted((r for r in rows if r.ok and r.feasible), key=lambda r: r.index)
    assert len(ok) >= 6
    points = np.array([[r.metrics[0], r.metrics[2]] for r in ok if r.metrics is not None])
    mask = synth.pareto_mask(points, ["min", "min"], study.objective_digits)
    # the budgets are met to solver accuracy: every added mass lies within 1e-6 relative of its budget or below
    for r in ok:
        assert r.metrics is not None and r.metrics[2] <= r.values[1] * (1 + SOLVER_NOISE)
    # independent pairwise check with the documented tolerance: no design on the front is beaten
    tol = tolerances(points, study.objective_digits)
    on = np.flatnonzero(mask)
    for i in on:
        assert not any(_beats(points[j], points[i], tol) for j in range(len(points))), ok[i].values
    # and every design left off is beaten by one on it
    for i in np.flatnonzero(~mask):
        assert any(_beats(points[j], points[i], tol) for j in on)
    # the case: at a 1 kg budget the longer cranks shake more for the same mass, so only 0.06 m stays
    one_kg = [(r.values[0], m) for r, m in zip(ok, mask, strict=True) if r.values[1] == 1.0]
    assert [c for c, m in one_kg if m] == [pytest.approx(0.06)]
