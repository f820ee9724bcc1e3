"""Parallel keys of hubs: DIN 6885-1 sections by shaft diameter, length from the hub's bearing pressure."""

from __future__ import annotations

import numpy as np
import pytest

from synth.errors import Infeasible, InvalidInput
from synth.strength.keys import STANDARD_KEY_LENGTHS, din6885_section, key_pressure, key_shear, size_key


def test_din6885_sections_match_published_examples() -> None:
    # Westermann, Technisches Zeichnen (Fachzeichnen), §3.1.1 Passfedern: d = 34 mm gives b = 10, h = 8,
    # t1 = 5, t2 = 3.3 mm. Wikipedia (de), "Passfeder": d = 40 mm gives 12 x 8.
    s = din6885_section(0.034)
    assert (s.b, s.h, s.t1, s.t2) == pytest.approx((0.010, 0.008, 0.005, 0.0033))
    s = din6885_section(0.040)
    assert (s.b, s.h) == pytest.approx((0.012, 0.008))
    with pytest.raises(InvalidInput, match="DIN 6885-1 covers"):
        din6885_section(0.300, "flywheel hub")


def test_key_lengths_match_shigley_example_7_6() -> None:
    # Shigley's Mechanical Engineering Design (Budynas & Nisbett), Example 7-6: 40 hp at 600 rev/min through a
    # 1 7/16 in shaft, a 3/8 in square key of cold-drawn steel S_y = 65 kpsi (S_sy = 0.577 S_y), n = 2.80:
    # shear needs l = 1.16 in, crushing on the half height in the hub l = 1.34 in (lbf, in and psi throughout).
    torque = 63025.0 * 40.0 / 600.0
    d, t = 1.4375, 0.375
    sy, n = 65e3, 2.80
    l_crush = float(key_pressure(np.array([torque]), d, t / 2.0, 1.0)[0]) / (sy / n)
    l_shear = float(key_shear(np.array([torque]), d, t, 1.0)[0]) / (0.577 * sy / n)
    assert l_crush == pytest.approx(1.34, abs=0.005)
    assert l_shear == pytest.approx(1.16, abs=0.005)


def test_key_stresses_match_a_published_calculation_sheet() -> None:
    # "Shaft Key Calculations" (D. Martin, studylib.net): T = 150 N·m times a service factor 3.333, key
    # 12.5 x 10 x 50 mm on a 50 mm shaft taken at the reduced diameter d - h/2 = 45 mm: shear 35.556 MPa,
    # compressive 88.889 MPa on half the key's height.
    torque = np.array([150.0 * (1.0 / 0.3)])
    assert float(key_shear(torque, 0.045, 0.0125, 0.050)[0]) == pytest.approx(35.556e6, rel=1e-4)
    assert float(key_pressure(torque, 0.045, 0.005, 0.050)[0]) == pytest.approx(88.889e6, rel=1e-4)


def test_key_is_the_least_standard_length_that_holds_the_pressure() -> None:
    phi = np.linspace(0.0, 2.0 * np.pi, 90, endpoint=False)
    torque = 200.0 + 100.0 * np.sin(phi)
    r = size_key("gear hub", 0.040, torque, 100e6, hub_length=0.08)
    assert r.section.b == pytest.approx(0.012)
    assert r.length in STANDARD_KEY_LENGTHS
    assert r.bearing_length == pytest.approx(r.length - r.section.b)   # form A: round ends carry nothing
    assert float(r.pressure.max()) <= 100e6 and all(c.passed for c in r.checks)
    shorter = STANDARD_KEY_LENGTHS[STANDARD_KEY_LENGTHS.index(r.length) - 1] - r.section.b
    assert float(key_pressure(torque, 0.040, r.section.h - r.section.t1, shorter).max()) > 100e6
    # Two keys carry 1.5 times one (phi = 0.75): the pressure at a given length falls to 2/3 of one key's.
    np.testing.assert_allclose(key_pressure(torque, 0.04, 0.003, 0.03, count=2),
                               key_pressure(torque, 0.04, 0.003, 0.03) / 1.5, rtol=1e-12)


def test_key_refuses_naming_the_hub_when_the_hub_is_too_short() -> None:
    with pytest.raises(Infeasible, match="flywheel hub: a DIN 6885 key 12 x 8") as exc:
        size_key("flywheel hub", 0.040, np.array([3000.0]), 100e6, hub_length=0.05)
    assert exc.value.constraint == "key_pressure"
    with pytest.raises(InvalidInput, match="allowed_pressure must be positive"):
        size_key("coupling", 0.040, np.array([300.0]), 0.0, hub_length=0.05)
