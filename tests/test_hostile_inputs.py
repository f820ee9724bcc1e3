"""Hostile text in every name that reaches a figure (PNG, SVG), the design record (PDF), the curves (CSV) or the
drawing (DXF), and extreme floats in every number of the documented examples: each answer is a 2xx keeping its
documented schema with finite numbers, or a problem keeping the Problem schema; a name within its limit works, a
name beyond it is a 422 naming the field. In-process, serial executor, few examples per property."""

from __future__ import annotations

import copy
import io
import json
from typing import Any

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import synth
from hostile import EXTREME_FLOATS, HOSTILE_TEXT, checker
from api.translate.machine import machine_from
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.analysis import AnalysisIn
from mechsynth_client.schemas.common import SIX_BAR_PRESS_EXAMPLE
from mechsynth_client.schemas.machine import MachineIn
from pypdf import PdfReader
from synth.machine.record import DesignRecord
from synth.machine.report import design_report_pdf
from test_api_robustness import ENDPOINTS

NAME_LIMIT = 40   # a trace point's name (AnalysisIn); link and point names of a general linkage allow 64
FIXTURE = [HealthCheck.function_scoped_fixture, HealthCheck.too_slow]
ANALYSIS = AnalysisIn.model_config["json_schema_extra"]["examples"][0]  # type: ignore[index]


def names(limit: int) -> st.SearchStrategy[str]:
    """Hostile text within ``limit`` characters: the known troublemakers, alone or run together, and any text."""
    known = st.sampled_from(HOSTILE_TEXT)
    joined = st.lists(known, min_size=2, max_size=4).map("".join)
    return st.one_of(known, joined, st.text(min_size=1, max_size=limit)).map(lambda s: s[:limit]).filter(bool)


def _with_trace(name: str) -> dict[str, Any]:
    body = copy.deepcopy(ANALYSIS)
    body["trace_points"] = [{"name": name, "link": "coupler", "position_m": [0.1, 0.05]}]
    body["samples"] = 36
    return body


@settings(max_examples=30, deadline=None, suppress_health_check=FIXTURE)
@given(name=names(NAME_LIMIT), fmt=st.sampled_from(["json", "png", "svg", "pdf", "csv", "dxf", "npz"]))
def test_a_hostile_trace_point_name_works_in_every_format(client: SynthClient, name: str, fmt: str) -> None:
    assume(name not in {"O", "A", "B", "Q"} and not name.startswith("S_"))  # joints and centres of mass
    r = client.http.post(f"/v1/analysis?format={fmt}", json=_with_trace(name))
    answer = checker(client.http)(r, "/v1/analysis")
    assert r.status_code == 200, r.text[:300]
    if fmt == "json":
        assert name in answer["points"]   # the name comes back as it was sent
    if fmt == "csv":
        assert answer.decode("utf-8")     # the curves are UTF-8 text whatever the names


def _renamed(node: Any, old: str, new: str) -> Any:
    """``node`` with every string (value or key) equal to ``old`` replaced by ``new``."""
    if isinstance(node, dict):
        return {(new if k == old else k): _renamed(v, old, new) for k, v in node.items()}
    if isinstance(node, list):
        return [_renamed(v, old, new) for v in node]
    return new if node == old else node


@settings(max_examples=12, deadline=None, suppress_health_check=FIXTURE)
@given(link=names(64), point=names(64), fmt=st.sampled_from(["png", "svg", "csv", "dxf"]))
def test_hostile_link_and_point_names_of_a_general_linkage_work(client: SynthClient, link: str, point: str,
                                                                fmt: str) -> None:
    taken = {"O", "Q", "G", "A", "B", "C", "D", "crank", "coupler", "rocker", "rod", "ram", "frame", "guide"}
    assume(link != point and link not in taken and point not in taken)
    assume(not link.startswith("S_") and not point.startswith("S_"))
    mechanism = _renamed(_renamed(SIX_BAR_PRESS_EXAMPLE, "rod", link), "C", point)
    r = client.http.post(f"/v1/analysis?format={fmt}", json={"mechanism": mechanism, "speed_rpm": 60,
                                                            "samples": 24})
    checker(client.http)(r, "/v1/analysis")
    assert r.status_code == 200, r.text[:300]


@pytest.fixture(scope="module")
def press_design() -> tuple[synth.MachineDesign, dict[str, Any]]:
    """The manual's press, designed once: the record's pages are what a name changes."""
    request = {**MachineIn.model_config["json_schema_extra"]["examples"][0], "samples": 72}  # type: ignore[index]
    return synth.design_machine(machine_from(MachineIn.model_validate(request), 6)), request


