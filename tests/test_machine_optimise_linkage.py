"""Any linkage's free dimensions chosen with its machine: the six-bar press of the manual with the guide's place
and the rocker's lever arm free, against a 16 × 16 grid of its own; the function met, bad input named, work
beyond the service's bound refused before it starts; the stages spread over a pool's workers give the engine's
own answer in one process (the same members in the same order, the same optimum, to 1e-12)."""

from __future__ import annotations

import copy
import math
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import orjson
import pytest
from fastapi.testclient import TestClient

import synth
from api.app import create_app
from api.media import Render
from api.execution.optimise_linkage import price_linkage_optimisation
from api.execution.plans import Limits
from api.execution.work import estimate_s
from api.settings import Settings
from api.translate.linkage import planar_linkage_from
from api.translate.optimise import linkage_optimise_from, linkage_optimise_out
from mechsynth_client import SynthClient
from mechsynth_client.schemas.common import PlanarLinkageIn
from mechsynth_client.schemas.optimise import (
    LINKAGE_DEFAULT_SAMPLES,
    LINKAGE_MAX_FREE,
    LINKAGE_MAX_REFINE_RUNS,
    LINKAGE_MAX_REFINED,
    LINKAGE_MAX_SAMPLES,
    LINKAGE_MIN_SAMPLES,
    LINKAGE_QUICK,
    SIX_BAR_OPTIMISE_EXAMPLE,
    LinkageOptimiseIn,
    LinkageOptimiseOut,
)
from synth.machine import optimise_linkage as engine
from synth.machine.optimise_linkage import optimise_linkage

GRID = 16


@pytest.fixture(scope="module")
def pool_client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[SynthClient]:
    """The endpoint as the service runs it, its stages as tasks on two worker processes; a deadline that leaves
    room for cores shared with other work; answers in full precision, to be held to the engine's."""
    settings = Settings(executor="pool", workers=2, request_deadline_s=300.0,
                        studies_db=str(tmp_path_factory.mktemp("linkage-pool") / "s.sqlite"))
    with TestClient(create_app(settings), base_url="http://localhost") as http:
        yield SynthClient(http=http, precision="full")


@pytest.fixture(scope="module")
def answer(pool_client: SynthClient) -> LinkageOptimiseOut:
    return pool_client.optimise_linkage(LinkageOptimiseIn.model_validate(SIX_BAR_OPTIMISE_EXAMPLE))


def test_bounds_match_the_engine() -> None:
    assert (LINKAGE_MIN_SAMPLES, LINKAGE_MAX_SAMPLES, LINKAGE_DEFAULT_SAMPLES) == (
        engine.MIN_SAMPLES, engine.MAX_SAMPLES, engine.DEFAULT_SAMPLES)
    assert (LINKAGE_MAX_FREE, LINKAGE_MAX_REFINED, LINKAGE_MAX_REFINE_RUNS) == (
        engine.MAX_FREE, engine.MAX_REFINED, engine.MAX_REFINE_RUNS)


def test_the_answer_meets_the_function(answer: LinkageOptimiseOut) -> None:
    a = answer
    assert a.design.passed
    body = SIX_BAR_OPTIMISE_EXAMPLE
    chosen = {f.path: f.value_m for f in a.free}
    assert list(chosen) == [d["path"] for d in body["free"]]  # type: ignore[union-attr]
    for d in body["free"]:  # type: ignore[union-attr]
        assert d["min"] <= chosen[d["path"]] <= d["max"]
    # the chosen press solved here over 3600 crank angles: the ram runs on the vertical guide through G, so its
    # stroke is the range of D's height, its time ratio the crank angles between the extremes
    mech = planar_linkage_from(PlanarLinkageIn.model_validate(a.mechanism))
    assert dict(mech.frame_points)["G"][0] == chosen["frame_points_m.G.x"]
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
    spec = linkage_optimise_from(LinkageOptimiseIn.model_validate(SIX_BAR_OPTIMISE_EXAMPLE), 6)
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


