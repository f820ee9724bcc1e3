"""Tooth numbers: the exact search against a plain Python enumeration, the undercut and interference limits,
hunting and reverted trains, the seed's gear trains, and the empty search."""

from __future__ import annotations

import itertools
import math
import random

import pytest

import synth

from conftest import CASES

ALPHA = math.radians(20.0)


def reference(target: float, stages: list[tuple[float, float]], zmin_small: int, zmin_large: int, zmax: int,
              tol: float | None, hunting: bool, reverted: bool) -> tuple[float, int] | None:
    """Every combination, in plain Python: (ratio error, teeth) of the best by the search's objective and ties.

    Interference from the textbook condition written out separately: the larger wheel's tip radius must stay
    within the smaller wheel's limit point, (z2/2 + 1)^2 <= (z2/2 cos a)^2 + ((z1 + z2)/2 sin a)^2.
    """
    def ok(zp: int, zg: int, lo: float, hi: float) -> bool:
        small, large = min(zp, zg), max(zp, zg)
        tip = (large / 2 + 1) ** 2
        limit = (large / 2 * math.cos(ALPHA)) ** 2 + ((small + large) / 2 * math.sin(ALPHA)) ** 2
        return (small >= zmin_small and large >= zmin_large and tip <= limit + 1e-9 and lo <= zg / zp <= hi
                and (not hunting or math.gcd(zp, zg) == 1))

    per_stage = [[(zp, zg) for zp in range(1, zmax + 1) for zg in range(1, zmax + 1) if ok(zp, zg, lo, hi)]
                 for lo, hi in stages]
    combos = []
    for combo in itertools.product(*per_stage):
        if reverted and len({zp + zg for zp, zg in combo}) > 1:
            continue
        ratio = math.prod(zg / zp for zp, zg in combo)
        err = abs(ratio / target - 1)
        if tol is None or err <= tol:
            combos.append((err, sum(zp + zg for zp, zg in combo)))
    if not combos:
        return None
    if tol is None:
        best = min(e for e, _ in combos)
        return min(((e, t) for e, t in combos if e <= best + 1e-12), key=lambda c: (c[1], c[0]))
    fewest = min(t for _, t in combos)
    return min((e, t) for e, t in combos if t == fewest)


def test_undercut_and_interference_limits() -> None:
    # 2/sin^2(20 deg) = 17.1 (the issue); the largest gear for a 13..17-tooth pinion at 20 deg full depth is the
    # textbook table 16, 26, 45, 101, 1309.
    assert synth.undercut_limit(ALPHA) == pytest.approx(17.1, abs=0.01)
    assert synth.undercut_limit(ALPHA, profile_shift=0.5) == pytest.approx(0.5 * 17.097, rel=1e-3)
    limits = synth.interference_limit([13, 14, 15, 16, 17], ALPHA)
    assert [math.floor(v) for v in limits] == [16, 26, 45, 101, 1309]
    assert math.isinf(float(synth.interference_limit(18, ALPHA)))


def test_search_equals_plain_enumeration_on_small_ranges() -> None:
    rng = random.Random(5)
    compared = 0
    for _ in range(40):
        n = rng.choice([1, 2, 2, 3])
        zmax = {1: 60, 2: 32, 3: 21}[n]
        min_teeth = rng.choice([None, 14]) if n < 3 else None
        ranges = [(1.0, rng.choice([2.5, 6.3])) for _ in range(n)]
        stages = synth.make_stages([synth.StageSpec("spur", lo, hi) for lo, hi in ranges], max_stages=6)
        hunting, reverted = rng.random() < 0.3, n > 1 and rng.random() < 0.3
        tol = rng.choice([None, None, 0.005, 0.02])
        target = rng.uniform(1.05, 2.3**n)
        rules = synth.ToothRules(min_teeth=min_teeth, max_teeth=zmax, hunting=hunting, reverted=reverted)
        zmin = min_teeth or 18
        ref = reference(target, ranges, zmin, zmin, zmax, tol, hunting, reverted)
        try:
            got = synth.tooth_numbers(target, stages, rules, tol, check_limit=0)
        except synth.Infeasible as exc:
            if exc.constraint in ("max_teeth", "stage_ratio_min") and "reachable_max" in exc.details:
                assert not exc.details["reachable_min"] <= target <= exc.details["reachable_max"]
                continue
            assert ref is None, (target, rules, tol)
            continue
        assert ref is not None
        assert got.ratio_error == pytest.approx(ref[0], abs=1e-12)
        assert got.total_teeth == ref[1]
        pairs = [(m.pinion_teeth, m.gear_teeth) for m in got.stages]
        assert synth.train_ratio(pairs) == pytest.approx(got.total_ratio, rel=1e-12)
        assert sum(zp + zg for zp, zg in pairs) == got.total_teeth
        compared += 1
    assert compared >= 20


