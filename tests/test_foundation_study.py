"""A design study over the frame on its isolators: the four foundation endpoints are study endpoints, and a study's
rows are the answers the endpoint sends, with the vertical mode where the one-degree-of-freedom closed form puts
it."""

from __future__ import annotations

import copy
import math
from typing import Any

import pytest

import synth
from api.execution.plans import Limits
from api.studies.tasks import ENDPOINTS, variant_function
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.foundation import IsolationIn
from synth.execution import SerialExecutor

ENDPOINT = "/v1/machines/isolation"
BASE = IsolationIn.model_json_schema()["examples"][0]
MASSES = [200.0, 400.0, 800.0]
SPEEDS = [240.0, 480.0]
SPEC: dict[str, Any] = {
    "endpoint": ENDPOINT,
    "base": {**copy.deepcopy(BASE), "samples": 120},
    "parameters": [{"path": "frame.mass_kg", "values": MASSES}, {"path": "speed_rpm", "values": SPEEDS}],
    "metrics": ["modes.0.frequency_Hz", "modes.1.frequency_Hz", "modes.2.frequency_Hz", "peak_force_N",
                "checks.relative_diff"],
    "objectives": {"peak_force_N": "min"},
}
LIMITS = Limits(max_samples=20_000, max_stages=6, solver_time_limit_s=20.0)


def test_every_foundation_endpoint_is_a_study_endpoint() -> None:
    for path in ("/v1/machines/isolation", "/v1/machines/isolation/design", "/v1/machines/elastic-drive",
                 "/v1/machines/regulation"):
        assert path in ENDPOINTS


def test_a_study_of_the_frame_on_its_isolators(client: SynthClient) -> None:
    rows: list[synth.VariantRow] = []
    executor = SerialExecutor()
    try:
        synth.run_study(synth.study_from_dict(SPEC), variant_function(ENDPOINT, LIMITS), executor, rows.extend)
    finally:
        executor.shutdown()
    rows.sort(key=lambda r: r.index)
    assert len(rows) == len(MASSES) * len(SPEEDS) and all(r.ok for r in rows)
    ky = sum(i["ky_N_m"] for i in BASE["isolators"])
    for r in rows:
        mass, _ = r.values
        assert r.metrics is not None
        # the isolators stand symmetric about the centre at one height: the vertical mode is one degree of
        # freedom, f = sqrt(sum k_y / m) / 2 pi, whatever the speed (its place among the three moves with m)
        vertical = math.sqrt(ky / float(mass)) / (2 * math.pi)
        assert min(abs(f / vertical - 1) for f in r.metrics[:3]) < 1e-9
        assert r.metrics[4] < 1e-5
    # a row is what the endpoint answers for the same body
    row = rows[3]
    body = copy.deepcopy(SPEC["base"])
    body["frame"]["mass_kg"], body["speed_rpm"] = row.values
    answer = client.isolate_machine(IsolationIn.model_validate(body))
    assert row.metrics == (*(m.frequency_Hz for m in answer.modes), answer.peak_force_N, answer.checks.relative_diff)
