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