def test_check_figure_is_a_plain_enumeration() -> None:
    result = synth.tooth_numbers(5.7, synth.make_stages(2, max_stages=6), synth.ToothRules(max_teeth=45))
    assert result.checks.enumeration_combinations is not None and result.checks.agrees is True
    assert result.checks.enumeration_ratio_error == pytest.approx(result.ratio_error, abs=1e-12)


def test_seed_train_ratios_and_exact_search() -> None:
    case = CASES["gear_train_example_10_3"]
    z = case["inputs"]
    pairs = [(z["Z1"], z["Z2"]), (z["Z2p"], z["Z3"]), (z["Z3p"], z["Z4"])]
    u = synth.train_ratio(pairs, external_meshes=z["external_meshes"])
    assert u == pytest.approx(case["expected"]["U14"], rel=case["tolerance_rel"])
    assert z["omega1_rad_s"] / u == pytest.approx(case["expected"]["omega4_rad_s"], rel=case["tolerance_rel"])
    # The seed's own train is admissible (pinions >= 18, gears <= 100), so the exact search must hit U = 12
    # exactly, with no more teeth than the seed uses.
    found = synth.tooth_numbers(case["expected"]["U14"], synth.make_stages(3, max_stages=6),
                                synth.ToothRules(max_teeth=100))
    assert found.ratio_error == pytest.approx(0.0, abs=1e-15)
    assert found.total_teeth <= sum(a + b for a, b in pairs)
    for cid in ("gear_train_variant_1", "gear_train_variant_2", "gear_train_variant_3", "gear_train_variant_4",
                "gear_train_variant_5", "gear_train_variant_8"):
        case = CASES[cid]
        inp, exp, rel = case["inputs"], case["expected"], case["tolerance_rel"]
        u = synth.train_ratio([(inp["z1"], inp["z2"]), (inp["z3"], inp["z4"])])
        assert u == pytest.approx(exp["U14_magnitude"], rel=rel, abs=5e-7)   # 0.166667 is printed to 6 places
        if "omega4_rad_s" in exp:
            assert inp["omega1_rad_s"] / u == pytest.approx(exp["omega4_rad_s"], rel=rel)
        else:
            assert inp["omega4_rad_s"] * u == pytest.approx(exp["omega1_rad_s"], rel=rel)


def test_user_min_teeth_overrides_undercut_and_warns() -> None:
    # Variant 1's train uses a 10-tooth wheel; a user's min_teeth of 10 admits it, with a warning, and the
    # interference limit still holds for every wheel below 17.1 teeth.
    stages = synth.make_stages(2, max_stages=6)
    result = synth.tooth_numbers(4.0, stages, synth.ToothRules(min_teeth=10, max_teeth=40), tolerance=0.0)
    assert result.ratio_error == 0.0 and result.warnings
    assert result.warnings[0].code == "below_undercut_limit" and "undercut" in result.warnings[0].message
    for m in result.stages:
        small, large = sorted((m.pinion_teeth, m.gear_teeth))
        assert large <= synth.interference_limit(small, ALPHA)
    strict = synth.tooth_numbers(4.0, stages, synth.ToothRules(max_teeth=40), tolerance=0.0)
    assert not strict.warnings and min(min(m.pinion_teeth, m.gear_teeth) for m in strict.stages) >= 18


