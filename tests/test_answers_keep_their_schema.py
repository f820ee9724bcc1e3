"""Inputs that used to answer 500 or a number-less 200, bodies the JSON reader cannot read, the Allow header over
every route of a path, and the OpenAPI document stating what the service enforces: its limits (from the
settings), the tags of its unions, the rules that tie fields together; a problem body keeps the Problem schema."""

from __future__ import annotations

import copy
import math
import re
from typing import Any

import jsonschema_rs
import pytest

import synth
from api.app import create_app
from api.media import Render, json_bytes
from api.problems import problem_response
from api.settings import Settings
from hostile import checker
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.analysis import AnalysisIn
from mechsynth_client.schemas.balancing import CorrectionOut, RotorOut, SliderCrankBalanceIn

ROTOR = {"masses": [{"mass_kg": 1.0, "radius_m": 0.1, "angle_deg": 20, "axial_position_m": 0.2},
                    {"mass_kg": 2.0, "radius_m": 0.05, "angle_deg": 115, "axial_position_m": 0.5}],
         "mode": "dynamic", "radii_m": [0.1, 0.1]}


def _example(model: Any, i: int = 0) -> dict[str, Any]:
    return copy.deepcopy(model.model_config["json_schema_extra"]["examples"][i])


def test_a_vanishing_pressure_angle_is_refused_naming_it(client: SynthClient) -> None:
    r = client.http.post("/v1/gears/teeth", json={"total_ratio": 17.3, "stages": 2, "pressure_angle_deg": 1e-200})
    assert r.status_code == 422 and checker(client.http)(r, "/v1/gears/teeth")["field"] == "pressure_angle_deg"
    with pytest.raises(synth.InvalidInput) as err:   # the engine guards its own callers too
        synth.ToothRules(pressure_angle=1e-200)
    assert err.value.field == "pressure_angle_deg"


@pytest.mark.parametrize("links", [{"crank": {}}, None])
@pytest.mark.parametrize("fmt", ["png", "svg"])
def test_a_massless_slider_crank_is_drawn(client: SynthClient, links: Any, fmt: str) -> None:
    body = _example(SliderCrankBalanceIn)
    if links is None:
        body["mechanism"].pop("links", None)
    else:
        body["mechanism"]["links"] = links
    r = client.http.post(f"/v1/balancing/slider-crank?format={fmt}", json=body)
    assert r.status_code == 200 and r.headers["content-type"].startswith(f"image/{fmt}"), r.text[:300]


def test_a_trace_point_named_like_mathtext_is_drawn_as_written(client: SynthClient) -> None:
    body = _example(AnalysisIn)
    body["trace_points"] = [{"name": "$\\foo{$", "link": "coupler", "position_m": [0.1, 0.05]}]
    r = client.http.post("/v1/analysis?format=svg", json=body)
    assert r.status_code == 200, r.text[:300]
    # SVG draws a text as one glyph per character after a comment holding the text: seven, the two dollar signs
    # alike and the two o's alike (a mathtext parse would have dropped the dollars or failed on \foo)
    drawn = r.content.decode().split("<!-- $\\foo{$ -->", 1)[1].split('<g id="', 1)[0]
    glyphs = re.findall(r'xlink:href="#([^"]+)"', drawn)
    assert len(glyphs) == 7 and glyphs[0] == glyphs[6] and glyphs[3] == glyphs[4], glyphs


@pytest.mark.parametrize(("planes", "ok"), [([1e-310, 2e-310], False), ([0.0, 1e-9], False),
                                            ([0.0, 0.004], False), ([0.0, 0.006], True), ([0.0, 1.0], True)])
def test_rotor_planes_closer_than_a_hundredth_of_the_rotor_are_refused(client: SynthClient, planes: list[float],
                                                                       ok: bool) -> None:
    # the rotor spans 0.5 m over its masses (0.2, 0.5) and the planes (0): the least gap is 0.005 m
    r = client.http.post("/v1/balancing/rotor", json={**ROTOR, "planes_m": planes})
    answer = checker(client.http)(r, "/v1/balancing/rotor")
    if ok:
        assert r.status_code == 200 and all(math.isfinite(c["mass_kg"]) for c in answer["corrections"])
        # independent check: the corrections cancel the static unbalance (sum m r e^{i theta}) of the masses
        total = sum(m["mass_kg"] * m["radius_m"] * complex(math.cos(math.radians(m["angle_deg"])),
                                                            math.sin(math.radians(m["angle_deg"])))
                    for m in ROTOR["masses"] + answer["corrections"])  # type: ignore[operator]
        assert abs(total) <= 1e-9 * answer["unbalance_before_kgm"] * max(1.0, 0.5 / planes[1])
    else:
        assert r.status_code == 422 and answer["field"] == "planes_m", answer


