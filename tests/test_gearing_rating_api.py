"""POST /v1/gears/rating and the drive's strength sizing through the in-process client: the examples, the
ISO/TR 6336-30 example through HTTP, a spectrum, and problems that name the field."""

from __future__ import annotations

import math
from typing import Any

import pytest

import synth
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.gearing import DriveIn
from mechsynth_client.schemas.rating import GRADES, RatingIn

from test_gearing_rating import TR_DUTY, TR_SPEC, TR_SPEED, TR_TORQUE

EXAMPLE: dict[str, Any] = RatingIn.model_config["json_schema_extra"]["examples"][0]   # type: ignore[index]


def test_rating_examples_work(client: SynthClient) -> None:
    for example in RatingIn.model_config["json_schema_extra"]["examples"]:   # type: ignore[index]
        response = client.http.post("/v1/gears/rating", json=example)
        assert response.status_code == 200, (example, response.json())


def test_rating_over_http_is_the_engine_rating(client: SynthClient) -> None:
    # The first example is ISO/TR 6336-30 example 1; the HTTP answer equals the engine's (tested factor by
    # factor against the report in test_gearing_rating.py).
    out = client.gears_rating(RatingIn.model_validate(EXAMPLE))
    engine = synth.rate_pair(TR_SPEC, TR_TORQUE, TR_SPEED, TR_DUTY)
    assert out.safety_contact == pytest.approx(list(engine.safety_contact), rel=1e-12)
    assert out.safety_root == pytest.approx(list(engine.safety_root), rel=1e-12)
    assert out.geometry.centre_distance_mm == pytest.approx(500.0)
    assert {f.symbol for f in out.factors} >= {"K_A", "K_V", "K_Hbeta", "K_Halpha", "Z_H", "Z_E", "Z_eps", "Z_beta",
                                               "Z_NT", "Z_L", "Z_v", "Z_R", "Z_W", "Z_X", "Y_F", "Y_S", "Y_B", "Y_DT",
                                               "Y_beta", "K_Fbeta", "K_Falpha", "Y_ST", "Y_NT", "Y_deltarelT",
                                               "Y_RrelT", "Y_X"}
    assert out.checks.hertz_contact_stress_MPa == pytest.approx(out.contact_stress_MPa[0], rel=1e-12)
    # tan(alpha_t) = tan(alpha_n)/cos(beta), written out.
    assert math.tan(math.radians(out.geometry.transverse_pressure_angle_deg)) == pytest.approx(
        math.tan(math.radians(20)) / math.cos(math.radians(15.8)), rel=1e-12)


def test_spectrum_rating_answers_life_and_miner_safety(client: SynthClient) -> None:
    body = dict(EXAMPLE, pinion_torque_Nm=None, load_spectrum={"torque_Nm": [TR_TORQUE] * 8})
    out = client.gears_rating(RatingIn.model_validate(body))
    assert out.spectrum is not None
    # Identity: a constant spectrum's Miner safety is the rating's safety factor.
    assert out.spectrum.safety_contact == pytest.approx(out.safety_contact, rel=1e-9)
    assert out.spectrum.rms_torque_Nm == pytest.approx(TR_TORQUE)


def test_materials_are_listed(client: SynthClient) -> None:
    names = [m.name for m in client.gears_materials()]
    assert sorted(names) == sorted(GRADES) == sorted(synth.gear_materials())


@pytest.mark.parametrize(("change", "field"), [
    ({"pinion_teeth": 12, "pinion_profile_shift": 0.0, "centre_distance_mm": None}, "pinion_profile_shift"),
    ({"face_width_mm": 300.0}, "face_width_mm"),
    ({"gear_material": "unobtainium"}, "gear_material"),
    ({"centre_distance_mm": 510.0}, "centre_distance_mm"),
    ({"pinion_profile_shift": 1.6, "centre_distance_mm": None}, "pinion_profile_shift"),
])
def test_bad_pairs_are_problems_naming_the_field(client: SynthClient, change: dict[str, Any], field: str) -> None:
    response = client.http.post("/v1/gears/rating", json={**EXAMPLE, **change})
    assert response.status_code == 422
    assert response.headers["content-type"].startswith("application/problem+json")
    assert response.json()["field"] == field


def test_unknown_material_lists_the_grades(client: SynthClient) -> None:
    response = client.http.post("/v1/gears/rating", json={**EXAMPLE, "pinion_material": "brass"})
    assert response.status_code == 422
    assert all(name in response.json()["detail"] for name in GRADES)


def test_drive_answers_gears_per_stage(client: SynthClient) -> None:
    example = DriveIn.model_config["json_schema_extra"]["examples"][0]   # type: ignore[index]
    out = client.gears_drive(DriveIn.model_validate(example))
    assert out.gears is not None and len(out.gears) == 2
    for k, g in enumerate(out.gears):
        assert g is not None
        assert g.pinion_torque_Nm == pytest.approx(out.shafts[k].torque_Nm, rel=1e-12)
        assert min(g.safety_contact) >= 1.1 * (1 - 1e-9) and min(g.safety_root) >= 1.5 * (1 - 1e-9)
        # Centre distance of an unshifted pair: (d1 + d2)/2.
        assert g.centre_distance_mm == pytest.approx(sum(g.reference_diameters_mm) / 2, rel=1e-9)
        assert g.binding in g.margins or g.binding == "min_face_width"
    assert out.gear_mass_kg == pytest.approx(sum(g.mass_kg for g in out.gears if g is not None))
