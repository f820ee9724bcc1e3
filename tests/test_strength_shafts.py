"""Shafts between two bearings: gear mesh forces, bearing reactions, DE-Goodman diameter with Marin factors."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from synth.errors import Infeasible, InvalidInput
from synth.strength.fatigue import reliability_factor, size_factor, surface_factor
from synth.strength.materials import Material, material
from synth.strength.shafts import (
    NOTCHES,
    ShaftLoad,
    ShaftSpec,
    bearing_reactions,
    de_goodman_diameter,
    de_goodman_safety,
    gear_mesh_forces,
    gear_shaft_loads,
    size_shaft,
)

N = 72
PHI = np.linspace(0.0, 2.0 * np.pi, N, endpoint=False)


def test_de_goodman_diameter_matches_shigley_problem_7_1() -> None:
    # Budynas & Nisbett, Shigley's Mechanical Engineering Design, 8th ed., solutions manual, problem 7-1(d):
    # Kf = 2.2, Kfs = 1.8, Ma = 600, Ta = 400, Mm = 500, Tm = 300 lbf·in, Se = 30 kpsi, Sut = 100 kpsi, n = 2:
    # DE-Goodman d = 1.073 in (eq. 7-8; units cancel, so lbf·in and psi give inches).
    d = de_goodman_diameter(600.0, 500.0, 400.0, 300.0, 2.2, 1.8, 30e3, 100e3, 2.0)
    assert d == pytest.approx(1.073, abs=5e-4)
    # Eq. 7-7 at that diameter gives back the design factor (identity).
    assert de_goodman_safety(600.0, 500.0, 400.0, 300.0, 2.2, 1.8, d, 30e3, 100e3) == pytest.approx(2.0, rel=1e-12)


def test_helical_gear_forces_match_shigley_example_13_8() -> None:
    # Shigley's Mechanical Engineering Design (Budynas & Nisbett), Example 13-8: a 1 hp motor at 1800 rev/min
    # drives an 18-tooth helical pinion, normal diametral pitch 12 teeth/in, alpha_n = 20 deg, psi = 30 deg:
    # d = 1.732 in, W_t = 40.4 lbf, W_r = 17.0 lbf, W_a = 23.3 lbf, W = 49.6 lbf (rounded in the book).
    torque = 63025.0 * 1.0 / 1800.0                   # [lbf·in]
    radius = 18.0 / (12.0 * math.cos(math.radians(30.0))) / 2.0
    force, moment, axial = gear_mesh_forces(np.array([torque]), radius, 0.0, helix_angle=math.radians(30.0))
    tangential, radial = force[0, 1], -force[0, 0]    # mesh toward +x: tangent +y, radial toward the axis -x
    assert tangential == pytest.approx(40.4, abs=0.05)
    assert radial == pytest.approx(17.0, abs=0.05)
    assert axial[0] == pytest.approx(23.3, abs=0.05)
    assert math.sqrt(tangential**2 + radial**2 + axial[0] ** 2) == pytest.approx(49.6, abs=0.1)
    # The axial force at the pitch point bends the shaft by r W_a (identity).
    assert float(np.hypot(*moment[0])) == pytest.approx(radius * axial[0], rel=1e-12)


def test_helical_gear_forces_match_shigley_problem_13_35() -> None:
    # Budynas & Nisbett, Shigley's Mechanical Engineering Design, 8th ed., solutions manual, problem 13-35:
    # P_n = 4 teeth/in, alpha_n = 20 deg, psi = 30 deg, 18-tooth pinion (d = 5.196 in), W_t = 800 lbf:
    # W_r = 336 lbf, W_a = 462 lbf, W = 983 lbf.
    radius = 18.0 / (4.0 * math.cos(math.radians(30.0))) / 2.0
    force, _, axial = gear_mesh_forces(np.array([800.0 * radius]), radius, 0.0, helix_angle=math.radians(30.0))
    assert -force[0, 0] == pytest.approx(336.0, abs=0.5)
    assert axial[0] == pytest.approx(462.0, abs=0.5)
    assert math.sqrt(float(force[0] @ force[0]) + axial[0] ** 2) == pytest.approx(983.0, abs=0.5)


def test_bearing_reactions_balance_forces_and_moments() -> None:
    # Identity: the shaft with its bearing reactions is in equilibrium at every angle, overhung loads included.
    f1 = np.stack([800 * np.cos(PHI), 300 + 500 * np.sin(PHI)], axis=1)
    f2 = np.stack([-200 + 0 * PHI, 400 * np.cos(2 * PHI)], axis=1)
    m2 = np.stack([30 * np.sin(PHI), 10 + 0 * PHI], axis=1)
    loads = [ShaftLoad("gear", 0.07, f1), ShaftLoad("crank", 0.26, f2, moment=m2)]
    ra, rb = bearing_reactions(loads, 0.2)
    np.testing.assert_allclose(ra + rb + f1 + f2, 0.0, atol=1e-9)
    # Moments about A: e_z x (0.2 R_B + 0.07 F1 + 0.26 F2) + M2 = 0.
    v = 0.2 * rb + 0.07 * f1 + 0.26 * f2
    np.testing.assert_allclose(np.stack([-v[:, 1], v[:, 0]], axis=1) + m2, 0.0, atol=1e-9)


def _independent_diameter(moment_amp: float, torque: float, mat: Material, spec: ShaftSpec, notch: str) -> float:
    # Shigley eq. 7-8 with Se(d) solved by a root finder instead of successive trials: n(d) = design factor.
    kt, kts = NOTCHES[notch]
    ka = surface_factor(mat.ultimate_strength, spec.surface)
    ke = reliability_factor(spec.reliability)

    def gap(d: float) -> float:
        se = ka * size_factor(d) * ke * mat.fatigue_limit
        return de_goodman_safety(moment_amp, 0.0, 0.0, torque, kt, kts, d, se, mat.ultimate_strength) \
            - spec.design_factor

    return float(brentq(gap, 1e-3, 0.5, xtol=1e-12))


def test_gear_shaft_diameter_agrees_with_an_independent_root_find() -> None:
    # A gear shaft at a ratio (not a whole number of turns per crank cycle): a steady 5 kN mesh load midway between
    # bearings 200 mm apart and 300 N·m through it: Ma = F L/4 fully reversed, Tm = 300 N·m under the keyseat.
    mat = material("C45E+QT")
    spec = ShaftSpec(span=0.2, turns_per_cycle=3.7)
    loads = [ShaftLoad("gear", 0.1, np.tile([0.0, -5e3], (N, 1)), torque=np.full(N, 300.0)),
             ShaftLoad("coupling", 0.25, np.zeros((N, 2)), torque=np.full(N, -300.0))]
    r = size_shaft("countershaft", loads, spec, mat)
    expected = _independent_diameter(5e3 * 0.2 / 4.0, 300.0, mat, spec, "keyseat_end_mill")
    assert r.diameter_required == pytest.approx(expected, rel=1e-7)
    assert r.diameter >= r.diameter_required
    assert r.fatigue_safety >= spec.design_factor and all(c.passed for c in r.checks)
    assert [s.name for s in r.sections if s.diameter_required == max(x.diameter_required for x in r.sections)] \
        == ["gear (right)"]


def test_crank_shaft_fibres_follow_a_load_that_turns_with_the_shaft() -> None:
    # A load fixed in the shaft's own frame (it turns with the crank) bends each fibre steadily: Ma = 0, so the
    # crank shaft (one turn per cycle) needs only the mean's share; the same load on a shaft at a ratio is taken
    # fully reversed. Independent: the steady case is eq. 7-8 with Ma = 0, Mm = F L/4 and Se from the same d.
    mat = material("C45E+QT")
    turning = 5e3 * np.stack([np.cos(PHI), np.sin(PHI)], axis=1)
    loads = [ShaftLoad("crank", 0.1, turning, torque=np.full(N, 300.0)),
             ShaftLoad("coupling", 0.25, np.zeros((N, 2)), torque=np.full(N, -300.0))]
    crank = size_shaft("crank shaft", loads, ShaftSpec(span=0.2, turns_per_cycle=1.0), mat)
    geared = size_shaft("crank shaft", loads, ShaftSpec(span=0.2, turns_per_cycle=1.5), mat)
    kt, kts = NOTCHES["keyseat_end_mill"]
    b = math.sqrt(4 * (kt * 250.0) ** 2 + 3 * (kts * 300.0) ** 2)
    steady = (16 * 2.0 / math.pi * b / mat.ultimate_strength) ** (1 / 3)
    assert crank.diameter_required == pytest.approx(steady, rel=1e-3)   # 72 fibres: the mean to cos(2.5 deg)
    assert geared.diameter_required > 1.3 * crank.diameter_required


def test_bad_shaft_input_names_the_shaft() -> None:
    mat = material("C45E+QT")
    load = [ShaftLoad("gear", 0.1, np.tile([0.0, -5e3], (N, 1)))]
    with pytest.raises(InvalidInput, match="s1.material: fatigue_limit_MPa"):
        size_shaft("s1", load, ShaftSpec(span=0.2), Material("x", 300e6, 500e6, 0.0, 2e11, 7850.0))
    with pytest.raises(InvalidInput, match="unknown notch"):
        size_shaft("s1", [ShaftLoad("gear", 0.1, load[0].force, notch="groove?")], ShaftSpec(span=0.2), mat)
    with pytest.raises(InvalidInput, match="bearing span"):
        size_shaft("s1", load, ShaftSpec(span=0.0), mat)
    with pytest.raises(Infeasible, match="shaft s1") as exc:
        size_shaft("s1", [ShaftLoad("gear", 0.1, load[0].force * 1e6)], ShaftSpec(span=0.2), mat)
    assert exc.value.constraint == "shaft_fatigue"


def test_intermediate_gear_shaft_carries_both_meshes_and_no_net_torque() -> None:
    # Identities: the gear takes the torque the pinion hands on (no net torque on the shaft), each tangential force
    # is T/r, and with one hand on both the thrusts oppose: W_a,g + W_a,p = T tan(beta) (1/r_g - 1/r_p).
    torque = 200.0 + 80.0 * np.cos(PHI)
    loads = gear_shaft_loads(torque, (0.05, 0.15, 0.0), (0.15, 0.04, math.pi),
                             helix_angle=math.radians(15.0))
    gear, pinion = loads
    assert gear.torque is not None and pinion.torque is not None and gear.axial is not None
    np.testing.assert_allclose(gear.torque + pinion.torque, 0.0, atol=1e-12)
    np.testing.assert_allclose(gear.force[:, 1], torque / 0.15, rtol=1e-12)     # mesh along +x: tangent +y
    np.testing.assert_allclose(pinion.force[:, 1], torque / 0.04, rtol=1e-12)   # mesh along -x: tangent -y, -T
    assert pinion.axial is not None
    expected = torque * math.tan(math.radians(15.0)) * (1 / 0.15 - 1 / 0.04)
    np.testing.assert_allclose(gear.axial + pinion.axial, expected, rtol=1e-12)
    r = size_shaft("intermediate", loads, ShaftSpec(span=0.2, turns_per_cycle=4.3), material("C45E+QT"))
    assert r.fatigue_safety >= 2.0
