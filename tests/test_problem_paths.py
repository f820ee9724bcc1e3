"""Errors a person can act on: field paths as the JSON the client sent, a "did you mean" for a misspelt field, a
body that is not a JSON object told to send JSON, and the OpenAPI document promising only what is served."""

from __future__ import annotations

from typing import Any

import pytest

from api.validation import did_you_mean, dotted, json_path
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE

SEND_JSON = "send JSON with content-type application/json"


def _machine(**changes: Any) -> dict[str, Any]:
    return {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "delta": 0.01,
            "loads": [{"type": "window", "torque_Nm": 40, "start_deg": 0, "end_deg": 180}], **changes}


@pytest.mark.parametrize(("path", "body", "field"), [
    # a discriminated union's tag ("fourbar") is pydantic's, not the client's
    ("/v1/analysis", {"mechanism": dict(FOURBAR_EXAMPLE, crank_length_m=-1), "speed_rpm": 100},
     "mechanism.crank_length_m"),
    ("/v1/analysis", {"mechanism": dict(FOURBAR_EXAMPLE, links={"crank": {"mass_kg": -1}}), "speed_rpm": 100},
     "mechanism.links.crank.mass_kg"),
    ("/v1/machines/design", _machine(loads=[{"type": "window", "torque_Nm": "forty"}]), "loads[0].torque_Nm"),
    # a union of types (a count or a list of stages): the member the client wrote, by index
    ("/v1/machines/design", _machine(drive={"stages": [{"type": "helical", "efficiency": 2}]}),
     "drive.stages[0].efficiency"),
])
def test_field_paths_are_the_json_the_client_sent(client: SynthClient, path: str, body: dict[str, Any],
                                                  field: str) -> None:
    r = client.http.post(path, json=body)
    assert r.status_code == 422 and r.headers["content-type"] == "application/problem+json"
    problem = r.json()
    assert problem["field"] == field and problem["detail"].startswith(field + ": ")
    # no error names a tag or a type the client never wrote
    assert not any(tag in e["field"] for e in problem["errors"] for tag in ("fourbar", "list[", "function-", "int"))


@pytest.mark.parametrize(("path", "body", "field", "meant"), [
    ("/v1/analysis", {"mechanism": dict(FOURBAR_EXAMPLE, crank_lenght_m=0.1), "speed_rpm": 100},
     "mechanism.crank_lenght_m", "crank_length_m"),
    ("/v1/analysis", {"mechanism": FOURBAR_EXAMPLE, "speed_rmp": 100}, "speed_rmp", "speed_rpm"),
    ("/v1/analysis", {"mechanism": dict(FOURBAR_EXAMPLE, links={"crank": {"mas_kg": 1}}), "speed_rpm": 100},
     "mechanism.links.crank.mas_kg", "mass_kg"),
    ("/v1/machines/design", _machine(drive={"stages": ["helical"], "synchronus_rpm": 1500}),
     "drive.synchronus_rpm", "synchronous_rpm"),
    ("/v1/machines/design", _machine(drive={"stages": [{"type": "helical", "ratoi": 3}]}),
     "drive.stages[0].ratoi", "ratio"),
])
def test_a_misspelt_field_gets_a_did_you_mean(client: SynthClient, path: str, body: dict[str, Any], field: str,
                                              meant: str) -> None:
    problem = client.http.post(path, json=body).json()
    assert problem["status"] == 422 and problem["field"] == field
    assert problem["did_you_mean"][0] == meant and meant in problem["valid"]
    assert f"did you mean {meant!r}?" in problem["detail"]


def test_a_body_that_is_not_a_json_object_is_told_to_send_json(client: SynthClient) -> None:
    cases = [(400, dict(content=b"", headers={"content-type": "application/json"})), (400, dict(content=b"")),
             (415, dict(content=b"speed_rpm=300", headers={"content-type": "application/x-www-form-urlencoded"})),
             (400, dict(content=b"[1, 2]", headers={"content-type": "application/json"})),
             (400, dict(content=b"{bad", headers={"content-type": "application/json"}))]
    for status, kwargs in cases:
        r = client.http.post("/v1/analysis", **kwargs)  # type: ignore[arg-type]
        assert r.status_code == status and r.headers["content-type"] == "application/problem+json", kwargs
        assert r.json()["detail"].endswith(SEND_JSON), r.json()
    # an object that fails a whole-request check is still a 422 about the request
    r = client.http.post("/v1/gears/split", json={"total_ratio": 10, "motor_speed_rpm": 1500,
                                                  "output_speed_rpm": 150})
    assert r.status_code == 422


def test_json_path_walks_the_body_not_the_model() -> None:
    body = {"mechanism": {"type": "fourbar", "links": {"crank": {"mass_kg": -1}}}, "drive": {"stages": [{}]}}
    assert json_path(("body", "mechanism", "fourbar", "links", "crank", "mass_kg"), body) == [
        "mechanism", "links", "crank", "mass_kg"]
    # a missing field is named; a union's type tags are not
    assert json_path(("body", "mechanism", "fourbar", "crank_length_m"), body) == ["mechanism", "crank_length_m"]
    assert json_path(("body", "drive", "stages", "list[union[str,StageIn]]", 0, "StageIn", "type"), body) == [
        "drive", "stages", 0, "type"]
    assert json_path(("body", "drive", "stages", "int"), body) == ["drive", "stages"]
    assert dotted(["drive", "stages", 0, "type"]) == "drive.stages[0].type" and dotted([]) == ""
    assert did_you_mean("speed_rmp", ["samples", "speed_rpm", "loads"]) == ["speed_rpm"]
    assert did_you_mean("zzz", ["samples", "speed_rpm"]) == []


def test_openapi_documents_study_errors_as_problems_and_flywheel_formats_served(client: SynthClient) -> None:
    doc = client.http.get("/openapi.json").json()
    for method in ("get", "delete"):
        responses = doc["paths"]["/v1/studies/{study_id}"][method]["responses"]
        errors = {code: r for code, r in responses.items() if code.startswith("4")}
        assert {"404", "422"} <= set(errors)
        assert all(list(r["content"]) == ["application/problem+json"] for r in errors.values()), errors
    assert "HTTPValidationError" not in str(doc)
    # /v1/flywheel: the formats it serves, and only those (no DXF: a flywheel has no mechanism to draw)
    op = doc["paths"]["/v1/flywheel"]["post"]
    fmt = next(p for p in op["parameters"] if p["name"] == "format")
    assert fmt["schema"]["anyOf"][0]["enum"] == ["json", "png", "svg", "pdf", "csv", "npz"]
    assert set(op["responses"]["200"]["content"]) == {"application/json", "image/png", "image/svg+xml",
                                                      "application/pdf", "text/csv", "application/x-npz"}
    tables = {"crank_angle_deg": [0, 120, 240, 360], "resisting_torque_Nm": [-10, -20, -5, -10],
              "driving_torque_Nm": [0, 0, 0, 0]}
    r = client.http.post("/v1/flywheel?format=dxf", json={"tables": tables, "mean_speed_rad_s": 10, "delta": 0.1})
    assert r.status_code == 422 and r.json()["field"] == "format"
    r = client.http.get("/v1/studies/no-such-study")
    assert r.status_code == 404 and r.headers["content-type"] == "application/problem+json"
