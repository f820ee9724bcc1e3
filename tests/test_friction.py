"""Friction in the pairs against closed forms and a friction-circle computation written here."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import event, given, settings
from hypothesis import strategies as st

import synth
from helpers import crank_fourbars, slider_cranks
from synth.warnings import check_friction, link_lengths
from synth.friction import PairFriction, breakaway_torque, friction_kinetostatics, validate_pairs

N = 360
OMEGA = 12.0


def _press(mu_guide: float, masses: bool = False) -> synth.Analysis:
    """An in-line slider-crank pressing P = 2 kN against the slider's motion over the whole cycle."""
    mech = synth.SliderCrank(crank=0.1, rod=0.35)
    links = {} if not masses else {"crank": synth.MassProps(3.0, (0.02, 0.0), 0.01),
                                   "rod": synth.MassProps(5.0, (0.15, 0.0), 0.06), "slider": synth.MassProps(8.0)}
    load = synth.ProcessLoad(kind="window", magnitude=2000.0)
    linkage = synth.Linkage(mech, links, gravity=synth.Gravity() if masses else None, loads=(load,))
    return synth.analyse(linkage, OMEGA, samples=N)


def _friction(an: synth.Analysis, pairs: list[PairFriction]) -> synth.FrictionAnalysis:
    return friction_kinetostatics(an.motion, an.linkage, an.kinetostatics, pairs)


def test_guide_friction_matches_the_closed_form_for_massless_links() -> None:
    # closed form (issue 25): |F| = P/(cos b - mu |sin b|), T = (P + mu |F sin b|) |v| / w, with the rod angle b
    # and the slider speed v taken from the kinematics; the cycle efficiency is the ratio of the work integrals
    mu, p = 0.12, 2000.0
    an = _press(mu)
    fr = _friction(an, [PairFriction("guide", mu)])
    beta = an.motion.link_angle["rod"]
    v = an.motion.point_vel["B"][:, 0]
    force = p / (np.cos(beta) - mu * np.abs(np.sin(beta)))
    moving = np.abs(v) > 1e-12
    torque = np.where(moving, (p + mu * np.abs(force * np.sin(beta))) * np.abs(v) / OMEGA, 0.0)
    assert np.max(np.abs(fr.driving_torque - torque)) <= 1e-9 * np.max(np.abs(torque))
    useful = np.mean(np.where(moving, p * np.abs(v), 0.0))
    assert fr.cycle_efficiency == pytest.approx(useful / np.mean(torque * OMEGA), rel=1e-9)
    # the guide's normal force is the rod force's vertical part; its friction is mu times it, against v
    normal = np.hypot(*fr.reactions["guide"].T)
    assert np.allclose(normal[moving], np.abs(force * np.sin(beta))[moving], rtol=1e-9, atol=1e-9 * p)
    assert np.allclose(fr.friction["guide"], -mu * normal * np.sign(v), rtol=0, atol=1e-9 * p)
    assert fr.residual <= 1e-12 and fr.power_check <= 1e-9 * np.max(np.abs(torque))