def test_hunting_and_reverted_trains() -> None:
    stages = synth.make_stages(2, max_stages=6)
    result = synth.tooth_numbers(12.0, stages, synth.ToothRules(max_teeth=90, hunting=True, reverted=True), 0.01)
    assert all(math.gcd(m.pinion_teeth, m.gear_teeth) == 1 for m in result.stages)
    sums = {m.pinion_teeth + m.gear_teeth for m in result.stages}
    assert len(sums) == 1 and result.ratio_error <= 0.01


def test_empty_search_names_what_to_relax() -> None:
    stages = synth.make_stages(2, max_stages=6)
    # 4.1 is within 1e-4 with 18..40 teeth (an ordinary train), but not with equal tooth sums.
    assert synth.tooth_numbers(4.1, stages, synth.ToothRules(max_teeth=40), tolerance=1e-4).ratio_error <= 1e-4
    with pytest.raises(synth.Infeasible) as err:
        synth.tooth_numbers(4.1, stages, synth.ToothRules(max_teeth=40, reverted=True), tolerance=1e-4)
    assert err.value.constraint == "reverted"
    with pytest.raises(synth.Infeasible) as err:
        synth.tooth_numbers(4.3, stages, synth.ToothRules(max_teeth=40), tolerance=1e-4)
    assert err.value.constraint == "tolerance"
    with pytest.raises(synth.Infeasible) as err:
        synth.tooth_numbers(30.0, stages, synth.ToothRules(max_teeth=40))
    assert err.value.constraint == "max_teeth" and err.value.details["reachable_max"] == pytest.approx((40 / 18) ** 2)
    with pytest.raises(synth.InvalidInput) as bad:
        synth.tooth_numbers(30.0, synth.make_stages(["spur", "belt"], max_stages=6))
    assert bad.value.field == "stages[1].type"


@pytest.mark.parametrize(("target", "tol", "n"), [(5.3, None, 3), (7.13, None, 3), (4.0, 1e-3, 3),
                                                  (2.3, None, 4), (2.5, 0.002, 4)])
def test_streamed_search_in_small_chunks_equals_enumeration(monkeypatch: pytest.MonkeyPatch, target: float,
                                                            tol: float | None, n: int) -> None:
    # Chunks of a few dozen products exercise the streaming, the screening grid, the shrinking window and the
    # early stop by teeth; the answer must be the plain enumeration's (same error within the tie rule, same teeth).
    from synth.gearing import teeth

    monkeypatch.setattr(teeth, "_CHUNK", 64)
    stages = synth.make_stages(n, max_stages=6)
    rules = synth.ToothRules(min_teeth=12, max_teeth=30 if n == 3 else 18)
    got = synth.tooth_numbers(target, stages, rules, tol, check_limit=0)
    ref = synth.enumerate_tooth_numbers(target, stages, rules, tol)
    assert ref is not None
    assert abs(got.ratio_error - ref[0]) <= teeth.TIE and got.total_teeth == ref[1]


def test_a_reverted_search_too_large_for_its_tables_is_refused_before_it_starts(
        monkeypatch: pytest.MonkeyPatch) -> None:
    # Six reverted stages of up to 1000 teeth: the middle tooth sums give about 127 pairs per stage, 2e6 and
    # more three-stage products even after pruning, past the table limit. The refusal must come from the probe
    # of the largest sampled tables, before any tooth sum is searched (it used to come after ~350 of them).
    from synth.gearing import teeth

    searched: list[int] = []
    original = teeth._search
    monkeypatch.setattr(teeth, "_search", lambda *a, **k: searched.append(1) or original(*a, **k))
    with pytest.raises(synth.TooLarge):
        synth.tooth_numbers(1997.3, synth.make_stages(6, max_stages=6),
                            synth.ToothRules(max_teeth=1000, reverted=True))
    assert searched == []
