"""Optimal counterweight balancing of slider-cranks and shapers: the closed forms it must reproduce, random designs
it must never lose to, its re-analysis check, the endpoint and the machine chain."""

from __future__ import annotations

import copy
import dataclasses
import math

import numpy as np
import pytest

import synth
from api.translate.balancing import balance_spec
from api.translate.linkage import linkage_from
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.balancing import SLIDER_CRANK_EXAMPLE, OptimalBalanceIn
from mechsynth_client.schemas.machine import PRESS_EXAMPLE, SHAPER_EXAMPLE, MachineIn
from synth.balancing.fourbar import _optimal_program
from synth.balancing.program import _TOLERANCES, CounterweightSolution, counterweight_layout, solve
from tests.conftest import CASES
from tests.helpers import shaper_from_case

SAMPLES = 360  # even: the in-line slider's even harmonics cannot alias onto the first order
SPEED = 150.0  # [rad/s]
CRANK, ROD = 0.05, 0.2  # [m]
ALL_TERMS = synth.Weights(shaking_force=1.0, shaking_moment=1.0, driving_torque=0.5, bearing_forces=0.2,
                          peak_shaking_force=0.1, peak_shaking_moment=0.1)


def _slider_crank(offset: float = 0.0) -> synth.Linkage:
    # the crank's centre of mass off its line, so both components of the counterweight's first moment matter
    return synth.Linkage(synth.SliderCrank(CRANK, ROD, offset), {
        "crank": synth.MassProps(1.0, (0.02, 0.005), 0.001),
        "rod": synth.MassProps(0.8, (0.06, 0.0), 0.003),
        "slider": synth.MassProps(1.2),
    })


def _shaper() -> tuple[synth.Linkage, float]:
    """The lecture-10 shaper of the seeds (the README's), with its masses, gravity and cutting load."""
    inputs = {**CASES["l10_shaper_kinematics_exact"]["inputs"], **CASES["l10_shaper_kinetostatics_ram_group"]["inputs"],
              "m1_kg": 5.0, "m3_kg": 10.0, "J3_kgm2": 0.3}
    return shaper_from_case(inputs), inputs["omega1_rad_s"]


def _force_rows(linkage: synth.Linkage) -> tuple[np.ndarray, np.ndarray, float]:
    """Shaking force over all angles as A @ h + c in the crank counterweight's first moment h, from the linear
    map's rows; and the RMS force before balancing."""
    an = synth.analyse(linkage, SPEED, samples=SAMPLES)
    lm = synth.linear_map(an.motion, linkage)
    rows = [lm.force_rows.start, lm.force_rows.start + 1]
    y = lm.y[:, rows, :].reshape(-1, lm.y.shape[2])
    c = y @ linkage.params() + lm.y0[:, rows].reshape(-1)
    crank = lm.columns("crank")
    return y[:, [crank.start + 1, crank.start + 2]], c, an.summary().rms_shaking_force


def _distance_allowed(a: np.ndarray, c: np.ndarray, f0: float) -> tuple[np.ndarray, float]:
    """The least-squares first moment and how far the program's answer may lie from it [kg·m].

    Force-only relative weights minimise F_rms(h)/F0 + eps·(m + J/l²); a crank counterweight on its radius limit
    l costs eps·2|h|/l. F_rms has the Hessian AᵀA/(N·F_rms*) at its minimum, so the added-mass term moves the
    minimiser by at most eps·(2/l)·F0·F_rms*/lambda_min(AᵀA/N) (first order). The solver stops at a relative gap
    of 1e-10 of the objective, which lets h sit sqrt(2·gap/curvature) off the minimiser.
    """
    h, *_ = np.linalg.lstsq(a, -c, rcond=None)
    n = len(c) // 2
    rms = float(np.linalg.norm(a @ h + c)) / math.sqrt(n)
    lam = float(np.linalg.eigvalsh(a.T @ a / n).min())
    eps = synth.Weights().added_mass
    shift = eps * (2 / CRANK) * f0 * rms / lam
    curvature = lam / (rms * f0)
    gap = _TOLERANCES["tol_gap_rel"] * rms / f0
    return h, shift + math.sqrt(2 * gap / curvature)