def test_revolute_friction_matches_the_friction_circle() -> None:
    # Friction circles of radius rho = f r at O, A and B; the massless rod is a two-force member whose line of
    # action is tangent to the circles at A and B (written here from the rod's, slider's and crank's balance).
    f, r = 0.15, 0.02
    rho = f * r
    p = 2000.0
    an = _press(0.0)
    fr = _friction(an, [PairFriction(j, f, r) for j in ("O", "A", "B")])
    m = an.motion
    length = 0.35
    beta, w_rod = m.link_angle["rod"], m.link_omega["rod"]
    a_pin, v = m.point_pos["A"], m.point_vel["B"][:, 0]
    expected = np.zeros(N)
    for k in range(N):
        if abs(v[k]) < 1e-12:
            continue
        s_a, s_b = np.sign(w_rod[k] - OMEGA), np.sign(w_rod[k])
        # the rod's moment balance about A: -L F sin(theta - b) - rho F (s_a + s_b) = 0
        k_sin = -rho * (s_a + s_b) / length
        theta = beta[k] + math.asin(k_sin)
        if np.sign(math.cos(theta)) != np.sign(v[k]):
            theta = beta[k] + math.pi - math.asin(k_sin)
        u = np.array([math.cos(theta), math.sin(theta)])
        force = p / abs(u[0])  # the slider's balance along the guide: F u_x = P sign(v)
        # crank: T + A x (-F u) + rho_A F s_a - rho_O F sign(w) = 0
        expected[k] = force * (a_pin[k, 0] * u[1] - a_pin[k, 1] * u[0]) - rho * force * s_a + rho * force
    # at the dead centres the slider speed is rounding noise whose sign decides the load's direction: compared
    # where the slider moves
    moving = np.abs(v) > 1e-9
    assert np.max(np.abs(fr.driving_torque - expected)[moving]) <= 1e-9 * np.max(np.abs(expected))
    # the friction moment in each pin is rho times its reaction's magnitude
    for j in ("O", "A", "B"):
        mag = np.hypot(*fr.reactions[j].T)
        assert np.allclose(np.abs(fr.friction[j]), rho * mag, rtol=1e-12, atol=1e-12)


def test_zero_friction_gives_the_frictionless_answer_exactly() -> None:
    an = _press(0.0, masses=True)
    fr = _friction(an, [PairFriction("guide", 0.0), PairFriction("A", 0.0, 0.01)])
    assert np.array_equal(fr.driving_torque, an.kinetostatics.driving_torque)
    assert np.array_equal(fr.unknowns, an.kinetostatics.unknowns)
    assert fr.iterations == 0 and fr.cycle_efficiency == pytest.approx(1.0, abs=1e-12)


def test_friction_with_masses_keeps_virtual_power_and_loses_power() -> None:
    # virtual power with friction: T w = T0 w + sum of the pairs' power losses (identity), every loss >= 0
    an = _press(0.0, masses=True)
    pairs = [PairFriction("guide", 0.15, viscous=20.0), PairFriction("O", 0.1, 0.03, viscous=0.05),
             PairFriction("A", 0.1, 0.02), PairFriction("B", 0.1, 0.015)]
    fr = _friction(an, pairs)
    assert fr.power_check <= 1e-9 * np.max(np.abs(fr.driving_torque))
    assert all(np.all(loss >= -1e-9) for loss in fr.power_loss.values())
    assert fr.cycle_efficiency is not None and 0.5 < fr.cycle_efficiency < 1.0
    eff = fr.efficiency[np.isfinite(fr.efficiency)]
    assert np.all(eff <= 1.0 + 1e-12)


def test_slotted_lever_friction_converges() -> None:
    # the shaper: slides that turn with the rocker, friction everywhere; Newton reaches its stated residual
    mech = synth.SlottedLever(crank=0.1, ground=0.3, rocker=0.6, ram_height=0.7)
    links = {"crank": synth.MassProps(5.0), "rocker": synth.MassProps(10.0, (0.25, 0.0), 0.3),
             "ram": synth.MassProps(12.0)}
    load = synth.ProcessLoad(kind="window", magnitude=1200.0, start=-math.pi / 3, end=math.pi / 3)
    linkage = synth.Linkage(mech, links, gravity=synth.Gravity(), loads=(load,))
    an = synth.analyse(linkage, 4.0, samples=N)
    pairs = [PairFriction(j.name, 0.12, 0.0 if j.kind == "prismatic" else 0.02)
             for j in mech.topology.joints]
    fr = _friction(an, pairs)
    assert fr.residual <= 1e-12
    assert fr.power_check <= 1e-8 * np.max(np.abs(fr.driving_torque))