def test_an_answer_holding_a_non_finite_number_is_a_problem_naming_its_path() -> None:
    out = RotorOut(corrections=[CorrectionOut(mass_kg=1.0, radius_m=0.1, angle_deg=0.0, axial_position_m=0.0),
                                CorrectionOut(mass_kg=math.nan, radius_m=0.1, angle_deg=0.0, axial_position_m=1.0)],
                   unbalance_before_kgm=1.0, moment_unbalance_before_kgm2=1.0, residual_unbalance_kgm=math.inf,
                   residual_moment_unbalance_kgm2=0.0)
    with pytest.raises(synth.InvalidInput) as err:
        json_bytes(out)
    assert err.value.field == "corrections[1].mass_kg"
    # the worker's render of every answer (JSON and npz alike) goes through the same guard
    for fmt in ("json", "npz"):
        with pytest.raises(synth.InvalidInput) as err:
            Render(lambda r: r, fmt=fmt)(out)
        assert err.value.field == "corrections[1].mass_kg"
    response = problem_response(err.value)
    assert response.status_code == 422 and b'"field":"corrections[1].mass_kg"' in response.body


@pytest.mark.parametrize(("content", "ctype", "status", "slug"), [
    (b"[" * 100_000 + b"]" * 100_000, "application/json", 400, "json-too-deep"),
    (b'{"speed_rpm": "\xff\xfe"}', "application/json", 400, "body-not-utf8"),
    (b'{"speed_rpm": 60}', "text/plain", 415, "unsupported-media-type"),
    (b'{"speed_rpm": 60}', "application/x-www-form-urlencoded", 415, "unsupported-media-type"),
])
def test_an_unreadable_body_is_answered_with_the_reason(client: SynthClient, content: bytes, ctype: str,
                                                        status: int, slug: str) -> None:
    r = client.http.post("/v1/analysis", content=content, headers={"content-type": ctype})
    problem = checker(client.http)(r, "/v1/analysis")
    assert r.status_code == status and problem["type"] == f"/problems/{slug}", problem
    assert "application/json" in problem["detail"]


@pytest.mark.parametrize(("path", "allow"), [("/v1/studies", "GET, POST"),
                                             ("/v1/studies/0123456789abcdef", "GET, DELETE"),
                                             ("/v1/analysis", "POST")])
def test_allow_lists_every_method_of_the_path(client: SynthClient, path: str, allow: str) -> None:
    r = client.http.options(path)
    assert r.status_code == 405 and r.headers["allow"] == allow


def test_the_document_states_the_limits_of_this_service() -> None:
    settings = Settings(max_samples=5000, max_stages=4, max_study_variants=777, max_body_bytes=123_456)
    doc = create_app(settings).openapi()
    schemas = doc["components"]["schemas"]
    assert schemas["AnalysisIn"]["properties"]["samples"]["maximum"] == 5000
    angles = schemas["AnalysisIn"]["properties"]["crank_angle_deg"]["anyOf"]
    assert [a.get("maxItems") for a in angles if a.get("type") == "array"] == [5000]
    assert schemas["FlywheelTablesIn"]["properties"]["crank_angle_deg"]["maxItems"] == 5000
    for name in ("TeethIn", "SplitIn", "DriveIn", "MachineDriveIn"):
        stages = schemas[name]["properties"]["stages"]["anyOf"]
        assert sorted(s.get("maximum", s.get("maxItems")) for s in stages) == [4, 4], name
    study = schemas["StudyIn"]["properties"]["samples"]["anyOf"]
    assert [s["maximum"] for s in study if s.get("type") == "integer"] == [777]
    assert "123456 bytes" in doc["paths"]["/v1/analysis"]["post"]["responses"]["413"]["description"]


def test_beyond_a_stated_limit_is_413(client: SynthClient) -> None:
    doc = client.http.get("/openapi.json").json()
    limit = doc["components"]["schemas"]["AnalysisIn"]["properties"]["samples"]["maximum"]
    body = {**_example(AnalysisIn), "samples": limit + 1}
    r = client.http.post("/v1/analysis", json=body)
    assert r.status_code == 413 and checker(client.http)(r, "/v1/analysis")["limit"] == limit
    limit = doc["components"]["schemas"]["TeethIn"]["properties"]["stages"]["anyOf"][0]["maximum"]
    r = client.http.post("/v1/gears/teeth", json={"total_ratio": 17.3, "stages": limit + 1})
    assert r.status_code == 413 and checker(client.http)(r, "/v1/gears/teeth")["limit"] == limit


def test_union_members_require_their_tag_as_the_service_does(client: SynthClient) -> None:
    doc = client.http.get("/openapi.json").json()
    for name in ("FourBarIn", "SliderCrankIn", "SlottedLeverIn", "PlanarLinkageIn"):
        assert "type" in doc["components"]["schemas"][name]["required"], name
    body = _example(AnalysisIn)
    body["mechanism"].pop("type")
    assert client.http.post("/v1/analysis", json=body).status_code == 422