def test_slider_crank_force_optimum_is_the_least_squares_crank_counterweight() -> None:
    # independent computation: the RMS force is linear in the crank counterweight's first moment, so its minimiser
    # is numpy's least squares on the map's columns (an offset slider-crank, no closed form)
    linkage = _slider_crank(offset=0.02)
    a, c, f0 = _force_rows(linkage)
    expected, allowed = _distance_allowed(a, c, f0)
    r = synth.balance_optimal(linkage, SPEED, samples=SAMPLES)
    assert [cw.link for cw in r.counterweights] == ["crank"]  # a slider-crank's default
    got = r.counterweights[0].params()[1:3]
    assert allowed < 1e-5 * float(np.linalg.norm(expected))
    assert float(np.linalg.norm(got - expected)) <= allowed
    # the crank counterweight sits on its default radius limit, the crank's length
    assert math.hypot(*r.counterweights[0].position) == pytest.approx(CRANK, rel=1e-9)


def test_inline_slider_crank_takes_the_rotating_mass_and_half_the_reciprocating() -> None:
    # textbook result: with the rod split statically into A and B (exact for the force, as its centre of mass on
    # AB moves as (1 - x/l)·A + (x/l)·B), a crank counterweight cancels the rotating mass and half of the
    # reciprocating mass's first order. In-line, x_B - r·cos(phi) has only even harmonics, so the first order is
    # exactly -m_rec·r·w²·cos(phi) and the RMS-optimal split is exactly one half.
    linkage = _slider_crank()
    m1, (x1, y1) = linkage.links["crank"].mass, linkage.links["crank"].com
    m2, x2 = linkage.links["rod"].mass, linkage.links["rod"].com[0]
    rotating = m1 * x1 / CRANK + m2 * (1 - x2 / ROD)
    reciprocating = linkage.links["slider"].mass + m2 * x2 / ROD
    textbook = np.array([-(rotating + reciprocating / 2) * CRANK, -m1 * y1])
    a, c, f0 = _force_rows(linkage)
    least_squares, allowed = _distance_allowed(a, c, f0)
    # the map's least squares is the textbook's to round-off
    assert least_squares == pytest.approx(textbook, rel=1e-9, abs=1e-12)
    r = synth.balance_optimal(linkage, SPEED, samples=SAMPLES)
    assert float(np.linalg.norm(r.counterweights[0].params()[1:3] - textbook)) <= allowed


def _random_designs(rng: np.random.Generator, links: tuple[str, ...], limits: dict[str, float], budget: float,
                    best: tuple[synth.Counterweight, ...], count: int = 30) -> list[list[synth.Counterweight]]:
    """Feasible designs on ``links``: half drawn anywhere within the limits, half near ``best`` (1 % moves),
    every one within its radius limit and, together, within the mass budget."""
    out = []
    for k in range(count):
        design = []
        near = {c.link: c for c in best} if k % 2 else {}
        for link in links:
            if link in near:
                c = near[link]
                mass = c.mass * (1 + 0.01 * rng.standard_normal())
                pos = np.array(c.position) + 0.01 * limits[link] * rng.standard_normal(2)
                inertia = c.inertia + 1e-4 * mass * limits[link] ** 2 * rng.random()
            else:
                mass = rng.random() * budget / len(links)
                pos = rng.random() * limits[link] * np.array([np.cos(t := rng.uniform(0, 2 * np.pi)), np.sin(t)])
                inertia = 0.1 * rng.random() * mass * limits[link] ** 2
            radius = float(np.hypot(*pos))
            if radius > limits[link]:
                pos = pos * limits[link] / radius
            design.append(synth.Counterweight(link, abs(mass), (float(pos[0]), float(pos[1])), inertia))
        total = sum(c.mass for c in design)
        if total > budget:
            design = [dataclasses.replace(c, mass=c.mass * budget / total) for c in design]
        out.append(design)
    return out


