"""Digits of the answers: JSON arrays at one quantum per array by default, every float64 exactly with
``?precision=full``, npz and stored answers always in full."""

from __future__ import annotations

import inspect
import json
import re
from collections import defaultdict
from typing import Any

import numpy as np
import pytest
from fastapi.routing import APIRoute

import synth
from api.deps import get_answer_solvers
from api.execution.plans import Limits
from api.library.tasks import answer_revision
from api.media import json_bytes
from api.settings import Settings
from api.translate.analysis import analysis_out
from api.translate.linkage import linkage_from
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.analysis import AnalysisIn
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE, SIX_BAR_PRESS_EXAMPLE
from mechsynth_client.schemas.flywheel import FlywheelIn
from mechsynth_client.schemas.foundation import RegulationIn


def _half_quantum(values: np.ndarray) -> float:
    """Half of 10^(e-7) for an array's largest magnitude in [10^e, 10^(e+1)) (docs/service.md, "Digits of an
    answer"), with the float64 round-off of writing and reading it back: the most a value may move."""
    m = float(np.abs(values).max(initial=0.0))
    e = int(np.floor(np.log10(m))) if m > 0 else 0
    e += (m >= 10.0 ** (e + 1)) - (m < 10.0**e) if m > 0 else 0
    return 10.0 ** (e - 7) / 2 * (1 + 1e-7) + float(np.spacing(m))


ANALYSIS = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 90, "gravity": {"g_m_s2": 9.81},
            "trace_points": [{"name": "P", "link": "coupler", "position_m": [0.15, 0.08]}],
            "instant_centres": True, "path_curvature": True}
CASES = {
    "analysis four-bar": ("/v1/analysis", ANALYSIS),
    "analysis six-bar": ("/v1/analysis", {"mechanism": SIX_BAR_PRESS_EXAMPLE, "speed_rpm": 60, "samples": 72}),
    "flywheel elastic drive": ("/v1/flywheel", FlywheelIn.model_json_schema()["examples"][2]),
    "regulation": ("/v1/machines/regulation", RegulationIn.model_json_schema()["examples"][0]),
}


def _leaves(value: Any, path: str = "") -> dict[str, Any]:
    """Every leaf of a parsed JSON answer by its path, written here independently of the service's walk."""
    if isinstance(value, dict):
        return {k: v for key, item in value.items() for k, v in _leaves(item, f"{path}.{key}").items()}
    if isinstance(value, list):
        return {k: v for i, item in enumerate(value) for k, v in _leaves(item, f"{path}[{i}]").items()}
    return {path: value}


def _post(client: SynthClient, path: str, body: dict[str, Any], **params: str) -> Any:
    r = client.http.post(path, json=body, params=params)
    assert r.status_code == 200, r.text
    return r


@pytest.mark.parametrize("case", list(CASES))
def test_the_default_answer_is_the_full_one_at_a_quantum_per_array(client: SynthClient, case: str) -> None:
    path, body = CASES[case]
    single_r, full_r = _post(client, path, body), _post(client, path, body, precision="full")
    single, full = _leaves(single_r.json()), _leaves(full_r.json())
    assert list(single) == list(full)   # the same fields, in the same order
    # the full values of each array (a leaf's path without its list positions), whose largest sets its quantum
    arrays: dict[str, list[float]] = defaultdict(list)
    for key, value in full.items():
        if isinstance(value, float):
            arrays[re.sub(r"\[\d+\]", "", key)].append(value)
    half = {name: _half_quantum(np.array(values)) for name, values in arrays.items()}
    reduced = 0
    for key, expected in full.items():
        got = single[key]
        assert type(got) is type(expected), key   # a float stays a float ("0.0", "120.0")
        if not isinstance(expected, float) or got == expected:
            assert got == expected, key   # text, flags, counts and single figures as they are
            continue
        # an array's number: within half its array's quantum
        assert abs(got - expected) <= half[re.sub(r"\[\d+\]", "", key)], key
        reduced += 1
    # the curves were written with fewer digits, and the answer is smaller for it
    assert reduced > 0.25 * sum(isinstance(v, float) for v in full.values())
    assert len(single_r.content) < 0.9 * len(full_r.content)