@settings(max_examples=4, deadline=None, suppress_health_check=FIXTURE)
@given(name=names(200))
def test_a_hostile_machine_name_titles_its_design_record(
        press_design: tuple[synth.MachineDesign, dict[str, Any]], name: str) -> None:
    design, request = press_design
    record = DesignRecord.of({**request, "name": name}, name=name, version="test")
    pdf = PdfReader(io.BytesIO(design_report_pdf(design, record=record)))
    assert pdf.metadata is not None and pdf.metadata.title == f"Machine design record: {name}"
    assert len(pdf.pages) >= 2


@pytest.mark.parametrize(("path", "body", "fields"), [
    ("/v1/analysis", _with_trace("x" * 10_000), {"trace_points[0].name"}),
    # the rod's name stands in its link and in the two joints on it: any of them is named
    ("/v1/analysis", {"mechanism": _renamed(SIX_BAR_PRESS_EXAMPLE, "rod", "$" * 10_000), "speed_rpm": 60},
     {"mechanism.links[3].name", "mechanism.joints[4].links[1]", "mechanism.joints[5].links[0]"}),
    ("/v1/machines/design", {**MachineIn.model_config["json_schema_extra"]["examples"][0],  # type: ignore[index]
                             "name": "\u202e" * 10_000}, {"name"}),
])
def test_a_name_beyond_its_limit_is_refused_naming_it(client: SynthClient, path: str, body: dict[str, Any],
                                                      fields: set[str]) -> None:
    r = client.http.post(path, json=body)
    problem = checker(client.http)(r, path)
    assert r.status_code == 422 and problem["field"] in fields, problem
    assert {e["field"] for e in problem["errors"]} <= fields


