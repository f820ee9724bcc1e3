"""The drive stage's pieces that are built once per layout or computed at once equal their plain construction,
bit for bit: the split's log-space program, its KKT check, the teeth-narrowed stage ranges and the tooth search's
enumeration check. Each reference below is the plain statement written out here, one point and one row at a time."""

from __future__ import annotations

import math
from collections.abc import Sequence

import clarabel
import numpy as np
import pytest
import scipy.sparse as sp

import synth
from synth.gearing import split, teeth
from synth.gearing.stages import Stage

SPUR = synth.StageSpec("spur", ratio_min=1.5, ratio_max=7.0)
LAYOUTS = {
    "one stage": ([SPUR], 5.0),
    "two stages": ([SPUR, "helical"], 14.0),
    "three stages": (["helical", SPUR, "helical"], 60.0),
    "a fixed ratio": ([synth.StageSpec("bevel", ratio=2.5), "helical", SPUR], 30.0),
    "two fixed ratios": ([synth.StageSpec("spur", ratio=2.0), "helical", synth.StageSpec("spur", ratio=3.0)], 21.0),
}
MODELS = [split.InertiaModel(), split.InertiaModel(2e-3, 0.4, (), 1e-4),
          split.InertiaModel(1e-3, 0.0, (1e-4, 2e-4, 3e-4, 4e-4), 5e-4)]


def _stages(name: str) -> tuple[tuple[Stage, ...], float]:
    specs, total = LAYOUTS[name]
    return synth.make_stages(specs, max_stages=6), total


def _plain_program(total: float, stages: Sequence[Stage], objective: str, model: split.InertiaModel,
                   input_torque: float) -> tuple[sp.csc_matrix, np.ndarray, list[object]]:
    """The log-space program stated per call from dense rows, as solve_split_log states it."""
    n = len(stages)
    exps, _ = split._exponents(n, objective)
    coeff = split._coefficients(objective, stages, model, input_torque)
    keep = coeff > 0
    exps, logc = exps[keep], np.log(coeff[keep])
    terms = len(logc)
    size = n + 1 + terms
    eq_a = [np.concatenate([np.ones(n), np.zeros(1 + terms)])]
    eq_b = [math.log(total)]
    le_a, le_b = [], []
    for k, s in enumerate(stages):
        e = np.zeros(size)
        e[k] = 1.0
        if s.ratio is not None:
            eq_a.append(e)
            eq_b.append(math.log(s.ratio))
        else:
            le_a += [e, -e]
            le_b += [math.log(s.ratio_max), -math.log(s.ratio_min)]
    le_a.append(np.concatenate([np.zeros(n + 1), np.ones(terms)]))
    le_b.append(1.0)
    cone_a = np.zeros((3 * terms, size))
    cone_a[0::3, :n] = -exps
    cone_a[0::3, n] = 1.0
    cone_a[2::3, n + 1 :] = -np.eye(terms)
    cone_b = np.zeros(3 * terms)
    cone_b[0::3] = logc
    cone_b[1::3] = 1.0
    a = sp.csc_matrix(np.vstack([np.array(eq_a), np.array(le_a), cone_a]))
    cones: list[object] = [clarabel.ZeroConeT(len(eq_b)), clarabel.NonnegativeConeT(len(le_b))]
    cones += [clarabel.ExponentialConeT() for _ in range(terms)]
    return a, np.concatenate([eq_b, le_b, cone_b]), cones


def _plain_kkt(objective: str, ratios: np.ndarray, stages: Sequence[Stage], model: split.InertiaModel,
               input_torque: float) -> float:
    """The KKT residual with one plain-model evaluation per perturbed point."""
    x = np.log(ratios)
    f0 = split._objective_value(objective, ratios, stages, model, input_torque)
    h = 1e-6
    grad = np.empty(len(x))
    for i in range(len(x)):
        e = np.zeros(len(x))
        e[i] = h
        grad[i] = (split._objective_value(objective, np.exp(x + e), stages, model, input_torque)
                   - split._objective_value(objective, np.exp(x - e), stages, model, input_torque)) / (2 * h)
    free = np.array([s.ratio is None for s in stages])
    lo = np.array([math.log(s.ratio_min) for s in stages])
    hi = np.array([math.log(s.ratio_max) for s in stages])
    tol = 1e-5
    at_lo, at_hi = free & (x <= lo + tol), free & (x >= hi - tol)
    interior = free & ~at_lo & ~at_hi
    if not free.any():
        return 0.0
    lam = float(np.mean(grad[interior])) if interior.any() else float(np.median(grad[free]))
    viol = np.zeros(len(x))
    viol[interior] = np.abs(grad[interior] - lam)
    viol[at_hi] = np.maximum(grad[at_hi] - lam, 0.0)
    viol[at_lo] = np.maximum(lam - grad[at_lo], 0.0)
    return float(np.max(viol) / abs(f0))