def test_full_precision_round_trips_the_engines_float64() -> None:
    # The engine's own arrays, and the same answer written in full: every float read back is the very float64.
    body = AnalysisIn.model_validate(ANALYSIS)
    result = synth.analyse(linkage_from(body), body.omega_rad_s, samples=body.samples, points=body.trace())
    answer = json.loads(json_bytes(analysis_out(result), "full"))
    ks = result.kinetostatics
    assert np.array_equal(np.array(answer["driving_torque_Nm"]), ks.driving_torque)
    assert np.array_equal(np.array(answer["shaking_force_N"]), ks.shaking_force)
    assert np.array_equal(np.array(answer["points"]["P"]["position_m"]), result.motion.point_pos["P"])
    single = json.loads(json_bytes(analysis_out(result), "single"))
    assert not np.array_equal(np.array(single["driving_torque_Nm"]), ks.driving_torque)


def test_client_asks_for_the_precision_it_was_made_with(client: SynthClient) -> None:
    # The shared client was made with precision="full": its answers are the engine's float64 exactly; the
    # default client gets the same answer at one quantum per array.
    body = AnalysisIn.model_validate({"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 36})
    engine = synth.analyse(linkage_from(body), body.omega_rad_s, samples=36).kinetostatics.driving_torque
    assert np.array_equal(client.analysis(body).driving_torque_Nm, engine)
    default = SynthClient(http=client.http)   # the shared client's connection, left open
    torque = np.array(default.analysis(body).driving_torque_Nm)
    assert not np.array_equal(torque, engine)
    assert np.abs(torque - engine).max() <= _half_quantum(engine)


def test_npz_holds_float64_whatever_the_precision(client: SynthClient) -> None:
    path, body = CASES["analysis four-bar"]
    single = _post(client, path, body, format="npz").content
    assert _post(client, path, body, format="npz", precision="full").content == single


def test_an_unknown_precision_is_refused_by_name(client: SynthClient) -> None:
    r = client.http.post("/v1/analysis", json=ANALYSIS, params={"precision": "double"})
    assert r.status_code == 422
    assert "precision" in r.text


def test_a_stored_answer_keeps_full_precision(client: SynthClient) -> None:
    # A library revision's answer is computed in a worker from the canonical request: the full answer, so a
    # signed revision never loses a digit.
    request = AnalysisIn.model_validate(ANALYSIS).model_dump(mode="json")
    stored, passed, _ = answer_revision("/v1/analysis", Limits.from_settings(Settings()), request)
    assert passed is True and stored is not None
    assert stored == _post(client, "/v1/analysis", request, precision="full").json()


def test_every_answer_endpoint_offers_the_precision(client: SynthClient) -> None:
    # Every handler answering with a plan takes ?precision= (and says so in the OpenAPI document); the others,
    # which answer with stored data or drawings, do not.
    from api import auth
    from api.library.router import router as library_router
    from api.routers import PREFIX, all_routers
    from api.studies.router import router as studies_router

    spec = client.http.get("/openapi.json").json()
    answering = []
    for route in (r for router in (*all_routers(), studies_router, library_router, auth.router)
                  for r in router.routes):
        if not isinstance(route, APIRoute):
            continue
        source = inspect.getsource(route.endpoint)
        calls = {d.call for d in route.dependant.dependencies}
        offered = get_answer_solvers in calls
        assert offered == bool(re.search(r"await (solvers\.)?answer_\w+\(", source)), route.path
        if offered:
            method = next(iter(route.methods)).lower()
            path = PREFIX + route.path
            params = {p["name"] for p in spec["paths"][path][method].get("parameters", [])}
            assert "precision" in params, path
            answering.append(path)
    assert {"/v1/analysis", "/v1/flywheel", "/v1/machines/design", "/v1/machines/optimise"} <= set(answering)
