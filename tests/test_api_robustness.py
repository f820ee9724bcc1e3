"""No input is answered with a 500: every endpoint's documented examples, mutated at random leaves; every answer
keeps its documented schema (problems the Problem schema)."""

from __future__ import annotations

import copy
import os
import json
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hostile import EXTREME_FLOATS, HOSTILE_TEXT, checker
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.analysis import AnalysisIn
from mechsynth_client.schemas.balancing import BalanceIn, FullBalanceIn, OptimalBalanceIn, RotorIn, SliderCrankBalanceIn
from mechsynth_client.schemas.flywheel import FlywheelIn
from mechsynth_client.schemas.machine import MachineIn
from mechsynth_client.schemas.synthesis import CrankRockerIn, PathIn, SliderCrankSynthesisIn
from mechsynth_client.schemas.gearing import DriveIn, SplitIn, TeethIn
from mechsynth_client.schemas.structure import StructureIn
from mechsynth_client.schemas.train import TrainIn

ENDPOINTS = {
    "/v1/analysis": AnalysisIn,
    "/v1/analysis/drawing": AnalysisIn,
    "/v1/balancing/static": BalanceIn,
    "/v1/balancing/full": FullBalanceIn,
    "/v1/balancing/optimal": OptimalBalanceIn,
    "/v1/balancing/rotor": RotorIn,
    "/v1/balancing/slider-crank": SliderCrankBalanceIn,
    "/v1/flywheel": FlywheelIn,
    "/v1/gears/split": SplitIn,
    "/v1/gears/teeth": TeethIn,
    "/v1/gears/drive": DriveIn,
    "/v1/gears/train": TrainIn,
    "/v1/structure": StructureIn,
    "/v1/synthesis/crank-rocker": CrankRockerIn,
    "/v1/synthesis/slider-crank": SliderCrankSynthesisIn,
    "/v1/synthesis/path": PathIn,
    "/v1/machines/design": MachineIn,
}
CASES = [(path, ex) for path, model in ENDPOINTS.items() for ex in model.model_config["json_schema_extra"]["examples"]]
# Values a hurried or hostile caller sends: signs, zeros, extremes, wrong types, empty containers, and the text
# and floats that break writers and arithmetic (tests/hostile.py).
ODD = [0, -1, 1e-300, 1e300, -1e300, 2.5, 10**9, "x", None, True, [], {}, [0.0], [1, 2, 3],
       *EXTREME_FLOATS[4:], *HOSTILE_TEXT[::4]]


def _leaves(obj: Any, path: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    if isinstance(obj, dict):
        return [p for k, v in obj.items() for p in _leaves(v, path + (k,))] or [path]
    if isinstance(obj, list) and obj:
        return [p for i, v in enumerate(obj) for p in _leaves(v, path + (i,))]
    return [path]


def _set(obj: Any, path: tuple[Any, ...], value: Any) -> Any:
    if not path:
        return value
    out = copy.deepcopy(obj)
    target = out
    for key in path[:-1]:
        target = target[key]
    target[path[-1]] = value
    return out


@st.composite
def mutated(draw: st.DrawFn) -> tuple[str, Any]:
    path, example = draw(st.sampled_from(CASES))
    body = example
    for _ in range(draw(st.integers(1, 3))):
        leaves = _leaves(body)
        body = _set(body, draw(st.sampled_from(leaves)), draw(st.sampled_from(ODD)))
    return path, body


@settings(max_examples=int(os.environ.get("SYNTH_FUZZ_EXAMPLES", "150")), deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(mutated())
def test_mutated_requests_never_answer_500(client: SynthClient, case: tuple[str, Any]) -> None:
    path, body = case
    r = client.http.post(path, content=json.dumps(body), headers={"content-type": "application/json"})
    assert r.status_code in (200, 413, 422, 504), (path, body, r.status_code, r.text[:500])
    # a 200 keeps the answer's schema with finite numbers, a problem keeps the Problem schema
    checker(client.http)(r, path)


@pytest.mark.parametrize(("path", "example"), CASES)
def test_examples_answer_200(client: SynthClient, path: str, example: Any) -> None:
    assert client.http.post(path, json=example).status_code == 200