@pytest.mark.parametrize("family", ["slider_crank", "shaper"])
def test_optimum_never_loses_to_random_feasible_designs(family: str) -> None:
    # property of a global optimum: every feasible design on the same links within the same limits scores at
    # least as much, the objective re-evaluated on a plain re-analysis for all of them alike
    if family == "slider_crank":
        linkage, speed, links = _slider_crank(offset=0.01), SPEED, ("crank", "rod")
    else:
        (linkage, speed), links = _shaper(), ("crank", "rocker")
    spec = synth.CounterweightSpec(links)
    budget = 0.5 * sum(p.mass for p in linkage.links.values())
    r = synth.balance_optimal(linkage, speed, spec, weights=ALL_TERMS, mass_budget=budget, samples=120)
    weights = synth.relative_weights(r.analysis_before, ALL_TERMS)
    limits = {link: spec.limit(linkage, link) for link in links}
    scores = [synth.objective_value(r.analysis_before, weights, [])]  # no counterweights is feasible too
    for design in _random_designs(np.random.default_rng(11), links, limits, budget, r.counterweights):
        an = synth.analyse(linkage.with_counterweights(design), speed, samples=120)
        scores.append(synth.objective_value(an, weights, design))
    assert r.objective is not None
    # the solver's relative gap is 1e-10 and the radius cone keeps a margin of 1e-7 of the limit
    assert r.objective <= min(scores) * (1 + 1e-7)


def _check_consistent(r: synth.BalanceResult, linkage: synth.Linkage, speed: float, samples: int,
                      given: synth.Weights) -> None:
    fresh = synth.analyse(linkage.with_counterweights(r.counterweights), speed, samples=samples)
    before = synth.analyse(linkage, speed, samples=samples).summary()
    for name, value in dataclasses.asdict(fresh.summary()).items():
        assert getattr(r.after, name) == pytest.approx(value, rel=1e-9, abs=1e-12), name
    force = float(np.hypot(*fresh.kinetostatics.shaking_force.T).max())
    moment = float(np.abs(fresh.kinetostatics.shaking_moment).max())
    assert r.residual_force == pytest.approx(force, rel=1e-9)
    assert r.residual_force_rel == pytest.approx(force / before.max_shaking_force, rel=1e-9)
    assert r.residual_moment == pytest.approx(moment, rel=1e-9)
    assert r.residual_moment_rel == pytest.approx(moment / before.max_shaking_moment, rel=1e-9)
    weights = synth.relative_weights(synth.analyse(linkage, speed, samples=samples), given)
    assert r.objective == pytest.approx(synth.objective_value(fresh, weights, r.counterweights), rel=1e-9)
    assert r.total_added_mass == pytest.approx(sum(c.mass for c in r.counterweights), rel=1e-12)


def test_every_answer_carries_its_re_analysis() -> None:
    # identity: the summary, residuals and objective after balancing are a fresh synth.analyse of the balanced
    # linkage, for each point of a sweep of both families
    sets = [synth.Weights(), synth.Weights(shaking_force=1.0, shaking_moment=1.0), ALL_TERMS]
    cases = [(_slider_crank(offset=0.01), SPEED, synth.CounterweightSpec(("crank", "rod"))),
             (*_shaper(), None)]
    for linkage, speed, spec in cases:
        points = synth.tradeoff(linkage, speed, spec, sets, samples=120)
        assert len(points) == len(sets)
        for r, given in zip(points, sets, strict=True):
            assert r.counterweights and r.weights == given
            _check_consistent(r, linkage, speed, 120, given)


def test_program_optimum_is_the_re_analysed_objective_with_sliding_pairs() -> None:
    # identity: the SOCP's value at its optimum is the objective re-evaluated on the plain model, every term
    # weighted; the shaper's bearing forces include three sliding pairs, whose normal forces count and whose
    # couples (moments, not forces) do not, on both sides
    linkage, speed = _shaper()
    spec = synth.CounterweightSpec().resolve(linkage)
    before = synth.analyse(linkage, speed, samples=120)
    weights = synth.relative_weights(before, ALL_TERMS)
    layout = counterweight_layout(spec, linkage)
    terms = tuple(k for k in dataclasses.asdict(ALL_TERMS) if k != "added_mass")
    built = _optimal_program(synth.linear_map(before.motion, linkage), linkage, layout, terms, 13.5)
    built.program.q = built.costs(weights)
    x = solve(built.program, 20.0, "test")
    cws = CounterweightSolution(layout, x).counterweights()
    after = synth.analyse(linkage.with_counterweights(cws), speed, samples=120)
    # the solver's relative gap is 1e-10
    assert float(built.program.q @ x) == pytest.approx(synth.objective_value(after, weights, cws), rel=1e-8)


