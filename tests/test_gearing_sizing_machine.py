"""The machine chain sizes its gears from the cyclic torque each pinion shaft passes on: the press and the four-bar
of the manual answer module, face width, centre distance and safety factors, and the design record shows them."""

from __future__ import annotations

import io
import math
from typing import Any

import numpy as np
import pytest
from pypdf import PdfReader

import synth
from api.translate.machine import machine_from
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.machine import FOURBAR_MACHINE_EXAMPLE, PRESS_EXAMPLE, MachineIn
from synth.machine.chain import _shaft_torques, _time_weights


@pytest.fixture(scope="module", params=["press", "fourbar"])
def machine(request: pytest.FixtureRequest) -> tuple[MachineIn, synth.MachineDesign]:
    body: dict[str, Any] = {"press": PRESS_EXAMPLE, "fourbar": FOURBAR_MACHINE_EXAMPLE}[request.param]
    m = MachineIn.model_validate(body)
    return m, synth.design_machine(machine_from(m, 12))


def test_every_cylindrical_stage_is_sized(machine: tuple[MachineIn, synth.MachineDesign]) -> None:
    _, d = machine
    assert d.gears is not None
    for k, s in enumerate(d.spec.drive.stages):
        g = d.gears.stages[k]
        if s.type not in ("spur", "helical", "open_spur"):
            assert g is None
            continue
        assert g is not None
        rules = d.spec.drive.strength
        assert rules is not None
        assert min(g.safety_contact) >= rules.duty.min_safety_contact * (1 - 1e-9)
        assert min(g.safety_root) >= rules.duty.min_safety_root * (1 - 1e-9)
        # The sized pair is rated at the peak torque the pinion shaft passes on in the simulated steady motion.
        assert g.rating.pinion_torque == pytest.approx(d.shafts[k].peak_torque, rel=1e-12)
        # Its teeth are the tooth search's, so the real ratio is the machine's.
        assert g.gear_teeth / g.pinion_teeth == pytest.approx(d.stage_ratios[k], rel=1e-12)


def test_spectrum_safety_is_miner_on_the_shaft_torque(machine: tuple[MachineIn, synth.MachineDesign]) -> None:
    # Independent path: rate the sized pair again on the shaft's torque series with its time weights.
    _, d = machine
    assert d.gears is not None and d.spec.drive.strength is not None
    torques = _shaft_torques(d.stage_ratios, d.drive, d.motion, d.placement, d.flywheel.design.flywheel_inertia)
    weights = _time_weights(d.motion)
    # time weights are the trapezoid rule of time_mean: the mean torque agrees with the shaft's
    assert float(weights @ torques[0]) == pytest.approx(d.shafts[0].mean_torque, rel=1e-3)
    for g in d.gears.stages:
        if g is None:
            continue
        spec = synth.GearPairSpec(g.pinion_teeth, g.gear_teeth, g.module, g.face_width, g.helix_angle,
                                  materials=d.spec.drive.strength.materials,
                                  accuracy_grade=d.spec.drive.strength.accuracy_grade,
                                  max_face_width_ratio=d.spec.drive.strength.max_face_width_ratio * 1.000001)
        s = synth.rate_spectrum(spec, torques[g.stage], d.shafts[g.stage].mean_speed, d.spec.drive.strength.duty,
                                weights)
        assert s.safety_contact == pytest.approx(g.safety_contact, rel=1e-6)
        assert s.safety_root == pytest.approx(g.safety_root, rel=1e-6)
        # The cyclic load is lighter than its peak held for the whole life.
        assert min(s.safety_contact) >= min(s.peak.safety_contact)


def test_the_cycle_sizes_lighter_than_its_peak(machine: tuple[MachineIn, synth.MachineDesign]) -> None:
    _, d = machine
    assert d.gears is not None and d.spec.drive.strength is not None
    for g in d.gears.stages:
        if g is None:
            continue
        peak = synth.size_stage(g.ratio, synth.StageLoad(d.shafts[g.stage].peak_torque, d.shafts[g.stage].mean_speed),
                                d.spec.drive.strength, helix_angle=g.helix_angle, pinion_teeth=g.pinion_teeth)
        assert g.mass <= peak.mass * (1 + 1e-9)


def test_machine_answer_and_report_carry_the_gears(client: SynthClient) -> None:
    press = MachineIn.model_validate(PRESS_EXAMPLE)
    out = client.design_machine(press)
    assert out.gears is not None and out.gears[0] is not None
    g = out.gears[0]
    assert g.module_mm in [m * 1e3 for m in synth.module_series("first")]
    assert g.centre_distance_mm == pytest.approx(sum(g.reference_diameters_mm) / 2, rel=1e-9)
    # reference diameter z m_n / cos(beta), written out
    assert g.reference_diameters_mm[0] == pytest.approx(
        g.pinion_teeth * g.module_mm / math.cos(math.radians(g.helix_angle_deg)), rel=1e-12)
    # a table's header wraps inside its column: words are compared, not line breaks
    text = " ".join(" ".join(page.extract_text().split())
                    for page in PdfReader(io.BytesIO(client.design_report_pdf(press))).pages)
    assert "module" in text and "centre distance" in text


def test_sizing_can_be_turned_off(client: SynthClient) -> None:
    body = {**PRESS_EXAMPLE, "drive": {**PRESS_EXAMPLE["drive"], "size_gears": False}}   # type: ignore[dict-item]
    out = client.design_machine(MachineIn.model_validate(body))
    assert out.gears is None
    assert np.isfinite(out.shafts[0].peak_torque_Nm)
