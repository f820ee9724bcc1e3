"""The machine's parts sized for strength through POST /v1/machines/design: a four-bar machine and the six-bar
press with every link, pin, bearing, crank shaft and key in the answer, their checks in the machine's one list,
the links sized before balancing and the machine analysed with them."""

from __future__ import annotations

import copy
import math
from typing import Any

import pytest

import synth
from api.translate.machine import machine_from
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.common import SIX_BAR_PRESS_EXAMPLE
from mechsynth_client.schemas.machine import FOURBAR_MACHINE_EXAMPLE, MachineIn

STRENGTH: dict[str, Any] = {"section": {"kind": "rectangle", "ratio": 3, "min_size_mm": 6}}
FOURBAR = {**copy.deepcopy(FOURBAR_MACHINE_EXAMPLE), "alternatives": False, "samples": 120,
           "strength": {**STRENGTH, "parts": {"bearing": {"kind": "rolling", "life_hours": 20000}}}}
PRESS = {"mechanism": SIX_BAR_PRESS_EXAMPLE, "gravity": {"g_m_s2": 9.81},
         "loads": [{"type": "window", "force_N": 2000, "start_deg": 0, "end_deg": 180}],
         "speed_rpm": 60, "samples": 120, "delta": 0.05,
         "drive": {"stages": ["helical", "helical"], "synchronous_rpm": 1500},
         "strength": {**STRENGTH, "links": [{"link": "crank", "section": {"kind": "round", "min_size_mm": 10}}]}}


@pytest.mark.parametrize(("body", "bars", "joints"), [
    (FOURBAR, {"crank", "coupler", "rocker"}, {"O", "A", "B", "Q"}),
    (PRESS, {"crank", "coupler", "rocker", "rod"}, {"O", "A", "B", "Q", "C", "D"}),
], ids=["fourbar", "press"])
def test_machine_sized_end_to_end(client: SynthClient, body: dict[str, Any], bars: set[str],
                                  joints: set[str]) -> None:
    out = client.design_machine(MachineIn.model_validate(body))
    s = out.strength
    assert s is not None
    assert {link.link for link in s.links} == bars
    # the crank's pivot is the crank shaft's journal on its two bearings; every other joint has a pin and a bushing or rolling bearing
    assert {j.joint for j in s.parts.joints} == joints - {"O"}
    assert all((j.bushing is not None or j.rolling is not None) and j.pin.diameter_mm >= j.pin.diameter_required_mm
               for j in s.parts.joints)
    shaft = s.parts.crank_shaft
    assert shaft is not None and shaft.diameter_mm >= shaft.diameter_required_mm > 0
    assert len(shaft.bearings) == 2
    assert {k.hub for k in shaft.keys} == {"crank hub", "coupling hub"}
    # the fixed point settled: its last pass chose the sections it was analysed with
    last = s.iterations[-1]
    assert last.sections == {link.link: link.section for link in s.links}
    assert last.largest_change_kg == 0.0
    # the machine was analysed with the sized links: the link masses in the answer's analysis are the bars'
    link_mass = {link.link: link.mass_kg for link in s.links}
    assert s.link_mass_kg == pytest.approx(sum(link_mass.values()), rel=1e-12)
    # every part's check is in the machine's one list, with the same verdict; the links' checks there too
    machine_checks = {c.name: c for c in out.checks}
    for c in s.parts.checks:
        assert machine_checks[f"{c.name}:{c.part}"].passed == c.passed
    for link in s.links:
        for c in link.checks:
            assert machine_checks[f"link_{c.name}:link {link.link}"].passed == c.passed
    assert out.passed == all(c.passed for c in out.checks)


def test_machine_links_are_the_sized_ones_in_its_analysis() -> None:
    spec = machine_from(MachineIn.model_validate(PRESS), 6)
    from api.translate.machine_strength import with_strength

    spec = with_strength(spec, MachineIn.model_validate(PRESS).strength)
    design = synth.design_machine(spec)
    assert design.strength is not None
    for name, sizing in design.strength.links.items():
        # the analysis before balancing carries the bar's mass rho A L exactly
        assert design.before.linkage.links[name].mass == pytest.approx(sizing.mass, rel=1e-12)
        # rho A L of the bar between its load points on the fixed point's analysis (before counterweights)
        bar = design.strength.sizing.links[name].forces
        assert sizing.mass == pytest.approx(sizing.material.density * sizing.section.area * bar.length, rel=1e-12)
    assert design.strength.parts.crank_shaft is not None
    assert math.isfinite(design.strength.parts.crank_shaft.shaft.fatigue_safety)


def test_the_design_record_has_the_parts_table_and_page() -> None:
    import io

    from pypdf import PdfReader

    from api.translate.machine_strength import with_strength
    from synth.machine.report import design_report_pdf

    body = MachineIn.model_validate(PRESS)
    design = synth.design_machine(with_strength(machine_from(body, 6), body.strength))
    assert design.strength is not None
    pages = [p.extract_text() for p in PdfReader(io.BytesIO(design_report_pdf(design))).pages]
    table = next(t for t in pages if "Parts sized for strength" in t)
    drawn = next(t for t in pages if "where its checks are least" in t)
    for name, link in design.strength.links.items():
        assert link.section.label in table and name in drawn and link.section.label in drawn
    for joint in design.strength.parts.joints:
        assert f"{joint}" in table
    assert "crank shaft" in table and "key, crank hub" in table