@pytest.mark.parametrize(("schema", "body", "valid"), [
    ("RatingIn", {"pinion_torque_Nm": 1.0, "load_spectrum": {"torque_Nm": [1.0]}}, False),
    ("DriveIn", {"output_speed_rpm": 60, "output_speed_rad_s": 6.28}, False),
    ("SplitIn", {"total_ratio": 10, "motor_speed_rpm": 1500}, False),
    ("SplitIn", {"motor_speed_rpm": 1500, "output_speed_rad_s": 10}, True),
    ("FlywheelIn", {"delta": 0.1, "machine_type": "piston_compressors"}, False),
    ("StudyConstraintIn", {"metric": "a"}, False),
])
def test_rules_that_tie_fields_together_are_in_the_schema(client: SynthClient, schema: str, body: dict[str, Any],
                                                          valid: bool) -> None:
    doc = client.http.get("/openapi.json").json()
    node = doc["components"]["schemas"][schema]
    # the rules alone (the fields' own requirements are the other part of the schema)
    rules = {k: v for k, v in node.items() if k in ("allOf", "oneOf", "anyOf", "not")}
    assert rules, schema
    assert jsonschema_rs.Draft202012Validator(rules).is_valid(body) == valid


def test_a_whole_number_written_with_a_fraction_is_an_integer(client: SynthClient) -> None:
    # JSON Schema's integer is any number without a fractional part; strict typing still refuses text and booleans
    ok = client.http.post("/v1/gears/teeth", json={"total_ratio": 17.3, "stages": 2.0, "max_teeth": 80.0})
    assert ok.status_code == 200 and len(ok.json()["stages"]) == 2
    for bad in (2.5, "2", True):
        r = client.http.post("/v1/gears/teeth", json={"total_ratio": 17.3, "stages": bad})
        assert r.status_code == 422 and checker(client.http)(r, "/v1/gears/teeth")["field"] == "stages"


def test_a_gear_stage_without_teeth_is_named_by_its_index_and_keeps_the_problem_schema(
        client: SynthClient) -> None:
    r = client.http.post("/v1/gears/teeth", json={"total_ratio": 3, "stages": [{"type": "spur", "ratio_min": 9.5,
                                                                                 "ratio_max": 9.9}],
                                                  "max_teeth": 20})
    problem = checker(client.http)(r, "/v1/gears/teeth")
    assert r.status_code == 422 and problem["stage_index"] == 0 and "stage" not in problem, problem


def test_a_non_finite_number_in_a_list_of_numbers_is_named_by_its_place() -> None:
    """Lists of Python numbers (a model's own tables) are checked in one array pass; a null in them is no
    number to refuse, and a NaN or an infinity is named by its place, in a row too."""
    from api.media import finite_answer

    curve = [0.5 * k for k in range(5000)]
    assert finite_answer({"curve": curve, "gaps": [1.0, None, 2.0]}) is not None
    for bad, path in ((math.nan, "curve[4321]"), (math.inf, "curve[4321]")):
        with pytest.raises(synth.InvalidInput) as err:
            finite_answer({"curve": curve[:4321] + [bad] + curve[4322:]})
        assert err.value.field == path
    with pytest.raises(synth.InvalidInput) as err:
        finite_answer({"rows": [[0.0, 1.0], [2.0, -math.inf]], "ok": [1, 2]})
    assert err.value.field == "rows[1][1]"


def _numbers_in(value: Any) -> int:
    """Numbers in a parsed JSON document (booleans are not numbers)."""
    if isinstance(value, dict):
        return sum(_numbers_in(v) for v in value.values())
    if isinstance(value, list):
        return sum(_numbers_in(v) for v in value)
    return int(isinstance(value, (int, float)) and not isinstance(value, bool))


def test_the_answer_size_bound_counts_every_number_the_answer_writes(client: SynthClient) -> None:
    # The bound on an answer's size counts its numbers from the model, before writing it; the independent count
    # is the numbers in the JSON it writes (single figures, text and flags, nulls, nested models, rows of points).
    import json

    from api.media import count_numbers
    from mechsynth_client.schemas.optimise import CRANK_ROCKER_OPTIMISE_EXAMPLE, QUICK_SCAN, MachineOptimiseIn

    models = [RotorOut(corrections=[CorrectionOut(mass_kg=1.0, radius_m=0.1, angle_deg=0.0, axial_position_m=0.0)],
                       unbalance_before_kgm=1.0, moment_unbalance_before_kgm2=2.0, residual_unbalance_kgm=0.0,
                       residual_moment_unbalance_kgm2=0.0),
              client.analysis(AnalysisIn.model_validate(_example(AnalysisIn))),
              client.optimise_machine(MachineOptimiseIn.model_validate({**CRANK_ROCKER_OPTIMISE_EXAMPLE,
                                                                        **QUICK_SCAN}))]
    for model in models:
        assert count_numbers(model) == _numbers_in(json.loads(json_bytes(model))), type(model).__name__
