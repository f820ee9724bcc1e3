"""POST /v1/analysis in-process: results equal the engine's, figures are PNG, bad input is a problem response."""

from __future__ import annotations

import json

import httpx
import numpy as np
import pytest

import synth
from api.translate.linkage import linkage_from
from mechsynth_client.client import InvalidInputError, NotAssemblableError, ProblemError, SynthClient, TooLargeError
from mechsynth_client.schemas.analysis import AnalysisIn
from conftest import CASES

EXAMPLES = AnalysisIn.model_config["json_schema_extra"]["examples"]  # type: ignore[index]
FOURBAR = EXAMPLES[0]["mechanism"]


def test_health(client: SynthClient) -> None:
    assert client.health() == {"status": "ok"}


@pytest.mark.parametrize("example", EXAMPLES)
def test_documented_examples_answer(client: SynthClient, example: dict) -> None:
    out = client.analysis(AnalysisIn.model_validate(example))
    assert len(out.crank_angle_deg) == example.get("samples", 360)
    assert out.checks.virtual_power_torque_max_diff_Nm < 1e-9 * (1 + out.summary.max_driving_torque_Nm)
    assert np.all(np.isfinite(out.driving_torque_Nm))


def test_response_equals_engine(client: SynthClient) -> None:
    req = AnalysisIn.model_validate({"mechanism": FOURBAR, "speed_rpm": 300, "samples": 72})
    out = client.analysis(req)
    an = synth.analyse(linkage_from(req), 300 * np.pi / 30, samples=72)
    assert out.driving_torque_Nm == pytest.approx(an.kinetostatics.driving_torque.tolist(), rel=1e-12)
    assert out.summary.rms_shaking_force_N == pytest.approx(an.summary().rms_shaking_force, rel=1e-12)
    assert out.grashof == "crank-rocker"
    assert set(out.joint_reactions_N) == {"O", "A", "B", "Q"}
    assert set(out.points) >= {"O", "A", "B", "Q", "S_crank", "S_coupler", "S_rocker"}


def test_seed_shaper_through_the_api(client: SynthClient) -> None:
    # The README's shaper request at crank angle 0 is the lecture-10 position (seed exact case).
    case = CASES["l10_shaper_drive_torque_exact"]
    body = dict(EXAMPLES[1], crank_angle_deg=[0.0], speed_rpm=case["inputs"]["omega1_rad_s"] * 30 / np.pi)
    out = client.analysis(AnalysisIn.model_validate(body))
    assert out.driving_torque_Nm[0] == pytest.approx(case["expected"]["M_drive_Nm"], rel=case["tolerance_rel"])


def test_counterweights_change_the_result(client: SynthClient) -> None:
    base = {"mechanism": FOURBAR, "speed_rpm": 300, "samples": 36}
    plain = client.analysis(AnalysisIn.model_validate(base))
    # A crank counterweight with m*r equal to the crank's own first moment cancels the crank's share exactly.
    crank = FOURBAR["links"]["crank"]
    cw = {"link": "crank", "mass_kg": crank["mass_kg"], "position_m": [-crank["com_m"][0], 0.0]}
    weighted = client.analysis(AnalysisIn.model_validate(dict(base, counterweights=[cw])))
    no_crank_mass = client.analysis(
        AnalysisIn.model_validate(dict(base, mechanism=dict(FOURBAR, links={**FOURBAR["links"], "crank": {}})))
    )
    assert np.asarray(weighted.shaking_force_N) == pytest.approx(np.asarray(no_crank_mass.shaking_force_N), abs=1e-9)
    assert abs(weighted.summary.rms_shaking_force_N - plain.summary.rms_shaking_force_N) > 1.0


def test_png(client: SynthClient) -> None:
    png = client.analysis_png(AnalysisIn.model_validate(EXAMPLES[0]), angle_deg=45)
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    r = client.http.post("/v1/analysis", json=EXAMPLES[1], headers={"accept": "image/png"})
    assert r.status_code == 200 and r.headers["content-type"] == "image/png"


def _problem(client: SynthClient, body: object, status: int, slug: str, **kw: object) -> dict:
    r = client.http.post("/v1/analysis", content=json.dumps(body) if not isinstance(body, bytes) else body,
                         headers={"content-type": "application/json"}, **kw)  # type: ignore[arg-type]
    assert r.status_code == status, r.text
    assert r.headers["content-type"].startswith("application/problem+json")
    problem = r.json()
    assert problem["type"] == f"/problems/{slug}" and problem["status"] == status
    return problem


