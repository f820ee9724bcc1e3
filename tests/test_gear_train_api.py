"""POST /v1/gears/train against the seeds' gear-train cases and Willis' equation, through the client."""

from __future__ import annotations

import pytest

from mechsynth_client.client import InvalidInputError, SynthClient
from mechsynth_client.schemas.train import TrainIn
from conftest import CASES


def _mesh(z1: int, z2: int, **kw: object) -> dict:
    return {"driving_teeth": z1, "driven_teeth": z2, **kw}


def test_example_10_3_ratio_and_output_speed(client: SynthClient) -> None:
    # Seed 004:592-613: U14 = (-1)^2 (30/20)(36/18)(100/25) = 12 with two external meshes (3'-4 internal).
    case = CASES["gear_train_example_10_3"]
    z, exp = case["inputs"], case["expected"]
    body = TrainIn.model_validate({"elements": [_mesh(z["Z1"], z["Z2"]), _mesh(z["Z2p"], z["Z3"]),
                                                _mesh(z["Z3p"], z["Z4"], internal=True)],
                                   "input_speed_rad_s": z["omega1_rad_s"]})
    out = client.gears_train(body)
    assert out.external_meshes == z["external_meshes"]
    assert out.ratio == pytest.approx(exp["U14"], rel=case["tolerance_rel"])
    assert out.shafts[-1].speed_rad_s == pytest.approx(exp["omega4_rad_s"], rel=case["tolerance_rel"])
    assert out.output_direction == 1 and out.checks.agrees


@pytest.mark.parametrize("case_id", ["gear_train_variant_1", "gear_train_variant_2", "gear_train_variant_3",
                                     "gear_train_variant_4", "gear_train_variant_5", "gear_train_variant_8"])
def test_self_study_variants(client: SynthClient, case_id: str) -> None:
    # The case's assumed layout: 1-2 mesh, 2 and 3 on one shaft, 3-4 mesh; magnitudes only. Speeds are given at
    # whichever end the case gives them. The case prints 6 significant digits (variant 5: 0.166667), hence 5e-6.
    case = CASES[case_id]
    z, exp = case["inputs"], case["expected"]
    rel = max(case["tolerance_rel"], 5e-6)
    elements = [_mesh(z["z1"], z["z2"]), _mesh(z["z3"], z["z4"])]
    if "omega1_rad_s" in z:
        out = client.gears_train(TrainIn.model_validate({"elements": elements, "input_speed_rad_s": z["omega1_rad_s"]}))
        assert abs(out.shafts[-1].speed_rad_s) == pytest.approx(exp["omega4_rad_s"], rel=rel)
    else:
        out = client.gears_train(TrainIn.model_validate({"elements": elements, "output_speed_rad_s": z["omega4_rad_s"]}))
        assert abs(out.shafts[0].speed_rad_s) == pytest.approx(exp["omega1_rad_s"], rel=rel)
    assert abs(out.ratio) == pytest.approx(exp["U14_magnitude"], rel=rel)


def test_idler_cancels(client: SynthClient) -> None:
    # Test item: the idler 2 cancels, U13 = z3/z1 = 2, + for two external meshes.
    case = CASES["test_idler_gear_ratio"]
    z = case["inputs"]
    body = TrainIn.model_validate({"elements": [_mesh(z["z1"], z["z2"]), _mesh(z["z2"], z["z3"], idler=True)]})
    out = client.gears_train(body)
    assert out.ratio == pytest.approx(case["expected"]["U13"], rel=case["tolerance_rel"])
    assert [w.name for w in out.wheels] == ["1", "2", "3"]


def test_pitch_diameters(client: SynthClient) -> None:
    # d = m·z; the course work's pair (its printed D1, D2 corrected) and the test item, in metres here.
    case = CASES["cw_gear_pitch_diameters"]
    z, exp = case["inputs"], case["expected"]
    out = client.gears_train(TrainIn.model_validate({"elements": [_mesh(z["Z1"], z["Z2"])], "module_m": z["module_m"]}))
    d = {w.name: w.pitch_diameter_m for w in out.wheels}
    assert d["1"] == pytest.approx(exp["D1_m"], rel=case["tolerance_rel"])
    assert d["2"] == pytest.approx(exp["D2_m"], rel=case["tolerance_rel"])
    assert abs(out.ratio) == pytest.approx(exp["u12"], rel=case["tolerance_rel"])
    item = CASES["test_pitch_diameter"]
    z = item["inputs"]
    out = client.gears_train(TrainIn.model_validate({"elements": [_mesh(z["z"], z["z"])],
                                                     "module_m": z["module_mm"] / 1000}))
    assert out.wheels[0].pitch_diameter_m * 1000 == pytest.approx(item["expected"]["d_mm"], rel=item["tolerance_rel"])