@pytest.mark.parametrize("objective", ["min_inertia", "min_volume"])
@pytest.mark.parametrize("layout", sorted(LAYOUTS))
def test_the_layouts_program_equals_its_plain_statement(layout: str, objective: str) -> None:
    # Identity: the cached matrix and the per-call right-hand side against the program stated from scratch.
    stages, total = _stages(layout)
    for model in MODELS[: 2 if len(stages) != 3 else 3]:
        for torque in (1.0, 37.5):
            program, b = split._log_program_of(total, stages, objective, model, torque)
            a, b_ref, cones = _plain_program(total, stages, objective, model, torque)
            assert program.a.shape == a.shape
            for got, ref in ((program.a.indptr, a.indptr), (program.a.indices, a.indices), (program.a.data, a.data)):
                assert np.array_equal(got, ref)
            assert np.array_equal(b, b_ref)
            assert [type(c) for c in program.cones] == [type(c) for c in cones]
            assert [repr(c) for c in program.cones] == [repr(c) for c in cones]
            assert program.p.shape == (a.shape[1], a.shape[1]) and program.p.nnz == 0
            assert program.q.tolist() == [1.0 if i == len(stages) else 0.0 for i in range(a.shape[1])]


@pytest.mark.parametrize("objective", ["min_inertia", "min_volume"])
@pytest.mark.parametrize("layout", sorted(LAYOUTS))
def test_the_kkt_check_equals_one_point_at_a_time(layout: str, objective: str) -> None:
    # Identity: the batched central differences against one plain-model evaluation per point, at the optimum
    # (residual near zero), at a ratio on a bound and off the optimum (residual of order one).
    stages, total = _stages(layout)
    for model in MODELS[: 2 if len(stages) != 3 else 3]:
        result = synth.split_ratio(total, stages, objective, inertia=model, input_torque=3.0)
        optimum = np.array(result.stage_ratios)
        free = [k for k, s in enumerate(stages) if s.ratio is None]
        off = optimum.copy()
        if len(free) >= 2:
            off[free[0]] *= 1.3
            off[free[1]] /= 1.3
        bound = optimum.copy()
        bound[free[0]] = stages[free[0]].ratio_max
        for ratios in (optimum, off, bound):
            got = split._kkt_residual(objective, ratios, stages, model, 3.0)
            assert repr(got) == repr(_plain_kkt(objective, ratios, stages, model, 3.0))
        if len(free) >= 2:
            assert split._kkt_residual(objective, off, stages, model, 3.0) > 1e-3


def test_teeth_narrowed_ranges_equal_the_admissible_pairs_on_the_whole_grid() -> None:
    # Independent computation: the narrowed range is the smallest and largest ratio of the pairs the rules admit,
    # enumerated over the whole tooth grid with pairs_admissible; unchanged stages are returned as they came.
    rules_list = [teeth.ToothRules(), teeth.ToothRules(max_teeth=40), teeth.ToothRules(min_teeth=12, hunting=True)]
    layouts = [synth.make_stages(["helical", "helical"], max_stages=6),
               synth.make_stages([synth.StageSpec("spur", ratio_min=1.0, ratio_max=9.0), "spur"], max_stages=6),
               synth.make_stages([synth.StageSpec("bevel", ratio=2.5), "helical"], max_stages=6)]
    for rules in rules_list:
        for stages in layouts:
            for _ in range(2):   # the second call answers from the cache
                narrowed, limits = split.teeth_limited(stages, rules)
                z = np.arange(1, rules.max_teeth + 1)
                zp, zg = (g.ravel() for g in np.meshgrid(z, z, indexing="ij"))
                expected_limits = []
                for k, s in enumerate(stages):
                    if not s.toothed or s.ratio is not None:
                        assert narrowed[k] == s
                        continue
                    ok = teeth.pairs_admissible(zp, zg, s, rules)
                    ratio = zg[ok] / zp[ok]
                    lo, hi = float(ratio.min()), float(ratio.max())
                    if lo > s.ratio_min * (1 + 1e-12) or hi < s.ratio_max * (1 - 1e-12):
                        expected_limits.append((k, lo, hi))
                        assert (narrowed[k].ratio_min, narrowed[k].ratio_max) == (max(lo, s.ratio_min),
                                                                                  min(hi, s.ratio_max))
                    else:
                        assert narrowed[k] == s
                assert [(lim.stage, lim.ratio_min, lim.ratio_max) for lim in limits] == expected_limits
                for lim in limits:
                    assert lim.smallest[1] / lim.smallest[0] == lim.ratio_min
                    assert lim.largest[1] / lim.largest[0] == lim.ratio_max