# The work is priced before it starts (api/execution/work.py): a chain run of the six-bar press costs 0.1 s and
# 0.1 ms per crank angle, 0.1072 s at its 72; the optimum's whole design 1 s. On one worker the default request
# (64 + 1 members, 4 starts of up to 60 runs) is 65 x 0.1072 + 240 x 0.1072 + 1 = 33.7 s, the refinement most of
# it; 512 + 1 members with one start of 20 runs are 513 x 0.1072 + 20 x 0.1072 + 1 = 58.1 s, the sample most.
@pytest.mark.parametrize(("change", "field", "got"), [({}, "refine_runs", 34),
                                                      ({"samples": 512, "refined": 1, "refine_runs": 20},
                                                       "samples", 59)])
def test_work_beyond_the_bound_is_refused_before_it_starts(tmp_path: Path, change: dict[str, Any], field: str,
                                                           got: int) -> None:
    settings = Settings(executor="serial", max_request_work_s=20.0, studies_db=str(tmp_path / "s.sqlite"))
    with TestClient(create_app(settings)) as c:
        start = time.monotonic()
        r = c.post("/v1/machines/optimise-linkage", json={**copy.deepcopy(SIX_BAR_OPTIMISE_EXAMPLE), **change})
        assert r.status_code == 413, r.text
        problem = r.json()
        assert (problem["field"], problem["got"], problem["limit"]) == (field, got, 20)
        assert time.monotonic() - start < 2.0  # refused at once, not after the work
        # 16 + 1 members and one start of 20 runs: 37 x 0.1072 + 1 = 5.0 s, within the bound; it runs
        quick = {**copy.deepcopy(SIX_BAR_OPTIMISE_EXAMPLE), **LINKAGE_QUICK, "refined": 0}
        assert c.post("/v1/machines/optimise-linkage", json=quick).status_code == 200


def test_the_price_is_the_time_on_the_workers_it_is_dealt_to() -> None:
    body = LinkageOptimiseIn.model_validate(SIX_BAR_OPTIMISE_EXAMPLE)
    lim = Limits(3600, 6, 20.0, max_work_s=20.0)
    # two workers share the 65 members (33 each) and take two starts each: 33 x 0.1072 + 120 x 0.1072 + 1 s
    assert price_linkage_optimisation(body, lim, 2) == pytest.approx(153 * 0.1072 + 1, rel=1e-12)
    with pytest.raises(synth.TooLarge):
        price_linkage_optimisation(body, lim, 1)
    # a study's variant runs on one worker: its estimate is the one-worker figure
    assert estimate_s("/v1/machines/optimise-linkage", body) == pytest.approx(305 * 0.1072 + 1, rel=1e-12)


# three refinement starts on two workers: one worker takes two of them, so the starts' order is exercised
BODY: dict[str, Any] = {**copy.deepcopy(SIX_BAR_OPTIMISE_EXAMPLE), "samples": 12, "refined": 3, "refine_runs": 10}

# how long a solver or a search took: the figures of an answer that are no function of the request
WALL_CLOCK = {"solve_time_s", "search_time_s", "elapsed_s"}


def _same(a: Any, b: Any, where: str = "") -> None:
    """Every number of ``a`` within 1e-12 relative of ``b``'s, everything else equal, member by member."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and a.keys() == b.keys(), where
        for k in a.keys() - WALL_CLOCK:
            _same(a[k], b[k], f"{where}.{k}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), where
        for k, (x, y) in enumerate(zip(a, b, strict=True)):
            _same(x, y, f"{where}.{k}")
    elif isinstance(a, float) and not isinstance(b, bool):
        assert isinstance(b, (int, float)) and math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-15), (where, a, b)
    else:
        assert a == b, (where, a, b)


def test_the_pool_answer_is_the_engine_answer_in_one_process(pool_client: SynthClient) -> None:
    body = LinkageOptimiseIn.model_validate(BODY)
    alone = optimise_linkage(linkage_optimise_from(body, 6))
    spread = pool_client.optimise_linkage(body)
    # the endpoint on the pool ran the scan, two shares of the sample, three starts and the conclusion as tasks
    assert spread.certificate.refined == alone.certificate.refined == 3
    # the engine's optimum written as the endpoint writes its answer
    mine = orjson.loads(Render(linkage_optimise_out, model_extra=(body.model_dump(mode="json"),))(alone)[0])
    theirs = spread.model_dump(mode="json")
    # every member (sample then each start's refinement, in order), the optimum's numbers, values and design
    assert [m["x"] for m in theirs["members"]] == [m["x"] for m in mine["members"]]
    _same(theirs, mine)
    assert spread.values["machine_mass"] == pytest.approx(alone.values[3], rel=1e-12)
