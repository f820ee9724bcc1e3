"""Rotor and slider-crank balancing against the seeds' formulas and independent re-analysis."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import synth

masses = st.lists(
    st.builds(synth.RotorMass, st.floats(0.01, 5), st.floats(0.01, 0.5), st.floats(-math.pi, math.pi),
              st.floats(-1, 2)),
    min_size=1, max_size=6,
)


@settings(max_examples=40, deadline=None)
@given(masses, st.floats(0.02, 0.5))
def test_static_rotor_balance(ms: list[synth.RotorMass], radius: float) -> None:
    # Seed [004:635-653]: m_k r_k = -sum m r (vector), on the given radius.
    result = synth.balance_rotor_static(ms, radius)
    (c,) = result.corrections
    total = sum(m.unbalance for m in ms)
    assert c.mass * c.radius == pytest.approx(abs(total), rel=1e-9, abs=1e-12)
    assert result.residual_unbalance <= 1e-9 * (1 + result.unbalance_before)


@settings(max_examples=40, deadline=None)
@given(masses)
def test_dynamic_rotor_balance_cancels_force_and_moment(ms: list[synth.RotorMass]) -> None:
    result = synth.balance_rotor_dynamic(ms, (-0.2, 1.3), (0.1, 0.15))
    assert result.residual_unbalance <= 1e-9 * (1 + result.unbalance_before)
    assert result.residual_moment <= 1e-9 * (1 + result.moment_before)


def test_two_plane_split_of_a_force_follows_the_seed() -> None:
    # Seed [004:659-679]: F at distances l1, l2 from the planes splits as F l2/(l1+l2) and F l1/(l1+l2).
    l1, l2, f = 0.3, 0.5, 0.2
    result = synth.balance_rotor_dynamic([synth.RotorMass(2.0, 0.1, 0.0, l1)], (0.0, l1 + l2), (1.0, 1.0))
    c1, c2 = result.corrections
    assert c1.mass == pytest.approx(f * l2 / (l1 + l2), rel=1e-12)
    assert c2.mass == pytest.approx(f * l1 / (l1 + l2), rel=1e-12)
    assert c1.angle == pytest.approx(math.pi, abs=1e-12) or c1.angle == pytest.approx(-math.pi, abs=1e-12)


def test_two_plane_split_of_a_moment_is_a_couple() -> None:
    # Seed [004:659-679]: a moment M is replaced by a couple M/(l1+l2) in the two planes.
    d = 0.8
    ms = [synth.RotorMass(1.0, 0.1, 0.0, 0.6), synth.RotorMass(1.0, 0.1, math.pi, 0.2)]  # a pure couple 0.04
    result = synth.balance_rotor_dynamic(ms, (0.0, d), (1.0, 1.0))
    c1, c2 = result.corrections
    assert c1.mass == pytest.approx(0.1 * 0.4 / d, rel=1e-12) and c2.mass == pytest.approx(c1.mass, rel=1e-12)


def test_bad_rotor_input_is_named() -> None:
    with pytest.raises(synth.InvalidInput) as err:
        synth.balance_rotor_dynamic([synth.RotorMass(1, 0.1, 0)], (0.5, 0.5), (0.1, 0.1))
    assert err.value.field == "planes_m"


def _slider_crank(r: float = 0.05, l_: float = 0.2) -> synth.Linkage:
    return synth.Linkage(synth.SliderCrank(r, l_), {
        "crank": synth.MassProps(1.0, (0.02, 0.0), 0.001),
        "rod": synth.MassProps(0.8, (0.06, 0.0), 0.003),
        "slider": synth.MassProps(1.2),
    })


def test_lanchester_masses_follow_the_seed() -> None:
    # Seed (6.32)-(6.33): m_I = m_B r/(2 l_I); m_II = lambda A2 m_B r/(2 l_II) with 4 lambda A2 ≈ r/l to first
    # order. The exact second order: a_B's 2nd harmonic is -4·c2·w², c2 the cos(2 phi) coefficient of the closed
    # form x_B = r cos(phi) + sqrt(l² - r² sin²(phi)) (quadrature here, exact for a smooth periodic function),
    # so m_II = m_B·c2/(2 l_II).
    r, l_ = 0.05, 0.2
    result = synth.balance_slider_crank(_slider_crank(r, l_), 150.0, balancer_radii=(0.04, 0.03))
    m_b = 1.2 + 0.8 * 0.06 / l_  # static split of the rod: its share at the slider
    phi = np.linspace(0, 2 * np.pi, 2048, endpoint=False)
    c2 = 2 * np.mean((r * np.cos(phi) + np.sqrt(l_**2 - (r * np.sin(phi)) ** 2)) * np.cos(2 * phi))
    first, second = result.pairs
    assert result.reciprocating_mass == pytest.approx(m_b, rel=1e-12)
    assert first.mass == pytest.approx(m_b * r / (2 * 0.04), rel=1e-9)
    assert second.mass == pytest.approx(m_b * c2 / (2 * 0.03), rel=1e-9)
    assert second.mass == pytest.approx((r / l_ / 4) * m_b * r / (2 * 0.03), rel=0.02)  # the seed's first order


@pytest.mark.parametrize("branch", [1, -1])
def test_lanchester_second_order_follows_the_branch(branch: int) -> None:
    # With the slider on the -x side x_B = r cos(phi) - sqrt(l² - r² sin²(phi)): the second harmonic of the
    # slider's inertia force changes sign, so the second pair turns half a period (180° of 2·phi) round.
    # The residual of orders 1 and 2 is then round-off, and the 4th order is the exact series' 4th harmonic:
    # F_4 = m_B·16·w²·|c4| with c4 the cos(4 phi) coefficient of x_B (quadrature here).
    r, l_, w = 0.05, 0.2, 150.0
    mech = synth.SliderCrank(r, l_, branch=branch)
    base = _slider_crank(r, l_)
    result = synth.balance_slider_crank(synth.Linkage(mech, base.links), w, samples=180)
    first, second = result.pairs
    assert math.degrees(first.phase) == pytest.approx(180.0, abs=1e-9)
    assert math.degrees(second.phase) % 360 == pytest.approx(180.0 if branch == 1 else 0.0, abs=1e-9)
    phi = np.linspace(0, 2 * np.pi, 2048, endpoint=False)
    x_b = r * np.cos(phi) + branch * np.sqrt(l_**2 - (r * np.sin(phi)) ** 2)
    c4 = 2 * np.mean(x_b * np.cos(4 * phi))
    f0 = result.before.max_shaking_force
    assert max(result.residual_by_order[:3]) < 1e-9 * f0
    assert result.residual_by_order[3] == pytest.approx(result.reciprocating_mass * 16 * w**2 * abs(c4), rel=1e-6)


def test_lanchester_residual_is_the_higher_orders() -> None:
    # Independent: the plain engine's shaking force with the crank counterweight, plus the balancer shafts.
    # What is left must be a small fraction, and balancing the 2nd order must help over the 1st alone.
    one = synth.balance_slider_crank(_slider_crank(), 150.0, orders=1)
    two = synth.balance_slider_crank(_slider_crank(), 150.0, orders=2)
    assert two.residual_rel < 0.01 < one.residual_rel
    # The remaining force is along the slide axis only (the crank counterweight took the rotating part).
    assert np.abs(two.after_force[:, 1]).max() < 1e-9 * two.before.max_shaking_force