def test_the_lever_counterweight_is_the_lightest_for_its_moment() -> None:
    # force-only weights leave a lever counterweight's mass free once its first moment is set; the added-mass
    # term (inertia over the lever's own length²) then wants all of it on the radius limit: m = |h|/r_max.
    # The term is flat there, and the solver stops within a few tenths of a per cent of the limit.
    linkage, speed = _shaper()
    r = synth.balance_optimal(linkage, speed, samples=120)
    lever = next(c for c in r.counterweights if c.link == "rocker")
    limit = synth.CounterweightSpec(("rocker",)).limit(linkage, "rocker")
    assert math.hypot(*lever.position) == pytest.approx(limit, rel=1e-2)
    assert r.total_added_mass < sum(p.mass for p in linkage.links.values())  # the default budget does not bind


def test_default_links_and_limits_per_family() -> None:
    sc = synth.CounterweightSpec().resolve(_slider_crank())
    shaper, _ = _shaper()
    sh = synth.CounterweightSpec().resolve(shaper)
    assert sc.links == ("crank",) and sh.links == ("crank", "rocker")
    # default radius limits: each link's own length (the rod's A-B, the shaper's lever O1-B)
    assert synth.CounterweightSpec(("crank", "rod")).limit(_slider_crank(), "rod") == ROD
    assert sh.limit(shaper, "rocker") == shaper.mechanism.rocker  # type: ignore[union-attr]


@pytest.mark.parametrize(("family", "link"), [("slider_crank", "slider"), ("shaper", "ram"),
                                              ("shaper", "ram_slider"), ("shaper", "slider")])
def test_a_counterweight_on_a_sliding_link_is_refused(family: str, link: str) -> None:
    linkage = _slider_crank() if family == "slider_crank" else _shaper()[0]
    with pytest.raises(synth.InvalidInput, match="reciprocating mass") as err:
        synth.balance_optimal(linkage, 10.0, synth.CounterweightSpec(("crank", link)), samples=36)
    assert err.value.field == "counterweight_links"


@pytest.mark.parametrize("mode", ["static", "full"])
def test_static_and_full_stay_four_bar_modes(mode: str) -> None:
    fn = synth.balance_static if mode == "static" else synth.balance_full
    with pytest.raises(synth.InvalidInput, match="Lanchester balancers") as err:
        fn(_slider_crank(), SPEED, samples=36)
    assert err.value.field == "mechanism.type"
    with pytest.raises(synth.InvalidInput, match="optimal mode") as err:
        fn(_shaper()[0], 4.0, samples=36)
    assert err.value.field == "mechanism.type"


def _shaper_body() -> dict[str, object]:
    return {k: SHAPER_EXAMPLE[k] for k in ("mechanism", "gravity", "loads")} | {"speed_rpm": 38.197, "samples": 120}


@pytest.mark.parametrize("family", ["slider_crank", "shaper"])
def test_optimal_endpoint_takes_slider_cranks_and_shapers(client: SynthClient, family: str) -> None:
    body = ({"mechanism": SLIDER_CRANK_EXAMPLE, "speed_rpm": 1500, "samples": 120} if family == "slider_crank"
            else _shaper_body())
    r = client.http.post("/v1/balancing/optimal", json=body)
    assert r.status_code == 200, r.text
    out = r.json()
    links = {"slider_crank": ["crank"], "shaper": ["crank", "rocker"]}[family]
    assert [c["link"] for c in out["counterweights"]] == links
    # force-only weights by default: the RMS force falls; the check figure is the plain model's
    assert out["summary_after"]["rms_shaking_force_N"] < 0.5 * out["summary_before"]["rms_shaking_force_N"]
    assert out["checks"]["residual_shaking_force_N"] == pytest.approx(out["summary_after"]["max_shaking_force_N"],
                                                                      rel=1e-12)
    # the engine's answer, to round-off (the endpoint converts rpm and calls it)
    req = OptimalBalanceIn.model_validate(body)
    engine = synth.balance_optimal(linkage_from(req), req.omega_rad_s, balance_spec(req), samples=120)
    for got, want in zip(out["counterweights"], engine.counterweights, strict=True):
        assert got["mass_kg"] == pytest.approx(want.mass, rel=1e-9)


