"""Responses written by orjson from the engine's arrays carry exactly what pydantic would write."""

from __future__ import annotations

import json

import numpy as np

import synth
from api.media import json_bytes
from api.translate.analysis import analysis_out
from api.translate.linkage import linkage_from
from mechsynth_client.schemas.analysis import AnalysisIn, AnalysisOut
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE

SLIDER = {"type": "slider_crank", "crank_length_m": 0.05, "rod_length_m": 0.2, "offset_m": 0.01,
          "links": {"rod": {"mass_kg": 0.8, "com_m": [0.06, 0.0], "inertia_kgm2": 0.004}, "slider": {"mass_kg": 1.2}}}


def _analysis(mechanism: dict[str, object]) -> AnalysisOut:
    body = AnalysisIn.model_validate({"mechanism": mechanism, "speed_rpm": 300, "samples": 180,
                                      "gravity": {"g_m_s2": 9.81},
                                      "trace_points": [{"name": "P", "link": "crank", "position_m": [0.02, 0.01]}]})
    result = synth.analyse(linkage_from(body), body.omega_rad_s, samples=body.samples, points=body.trace())
    return analysis_out(result)


def test_orjson_bytes_parse_to_the_pydantic_json() -> None:
    # The pydantic path validates the same answer against the schema and writes it with model_dump_json; both
    # texts must parse to equal content, field for field and float for float (both write shortest round-trips).
    for mechanism in (FOURBAR_EXAMPLE, SLIDER):
        out = _analysis(mechanism)
        fast = json.loads(json_bytes(out))
        slow = json.loads(out.to_lists().model_dump_json())
        assert fast == slow
        assert list(fast) == list(AnalysisOut.model_fields)


def test_strided_arrays_are_written_in_order() -> None:
    # Joint reactions are column slices of the solved unknowns (not contiguous): written row by row all the same.
    out = _analysis(SLIDER)
    name, reaction = next(iter(out.joint_reactions_N.items()))
    assert isinstance(reaction, np.ndarray) and not reaction.flags.c_contiguous
    assert json.loads(json_bytes(out))["joint_reactions_N"][name] == reaction.tolist()


def test_the_service_answer_validates_against_the_schema(client) -> None:  # type: ignore[no-untyped-def]
    body = AnalysisIn.model_validate({"mechanism": SLIDER, "speed_rpm": 300, "samples": 36})
    answer = client.analysis(body)
    engine = synth.analyse(linkage_from(body), body.omega_rad_s, samples=36)
    assert np.allclose(answer.driving_torque_Nm, engine.kinetostatics.driving_torque, rtol=0, atol=0)
