"""The linkage optimisation as a design study and in the design library: each variant optimised in one task (the
engine's stages one after another), every row the endpoint's own answer (its stages as separate tasks); a kept
revision's answer the endpoint's too."""

from __future__ import annotations

import copy
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient

from api.app import create_app
from api.settings import Settings
from mechsynth_client import SynthClient
from mechsynth_client.schemas.optimise import SIX_BAR_OPTIMISE_EXAMPLE, LinkageOptimiseIn
from mechsynth_client.schemas.studies import StudyIn

ENDPOINT = "/v1/machines/optimise-linkage"
# a small sample and one short refinement, so that each optimisation takes a second or two
BASE: dict[str, Any] = {**copy.deepcopy(SIX_BAR_OPTIMISE_EXAMPLE), "samples": 8, "refined": 1, "refine_runs": 10}
LEAST_STROKES = [0.18, 0.20]
METRICS = ["score", "values.machine_mass", "free.0.value_m", "free.1.value_m", "stroke_or_swing",
           "certificate.designed"]


@pytest.fixture(scope="module")
def own_client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[SynthClient]:
    """A service of its own (its own store), so that its studies and designs meet no other test's."""
    where: Path = tmp_path_factory.mktemp("linkage-study")
    settings = Settings(executor="serial", request_deadline_s=300.0, studies_db=str(where / "s.sqlite"))
    with TestClient(create_app(settings), base_url="http://localhost") as http:
        yield SynthClient(http=http)


def _variant(least_stroke: float) -> dict[str, Any]:
    body = copy.deepcopy(BASE)
    body["stroke_m"] = {**body["stroke_m"], "min": least_stroke}
    return body


def test_study_rows_are_the_endpoint_answers(own_client: SynthClient) -> None:
    spec = {"endpoint": ENDPOINT, "base": copy.deepcopy(BASE),
            "parameters": [{"path": "stroke_m.min", "values": LEAST_STROKES}], "sampling": "grid",
            "metrics": METRICS, "objectives": {"values.machine_mass": "min"}}
    study = own_client.study(StudyIn.model_validate(spec))
    status = study.wait()
    assert (status.state, status.done, status.failed) == ("done", len(LEAST_STROKES), 0)
    rows = sorted(study.results(), key=lambda r: r["stroke_m.min"])
    for row, least in zip(rows, LEAST_STROKES, strict=True):
        alone = own_client.optimise_linkage(LinkageOptimiseIn.model_validate(_variant(least)))
        # the study's task runs the engine's stages in one process, the endpoint runs them as tasks: one answer
        assert row["score"] == pytest.approx(alone.score, rel=1e-12)
        assert row["values.machine_mass"] == pytest.approx(alone.values["machine_mass"], rel=1e-12)
        assert [row["free.0.value_m"], row["free.1.value_m"]] == [f.value_m for f in alone.free]
        assert row["certificate.designed"] == alone.certificate.designed
        # the variant's own function is met, and the press is lightest on the least stroke it may have (less
        # work a turn for the same force): each optimum sits on its own least stroke
        assert least <= row["stroke_or_swing"] <= least * 1.01


def test_the_library_keeps_it_with_the_endpoints_answer(own_client: SynthClient) -> None:
    lib = own_client.library
    saved = lib.save("press", "six-bar", ENDPOINT, copy.deepcopy(BASE), message="first", author="ann")
    kept = lib.revision("press", "six-bar", saved.number)
    direct = own_client.http.post(ENDPOINT, json=BASE).json()
    assert kept.answer is not None and kept.passed is True
    assert kept.answer["values"]["machine_mass"] == pytest.approx(direct["values"]["machine_mass"], rel=1e-12)
    assert kept.answer["free"] == direct["free"]
    # the request kept is the canonical one: the defaults filled in
    assert kept.request["min_transmission_angle_deg"] == 30 and kept.request["prices"] is not None