# The endpoints whose documented examples answer within a second or so; the machine design, its optimisation and
# path synthesis take seconds per request and have their own tests.
QUICK = {path: model for path, model in ENDPOINTS.items() if path not in {"/v1/machines/design"}}
def _numbers(node: Any, at: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    """Paths of the numbers (not booleans) in a JSON document."""
    if isinstance(node, dict):
        return [p for k, v in node.items() for p in _numbers(v, at + (k,))]
    if isinstance(node, list):
        return [p for i, v in enumerate(node) for p in _numbers(v, at + (i,))]
    return [at] if isinstance(node, (int, float)) and not isinstance(node, bool) else []


CASES = [(path, example) for path, model in QUICK.items()
         for example in model.model_config["json_schema_extra"]["examples"]  # type: ignore[index]
         if _numbers(example)]


@st.composite
def extreme(draw: st.DrawFn) -> tuple[str, Any]:
    """A documented example with one to three of its numbers set to extreme floats."""
    path, example = draw(st.sampled_from(CASES))
    body = copy.deepcopy(example)
    leaves = _numbers(body)
    for _ in range(draw(st.integers(1, 3))):
        where = draw(st.sampled_from(leaves))
        target = body
        for key in where[:-1]:
            target = target[key]
        target[where[-1]] = draw(st.sampled_from(EXTREME_FLOATS))
    return path, body


@settings(max_examples=60, deadline=None, suppress_health_check=FIXTURE)
@given(case=extreme())
def test_extreme_floats_answer_finite_numbers_or_a_problem(client: SynthClient, case: tuple[str, Any]) -> None:
    path, body = case
    r = client.http.post(path, content=json.dumps(body), headers={"content-type": "application/json"})
    checker(client.http)(r, path)


#: Positive numbers a careless caller sends where a size, a speed or a ratio goes: subnormals (their squares and
#: products underflow to zero) and near-zero normals (a speed band or a step lost in rounding).
TINY_POSITIVES = [5e-324, 1e-310, 2.2250738585072014e-308, 1e-200, 1e-20, 1e-16]


def _documented_examples(slow: tuple[str, ...] = ("/v1/machines/", "/v1/synthesis/path")) -> list[tuple[str, Any]]:
    """Every POST operation's documented request examples, from the service's own OpenAPI document, but those of
    the operations that take seconds per request (machine design and optimisation, path synthesis) and of the
    library and studies (their bodies hold requests, which the operations' own examples cover)."""
    from api.app import app

    doc = app.openapi()
    slow = (*slow, "/v1/studies", "/v1/library", "/v1/auth", "/v1/users")
    out: list[tuple[str, Any]] = []
    for path, item in doc["paths"].items():
        content = item.get("post", {}).get("requestBody", {}).get("content", {}).get("application/json", {})
        if not content or "{" in path or path.startswith(slow):
            continue
        examples = [e["value"] for e in content.get("examples", {}).values()]
        if not examples and "$ref" in content.get("schema", {}):
            examples = doc["components"]["schemas"][content["schema"]["$ref"].split("/")[-1]].get("examples", [])
        out += [(path, e) for e in examples if _numbers(e)]
    return out


DOCUMENTED = _documented_examples()
EVERY_EXAMPLE = _documented_examples(slow=())


@st.composite
def tiny(draw: st.DrawFn) -> tuple[str, Any]:
    """A documented example with one of its positive numbers set to a tiny positive."""
    path, example = draw(st.sampled_from(DOCUMENTED))
    body = copy.deepcopy(example)
    leaves = [p for p in _numbers(body) if _at(body, p) > 0]
    assume(leaves)
    where = draw(st.sampled_from(leaves))
    target = body
    for key in where[:-1]:
        target = target[key]
    target[where[-1]] = draw(st.sampled_from(TINY_POSITIVES))
    return path, body


def _at(node: Any, where: tuple[Any, ...]) -> Any:
    for key in where:
        node = node[key]
    return node


# numpy's overflow and invalid-value warnings are what the service itself meets (it answers on, and a NaN becomes
# a refusal): here they are not turned into errors, so the answer the service gives is what is checked
@pytest.mark.filterwarnings("ignore::RuntimeWarning")
@settings(max_examples=60, deadline=None, suppress_health_check=FIXTURE)
@given(case=tiny())
def test_tiny_positive_numbers_answer_finite_numbers_or_a_problem(client: SynthClient, case: tuple[str, Any]) -> None:
    path, body = case
    r = client.http.post(path, content=json.dumps(body), headers={"content-type": "application/json"})
    checker(client.http)(r, path)


def _example(path: str, where: str | None = None) -> dict[str, Any]:
    """The first documented example of ``path`` (the first holding the dotted path ``where``)."""
    for p, example in EVERY_EXAMPLE:
        if p == path:
            try:
                _ = _at(example, tuple(int(k) if k.isdigit() else k for k in where.split("."))) if where else None
            except (KeyError, IndexError, TypeError):
                continue
            return copy.deepcopy(example)
    raise LookupError(path)


def _set(body: dict[str, Any], where: str, value: Any) -> dict[str, Any]:
    keys = [int(k) if k.isdigit() else k for k in where.split(".")]
    _at(body, tuple(keys[:-1]))[keys[-1]] = value
    return body


FOURBAR = {"type": "fourbar", "coupler_length_m": 0.25, "crank_length_m": 0.1, "ground_length_m": 0.3,
           "rocker_length_m": 0.25}


# Each case once answered 500 (a division by zero or a NaN deep in the engine); each now answers 422 naming the
# field the tiny number was sent in.
@pytest.mark.parametrize(("path", "where", "value", "field"), [
    ("/v1/flywheel", "delta", 1e-20, "delta"),
    ("/v1/flywheel", "delta", 1e-16, "delta"),
    ("/v1/balancing/engine", "speed_rpm", 1e-310, "speed_rpm"),
    ("/v1/flywheel", "tables.crank_angle_deg.1", 1e-310, "tables.crank_angle_deg[1]"),
    ("/v1/flywheel", "elastic_drive.stiffness_Nm_rad", 5e-324, "elastic_drive.stiffness_Nm_rad"),
    ("/v1/flywheel", "motor.rotor_inertia_kgm2", 5e-324, "motor.rotor_inertia_kgm2"),
    ("/v1/cams/analysis", "follower.arm_length_m", 5e-324, "follower.arm_length_m"),
    ("/v1/machines/isolation/design", "frame.mass_kg", 5e-324, "frame.mass_kg"),
    ("/v1/machines/elastic-drive", "elements.1.speed_ratio", 5e-324, "elements.1.speed_ratio"),
])
def test_a_tiny_number_that_broke_the_engine_is_refused_naming_its_field(
        client: SynthClient, path: str, where: str, value: float, field: str) -> None:
    body = _set(_example(path, where), where, value)
    if path == "/v1/flywheel" and where == "delta":
        body = {"delta": value, "mean_speed_rpm": 300, "mechanism": FOURBAR}
    r = client.http.post(path, json=body)
    problem = checker(client.http)(r, path)
    assert r.status_code == 422 and field.split("[")[0].split(".")[-1] in problem["field"], problem


@pytest.mark.parametrize("query", ["since=0001-01-01T00:00:00", "until=0001-01-01T00:00:00",
                                   "since=9999-12-31T23:59:59-14:00", "until=1969-12-31T23:59:59Z",
                                   "since=0001-01-01T00:00:00%2B14:00"])
def test_a_date_at_the_calendar_s_edge_is_refused_naming_the_query(client: SynthClient, query: str) -> None:
    r = client.http.get(f"/v1/library/revisions?{query}")
    assert r.status_code == 422 and r.json()["field"] == query.split("=")[0], r.text


@pytest.mark.parametrize("query", ["since=1970-01-01T00:00:00Z", "until=9999-12-31T23:59:59"])
def test_a_date_within_the_library_s_times_is_searched(client: SynthClient, query: str) -> None:
    assert client.http.get(f"/v1/library/revisions?{query}").status_code == 200
