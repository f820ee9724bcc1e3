"""Arrays without JSON: the ``.npz`` answers of the analysis and the flywheel hold every number of the JSON answer."""

from __future__ import annotations

import io
from typing import Any

import numpy as np
import pytest

from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.analysis import AnalysisIn
from mechsynth_client.schemas.balancing import BalanceIn
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE, SIX_BAR_PRESS_EXAMPLE
from mechsynth_client.schemas.flywheel import FlywheelIn

FLYWHEEL_EXAMPLES: list[dict[str, Any]] = FlywheelIn.model_json_schema()["examples"]


def _numbers(value: Any, path: str = "") -> dict[str, Any]:
    """Every number of a parsed JSON answer by its path (names joined by '/'), lists of numbers whole: written
    here independently of the service's own flattening."""
    if isinstance(value, dict):
        out: dict[str, Any] = {}
        for key, item in value.items():
            out.update(_numbers(item, f"{path}/{key}" if path else key))
        return out
    if isinstance(value, list):
        leaf = value
        while isinstance(leaf, list) and leaf:
            leaf = leaf[0]
        if isinstance(leaf, (int, float)) and not isinstance(leaf, bool):
            return {path: value}
        out = {}
        for i, item in enumerate(value):
            out.update(_numbers(item, f"{path}/{i}"))
        return out
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return {path: value}
    return {}


def _same(arrays: dict[str, np.ndarray], answer: dict[str, Any]) -> None:
    expected = _numbers(answer)
    assert set(arrays) == set(expected)
    for key, value in expected.items():
        # The archive holds the engine's float64 values and the full-precision JSON their shortest round-trip
        # decimal form: equal bit for bit.
        assert np.array_equal(arrays[key], np.asarray(value, dtype=float)), key


@pytest.mark.parametrize("mechanism", [FOURBAR_EXAMPLE, SIX_BAR_PRESS_EXAMPLE], ids=["fourbar", "six-bar"])
def test_analysis_arrays_equal_the_json_answer(client: SynthClient, mechanism: dict[str, Any]) -> None:
    body = AnalysisIn.model_validate({"mechanism": mechanism, "speed_rpm": 120, "samples": 72,
                                      "gravity": {"g_m_s2": 9.81}})
    answer = client.http.post("/v1/analysis", json=body.model_dump(mode="json", exclude_none=True),
                              params={"precision": "full"})
    assert answer.headers["content-type"].startswith("application/json")
    arrays = client.analysis_arrays(body)
    _same(arrays, answer.json())
    # the arrays have the answer's shapes: one row per crank angle, pairs as (N, 2)
    assert arrays["driving_torque_Nm"].shape == (72,)
    assert arrays["joint_reactions_N/A"].shape == (72, 2)


def test_accept_header_chooses_npz(client: SynthClient) -> None:
    payload = {"mechanism": FOURBAR_EXAMPLE, "samples": 36}
    by_header = client.http.post("/v1/analysis", json=payload, headers={"accept": "application/x-npz"})
    assert by_header.headers["content-type"] == "application/x-npz"
    with np.load(io.BytesIO(by_header.content), allow_pickle=False) as archive:
        _same({key: archive[key] for key in archive.files},
              client.http.post("/v1/analysis", json=payload, params={"precision": "full"}).json())


@pytest.mark.parametrize("example", FLYWHEEL_EXAMPLES, ids=["tables", "mechanism", "elastic-drive"])
def test_flywheel_arrays_equal_the_json_answer(client: SynthClient, example: dict[str, Any]) -> None:
    body = FlywheelIn.model_validate(example)
    answer = client.http.post("/v1/flywheel", json=body.model_dump(mode="json", exclude_none=True),
                              params={"precision": "full"}).json()
    _same(client.flywheel_arrays(body), answer)


def test_npz_is_refused_by_name_where_not_offered(client: SynthClient) -> None:
    example = BalanceIn.model_json_schema()["examples"][0]
    problem = client.http.post("/v1/balancing/static", params={"format": "npz"}, json=example)
    assert problem.status_code in (400, 422)
    assert problem.headers["content-type"].startswith("application/problem+json")
    assert "format" in problem.text
