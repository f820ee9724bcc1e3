"""The machine chain's split and the tooth search agree: a drive the teeth endpoint builds, the chain builds.

Independent derivation used throughout: the largest ratio one external pair makes within the tooth bounds is the
largest wheel over the smallest pinion free of undercut, max_teeth / ceil(2 / sin² 20°) = 100 / 18, written here
from the involute undercut condition, not from the engine's tables.
"""

from __future__ import annotations

import copy
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import synth
from api.translate.machine import machine_from
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.gearing import TeethIn
from mechsynth_client.schemas.machine import FOURBAR_MACHINE_EXAMPLE, MachineIn
from synth.machine.chain import TOOTH_RATIO_ROOM

MAX_TEETH = 100
SMALLEST_PINION = math.ceil(2 / math.sin(math.radians(20.0)) ** 2)   # undercut limit 17.1 -> 18 teeth
LARGEST_PAIR_RATIO = MAX_TEETH / SMALLEST_PINION


def _body(speed_rpm: float, samples: int | None = None) -> MachineIn:
    body = copy.deepcopy(FOURBAR_MACHINE_EXAMPLE)
    body.update(speed_rpm=speed_rpm, alternatives=False,
                drive={"stages": ["helical", "helical"], "synchronous_rpm": 1500})
    if samples is not None:
        body["samples"] = samples
        body["drive"]["size_gears"] = False
    return MachineIn.model_validate(body)


def test_two_helical_stages_at_62_rpm_design_and_pass(client: SynthClient) -> None:
    # the teeth endpoint builds this train at once (the chain used to refuse it: 422, no pair for stage 1)
    alone = client.gears_teeth(TeethIn.model_validate({"total_ratio": 1435 / 62, "stages": 2}))
    assert all(m.gear_teeth / m.pinion_teeth <= LARGEST_PAIR_RATIO + 1e-12 for m in alone.stages)
    design = client.design_machine(_body(62))
    assert design.passed
    split = design.drive.stage_ratios
    assert max(split) <= LARGEST_PAIR_RATIO * (1 + 1e-9)
    # the real ratios are the teeth's, each pair within the bounds, within the room around the split's ratio
    teeth = design.teeth
    assert teeth is not None
    for mesh, u in zip(teeth.stages, split, strict=True):
        assert SMALLEST_PINION <= min(mesh.pinion_teeth, mesh.gear_teeth)
        assert max(mesh.pinion_teeth, mesh.gear_teeth) <= MAX_TEETH
        assert mesh.gear_teeth / mesh.pinion_teeth == pytest.approx(u, rel=TOOTH_RATIO_ROOM)
    # the split sits on the largest ratio a pair makes: the answer says which stage and which limit
    at_limit = [w for w in design.warnings if w.code == "stage_ratio_at_teeth_limit"]
    assert at_limit and all(w.value == pytest.approx(LARGEST_PAIR_RATIO, rel=1e-9) for w in at_limit)
    assert {w.field for w in at_limit} <= {"drive.stages[0]", "drive.stages[1]"}
    # the message names the stage its field points at: stages[0] is "the first stage", stages[1] "the second"
    for w in at_limit:
        named = {"drive.stages[0]": "the first stage", "drive.stages[1]": "the second stage"}[w.field]
        assert w.message.startswith(named), (w.field, w.message)
        # and the ratio it sits at is that stage's share of the split
        assert w.value == pytest.approx(split[int(w.field[-2])], rel=1e-9)


@settings(max_examples=12)
@given(speed_rpm=st.floats(35.0, 400.0))
def test_where_the_teeth_find_a_train_the_chain_designs(speed_rpm: float) -> None:
    # 1500/n is the largest ratio a motor of the 1500 rpm class can ask for; slower motors ask less, and the tooth
    # search's closest mode answers every ratio between its reach's ends
    stages = synth.make_stages(["helical", "helical"], max_stages=4)
    try:
        synth.tooth_numbers(1500 / speed_rpm, stages)
    except synth.Infeasible:
        return
    design = synth.design_machine(machine_from(_body(speed_rpm, samples=72), max_stages=4))
    assert all(math.isfinite(u) for u in design.stage_ratios)
    assert design.teeth is not None
    assert math.prod(design.stage_ratios) == pytest.approx(design.teeth.total_ratio, rel=1e-12)