def _plain_enumeration(target: float, stages: Sequence[Stage], rules: teeth.ToothRules,
                       tolerance: float | None) -> tuple[float, int, list[tuple[int, int]], int] | None:
    """Every combination by index grids, as the enumeration check was first stated."""
    pairs = teeth._stage_sets(stages, rules, None)
    grids = np.meshgrid(*[np.arange(len(p[0])) for p in pairs], indexing="ij")
    idx = [g.ravel() for g in grids]
    ratio = np.ones(idx[0].shape)
    total = np.zeros(idx[0].shape, dtype=np.int64)
    sums = []
    for (zp, zg), i in zip(pairs, idx, strict=True):
        ratio = ratio * (zg[i] / zp[i])
        total = total + zp[i] + zg[i]
        sums.append(zp[i] + zg[i])
    ok = np.ones(ratio.shape, dtype=bool)
    if rules.reverted:
        for s in sums[1:]:
            ok &= s == sums[0]
    err = np.abs(ratio / target - 1)
    if tolerance is not None:
        ok &= err <= tolerance * (1 + 1e-12) + 1e-15
    if not ok.any():
        return None
    cand = np.nonzero(ok)[0]
    if tolerance is None:
        cand = cand[err[cand] <= err[cand].min() + teeth.TIE]
        k = cand[np.lexsort((err[cand], total[cand]))[0]]
    else:
        cand = cand[total[cand] == total[cand].min()]
        k = cand[np.argmin(err[cand])]
    return float(err[k]), int(total[k]), [(int(zp[i[k]]), int(zg[i[k]])) for (zp, zg), i in zip(pairs, idx)], ratio.size


@pytest.mark.parametrize("rules, tolerance", [(teeth.ToothRules(max_teeth=60), None),
                                              (teeth.ToothRules(max_teeth=60), 0.01),
                                              (teeth.ToothRules(max_teeth=60, hunting=True), None),
                                              (teeth.ToothRules(max_teeth=36, reverted=True), None),
                                              (teeth.ToothRules(max_teeth=36, reverted=True), 0.02)])
def test_the_enumeration_check_equals_its_plain_statement_and_the_search(rules: teeth.ToothRules,
                                                                         tolerance: float | None) -> None:
    # Identity: the outer-product enumeration against index grids; the search's answer against both.
    spur = synth.StageSpec("spur", ratio_min=1.2, ratio_max=5.0)
    for n, target in ((1, 2.05), (2, 3.9), (3, 7.5)):
        if rules.reverted and n == 1:
            continue
        if n == 3 and rules.max_teeth > 40:
            continue
        stages = synth.make_stages([spur] * n, max_stages=6)
        got = teeth.enumerate_tooth_numbers(target, stages, rules, tolerance)
        ref = _plain_enumeration(target, stages, rules, tolerance)
        assert repr(got) == repr(ref)
        if got is None:
            with pytest.raises(synth.Infeasible):
                teeth.serial_tooth_numbers(target, stages, rules, tolerance, check_limit=10**7)
            continue
        result = teeth.serial_tooth_numbers(target, stages, rules, tolerance, check_limit=10**7)
        assert result.checks.agrees is True
        assert (result.checks.enumeration_ratio_error, result.checks.enumeration_total_teeth) == got[:2]
        assert [(m.pinion_teeth, m.gear_teeth) for m in result.stages] == got[2] or (
            abs(result.ratio_error - got[0]) <= teeth.TIE and result.total_teeth == got[1])
