"""Every revolute joint of an analysed linkage with its pin and bearing: the four-bar and the six-bar press."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings

import synth
from synth.strength.bearings import joint_rotation, mean_load, rating_life
from synth.strength.joints import JointPartSpec, cycle_time, size_joints
from synth.strength.materials import MATERIALS
from synth.strength.pins import STANDARD_PIN_DIAMETERS, PinJoint, PinLimits, pin_stresses, size_pin
from helpers import crank_fourbars
from test_strength_links import fourbar, press

RPM = 2 * math.pi / 60


@pytest.mark.parametrize("linkage", [fourbar(), press()], ids=["fourbar", "press"])
def test_every_revolute_joint_gets_a_pin_and_a_bushing_that_pass(linkage: synth.Linkage) -> None:
    analysis = synth.analyse(linkage, 60 * RPM, samples=180)
    parts = size_joints(analysis, JointPartSpec(MATERIALS["C45E+QT"]))
    revolute = {j.name for j in linkage.mechanism.topology.joints if j.kind == "revolute"}
    assert set(parts) == revolute
    for name, p in parts.items():
        assert p.passed and p.bushing is not None
        # Second path: the peak pin stress from the analysis' reaction magnitudes (Analysis.bearing_forces),
        # not from the reaction vectors the pin was sized on.
        peak = float(analysis.bearing_forces()[name].max())
        per_newton = pin_stresses(np.array([[1.0, 0.0]]), JointPartSpec(MATERIALS["C45E+QT"]).pin, p.pin.diameter)
        assert float(p.pin.bending_stress.max()) == pytest.approx(peak * float(per_newton["bending"][0]),
                                                                  rel=1e-12)
        assert float(p.bushing.pressure.max()) == pytest.approx(peak / (p.pin.diameter * p.bushing.length),
                                                                rel=1e-12)


def test_rolling_bearings_on_the_press_reach_their_life_and_count_oscillation() -> None:
    analysis = synth.analyse(press(), 60 * RPM, samples=360)
    spec = JointPartSpec(MATERIALS["C45E+QT"], bearing="rolling", life_hours=10000.0)
    parts = size_joints(analysis, spec)
    period = cycle_time(analysis)
    assert period == pytest.approx(1.0)
    # The crank's pivot O turns one whole revolution a cycle; the rocker's pivot Q only swings (net turn nil).
    rot_o = parts["O"].rolling.rotation if parts["O"].rolling else None
    rot_q = parts["Q"].rolling.rotation if parts["Q"].rolling else None
    assert rot_o is not None and not rot_o.oscillating and rot_o.revolutions == pytest.approx(1.0, rel=1e-12)
    assert rot_q is not None and rot_q.oscillating
    for name, p in parts.items():
        r = p.rolling
        assert r is not None and r.life_hours >= 10000.0 and p.pin.diameter >= r.bearing.bore - 1e-12
        # Independent recomputation of the life from the reaction and the links' speeds.
        react = analysis.kinetostatics.reactions[name]
        a, b = p.links
        w = (analysis.motion.link_omega[b] if b else 0) - (analysis.motion.link_omega[a] if a else 0)
        p_mean = mean_load(react, np.asarray(w, dtype=float), r.bearing.exponent)
        revs = joint_rotation(np.asarray(w, dtype=float), period).revolutions
        hours = rating_life(r.bearing.dynamic_rating, p_mean, r.bearing.exponent) * 1e6 / (revs * 3600 / period)
        assert r.life_hours == pytest.approx(hours, rel=1e-12)


def test_joint_specs_are_checked() -> None:
    analysis = synth.analyse(fourbar(), 60 * RPM, samples=90)
    with pytest.raises(synth.InvalidInput, match="not revolute joints"):
        size_joints(analysis, JointPartSpec(MATERIALS["C45E+QT"]), {"Z": JointPartSpec(MATERIALS["C45E+QT"])})
    bad = dataclasses.replace(MATERIALS["C45E+QT"], ultimate_strength=float("nan"))
    with pytest.raises(synth.InvalidInput, match="ultimate_strength"):
        size_joints(analysis, JointPartSpec(bad))
    short = synth.analyse(fourbar(), 60 * RPM, phi=np.linspace(0.0, math.pi, 30))
    with pytest.raises(synth.InvalidInput, match="one whole crank revolution"):
        size_joints(short, JointPartSpec(MATERIALS["C45E+QT"]))


@settings(max_examples=10, deadline=None)
@given(crank_fourbars())
def test_every_pin_is_the_least_standard_one_on_random_fourbars(linkage: synth.Linkage) -> None:
    # Property: on any assemblable four-bar's reactions, each chosen pin meets every check and the standard
    # diameter one step smaller fails one (unless the smallest of the series already does).
    analysis = synth.analyse(linkage, 300 * RPM, samples=72)
    limits = PinLimits(100e6, 60e6, 40e6)
    for j in linkage.mechanism.topology.joints:
        reaction = analysis.kinetostatics.reactions[j.name]
        pin = size_pin(j.name, reaction, PinJoint(), limits)
        assert all(c.passed for c in pin.checks)
        smaller = [d for d in STANDARD_PIN_DIAMETERS if d < pin.diameter]
        if smaller:
            s = pin_stresses(reaction, PinJoint(), smaller[-1])
            assert (s["shear"].max() > 60e6 or s["bending"].max() > 100e6
                    or max(s["rod_pressure"].max(), s["fork_pressure"].max()) > 40e6)
