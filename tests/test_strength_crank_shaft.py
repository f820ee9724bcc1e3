"""The press's crank shaft from its analysis: loads, diameter, bearings and hub keys, end to end."""

from __future__ import annotations

import math

import numpy as np
import pytest

import synth
from synth.strength.bearings import select_rolling_bearing
from synth.strength.crank_shaft import CrankShaftLayout, crank_pivot, crank_shaft_loads, hub_torques
from synth.strength.keys import size_key
from synth.strength.materials import MATERIALS
from synth.strength.shafts import ShaftSpec, size_shaft
from test_strength_links import press

RPM = 2 * math.pi / 60


def test_press_crank_shaft_with_a_gear_drive_and_a_flywheel() -> None:
    analysis = synth.analyse(press(), 60 * RPM, samples=360)
    layout = CrankShaftLayout(span=0.25, crank_position=-0.06, drive_position=0.125, drive="gear",
                              pitch_radius=0.12, mesh_angle=math.radians(200.0), helix_angle=math.radians(12.0),
                              flywheel_position=0.32, flywheel_mass=40.0)
    loads = crank_shaft_loads(analysis, layout)
    shaft = size_shaft("crank shaft", loads, ShaftSpec(span=0.25, turns_per_cycle=1.0), MATERIALS["42CrMo4+QT"])
    assert all(c.passed for c in shaft.checks)
    # Identity: the bearings carry what the analysis says the frame gives the crank at its pivot, plus the
    # drive's mesh force and the flywheel's weight (the shaft's own equilibrium, a second path to the reactions).
    pivot = analysis.kinetostatics.reactions[crank_pivot(analysis)]
    mesh = loads[1].force
    weight = np.array([0.0, -40.0 * 9.81])
    np.testing.assert_allclose(shaft.bearing_a + shaft.bearing_b, pivot - mesh - weight, atol=1e-9 * 1e4)
    # The helical mesh's axial force is flagged: the radial lives leave it out.
    assert [w.code for w in shaft.warnings] == ["shaft_axial_load"]
    # Each bearing of the shaft is chosen on its own reaction at the shaft's speed, bore at least the shaft's.
    w = np.full(360, 60 * RPM)
    for label, react in (("crank shaft A", shaft.bearing_a), ("crank shaft B", shaft.bearing_b)):
        b = select_rolling_bearing(label, react, w, 1.0, min_bore=shaft.diameter, required_life_hours=40000.0)
        assert b.bearing.bore >= shaft.diameter and b.life_hours >= 40000.0
    # Keys: the crank's hub passes the driving torque, the flywheel's its swing about the mean.
    torques = hub_torques(analysis)
    crank_key = size_key("crank hub", shaft.diameter, torques["crank"], 150e6, hub_length=0.09)
    flywheel_key = size_key("flywheel hub", shaft.diameter, torques["flywheel"], 150e6, hub_length=0.09)
    assert crank_key.checks[0].passed and flywheel_key.checks[0].passed
    assert float(torques["flywheel"].mean()) == pytest.approx(0.0, abs=1e-9)
