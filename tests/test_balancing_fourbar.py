"""Four-bar balancing: static, full and optimal programs against closed forms, identities and re-analysis."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings

import synth
from helpers import crank_fourbars, spectral_derivative
from synth.kinematics.motion import cross

SPEED = 20.0


def _linkage(coupler_y: float = 0.0) -> synth.Linkage:
    fb = synth.FourBar(0.3, 0.1, 0.35, 0.25)
    return synth.Linkage(fb, {
        "crank": synth.MassProps(1.0, (0.05, 0.01), 0.001),
        "coupler": synth.MassProps(2.0, (0.175, coupler_y), 0.02),
        "rocker": synth.MassProps(1.5, (0.125, 0.01), 0.008),
    })


@settings(max_examples=25, deadline=None)
@given(crank_fourbars())
def test_static_balance_zeroes_the_shaking_force(linkage: synth.Linkage) -> None:
    # Re-analysed with the plain model: the force left is round-off of the original.
    result = synth.balance_static(linkage, SPEED, samples=120)
    assert result.residual_force_rel < 1e-9


@settings(max_examples=25, deadline=None)
@given(crank_fourbars())
def test_static_optimiser_agrees_with_the_exact_conditions(linkage: synth.Linkage) -> None:
    # Berkof-Lowen / seed (3.8) and corrected (3.9): the first moments are forced; the least mass puts each
    # counterweight at its largest radius (the link length by default).
    result = synth.balance_static(linkage, SPEED, samples=90)
    exact = synth.exact_static_counterweights(linkage)
    got = {cw.link: cw.params()[1:3] for cw in result.counterweights}
    scale = max(float(np.hypot(*h)) for h in exact.values()) + float(linkage.params_of("coupler")[0]) * 1e-3
    for link, h in exact.items():
        assert got.get(link, np.zeros(2)) == pytest.approx(np.array(h), abs=1e-6 * scale)
        length = getattr(linkage.mechanism, link)
        mass = next((c.mass for c in result.counterweights if c.link == link), 0.0)
        assert mass == pytest.approx(np.hypot(*h) / length, rel=1e-6, abs=1e-6 * scale / length)


def test_coupler_and_rocker_counterweights_also_balance() -> None:
    # The seed's variant [001:1394]: counterweights on coupler and rocker, with the crank left as it is.
    linkage = _linkage()
    crank_only = synth.Linkage(linkage.mechanism, {**linkage.links, "crank": synth.MassProps(0.5, (-0.15, 0), 0.0)})
    spec = synth.CounterweightSpec(("coupler", "rocker"), {"coupler": 0.5, "rocker": 0.5})
    result = synth.balance_static(crank_only, SPEED, spec, samples=120)
    assert result.residual_force_rel < 1e-9
    # The seed's consequence: with a counterweight beyond the rocker pivot, the coupler's centre moves past A.
    assert any(c.link == "coupler" for c in result.counterweights)


def test_min_inertia_needs_and_respects_a_budget() -> None:
    linkage = _linkage()
    with pytest.raises(synth.InvalidInput):
        synth.balance_static(linkage, SPEED, objective="min_inertia")
    light = synth.balance_static(linkage, SPEED, samples=90)
    heavy = synth.balance_static(linkage, SPEED, samples=90, objective="min_inertia",
                                 mass_budget=2 * light.total_added_mass)
    assert heavy.total_added_mass == pytest.approx(2 * light.total_added_mass, rel=1e-6)
    assert heavy.added_inertia < light.added_inertia
    assert heavy.residual_force_rel < 1e-9


def test_budget_too_low_names_the_limit() -> None:
    with pytest.raises(synth.Infeasible) as err:
        synth.balance_static(_linkage(), SPEED, mass_budget=0.1)
    assert err.value.constraint == "mass_budget_kg"
    assert err.value.details["required_mass_kg"] > 0.1


def test_only_a_crank_counterweight_cannot_zero_the_force() -> None:
    with pytest.raises(synth.Infeasible) as err:
        synth.balance_static(_linkage(), SPEED, synth.CounterweightSpec(("crank",)))
    assert err.value.constraint == "counterweight_links"


@settings(max_examples=15, deadline=None)
@given(crank_fourbars())
def test_full_balance_zeroes_force_and_moment(linkage: synth.Linkage) -> None:
    coupler = linkage.mass_props("coupler")
    inline = synth.Linkage(linkage.mechanism, {
        **linkage.links,
        "coupler": synth.MassProps(coupler.mass, (0.4 * linkage.mechanism.coupler, 0.0), coupler.inertia),
    })
    result = synth.balance_full(inline, SPEED, samples=120)
    assert result.residual_force_rel < 1e-8 and result.residual_moment_rel < 1e-7
    assert result.coupler_inertia == pytest.approx(synth.pendulum_inertia(inline), rel=1e-6)


def test_full_balance_angular_momentum_vanishes() -> None:
    # Independent of the moment rows: the links' angular momentum about O plus the rotors' is constant.
    linkage = _linkage()
    result = synth.balance_full(linkage, SPEED, samples=256)
    an = result.analysis_after
    m = an.motion
    h = np.zeros(256)
    for link in linkage.mechanism.topology.links:
        p = an.linkage.mass_props(link)
        s = m.point_on(link, p.com)
        h += p.mass * cross(s.pos, s.vel) + p.inertia * m.link_omega[link]
    for r in result.counter_rotors:
        h -= r.ratio * r.inertia * m.link_omega[r.link]
    scale = float(np.abs(result.analysis_before.kinetostatics.shaking_moment).max())
    assert np.abs(SPEED * spectral_derivative(h)).max() < 1e-7 * scale


def test_full_balance_says_plainly_when_the_coupler_cannot_be_a_pendulum() -> None:
    with pytest.raises(synth.Infeasible) as err:
        synth.balance_full(_linkage(coupler_y=0.02), SPEED)
    assert err.value.constraint == "links.coupler.com_m" and "optimal" in str(err.value)


def test_optimal_force_only_crank_only_equals_least_squares() -> None:
    linkage = _linkage()
    spec = synth.CounterweightSpec(("crank",), {"crank": 10.0})
    result = synth.balance_optimal(linkage, SPEED, spec, weights=synth.Weights(shaking_force=1.0), samples=180)
    h = result.counterweights[0].params()[1:3]
    expected = np.array(synth.least_squares_crank_counterweight(linkage, SPEED, samples=180))
    assert h == pytest.approx(expected, rel=1e-5)


def test_optimal_never_worse_than_designs_tried() -> None:
    # The SOCP's objective (from the plain re-analysis) is no larger than that of random feasible designs.
    linkage = _linkage()
    weights = synth.Weights(shaking_force=1.0, shaking_moment=2.0, driving_torque=1.0, bearing_forces=0.1)
    budget = 4.0
    best = synth.balance_optimal(linkage, SPEED, weights=weights, mass_budget=budget, samples=120)
    assert best.total_added_mass <= budget * (1 + 1e-7)
    rng = np.random.default_rng(7)
    for _ in range(40):
        cws = []
        for link, length in (("crank", 0.1), ("rocker", 0.25)):
            m = rng.uniform(0, budget / 2)
            r = rng.uniform(0, length)
            a = rng.uniform(-np.pi, np.pi)
            cws.append(synth.Counterweight(link, m, (r * np.cos(a), r * np.sin(a)), rng.uniform(0, 0.01)))
        trial = synth.analyse(linkage.with_counterweights(cws), SPEED, samples=120)
        assert best.objective <= synth.objective_value(trial, weights, cws) * (1 + 1e-6)


def test_tradeoff_points_are_each_verified() -> None:
    linkage = _linkage()
    sets = [synth.Weights(shaking_force=1.0), synth.Weights(shaking_force=1.0, driving_torque=10.0)]
    points = synth.tradeoff(linkage, SPEED, None, sets, mass_budget=4.0, samples=90)
    assert len(points) == 2
    assert points[0].after.rms_shaking_force <= points[1].after.rms_shaking_force + 1e-9
    assert points[1].after.rms_driving_torque <= points[0].after.rms_driving_torque + 1e-9


def test_fixed_radius_and_fixed_angle() -> None:
    # Fixed radius: the least mass is |h|/r with h from the exact conditions; the counterweight sits on the circle.
    linkage = _linkage()
    spec = synth.CounterweightSpec(("crank", "rocker"), radius={"crank": 0.06, "rocker": 0.2})
    result = synth.balance_static(linkage, SPEED, spec, samples=120)
    exact = synth.exact_static_counterweights(linkage)
    for cw in result.counterweights:
        r = spec.radius[cw.link]  # type: ignore[index]
        assert np.hypot(*cw.position) == pytest.approx(r, rel=1e-6)
        assert cw.mass == pytest.approx(np.hypot(*exact[cw.link]) / r, rel=1e-6)
    assert result.residual_force_rel < 1e-9
    # A fixed angle the exact first moment does not point along cannot balance.
    bad = synth.CounterweightSpec(("crank", "rocker"), angle={"crank": 0.0})
    with pytest.raises(synth.Infeasible) as err:
        synth.balance_static(linkage, SPEED, bad, samples=60)
    assert err.value.constraint == "angle_deg"


def test_time_budget_is_a_timeout() -> None:
    # A budget no solve can meet: the solver's own limit stops it, reported as SolverTimeout (504 over HTTP).
    with pytest.raises(synth.SolverTimeout):
        synth.balance_optimal(_linkage(), SPEED, weights=synth.Weights(1.0, 1.0, 1.0, 1.0), samples=360,
                              time_limit_s=1e-7)
