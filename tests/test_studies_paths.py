"""A study's metrics are checked against its endpoint's response model when it is created: a misspelt path is a
422 naming the field and the names valid where it went wrong, and every path a real answer has is accepted."""

from __future__ import annotations

import json
import re
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient

from api.app import create_app
from api.execution.plans import Limits
from mechsynth_client.schemas.common import SummaryOut
from mechsynth_client.schemas.studies import STUDY_EXAMPLE
from api.settings import Settings
from api.studies.paths import LIST_INDEX, MetricPathError, check_metric, check_metrics, response_models
from api.studies.tasks import ENDPOINTS, run_endpoint
from test_studies_run import SPEC

STUDIES_PAGE = Path(__file__).resolve().parents[1] / "docs" / "studies.md"
LIMITS = Limits(max_samples=20_000, max_stages=6, solver_time_limit_s=20.0)


@pytest.fixture()
def http(tmp_path: Path) -> Iterator[TestClient]:
    with TestClient(create_app(Settings(executor="serial", studies_db=str(tmp_path / "s.sqlite")))) as client:
        yield client


def test_a_misspelt_metric_is_refused_with_the_names_valid_there_and_nothing_is_stored(http: TestClient) -> None:
    metrics = [*SPEC["metrics"][:2], "summary_after.rms_shaking_forc_N"]
    answer = http.post("/v1/studies", json={**SPEC, "metrics": metrics, "objectives": {}, "constraints": []})
    assert answer.status_code == 422 and answer.headers["content-type"] == "application/problem+json"
    problem = answer.json()
    assert problem["field"] == "metrics[2]" and problem["segment"] == "rms_shaking_forc_N"
    # summary_after is a SummaryOut in /v1/balancing/static's answer: its fields are the names valid there.
    assert problem["valid"] == sorted(SummaryOut.model_fields)
    assert "rms_shaking_force_N" in problem["detail"] and "rms_shaking_forc_N" in problem["detail"]
    assert http.get("/v1/studies").json() == []


@pytest.mark.parametrize("change,field,segment", [
    ({"metrics": ["total_added_mass"]}, "metrics[0]", "total_added_mass"),
    ({"metrics": ["summary_after"]}, "metrics[0]", None),                 # an object, not a number
    ({"metrics": ["placements.first.radius_m"]}, "metrics[0]", "first"),  # a list takes an index
    ({"metrics": ["mode"]}, "metrics[0]", None),                          # text
])
def test_bad_metric_paths_name_the_field_and_the_part(http: TestClient, change: dict[str, Any], field: str,
                                                      segment: str | None) -> None:
    answer = http.post("/v1/studies", json={**SPEC, "objectives": {}, "constraints": [], **change})
    assert answer.status_code == 422
    assert (answer.json()["field"], answer.json()["segment"]) == (field, segment)


@pytest.mark.parametrize("change,field", [
    ({"objectives": {"nothing": "min"}}, "objectives.nothing"),
    ({"constraints": [SPEC["constraints"][0], {"metric": "nothing", "max": 1.0}]}, "constraints[1].metric"),
])
def test_objectives_and_constraints_name_one_of_the_metrics(http: TestClient, change: dict[str, Any],
                                                            field: str) -> None:
    answer = http.post("/v1/studies", json={**SPEC, **change})
    assert answer.status_code == 422 and answer.json()["field"] == field
    assert http.get("/v1/studies").json() == []


def test_a_deep_path_through_a_dict_and_lists_is_accepted_and_read(http: TestClient) -> None:
    # joint_reactions_N maps joint names to [x, y] reactions at each crank angle; A is the crank pin.
    spec = {"endpoint": "/v1/analysis", "base": {"mechanism": SPEC["base"]["mechanism"], "samples": 36},
            "parameters": [{"path": "speed_rpm", "values": [120.0, 300.0]}],
            "metrics": ["joint_reactions_N.A.3.0", "links.coupler.angular_velocity_rad_s.9",
                        "summary.max_bearing_force_N"]}
    created = http.post("/v1/studies", json=spec)
    assert created.status_code == 202, created.json()
    study_id = created.json()["id"]
    deadline = time.monotonic() + 60
    while http.get(f"/v1/studies/{study_id}").json()["state"] == "running" and time.monotonic() < deadline:
        time.sleep(0.05)
    rows = http.get(f"/v1/studies/{study_id}/results").json()["variants"]
    for row in rows:
        # The values the endpoint itself answers for the same body, read by hand.
        body = {**spec["base"], "speed_rpm": row["parameters"]["speed_rpm"]}
        direct = http.post("/v1/analysis", params={"precision": "full"}, json=body).json()
        assert row["metrics"] == {
            "joint_reactions_N.A.3.0": direct["joint_reactions_N"]["A"][3][0],
            "links.coupler.angular_velocity_rad_s.9": direct["links"]["coupler"]["angular_velocity_rad_s"][9],
            "summary.max_bearing_force_N": direct["summary"]["max_bearing_force_N"],
        }


