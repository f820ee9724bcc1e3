"""Bearings of joints and shafts: plain bushings by p, v and p·v; rolling bearings by ISO 281 basic rating life."""

from __future__ import annotations

import math

import numpy as np
import pytest

from synth.errors import Infeasible, InvalidInput
from synth.strength.bearings import (
    BushingMaterial,
    RollingBearing,
    bearing_catalogue,
    bushing_materials,
    joint_rotation,
    mean_load,
    rating_life,
    required_dynamic_rating,
    select_rolling_bearing,
    size_bushing,
)

LB = 4.4482216152605  # [N]


def test_mean_load_of_a_duty_cycle_matches_mott_example_14_6() -> None:
    # Mott, Machine Elements in Mechanical Design, 4th ed., Example Problem 14-6: a 6308 at 600 rpm under 650 lb
    # for 30 min, 750 lb for 10 min, 250 lb for 20 min; mean effective load F_m = 597 lb (p = 3, constant speed).
    load = np.repeat([650.0, 750.0, 250.0], [30, 10, 20]) * LB
    speed = np.full(load.size, 600.0 * math.pi / 30.0)
    assert mean_load(load, speed, 3.0) / LB == pytest.approx(597.0, abs=0.5)


def test_roller_rating_matches_shigley_problem_11_3() -> None:
    # Budynas & Nisbett, Shigley's Mechanical Engineering Design, 8th ed., solution to problem 11-3: straight
    # roller bearing, design load 10.279 kN for 1440 rating lives: C10 = 10.279 (1440)^(3/10) = 91.1 kN.
    assert required_dynamic_rating(10.279e3, 1440.0, 10.0 / 3.0) == pytest.approx(91.1e3, rel=1e-3)


def test_ball_bearing_life_in_hours_matches_skf_example() -> None:
    # SKF rolling bearings catalogue, "Selecting bearing size", calculation example: a 6309 (C = 55.3 kN) at
    # 3000 r/min under Fr = 10 kN: L10 = 169 million revolutions, L10h = 10^6/(60 n) L10 = 940 h.
    c = 55.3e3
    l10 = rating_life(c, 10e3, 3.0)
    assert l10 == pytest.approx(169.0, rel=2e-3)
    custom = [RollingBearing("6309", "deep_groove_ball", 0.045, 0.100, 0.025, c, 31.5e3)]
    w = np.full(36, 3000.0 * math.pi / 30.0)
    r = select_rolling_bearing("shaft A", np.full(36, 10e3), w, 0.5, min_bore=0.045, required_life_hours=900.0,
                               catalogue=custom)
    assert r.life_hours == pytest.approx(940.0, rel=2e-3)


def test_oscillating_joint_life_counts_the_swept_revolutions_as_the_manufacturers_do() -> None:
    # Harmonic Drive output bearing for oscillating motion (SHG series manual, eq. 44.1):
    # L_OC = 10^6 / (60 n_1) * 180 / phi * (C / P)^B, phi the full swing [deg], n_1 oscillations per minute.
    # A rocker pin swinging sinusoidally through phi = 40 deg at 30 cycles a minute under a steady 2 kN.
    n, phi_deg, n1 = 720, 40.0, 30.0
    period = 60.0 / n1
    t = np.arange(n) * period / n
    amp = math.radians(phi_deg) / 2.0
    w = amp * (2.0 * math.pi / period) * np.cos(2.0 * math.pi * t / period)
    rot = joint_rotation(w, period)
    assert rot.oscillating
    assert math.degrees(rot.swing) == pytest.approx(phi_deg, rel=1e-3)
    bearing = RollingBearing("NA 4904", "needle_roller", 0.020, 0.037, 0.017, 21.6e3, 28e3)
    r = select_rolling_bearing("rocker pin", np.full(n, 2e3), w, period, min_bore=0.02, required_life_hours=1.0,
                               catalogue=[bearing])
    expected = 1e6 / (60.0 * n1) * 180.0 / phi_deg * (21.6e3 / 2e3) ** (10.0 / 3.0)
    # |w| has kinks at the turning points: the rectangle rule over 720 samples is good to about 1e-5.
    assert r.life_hours == pytest.approx(expected, rel=1e-4)
    assert r.warnings == ()


def test_mean_load_weights_each_load_by_the_revolutions_made_under_it() -> None:
    # Independent computation: half a cycle at 3 kN turning at 2 rad/s, half at 1 kN turning at 6 rad/s:
    # revolutions weigh 1:3, so P^3 = (27 * 1 + 1 * 3) / 4 kN^3.
    load = np.repeat([3e3, 1e3], 50)
    speed = np.repeat([2.0, -6.0], 50)
    assert mean_load(load, speed, 3.0) == pytest.approx(1e3 * (30.0 / 4.0) ** (1.0 / 3.0), rel=1e-12)


