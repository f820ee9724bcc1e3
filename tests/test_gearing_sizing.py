"""Sizing for strength: the chosen module and face width meet S_Hmin and S_Fmin, a module step smaller fails,
a plain grid search finds nothing lighter, the strength split agrees with the sizing, and the drive reports it."""

from __future__ import annotations

import math

import numpy as np
import pytest

import synth

RPM = math.pi / 30
RULES = synth.SizingRules(materials=("case_hardened_MQ", "case_hardened_MQ"), accuracy_grade=6,
                          duty=synth.Duty(application_factor=1.25, life=20_000.0, min_safety_contact=1.1,
                                          min_safety_root=1.5))
LOAD = synth.StageLoad(400.0, 1450 * RPM)


@pytest.fixture(scope="module")
def sized() -> synth.SizedStage:
    return synth.size_stage(4.0, LOAD, RULES)


def _safeties(module: float, width: float, z1: int = 19, z2: int = 76) -> np.ndarray:
    spec = synth.GearPairSpec(z1, z2, module, width, 0.0, (0.0, 0.0), None, RULES.accuracy_grade,
                              RULES.materials, max_face_width_ratio=RULES.max_face_width_ratio * (1 + 1e-9))
    r = synth.rate_pair(spec, float(LOAD.torque), LOAD.speed, RULES.duty)
    return np.array([*r.safety_contact, *r.safety_root])


def test_sized_pair_meets_every_minimum_safety(sized: synth.SizedStage) -> None:
    # Independent re-rating of the answer with the plain rating function.
    s = _safeties(sized.module, sized.face_width)
    assert min(s[:2]) >= 1.1 * (1 - 1e-9)
    assert min(s[2:]) >= 1.5 * (1 - 1e-9)
    assert sized.safety_contact == pytest.approx(tuple(s[:2]), rel=1e-12)


def test_binding_constraint_is_active_at_the_answer(sized: synth.SizedStage) -> None:
    # The face width is the least that works: the binding margin is zero to the bisection's resolution.
    assert sized.binding in ("contact_pinion", "contact_gear", "root_pinion", "root_gear")
    assert sized.margins[sized.binding] == pytest.approx(0.0, abs=1e-6)
    assert min(sized.margins.values()) >= -1e-12


def test_one_module_step_smaller_fails_a_constraint(sized: synth.SizedStage) -> None:
    series = synth.module_series("first")
    smaller = series[series.index(sized.module) - 1]
    s = _safeties(smaller, sized.face_width)
    need = np.array([1.1, 1.1, 1.5, 1.5])
    assert np.min(s / need) < 1
    assert sized.smaller_module is not None and sized.smaller_module[0] == smaller
    assert sized.smaller_module[1] != "none"


def test_no_lighter_design_on_a_plain_grid(sized: synth.SizedStage) -> None:
    # Independent search: every module of the series against 60 face widths between the ratio limits.
    best = math.inf
    for m in synth.module_series("first"):
        d1, d2 = 19 * m, 76 * m
        for b in np.linspace(0.2 * d1, 1.0 * d1, 60):
            try:
                s = _safeties(m, float(b))
            except synth.InvalidInput:
                continue
            if min(s[:2]) >= 1.1 and min(s[2:]) >= 1.5:
                best = min(best, 7830 * math.pi / 4 * b * (d1**2 + d2**2))
    assert sized.mass <= best * (1 + 1e-9)
    assert sized.mass == pytest.approx(7830 * math.pi / 4 * sized.face_width * sum(d**2 for d in sized.diameters))


def test_spectrum_sizing_is_lighter_than_sizing_for_the_peak() -> None:
    # A torque varying over the cycle does less damage than its peak held all the time.
    torque = 400.0 * (0.6 + 0.4 * np.sin(np.linspace(0, 2 * np.pi, 72, endpoint=False)))
    spectrum = synth.size_stage(4.0, synth.StageLoad(torque, LOAD.speed), RULES)
    peak = synth.size_stage(4.0, synth.StageLoad(float(torque.max()), LOAD.speed), RULES)
    assert spectrum.mass < peak.mass
    assert min(spectrum.safety_contact) >= 1.1 * (1 - 1e-9)


def test_strength_split_agrees_with_the_sizing() -> None:
    stages = synth.make_stages(["helical", "helical"], max_stages=6)
    result = synth.split_for_strength(20.0, stages, 60.0, 1450 * RPM, RULES)
    u = result.split.stage_ratios
    assert u[0] * u[1] == pytest.approx(20.0, rel=1e-9)
    # The split's volume model, with coefficients read off the sizing, predicts the sized volume within the
    # rounding of modules and teeth (a few per cent).
    assert result.volume_agreement < 0.1
    assert all(s is not None for s in result.sizing.stages)


def test_drive_answers_module_width_and_safety_per_stage() -> None:
    stages = synth.make_stages(["helical", "spur"], max_stages=6)
    r = synth.design_drive(3000.0, 60 * RPM, stages, objective="min_volume", strength=RULES)
    assert r.gears is not None and len(r.gears.stages) == 2
    for k, g in enumerate(r.gears.stages):
        assert g is not None
        # Each stage is sized for the torque its pinion shaft carries.
        assert g.rating.pinion_torque == pytest.approx(r.shafts[k].torque, rel=1e-12)
        assert min(g.safety_contact) >= 1.1 * (1 - 1e-9) and min(g.safety_root) >= 1.5 * (1 - 1e-9)
        assert g.centre_distance == pytest.approx(sum(g.diameters) / 2, rel=1e-9)
    assert r.volume_agreement is not None


def test_sizing_an_impossible_load_names_the_stage() -> None:
    with pytest.raises(synth.Infeasible) as exc:
        synth.size_stage(4.0, synth.StageLoad(5e7, LOAD.speed), RULES, stage=2)
    assert exc.value.details["stage_index"] == 2


def test_a_sized_stage_in_a_resonance_range_says_so_in_the_drive() -> None:
    stages = synth.make_stages(["helical", "spur"], max_stages=6)
    r = synth.design_drive(3000.0, 60 * RPM, stages, objective="min_volume", strength=RULES)
    assert r.gears is not None
    # every sized stage's own resonance warnings, and only those, are in the drive's list under its stage
    expected = sorted((f"stages[{k}]", w.code) for k, g in enumerate(r.gears.stages) if g is not None
                      for w in g.rating.warnings)
    codes = {"gear_main_resonance", "gear_intermediate_resonance", "gear_subcritical_resonance"}
    assert sorted((w.field, w.code) for w in r.warnings if w.code in codes) == expected
    # each sized stage's ratio N places it: a warning exactly when N lies in a range the rating names
    for g in r.gears.stages:
        assert g is not None
        n = g.rating.factor("N").pinion
        assert bool(g.rating.warnings) == any(not c.passed for c in g.rating.validity)
        assert (0.85 < n <= 1.15) == ("gear_main_resonance" in {w.code for w in g.rating.warnings})


def test_a_stage_sized_at_high_speed_is_rated_with_its_resonance_range() -> None:
    # a 50 N·m pinion at 15 000 rpm: the sizing's pair runs at N = 1.33, between the main resonance and the
    # supercritical range (ISO 6336-1), and says so; N grows with the speed alone for the same pair
    from synth.gearing.sizing import StageLoad, size_stage

    g = size_stage(3.0, StageLoad(50.0, 15000 * RPM))
    n = g.rating.factor("N").pinion
    assert 1.15 < n < 1.5 and [w.code for w in g.rating.warnings] == ["gear_intermediate_resonance"]