@pytest.mark.parametrize("endpoint,path", [
    ("/v1/balancing/optimal", "tradeoff.0.summary_after.rms_shaking_force_N"),  # a list of models
    ("/v1/balancing/full", "counter_rotors.1.inertia_kgm2"),                    # an Optional list
    ("/v1/machines/design", "balancing.summary_after.rms_shaking_force_N"),     # an Optional model
    ("/v1/analysis", "transmission_angle_deg.0"),                               # an Optional list of numbers
    ("/v1/balancing/static", "objective"),                                      # an Optional number
])
def test_optional_and_nested_fields_are_walked_through_their_branches(endpoint: str, path: str) -> None:
    check_metrics(endpoint, [path])


def test_a_list_level_names_its_index() -> None:
    with pytest.raises(MetricPathError) as err:
        check_metric(response_models()["/v1/analysis"], "joint_reactions_N.A.x", "metrics[0]")
    assert (err.value.segment, err.value.valid) == ("x", [LIST_INDEX])
    assert "give an item's index" in str(err.value)


def _leaves(value: Any, path: str = "") -> Iterator[tuple[str, Any]]:
    """Every leaf of a JSON answer with its dotted path; of a list, the first and the last item only."""
    if isinstance(value, dict):
        for key, item in value.items():
            yield from _leaves(item, f"{path}.{key}" if path else key)
    elif isinstance(value, list):
        for i in sorted({0, len(value) - 1} if value else set()):
            yield from _leaves(value[i], f"{path}.{i}")
    else:
        yield path, value


@pytest.mark.parametrize("endpoint", sorted(ENDPOINTS))
def test_every_number_in_a_real_answer_is_a_valid_metric_and_nothing_else_is(endpoint: str) -> None:
    # The endpoint's documented example, answered as a study variant would be: the paths come from real JSON,
    # not from the model the check walks.
    extra: Any = ENDPOINTS[endpoint][0].model_config.get("json_schema_extra")
    example = extra["examples"][0]
    answer = run_endpoint(endpoint, LIMITS, example)
    model = response_models()[endpoint]
    numbers = 0
    for path, value in _leaves(answer):
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            check_metric(model, path, "metrics[0]", endpoint)
            with pytest.raises(MetricPathError) as err:   # the top level is a model: a misspelt name is not there
                check_metric(model, "typo_" + path, "metrics[0]", endpoint)
            assert err.value.segment == "typo_" + path.split(".")[0]
            numbers += 1
        elif value is not None:
            with pytest.raises(MetricPathError) as err:
                check_metric(model, path, "metrics[0]", endpoint)
            assert err.value.segment is None      # the path exists; it is text or a flag
    assert numbers > 0


def test_every_endpoint_answers_with_the_model_the_manual_documents(http: TestClient) -> None:
    paths = http.get("/openapi.json").json()["paths"]
    for endpoint, model in response_models().items():
        schema = paths[endpoint]["post"]["responses"]["200"]["content"]["application/json"]["schema"]
        assert schema["$ref"].rsplit("/", 1)[1] == model.__name__


def _readme_studies() -> list[dict[str, Any]]:
    """The endpoint, metrics, objectives and constraints of every study example of the studies page."""
    section = STUDIES_PAGE.read_text()
    found = []
    for block in re.split(r'"endpoint": ', section)[1:]:
        endpoint = json.loads(block.split(",", 1)[0])
        metrics = json.loads(re.search(r'"metrics": (\[[^\]]*\])', block).group(1))  # type: ignore[union-attr]
        objectives = re.search(r'"objectives": (\{[^}]*\})', block)
        constraints = re.findall(r'"metric": ("[^"]+")', block)
        found.append({"endpoint": endpoint, "metrics": metrics,
                      "objectives": json.loads(objectives.group(1)) if objectives else {},
                      "constraints": [json.loads(c) for c in constraints]})
    return found


def test_the_metrics_of_the_readme_and_the_other_study_examples_are_valid() -> None:
    readme = _readme_studies()
    assert len(readme) == 2     # the curl example and the Python one
    for spec in [*readme, STUDY_EXAMPLE, SPEC]:
        check_metrics(spec["endpoint"], spec["metrics"])
        assert set(spec.get("objectives") or {}) <= set(spec["metrics"])
        assert {c if isinstance(c, str) else c["metric"] for c in spec.get("constraints") or []} <= \
            set(spec["metrics"])