@pytest.mark.parametrize(("fixed", "inp", "outp"), [("ring", "sun", "carrier"), ("sun", "ring", "carrier"),
                                                    ("carrier", "sun", "ring"), ("ring", "carrier", "sun")])
def test_planetary_stage_obeys_willis(client: SynthClient, fixed: str, inp: str, outp: str) -> None:
    # Independent: Willis' equation (w_s - w_c)/(w_r - w_c) = -z_r/z_s with the held member at rest, solved here
    # by substitution for the free member's speed.
    zs, zp, zr, w_in = 20, 31, 82, 150.0
    body = TrainIn.model_validate({"elements": [{"type": "planetary", "sun_teeth": zs, "planet_teeth": zp,
                                                 "ring_teeth": zr, "fixed": fixed, "input": inp, "output": outp}],
                                   "input_speed_rad_s": w_in})
    out = client.gears_train(body)
    w = {fixed: 0.0, inp: w_in}
    i0 = -zr / zs
    if outp == "carrier":
        w["carrier"] = (w["sun"] - i0 * w["ring"]) / (1 - i0)
    elif outp == "ring":
        w["ring"] = (w["sun"] - w["carrier"]) / i0 + w["carrier"]
    else:
        w["sun"] = i0 * (w["ring"] - w["carrier"]) + w["carrier"]
    assert out.shafts[-1].speed_rad_s == pytest.approx(w[outp], rel=1e-12)
    assert (w["sun"] - w["carrier"]) == pytest.approx(i0 * (w["ring"] - w["carrier"]), rel=1e-12)


def test_impossible_trains_are_named(client: SynthClient) -> None:
    with pytest.raises(InvalidInputError) as err:
        client.gears_train(TrainIn.model_validate({"elements": [{"type": "planetary", "sun_teeth": 20,
                                                                 "planet_teeth": 30, "ring_teeth": 81}]}))
    assert err.value.problem["field"] == "elements[0].ring_teeth"


def test_a_ratio_beyond_any_real_train_is_named(client: SynthClient) -> None:
    # 64 stepped planetary stages of ratio 1 + (10000/1)·(10000/1) each: about 1e512, beyond floating point.
    element = {"type": "planetary", "sun_teeth": 1, "planet_teeth": 10000, "ring_teeth": 10000, "planet_ring_teeth": 1}
    with pytest.raises(InvalidInputError) as err:
        client.gears_train(TrainIn.model_validate({"elements": [element] * 64, "output_speed_rad_s": 1e6}))
    assert err.value.problem["field"].startswith("elements[")


@pytest.mark.parametrize(("fixed", "inp", "outp", "expected"), [
    # Independent closed forms with k = z_r/z_s = 4 and eta0 = 0.95 (seed digest section 9: efficiency is the
    # useful over the driving work; the loss is the meshes' in the carrier's frame):
    ("ring", "sun", "carrier", (1 + 0.95 * 4) / (1 + 4)),  # sun in, ring held
    ("sun", "ring", "carrier", 1 - 0.05 / (1 + 4)),  # ring in, sun held: the meshes carry a fifth of the power
    ("carrier", "sun", "ring", 0.95),  # carrier held: an ordinary train
])
def test_planetary_efficiency_depends_on_the_held_member(client: SynthClient, fixed: str, inp: str, outp: str,
                                                         expected: float) -> None:
    body = TrainIn.model_validate({"elements": [{"type": "planetary", "sun_teeth": 20, "planet_teeth": 30,
                                                 "ring_teeth": 80, "fixed": fixed, "input": inp, "output": outp,
                                                 "basic_efficiency": 0.95}]})
    assert client.gears_train(body).efficiency == pytest.approx(expected, rel=1e-12)
