"""Any linkage's free dimensions chosen with its machine: the six-bar press of the manual with the guide's place
and the rocker's lever arm free, against a 16 × 16 grid of its own; the function met, bad input named."""

from __future__ import annotations

import copy
import math
from typing import Any

import numpy as np
import pytest

from mechsynth_client import SynthClient
from mechsynth_client.schemas.common import PlanarLinkageIn
from mechsynth_client.schemas.optimise import (
    LINKAGE_DEFAULT_SAMPLES,
    LINKAGE_MAX_FREE,
    LINKAGE_MAX_REFINE_RUNS,
    LINKAGE_MAX_REFINED,
    LINKAGE_MAX_SAMPLES,
    LINKAGE_MIN_SAMPLES,
    SIX_BAR_OPTIMISE_EXAMPLE,
    LinkageOptimiseIn,
    LinkageOptimiseOut,
)
from synth.machine import optimise_linkage as engine

GRID = 16


@pytest.fixture(scope="module")
def answer(client: SynthClient) -> LinkageOptimiseOut:
    return client.optimise_linkage(LinkageOptimiseIn.model_validate(SIX_BAR_OPTIMISE_EXAMPLE))


def test_bounds_match_the_engine() -> None:
    assert (LINKAGE_MIN_SAMPLES, LINKAGE_MAX_SAMPLES, LINKAGE_DEFAULT_SAMPLES) == (
        engine.MIN_SAMPLES, engine.MAX_SAMPLES, engine.DEFAULT_SAMPLES)
    assert (LINKAGE_MAX_FREE, LINKAGE_MAX_REFINED, LINKAGE_MAX_REFINE_RUNS) == (
        engine.MAX_FREE, engine.MAX_REFINED, engine.MAX_REFINE_RUNS)


def test_the_answer_meets_the_function(answer: LinkageOptimiseOut) -> None:
    a = answer
    assert a.design.passed
    body = SIX_BAR_OPTIMISE_EXAMPLE
    for d in body["free"]:  # type: ignore[union-attr]
        assert d["min"] <= a.free[d["path"]] <= d["max"]
    # the chosen press solved here over 3600 crank angles: the ram runs on the vertical guide through G, so its
    # stroke is the range of D's height, its time ratio the crank angles between the extremes
    mech = PlanarLinkageIn.model_validate(a.mechanism).to_mechanism()
    assert dict(mech.frame_points)["G"][0] == a.free["frame_points_m.G.x"]
    phi = np.linspace(0, 2 * math.pi, 3600, endpoint=False)
    points, _ = mech.solve(phi)
    y = points["D"].pos[:, 1]
    stroke = float(y.max() - y.min())
    assert stroke == pytest.approx(a.stroke_or_swing, rel=1e-4)
    assert 0.18 <= stroke <= 0.26
    forward = (phi[np.argmax(y)] - phi[np.argmin(y)]) % (2 * math.pi)
    ratio = max(forward, 2 * math.pi - forward) / min(forward, 2 * math.pi - forward)
    # the ram reaches its top twice a turn (the rod passes upright twice): the time ratio has two readings, and
    # the one from the highest sample here is one of them, to a sample step of 0.1° on each extreme
    lo, hi = a.time_ratio_range
    assert lo * (1 - 2e-3) <= ratio <= hi * (1 + 2e-3)
    assert 1.2 <= lo <= hi <= 2.0 and a.min_transmission_angle_deg >= 30
    # the answer's machine mass is its parts'
    assert a.values["machine_mass"] == pytest.approx(a.parts.machine_mass_kg, rel=1e-12)
    assert a.parts.machine_mass_kg == pytest.approx(a.parts.flywheel_kg + a.parts.counterweights_kg
                                                    + a.parts.motor_kg + a.parts.gears_kg, rel=1e-12)
    c = a.certificate
    assert c.gap_bound is None and "no gap bound" in c.statement
    assert c.sampled == LINKAGE_DEFAULT_SAMPLES + 1  # the request's own numbers lie in the box
    assert 0 < c.kinematic_feasible <= c.sampled and c.refined == 4 and c.refine_runs > 0


def test_never_worse_than_a_grid_of_its_own(answer: LinkageOptimiseOut) -> None:
    spec = LinkageOptimiseIn.model_validate(SIX_BAR_OPTIMISE_EXAMPLE).to_engine(6)
    lo = [d.lo for d in spec.free]
    hi = [d.hi for d in spec.free]
    best = math.inf
    feasible = 0
    for gx in np.linspace(lo[0], hi[0], GRID):
        for gy in np.linspace(lo[1], hi[1], GRID):
            m = engine.design_member(spec, (gx, gy), "grid")
            if m.feasible and m.values is not None:
                feasible += 1
                best = min(best, m.values[3])
    assert feasible >= 16
    # the grid's members scored on their steady machine, as the search scores its own
    assert answer.values["machine_mass"] <= best * (1 + 1e-4), (answer.values["machine_mass"], best)


@pytest.mark.parametrize(("change", "field"), [
    ({"free": [{"path": "frame_points_m.Z.x", "min": 0.4, "max": 0.5}]}, "free.0.path"),
    ({"free": [{"path": "links.rocker.colour", "min": 0.4, "max": 0.5}]}, "free.0.path"),
    ({"free": [{"path": "links.ram.length_m", "min": 0.4, "max": 0.5}]}, "free.0.path"),
    ({"free": [{"path": "frame_points_m.G.x", "min": 0.5, "max": 0.4}]}, "free.0.min"),
    ({"stroke_m": {"min": 0.3, "max": 0.2}}, "stroke_m.min"),
])
def test_bad_input_is_named(client: SynthClient, change: dict[str, Any], field: str) -> None:
    body = {**copy.deepcopy(SIX_BAR_OPTIMISE_EXAMPLE), **change}
    r = client.http.post("/v1/machines/optimise-linkage", json=body)
    assert r.status_code == 422, r.text
    problem = r.json()
    assert problem.get("field") == field or any(e.get("field") == field for e in problem.get("errors", [])), problem


def test_a_function_no_member_meets_is_infeasible(client: SynthClient) -> None:
    body = {**copy.deepcopy(SIX_BAR_OPTIMISE_EXAMPLE), "stroke_m": {"min": 1.0, "max": 1.2}}
    r = client.http.post("/v1/machines/optimise-linkage", json=body)
    assert r.status_code == 422, r.text
    assert r.json()["type"] == "/problems/infeasible"
