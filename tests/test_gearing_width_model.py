"""A pair's rating model moved to another face width (what the sizing's width search does at every step) is the
model built from scratch at that width, to the last bit: the geometry, every factor, the stresses over a load
spectrum, the Miner sums' verdict and the spectrum's safety factors; and a width beyond the ratio is refused."""

from __future__ import annotations

import math

import numpy as np
import pytest

import synth
from synth.errors import InvalidInput
from synth.gearing.life import SpectrumLanes, _damage, spectrum_feasible, spectrum_safety
from synth.gearing.rating import PairModel, _result

DUTY = synth.Duty(application_factor=1.0, life=20_000.0, min_safety_contact=1.0, min_safety_root=1.4)


def _spec(width: float, helix_deg: float, grade: int) -> synth.GearPairSpec:
    return synth.GearPairSpec(33, 100, 2.5e-3, width, math.radians(helix_deg), (0.0, 0.0), None, grade,
                              ("through_hardened_alloy_MQ", "through_hardened_alloy_MQ"),
                              max_face_width_ratio=1.0 + 1e-9)


@pytest.mark.parametrize(("helix_deg", "grade"), [(0.0, 7), (15.0, 7), (22.0, 5)])
def test_a_model_at_another_width_is_the_model_built_there(helix_deg: float, grade: int) -> None:
    rng = np.random.default_rng(int(helix_deg) + grade)
    torque = np.abs(100.0 * (0.5 + 0.4 * np.sin(np.linspace(0, 2 * np.pi, 721)) + 0.1 * rng.random(721)))
    speed = 150.0
    d1 = 33 * 2.5e-3 / math.cos(math.radians(helix_deg))
    wide = PairModel(_spec(d1, helix_deg, grade), DUTY, speed)
    # widths across the range, among them ones where the overlap ratio passes 1 and f_Hbeta's rounding steps
    verdicts = set()
    for width in np.exp(np.linspace(math.log(0.2 * d1), math.log(d1), 17)):
        moved, built = wide.at_width(float(width)), PairModel(_spec(float(width), helix_deg, grade), DUTY, speed)
        assert moved.geometry == built.geometry and moved.spec == built.spec
        for name in ("f_hbeta", "z_eps", "z_b", "z_d", "y_beta", "n_f", "fpb", "ff", "n_ratio"):
            assert getattr(moved, name) == getattr(built, name), name
        (sh0_m, lanes_m, lf_m), (sh0_b, lanes_b, lf_b) = moved.lane_stresses(torque), built.lane_stresses(torque)
        assert np.array_equal(sh0_m, sh0_b) and np.array_equal(lanes_m, lanes_b)
        for name in ("ft", "kv", "khb", "kfb", "kha", "kfa"):
            assert np.array_equal(getattr(lf_m, name), getattr(lf_b, name)), name
        assert repr(_result(moved, float(torque.max()))) == repr(_result(built, float(torque.max())))
        lanes = SpectrumLanes.of(wide, torque)
        # the verdict (which may skip sums a bound settles) is the plain one: every sum at the minimum factors
        need = np.array([DUTY.min_safety_contact] * 2 + [DUTY.min_safety_root] * 2)
        plain = bool(np.all(_damage(lanes.stresses(built), lanes.reference, lanes.knots, lanes.cycles_each, need)
                            <= 1))
        assert lanes.feasible(moved) == spectrum_feasible(built, torque) == plain
        verdicts.add(plain)
        _, _, s_h, s_f = spectrum_safety(built, torque)
        assert tuple(lanes.safety(moved)) == (*s_h, *s_f)
    assert verdicts == {True, False}             # the sweep crosses the least width


def test_a_width_beyond_the_ratio_is_refused_as_the_geometry_refuses_it() -> None:
    wide = PairModel(_spec(0.05, 15.0, 7), DUTY, 150.0)
    with pytest.raises(InvalidInput) as moved:
        wide.at_width(0.2)
    with pytest.raises(InvalidInput) as built:
        PairModel(_spec(0.2, 15.0, 7), DUTY, 150.0)
    assert moved.value.field == built.value.field == "face_width_mm"