def test_not_assemblable_names_the_ranges(client: SynthClient) -> None:
    mech = {"type": "fourbar", "ground_length_m": 0.2, "crank_length_m": 0.15, "coupler_length_m": 0.1,
            "rocker_length_m": 0.12}
    problem = _problem(client, {"mechanism": mech}, 422, "not-assemblable")
    (start, end), = problem["not_assemblable_ranges_deg"]
    assert 0 < start < end < 360
    with pytest.raises(NotAssemblableError) as err:
        client.analysis(AnalysisIn.model_validate({"mechanism": mech}))
    assert err.value.problem["not_assemblable_ranges_deg"] == problem["not_assemblable_ranges_deg"]


@pytest.mark.parametrize(
    ("patch", "field"),
    [
        ({"mechanism": dict(FOURBAR, links={"crank": {"mass_kg": -1}})}, "mass_kg"),
        ({"mechanism": dict(FOURBAR, crank_length_m=0)}, "crank_length_m"),
        ({"speed_rpm": -5}, "speed_rpm"),
        ({"counterweights": [{"link": "flywheel", "mass_kg": 1, "position_m": [0, 0]}]}, "counterweights[0].link"),
        ({"loads": [{"type": "window", "force_N": 100}]}, "loads.torque_Nm"),
        ({"mechanism": dict(FOURBAR, ground_length_m=2.0)}, "mechanism"),
        ({"colour": "red"}, "colour"),
    ],
)
def test_bad_input_names_the_field(client: SynthClient, patch: dict, field: str) -> None:
    problem = _problem(client, {"mechanism": FOURBAR, **patch}, 422, "invalid-input")
    assert field in problem["field"]


def test_nan_is_422_and_malformed_json_400(client: SynthClient) -> None:
    body = json.dumps({"mechanism": FOURBAR}).replace('"crank_length_m": 0.1', '"crank_length_m": NaN').encode()
    problem = _problem(client, body, 422, "invalid-input")
    assert "crank_length_m" in problem["field"]
    malformed = _problem(client, b"{not json", 400, "malformed-json")
    assert malformed["position"] == 1 and "JSON" in malformed["detail"]


def test_size_limits_are_413(client: SynthClient) -> None:
    problem = _problem(client, {"mechanism": FOURBAR, "samples": 10**6}, 413, "too-large")
    assert problem["limit"] < 10**6 and problem["field"] == "samples"
    huge = {"mechanism": FOURBAR, "crank_angle_deg": [0.0] * 400_000}
    _problem(client, huge, 413, "too-large")


def test_client_decodes_problems_without_a_server() -> None:
    def handler(request: httpx.Request) -> httpx.Response:
        body = {"type": "/problems/too-large", "title": "Request too large", "status": 413, "detail": "x", "limit": 5}
        return httpx.Response(413, json=body, headers={"content-type": "application/problem+json"})

    c = SynthClient(http=httpx.Client(transport=httpx.MockTransport(handler), base_url="http://test"))
    with pytest.raises(TooLargeError) as err:
        c.analysis(AnalysisIn.model_validate({"mechanism": FOURBAR}))
    assert err.value.status == 413 and err.value.problem["limit"] == 5
    assert isinstance(err.value, ProblemError) and not isinstance(err.value, InvalidInputError)


def test_openapi_documents_the_endpoint(client: SynthClient) -> None:
    spec = client.http.get("/openapi.json").json()
    assert "/v1/analysis" in spec["paths"]
    assert "image/png" in spec["paths"]["/v1/analysis"]["post"]["responses"]["200"]["content"]


def test_trace_points_follow_their_link(client: SynthClient) -> None:
    # A coupler point at the coupler's far joint must move exactly like joint B.
    body = {"mechanism": FOURBAR, "samples": 24,
            "trace_points": [{"name": "P", "link": "coupler", "position_m": [FOURBAR["coupler_length_m"], 0.0]}]}
    out = client.analysis(AnalysisIn.model_validate(body))
    assert np.asarray(out.points["P"].acceleration_m_s2) == pytest.approx(
        np.asarray(out.points["B"].acceleration_m_s2), abs=1e-9)
    bad = dict(body, trace_points=[{"name": "P", "link": "crankshaft", "position_m": [0, 0]}])
    assert _problem(client, bad, 422, "invalid-input")["field"] == "trace_points"
