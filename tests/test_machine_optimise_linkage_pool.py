"""The linkage optimisation spread over a pool's workers gives the engine's own answer in one process: the same
members in the same order, the same optimum, to 1e-12."""

from __future__ import annotations

import copy
import math
from typing import Any

import orjson
import pytest

from api.media import Render

from mechsynth_client import SynthClient
from mechsynth_client.schemas.optimise import SIX_BAR_OPTIMISE_EXAMPLE, LinkageOptimiseIn, LinkageOptimiseOut
from synth.machine.optimise_linkage import optimise_linkage

# three refinement starts on two workers: one worker takes two of them, so the starts' order is exercised
BODY: dict[str, Any] = {**copy.deepcopy(SIX_BAR_OPTIMISE_EXAMPLE), "samples": 12, "refined": 3, "refine_runs": 10}

# how long a solver or a search took: the figures of an answer that are no function of the request
WALL_CLOCK = {"solve_time_s", "search_time_s", "elapsed_s"}


def _same(a: Any, b: Any, where: str = "") -> None:
    """Every number of ``a`` within 1e-12 relative of ``b``'s, everything else equal, member by member."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and a.keys() == b.keys(), where
        for k in a.keys() - WALL_CLOCK:
            _same(a[k], b[k], f"{where}.{k}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), where
        for k, (x, y) in enumerate(zip(a, b, strict=True)):
            _same(x, y, f"{where}.{k}")
    elif isinstance(a, float) and not isinstance(b, bool):
        assert isinstance(b, (int, float)) and math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-15), (where, a, b)
    else:
        assert a == b, (where, a, b)


@pytest.fixture(scope="module")
def pool_client():  # type: ignore[no-untyped-def]
    """The endpoint as the service runs it: its stages as tasks on worker processes."""
    with SynthClient.in_process("pool") as c:
        yield c


def test_the_pool_answer_is_the_engine_answer_in_one_process(pool_client: SynthClient) -> None:
    body = LinkageOptimiseIn.model_validate(BODY)
    alone = optimise_linkage(body.to_engine(6))
    spread = pool_client.optimise_linkage(body)
    # the pool really spread the work: the answer came through the staged endpoint, which refined three starts
    assert spread.certificate.refined == alone.certificate.refined == 3
    # the engine's optimum written as the endpoint writes its answer
    mine = orjson.loads(Render(LinkageOptimiseOut.from_engine, model_extra=(body.model_dump(mode="json"),))(alone)[0])
    theirs = spread.model_dump(mode="json")
    # every member (sample then each start's refinement, in order), the optimum's numbers, values and design
    assert [m["x"] for m in theirs["members"]] == [m["x"] for m in mine["members"]]
    _same(theirs, mine)
    assert spread.values["machine_mass"] == pytest.approx(alone.values[3], rel=1e-12)