@pytest.mark.parametrize(("family", "link"), [("slider_crank", "slider"), ("shaper", "ram")])
def test_optimal_endpoint_refuses_a_counterweight_on_a_sliding_link(client: SynthClient, family: str,
                                                                    link: str) -> None:
    body = ({"mechanism": SLIDER_CRANK_EXAMPLE, "speed_rpm": 1500} if family == "slider_crank" else _shaper_body())
    r = client.http.post("/v1/balancing/optimal", json=body | {"counterweight_links": ["crank", link]})
    assert r.status_code == 422 and r.json()["field"] == "counterweight_links"
    assert "reciprocating mass" in r.json()["detail"]


def test_exports_of_a_slider_crank_balance(client: SynthClient) -> None:
    body = OptimalBalanceIn.model_validate({"mechanism": SLIDER_CRANK_EXAMPLE, "speed_rpm": 1500, "samples": 72,
                                            "counterweight_links": ["crank", "rod"],
                                            "weights": {"shaking_force": 1.0, "shaking_moment": 1.0},
                                            "sweep": [{"shaking_force": 1.0}]})
    png = client.balance_png("optimal", body)
    assert png.startswith(b"\x89PNG") and len(png) > 50_000
    assert client.balance_png("optimal", body, "svg").lstrip().startswith(b"<?xml")
    assert client.balance_png("optimal", body, "pdf").startswith(b"%PDF")
    rows = client.balance_csv("optimal", body).splitlines()
    assert len(rows) == 73 and rows[0].startswith("crank_angle_deg,shaking_force_x_before_N")
    dxf = client.balance_dxf("optimal", body).decode()
    # the counterweights are drawn on their links, labelled with link, mass, radius and angle
    assert "COUNTERWEIGHTS" in dxf and "crank: " in dxf and "rod: " in dxf


def _press(**balancing: object) -> MachineIn:
    body = copy.deepcopy(PRESS_EXAMPLE)
    body["samples"] = 120
    body["balancing"] = balancing
    return MachineIn.model_validate(body)


def test_press_balanced_optimally_in_the_machine_chain(client: SynthClient) -> None:
    out = client.design_machine(_press(mode="optimal"))
    # check figure: the assembled machine simulated to its steady state (the chain's 1e-3)
    assert out.passed
    assert out.simulation.achieved_delta == pytest.approx(out.simulation.target_delta, rel=1e-3)
    assert out.balancing_mode == "optimal" and out.balancing is not None and out.slider_crank_balancing is None
    assert out.summary_after_balancing.rms_shaking_force_N < out.analysis.summary.rms_shaking_force_N
    # the stage is the balancing endpoint's answer for the same linkage
    alone = client.balance_optimal(OptimalBalanceIn.model_validate(
        {k: v for k, v in PRESS_EXAMPLE.items() if k in ("mechanism", "loads", "speed_rpm")} | {"samples": 120}))
    assert out.balancing.counterweights[0].mass_kg == pytest.approx(alone.counterweights[0].mass_kg, rel=1e-9)


def test_press_alternatives_include_optimal(client: SynthClient) -> None:
    out = client.design_machine(_press(mode="static").model_copy(update={"alternatives": True}))
    by_mode = {a.mode: a for a in out.alternatives}
    assert set(by_mode) == {"none", "full", "optimal"} and all(a.available for a in by_mode.values())
    # optimal weighs force and moment alike; its force is below the Lanchester static answer's (rotating masses
    # only) and above none's never
    assert by_mode["optimal"].rms_shaking_force_N < out.summary_after_balancing.rms_shaking_force_N
    assert by_mode["optimal"].rms_shaking_force_N < by_mode["none"].rms_shaking_force_N
