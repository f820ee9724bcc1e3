"""/v1/balancing/* in-process: examples, counterweights sent back to /v1/analysis, figures, problem responses."""

from __future__ import annotations

import json

import pytest

from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.analysis import AnalysisIn
from mechsynth_client.schemas.balancing import (
    BalanceIn,
    FullBalanceIn,
    OptimalBalanceIn,
    RotorIn,
    SliderCrankBalanceIn,
)
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE, SIX_BAR_PRESS_EXAMPLE

MODELS = [BalanceIn, FullBalanceIn, OptimalBalanceIn, RotorIn, SliderCrankBalanceIn]
PATHS = ["static", "full", "optimal", "rotor", "slider-crank"]


@pytest.mark.parametrize(("model", "path"), list(zip(MODELS, PATHS)))
def test_documented_examples_answer(client: SynthClient, model: type, path: str) -> None:
    for example in model.model_config["json_schema_extra"]["examples"]:
        r = client.http.post(f"/v1/balancing/{path}", json=example)
        assert r.status_code == 200, r.text


def test_static_counterweights_send_back_to_analysis(client: SynthClient) -> None:
    # The answer's counterweights, re-sent to /v1/analysis as they are, give the answer's summary_after.
    body = BalanceIn.model_validate(BalanceIn.model_config["json_schema_extra"]["examples"][0])
    out = client.balance_static(body)
    assert out.checks.residual_shaking_force_rel < 1e-9
    check = client.analysis(AnalysisIn.model_validate(
        {"mechanism": body.mechanism.model_dump(), "speed_rpm": body.speed_rpm,
         "counterweights": [c.model_dump() for c in out.counterweights]}))
    assert check.summary.max_shaking_force_N == pytest.approx(out.summary_after.max_shaking_force_N, abs=1e-9)
    assert check.summary.max_shaking_force_N < 1e-9 * out.summary_before.max_shaking_force_N
    assert {p.link for p in out.placements} == {"crank", "rocker"}


def test_full_reports_rotors_and_coupler(client: SynthClient) -> None:
    out = client.balance_full(FullBalanceIn.model_validate(
        FullBalanceIn.model_config["json_schema_extra"]["examples"][0]))
    assert out.checks.residual_shaking_moment_rel < 1e-7
    coupler = FOURBAR_EXAMPLE["links"]["coupler"]
    x, length = coupler["com_m"][0], FOURBAR_EXAMPLE["coupler_length_m"]
    assert out.coupler_inertia_kgm2 == pytest.approx(coupler["mass_kg"] * x * (length - x), rel=1e-6)
    assert out.counter_rotors is not None and {r.link for r in out.counter_rotors} == {"crank", "rocker"}


def test_optimal_returns_the_tradeoff_curve(client: SynthClient) -> None:
    example = OptimalBalanceIn.model_config["json_schema_extra"]["examples"][0]
    out = client.balance_optimal(OptimalBalanceIn.model_validate(example))
    assert len(out.tradeoff) == len(example["sweep"])
    assert out.total_added_mass_kg <= example["mass_budget_kg"] * (1 + 1e-7)


def test_png(client: SynthClient) -> None:
    body = BalanceIn.model_validate(BalanceIn.model_config["json_schema_extra"]["examples"][0])
    assert client.balance_png("static", body)[:4] == b"\x89PNG"


@pytest.mark.parametrize(
    ("path", "patch", "slug", "key", "value"),
    [
        ("static", {"mass_budget_kg": 0.1}, "infeasible", "constraint", "mass_budget_kg"),
        ("static", {"counterweight_links": ["crank"]}, "infeasible", "constraint", "counterweight_links"),
        ("static", {"counterweight_links": ["flywheel"]}, "invalid-input", "field", "counterweight_links"),
        ("static", {"max_radius_m": {"crank": -1}}, "invalid-input", "field", "max_radius_m.crank"),
        ("static", {"objective": "min_inertia"}, "invalid-input", "field", "mass_budget_kg"),
        ("full", {"mechanism": {**FOURBAR_EXAMPLE, "links": {**FOURBAR_EXAMPLE["links"],
                  "coupler": {"mass_kg": 2.0, "com_m": [0.175, 0.03], "inertia_kgm2": 0.02}}}},
         "infeasible", "constraint", "links.coupler.com_m"),
        ("optimal", {"weights": {"shaking_force": 0}}, "invalid-input", "field", "weights"),
    ],
)
def test_problems_name_the_limit(client: SynthClient, path: str, patch: dict, slug: str, key: str,
                                 value: str) -> None:
    body = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, **patch}
    r = client.http.post(f"/v1/balancing/{path}", json=body)
    assert r.status_code == 422, r.text
    problem = r.json()
    assert problem["type"] == f"/problems/{slug}" and problem[key] == value


def test_slider_crank_endpoint_rejects_a_fourbar(client: SynthClient) -> None:
    r = client.http.post("/v1/balancing/slider-crank", json={"mechanism": FOURBAR_EXAMPLE})
    assert r.status_code == 422 and r.json()["field"] == "mechanism.type"


def test_optimal_balancing_of_a_linkage_does_not_depend_on_its_crank_s_name(client: SynthClient) -> None:
    # Identity: renaming a link renames the answer and changes no number. The six-bar press's crank called
    # "input" used to reach a lookup by the literal name "crank".
    renamed = json.loads(json.dumps(SIX_BAR_PRESS_EXAMPLE).replace('"crank"', '"input"')
                         .replace('"input": "input"', '"crank": "input"'))
    by_name: dict[str, dict[str, float]] = {}
    for mechanism, crank in ((SIX_BAR_PRESS_EXAMPLE, "crank"), (renamed, "input")):
        out = client.balance_optimal(OptimalBalanceIn.model_validate({"mechanism": mechanism, "speed_rpm": 100}))
        by_name[crank] = {("crank" if c.link == crank else c.link): c.mass_kg for c in out.counterweights}
    assert by_name["crank"].keys() == by_name["input"].keys()
    for link, mass in by_name["crank"].items():
        assert by_name["input"][link] == pytest.approx(mass, rel=1e-9, abs=1e-12)
