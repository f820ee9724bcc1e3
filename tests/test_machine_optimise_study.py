"""The whole-machine optimisation as a design study: each variant optimised in one task, progress variant by
variant, every row the endpoint's own answer."""

from __future__ import annotations

import copy

import pytest

from mechsynth_client import SynthClient
from mechsynth_client.schemas.optimise import CRANK_ROCKER_OPTIMISE_EXAMPLE, MachineOptimiseIn
from mechsynth_client.schemas.studies import StudyIn

SWINGS = [36.0, 44.0]


@pytest.fixture(scope="module")
def pool_client():  # type: ignore[no-untyped-def]
    """The endpoint as the service runs it: the candidates' chains spread over worker processes."""
    with SynthClient.in_process("pool") as c:
        yield c


def test_optimisation_study_rows_are_the_endpoint_answers(client: SynthClient, pool_client: SynthClient) -> None:
    spec = {"endpoint": "/v1/machines/optimise", "base": copy.deepcopy(CRANK_ROCKER_OPTIMISE_EXAMPLE),
            "parameters": [{"path": "function.swing_deg", "values": SWINGS}], "sampling": "grid",
            "metrics": ["score", "chain_score", "parameter"], "objectives": {"score": "min"}}
    study = client.study(StudyIn.model_validate(spec))
    status = study.wait()
    assert (status.state, status.done, status.failed) == ("done", len(SWINGS), 0)
    rows = sorted(study.results(), key=lambda r: r["function.swing_deg"])
    for row, swing in zip(rows, SWINGS, strict=True):
        body = copy.deepcopy(CRANK_ROCKER_OPTIMISE_EXAMPLE)
        body["function"] = {**body["function"], "swing_deg": swing}  # type: ignore[dict-item]
        alone = pool_client.optimise_machine(MachineOptimiseIn.model_validate(body))
        # the study's task runs the engine in one process, the endpoint on the pool spreads the chains over its
        # workers: the same answer
        assert row["parameter"] == alone.parameter
        assert row["score"] == pytest.approx(alone.score, rel=1e-12)
        # never worse than the chain's machine of the same function
        assert row["score"] <= row["chain_score"] + 1e-12