def test_selection_takes_the_smallest_bearing_that_lasts_and_refuses_naming_the_joint() -> None:
    phi = np.linspace(0.0, 2.0 * np.pi, 120, endpoint=False)
    load = np.stack([4e3 + 3e3 * np.cos(phi), 2e3 * np.sin(phi)], axis=1)
    w = 15.0 + 5.0 * np.cos(phi)
    r = select_rolling_bearing("B", load, w, 0.5, min_bore=0.025, required_life_hours=20000.0)
    assert r.life_hours >= 20000.0 and r.bearing.bore >= 0.025
    # Every smaller catalogue bearing of admissible bore falls short: the choice is the least that works.
    for b in bearing_catalogue():
        if b.bore >= 0.025 and (b.outer, b.width) < (r.bearing.outer, r.bearing.width):
            p = mean_load(load, w, b.exponent)
            hours = rating_life(b.dynamic_rating, p, b.exponent) * 1e6 / (r.rotation.revolutions * 3600 / 0.5)
            assert hours < 20000.0 or b.static_rating / r.peak_load < 1.0
    with pytest.raises(Infeasible, match="B: no catalogue bearing") as exc:
        select_rolling_bearing("B", load * 100, w, 0.5, min_bore=0.025, required_life_hours=50000.0)
    assert exc.value.constraint == "bearing_life"


def test_small_swing_is_flagged() -> None:
    n = 200
    t = np.arange(n) / n
    w = math.radians(1.0) * math.pi * np.cos(2 * math.pi * t)   # a 2 degree swing in one second
    r = select_rolling_bearing("C", np.full(n, 500.0), w, 1.0, min_bore=0.01, required_life_hours=100.0)
    assert [x.code for x in r.warnings] == ["bearing_small_oscillation"]


def test_bushing_mean_sliding_speed_matches_the_glycodur_formula() -> None:
    # GLYCODUR plain bearings (manufacturer's design guide), sliding velocity of an oscillating bushing:
    # v = 5.82e-7 d beta f [m/s], d bore [mm], beta half the swing [deg], f oscillations per minute.
    d_mm, beta, f = 30.0, 25.0, 40.0
    n = 400
    period = 60.0 / f
    t = np.arange(n) * period / n
    w = math.radians(beta) * (2 * math.pi / period) * np.cos(2 * math.pi * t / period)
    r = size_bushing("D", np.full(n, 3e3), w, d_mm / 1e3, bushing_materials()["ptfe_composite_dry"])
    assert float(r.sliding_speed.mean()) == pytest.approx(5.82e-7 * d_mm * beta * f, rel=1e-3)


def test_bushing_length_meets_pressure_and_pv_and_refuses_beyond_its_ratio() -> None:
    phi = np.linspace(0.0, 2.0 * np.pi, 100, endpoint=False)
    load = 5e3 * (1.2 + np.cos(phi))
    w = 8.0 * np.sin(phi)
    mat = BushingMaterial("test", 10e6, 2.0, 0.5e6)
    r = size_bushing("E", load, w, 0.03, mat)
    assert all(c.passed for c in r.checks)
    # One millimetre shorter breaks a check: the length is the least whole millimetre.
    shorter = size_bushing("E", load, w, 0.03, mat, length=r.length - 1e-3)
    if r.length - 1e-3 >= 0.5 * 0.03:
        assert not all(c.passed for c in shorter.checks)
    # Identity: p·v = F |w| / (2 b).
    np.testing.assert_allclose(r.pv, load * np.abs(w) / (2 * r.length), rtol=1e-12)
    with pytest.raises(Infeasible, match="E: .*beyond b/d") as exc:
        size_bushing("E", load * 20, w, 0.03, mat)
    assert exc.value.constraint in {"bushing_pressure", "bushing_pv"}
    with pytest.raises(Infeasible, match="sliding speed") as exc:
        size_bushing("E", load, w * 100, 0.03, mat)
    assert exc.value.constraint == "bushing_speed"
    with pytest.raises(InvalidInput, match="has no pv_limit"):
        size_bushing("E", load, w, 0.03, BushingMaterial("bad", 10e6, 2.0, 0.0))


def test_catalogue_is_well_formed() -> None:
    cat = bearing_catalogue()
    assert len(cat) > 40
    assert {b.type for b in cat} == {"deep_groove_ball", "cylindrical_roller", "needle_roller"}
    assert all(b.outer > b.bore and b.static_rating > 0 for b in cat)


def test_a_small_bore_takes_its_largest_length_when_the_next_whole_millimetre_passes_it() -> None:
    # p = F/(d b): 360 N on a 5 mm bore at the sintered bronze's 10 MPa needs b = 7.2 mm, within b/d = 1.5 (7.5 mm)
    # though its next whole millimetre (8 mm) is not; 400 N needs 8.0 mm, beyond it.
    from synth.strength.bearings import bushing_materials, size_bushing

    bronze = bushing_materials()["sintered_bronze_oil"]
    w = np.full(36, 0.5)
    fit = size_bushing("joint A", np.full(36, 360.0), w, 5e-3, bronze)
    assert fit.length == pytest.approx(7.5e-3, rel=1e-12)
    assert float(fit.pressure.max()) == pytest.approx(360.0 / (5e-3 * 7.5e-3), rel=1e-12)
    assert all(c.passed for c in fit.checks)
    with pytest.raises(Infeasible, match="8.0 mm of length for pressure"):
        size_bushing("joint A", np.full(36, 400.0), w, 5e-3, bronze)
