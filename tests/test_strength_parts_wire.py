"""The parts block on the wire: a JSON block to the engine's specs, the sized parts back to JSON."""

from __future__ import annotations

import json
import math

import pydantic
import pytest

import synth
from api.translate.strength_parts import parts_out, parts_spec
from mechsynth_client.schemas.strength_parts import PartsIn, PartsOut
from synth.strength.parts import size_parts
from synth.strength.pins import load_kind
from test_strength_links import press

RPM = 2 * math.pi / 60
BLOCK = {
    "pin_material": {"grade": "C45E+QT"},
    "bearing": {"kind": "bushing", "bushing_material": "cast_bronze_greased"},
    "joints": [{"joint": "Q", "bearing": {"kind": "rolling", "life_hours": 30000}},
               {"joint": "C", "pin": {"shear_planes": 1, "rod_thickness_mm": 30, "fixed_in": "rocker"}}],
    "crank_shaft": {"span_mm": 250, "crank_position_mm": -60, "drive_position_mm": 125, "drive": "gear",
                    "pitch_radius_mm": 120, "mesh_angle_deg": 200, "helix_angle_deg": 12,
                    "flywheel_position_mm": 320, "flywheel_mass_kg": 40,
                    "keys": [{"hub": "crank", "hub_length_mm": 90, "allowed_pressure_MPa": 150},
                             {"hub": "flywheel", "hub_length_mm": 90, "allowed_pressure_MPa": 150}]},
}


def test_parts_block_round_trip_on_the_press() -> None:
    block = PartsIn.model_validate(BLOCK)
    analysis = synth.analyse(press(), 60 * RPM, samples=360)
    out = parts_out(size_parts(analysis, parts_spec(block)))
    again = PartsOut.model_validate_json(out.model_dump_json())
    assert again == out
    by_joint = {j.joint: j for j in out.joints}
    # The crank's pivot O is the crank shaft's journal: sized with the shaft, not as a pin.
    assert set(by_joint) == {"A", "B", "Q", "C", "D"}
    assert by_joint["Q"].rolling is not None and by_joint["Q"].rolling.oscillating
    assert by_joint["A"].bushing is not None and by_joint["A"].bushing.material == "cast_bronze_greased"
    assert by_joint["Q"].links == ["frame", "rocker"]
    # The pin pressed into the rocker reads its kind of load in the rocker's frame.
    expected = load_kind(analysis.kinetostatics.reactions["C"], analysis.motion.link_angle["rocker"])
    assert by_joint["C"].pin.load_kind == expected
    assert out.crank_shaft is not None and [k.hub for k in out.crank_shaft.keys] == ["crank hub", "flywheel hub"]
    assert out.crank_shaft.keys[0].designation.startswith("DIN 6885 A ")
    assert len(out.crank_shaft.bearings) == 2
    # Every part's own figures are in the one list of checks, converted to MPa, mm and hours.
    names = {c.name for c in out.checks}
    assert {"pin_bending", "bushing_pv", "bearing_life", "shaft_fatigue_safety", "key_pressure"} <= names
    life = next(c for c in out.checks if c.part == "joint Q" and c.name == "bearing_life")
    assert life.value == pytest.approx(by_joint["Q"].rolling.life_hours) and life.limit == 30000.0
    assert out.passed == all(c.passed for c in out.checks)
    assert [w.code for w in out.warnings] == ["shaft_axial_load"]
    json.loads(out.model_dump_json())


def test_parts_block_refuses_naming_the_field() -> None:
    with pytest.raises(pydantic.ValidationError, match="pitch_radius_mm"):
        PartsIn.model_validate({"crank_shaft": {"span_mm": 200, "crank_position_mm": 0, "drive_position_mm": 100,
                                                "drive": "gear"}})
    with pytest.raises(pydantic.ValidationError):
        PartsIn.model_validate({"bearing": {"kind": "ball"}})
    analysis = synth.analyse(press(), 60 * RPM, samples=36)
    with pytest.raises(synth.InvalidInput, match="not revolute joints") as exc:
        size_parts(analysis, parts_spec(PartsIn.model_validate({"joints": [{"joint": "guide"}]})))
    assert exc.value.field == "joints"
    twice = {"joints": [{"joint": "A"}, {"joint": "A"}]}
    with pytest.raises(synth.InvalidInput, match="listed twice") as exc:
        parts_spec(PartsIn.model_validate(twice))
    assert exc.value.field == "parts.joints[1].joint"
    own = {"pin_material": {"name": "mine", "yield_strength_MPa": 300}}
    with pytest.raises(pydantic.ValidationError, match="carries every limit"):
        PartsIn.model_validate(own)