def _plain_sizing(ratio: float, load: synth.StageLoad, rules: synth.SizingRules, helix: float,
                  z1: int) -> tuple[float, float, int]:
    """The sizing's search written plainly here: every module of the series in order, each bisected to the end
    (26 halvings of its log width range), the lightest kept (a later one must be strictly lighter), the series
    left once a module's narrowest face is already no lighter than the best: module, width, modules examined."""
    from synth.gearing.sizing import _feasible, _model, _spec
    z2 = max(int(round(ratio * z1)), z1)
    rho = np.array([synth.gear_material(n).density for n in rules.materials])
    best: tuple[float, float, float] | None = None
    examined = 0
    for m in synth.module_series(rules.series):
        d = np.array([z1, z2]) * m / math.cos(helix)
        b_lo, b_hi = rules.min_face_width_ratio * d[0], rules.max_face_width_ratio * d[0]
        if best is not None and float(np.sum(rho * math.pi / 4 * b_lo * d**2)) >= best[0]:
            break
        examined += 1
        wide, lanes = _model(rules, _spec(rules, z1, z2, m, b_hi, helix), load)
        if not _feasible(wide, lanes, load):
            continue
        narrowest = _feasible(wide.at_width(b_lo), lanes, load)
        if narrowest:
            b = b_lo
        else:
            lo, hi = math.log(b_lo), math.log(b_hi)
            for _ in range(26):
                mid = (lo + hi) / 2
                lo, hi = (lo, mid) if _feasible(wide.at_width(math.exp(mid)), lanes, load) else (mid, hi)
            b = math.exp(hi)
        mass = float(np.sum(rho * math.pi / 4 * b * d**2))
        if best is None or mass < best[0]:
            best = (mass, m, b)
        if narrowest:
            break
    assert best is not None
    return best[1], best[2], examined


@pytest.mark.parametrize("seed", range(4))
def test_sizing_settles_losing_modules_early_and_answers_the_plain_search(seed: int) -> None:
    # The sizing bisects a module only as far as deciding whether it can be the lightest needs: it must answer
    # the module, the width (to the last bit) and the modules examined of the plain search.
    rng = np.random.default_rng(500 + seed)
    for _ in range(5):
        helix = math.radians(float(rng.choice([0.0, 15.0])))
        z1 = int(rng.choice([19, 25, 31]))
        rules = synth.SizingRules(materials=("through_hardened_alloy_MQ",) * 2 if rng.random() < 0.5 else
                                  ("case_hardened_MQ",) * 2, series="first_and_second" if rng.random() < 0.5
                                  else "first", duty=DUTY)
        phase = np.linspace(0, 2 * np.pi, 181)
        load = synth.StageLoad(10 ** rng.uniform(1.0, 3.0) * (0.6 + 0.4 * np.sin(phase + rng.uniform(0, 3))),
                               float(rng.uniform(20.0, 150.0)))
        ratio = float(rng.uniform(1.5, 5.0))
        try:
            plain = _plain_sizing(ratio, load, rules, helix, z1)
        except AssertionError:
            continue                     # no module carries it: the sizing refuses, as another test checks
        sized = synth.size_stage(ratio, load, rules, helix_angle=helix, pinion_teeth=z1)
        assert (sized.module, sized.face_width, sized.modules_examined) == plain


@pytest.mark.parametrize(("helix_deg", "grade"), [(0.0, 7), (15.0, 7)])
def test_lanes_that_fall_short_are_those_whose_safety_factors_do(helix_deg: float, grade: int) -> None:
    # One Miner sum per lane at the minimum factors names the lanes short of them; where it answers, it is the
    # verdict of the safety factors themselves (the bisection), lane by lane.
    torque = np.abs(100.0 * (0.5 + 0.4 * np.sin(np.linspace(0, 2 * np.pi, 361))))
    d1 = 33 * 2.5e-3 / math.cos(math.radians(helix_deg))
    wide = PairModel(_spec(d1, helix_deg, grade), DUTY, 150.0)
    lanes = SpectrumLanes.of(wide, torque)
    need = np.array([DUTY.min_safety_contact] * 2 + [DUTY.min_safety_root] * 2)
    answered = 0
    for width in np.exp(np.linspace(math.log(0.2 * d1), math.log(d1), 25)):
        model = wide.at_width(float(width))
        failing = lanes.failing(model)
        if failing is None:
            continue
        answered += 1
        assert failing == [int(j) for j in np.flatnonzero(lanes.safety(model) / need - 1 < 0)]
    assert answered >= 20