def test_bad_friction_names_the_pair() -> None:
    an = _press(0.0)
    cases = [(PairFriction("guide", -0.1), "friction.guide.coefficient"),
             (PairFriction("guide", 5.0), "friction.guide.coefficient"),
             (PairFriction("A", 0.1, 0.2), "friction.A.journal_radius_m"),
             (PairFriction("guide", 0.1, 0.01), "friction.guide.journal_radius_m"),
             (PairFriction("Z", 0.1), "friction.Z")]
    for pair, field in cases:
        with pytest.raises(synth.InvalidInput) as err:
            validate_pairs(an.motion, an.linkage, [pair])
        assert err.value.field == field
    warned = check_friction([PairFriction("guide", 1.2)])
    assert [w.field for w in warned] == ["friction.guide.coefficient"]
    warned = check_friction([PairFriction("guide", 0.5, static_coefficient=1.1)])
    assert [w.field for w in warned] == ["friction.guide.static_coefficient"]


def test_self_locking_is_a_problem_naming_the_angles() -> None:
    # cos b - mu |sin b| <= 0 for mu >= cot(b_max): a short rod with a guide coefficient of 3 locks
    mech = synth.SliderCrank(crank=0.1, rod=0.12)
    linkage = synth.Linkage(mech, {}, loads=(synth.ProcessLoad(kind="window", magnitude=1000.0),))
    an = synth.analyse(linkage, OMEGA, samples=N)
    with pytest.raises(synth.Infeasible) as err:
        friction_kinetostatics(an.motion, an.linkage, an.kinetostatics, [PairFriction("guide", 3.0)])
    assert err.value.constraint == "friction" and err.value.details["phi_deg"]


def test_breakaway_torque_is_the_closed_form_at_rest_with_the_static_coefficient() -> None:
    # at rest (no inertia) the same closed form with f0: loss torque = f0 |F sin b| |v| / w,
    # |F| = P / (cos b - f0 |sin b|), v / w the slider's speed ratio
    f, f0, p = 0.1, 0.17, 2000.0
    an = _press(0.0)
    rest = breakaway_torque(an.linkage, [PairFriction("guide", f, static_coefficient=f0)], an.motion.phi)
    beta = an.motion.link_angle["rod"]
    ratio = np.abs(an.motion.point_vel["B"][:, 0]) / OMEGA
    force = p / (np.cos(beta) - f0 * np.abs(np.sin(beta)))
    expected = f0 * np.abs(force * np.sin(beta)) * ratio
    moving = ratio > 1e-9
    assert np.max(np.abs(rest - expected)[moving]) <= 1e-9 * np.max(expected)


@settings(max_examples=25, deadline=None)
@given(st.one_of(crank_fourbars(), slider_cranks()), st.floats(0.0, 0.3), st.floats(0.0, 0.01), st.booleans())
def test_random_linkages_lose_power_and_keep_virtual_power(linkage: synth.Linkage, mu: float, radius: float,
                                                          gravity: bool) -> None:
    # on random assemblable four-bars and slider-cranks with friction in every pair: every pair's loss is >= 0,
    # the drive supplies exactly what friction dissipates (T w = T0 w + P_loss, virtual power), and the
    # instantaneous efficiency never exceeds one
    topo = linkage.mechanism.topology
    loaded = synth.Linkage(linkage.mechanism, linkage.links, gravity=synth.Gravity() if gravity else None,
                           loads=(synth.ProcessLoad("window", 30.0, 0.5, 3.5),))
    lengths = [v for v in link_lengths(linkage.mechanism).values()]
    r = min(radius, 0.5 * min(lengths))
    pairs = [PairFriction(j.name, mu, 0.0 if j.kind == "prismatic" else r) for j in topo.joints]
    an = synth.analyse(loaded, 7.0, samples=72)
    try:
        fr = friction_kinetostatics(an.motion, an.linkage, an.kinetostatics, pairs)
    except synth.Infeasible:
        event("self-locks")
        return  # a geometry that self-locks at this coefficient: the problem names the angles (tested above)
    scale = 1.0 + float(np.abs(fr.driving_torque).max())
    assert fr.residual <= 1e-12
    assert fr.power_check <= 1e-9 * scale
    assert all(float(loss.min()) >= -1e-12 * scale * 7.0 for loss in fr.power_loss.values())
    eff = fr.efficiency[np.isfinite(fr.efficiency)]
    assert np.all(eff <= 1.0 + 1e-12)
