"""A machine design an office can sign: the README machines meet every check at the motor's real operating point,
every stage's warnings reach the top level, likely unit mistakes are refused before the chain, the flywheel is
named where it sits, and the PDF report is an A4 design record whose text holds the inputs."""

from __future__ import annotations

import copy
import hashlib
import io
import json
import math
import re
from typing import Any

import numpy as np
import pytest
from pypdf import PdfReader

import synth
from api.translate.machine import machine_from
from mechsynth_client.client import InfeasibleError, InvalidInputError, SynthClient
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE
from mechsynth_client.schemas.machine import PRESS_EXAMPLE, MachineIn
from synth.machine.record import DesignRecord
from synth.machine.report import design_report_pdf
from synth.machine.stages import stage

RPM = math.pi / 30
# The README's four-bar machine ("Design a whole machine"): before the ratio followed the motor's operating
# point it answered passed=false, the crank at 315.6 rpm for 300.
FOURBAR_MACHINE: dict[str, Any] = {
    "mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "delta": 0.01,
    "loads": [{"type": "window", "torque_Nm": 40, "start_deg": 0, "end_deg": 180}],
    "drive": {"stages": ["helical"], "synchronous_rpm": 1500}, "balancing": {"mode": "full"}}


def _body(base: dict[str, Any], **changes: Any) -> MachineIn:
    body = copy.deepcopy(base)
    body.update(changes)
    return MachineIn.model_validate(body)


def _operating_speed(motor: Any, power: float) -> float:
    """Written apart from the engine: k·(w_s - w)·w = power on the line from (w_s, 0) through the rated point,
    the upper root [rad/s]."""
    ws, wr = motor.synchronous_rpm * RPM, motor.rated_rpm * RPM
    k = motor.rated_power_W / wr / (ws - wr)
    return 0.5 * (ws + math.sqrt(ws * ws - 4 * power / k))


@pytest.fixture(scope="module")
def fourbar(client: SynthClient):  # type: ignore[no-untyped-def]
    return client.design_machine(_body(FOURBAR_MACHINE))


@pytest.mark.parametrize("name", ["fourbar", "press"])
def test_readme_machines_meet_every_check_at_the_motors_operating_point(client: SynthClient, fourbar,  # type: ignore[no-untyped-def]
                                                                        name: str) -> None:
    out = fourbar if name == "fourbar" else client.design_machine(MachineIn.model_validate(PRESS_EXAMPLE))
    assert out.passed and all(c.passed for c in out.checks), out.checks
    speed = next(c for c in out.checks if c.name == "mean_speed")
    target = 300.0 if name == "fourbar" else float(PRESS_EXAMPLE["speed_rpm"])  # type: ignore[arg-type]
    # the simulated crank runs at the working speed within the tooth rounding (TOOTH_RATIO_ROOM is 5 %; the
    # teeth found here are within 1 %), far inside the 5 % tolerance that failed before
    assert speed.value == pytest.approx(abs(out.simulation.mean_crank_speed_rpm / target - 1), rel=1e-9)
    assert speed.value < 0.01
    # the ratio is the operating speed over the working speed, the operating speed from the catalogue data
    # (independent formula above) at the mean crank power over the train's efficiency
    w_op = _operating_speed(out.motor.motor, out.reduced.mean_power_W / out.motor.train_efficiency)
    assert out.motor.operating_speed_rpm == pytest.approx(w_op / RPM, rel=1e-12)
    assert out.drive.total_ratio == pytest.approx(w_op / (target * RPM), rel=1e-12)
    assert out.motor.motor.rated_rpm < out.motor.operating_speed_rpm < out.motor.motor.synchronous_rpm
    # check figure: the simulated machine's mean motor speed lands on that operating point; they differ by the
    # tooth rounding's change of the crank power and by the time- against angle-average (order delta²)
    assert out.motor.simulated_mean_speed_rpm == pytest.approx(out.motor.operating_speed_rpm, rel=2e-3)


def test_a_millimetre_machine_is_refused_naming_the_field(client: SynthClient) -> None:
    mm = dict(FOURBAR_EXAMPLE, ground_length_m=300, crank_length_m=100, coupler_length_m=250, rocker_length_m=250)
    with pytest.raises(InvalidInputError) as err:
        client.design_machine(_body(FOURBAR_MACHINE, mechanism=mm))
    problem = err.value.problem
    # the same code /v1/analysis warns with, before any solver runs (it used to answer "shooting ... did not
    # converge")
    assert problem["code"] == "length_likely_mm" and problem["field"] == "mechanism.ground_length_m"
    assert "millimetres" in problem["detail"] and "shooting" not in problem["detail"]
    assert client.http.post("/v1/analysis", json={"mechanism": mm, "speed_rpm": 300}).json()["warnings"][0][
        "code"] == "length_likely_mm"


def test_gram_masses_are_refused_too(client: SynthClient) -> None:
    grams = copy.deepcopy(FOURBAR_EXAMPLE)
    grams["links"]["coupler"]["mass_kg"] = 2000.0  # type: ignore[index]
    r = client.http.post("/v1/machines/design", json=_body(FOURBAR_MACHINE, mechanism=grams).model_dump(mode="json"))
    assert r.status_code == 422 and r.json()["code"] == "mass_likely_grams"
    assert r.json()["field"] == "mechanism.links.coupler.mass_kg"


def _transmission_angle_min(ground: float, crank: float, coupler: float, rocker: float) -> float:
    """Independent of the engine: the deviation of the transmission angle from 90° is largest where the diagonal
    B-O... A-Q is longest or shortest; the law of cosines over a fine crank grid [deg]."""
    phi = np.linspace(0, 2 * np.pi, 200_001)
    diag2 = ground**2 + crank**2 - 2 * ground * crank * np.cos(phi)
    mu = np.arccos((coupler**2 + rocker**2 - diag2) / (2 * coupler * rocker))
    return float(np.degrees(np.minimum(mu, np.pi - mu)).min())


def test_stage_warnings_reach_the_top_level_and_the_report(client: SynthClient) -> None:
    body = _body(FOURBAR_MACHINE, mechanism=dict(FOURBAR_EXAMPLE, crank_length_m=0.14))
    out = client.design_machine(body)
    low = [w for w in out.warnings if w.code == "transmission_angle_low"]
    assert len(low) == 1 and low[0].stage == "analysis" and low[0].field == "mechanism"
    # 37.3° in the issue; the warning takes the smallest over the 360 samples, the grid here is 500 times finer
    assert low[0].value == pytest.approx(_transmission_angle_min(0.30, 0.14, 0.25, 0.25), abs=0.02)
    assert low[0].value == pytest.approx(37.3, abs=0.05)
    assert {w.stage for w in out.warnings} >= {"analysis", "drive"}
    assert all(w.stage is not None for w in out.warnings)
    # the record as the endpoint writes it, made here past the request's deadline (a busy machine)
    record = DesignRecord.of(body.model_dump(mode="json"), name=body.name, version="0.0-test")
    text = _pdf_text(design_report_pdf(synth.design_machine(machine_from(body, 4)), record=record))
    assert "transmission_angle_low" in text and "[analysis]" in text


def _pdf_text(pdf: bytes) -> str:
    return "\n".join(page.extract_text() for page in PdfReader(io.BytesIO(pdf)).pages)


def test_flywheel_is_named_where_it_sits(fourbar) -> None:  # type: ignore[no-untyped-def]
    body = fourbar.flywheel_body
    assert body is not None and body.shaft == fourbar.flywheel_shaft == "motor"
    # identity: inertia on the shaft times the square of its speed ratio is the crank-equivalent, which is the
    # flywheel sizing's figure
    assert body.crank_equivalent_inertia_kgm2 == pytest.approx(body.inertia_on_shaft_kgm2 * body.speed_ratio**2,
                                                               rel=1e-12)
    assert body.crank_equivalent_inertia_kgm2 == pytest.approx(fourbar.flywheel.flywheel_inertia_kgm2, rel=1e-9)
    assert body.speed_ratio == pytest.approx(fourbar.motor.train_ratio, rel=1e-12)
    # the body's inertia from its dimensions, computed here: a rim of density 7200 kg/m³ (the default cast iron)
    r_out, r_in = body.outer_diameter_m / 2, body.outer_diameter_m / 2 - body.rim_thickness_m
    mass = 7200.0 * math.pi * (r_out**2 - r_in**2) * body.width_m
    assert body.mass_kg == pytest.approx(mass, rel=1e-6)
    assert body.inertia_on_shaft_kgm2 == pytest.approx(0.5 * mass * (r_out**2 + r_in**2), rel=1e-6)


def test_report_is_an_a4_design_record_with_its_inputs(client: SynthClient, fourbar) -> None:  # type: ignore[no-untyped-def]
    title_block = {"project": "Press line 4", "number": "MD-0042", "revision": "B", "designed_by": "A. Designer",
                   "designed_on": "2026-11-20", "checked_by": "B. Checker", "state": "checked"}
    body = _body(FOURBAR_MACHINE, name="four-bar at 300 rpm", alternatives=True, title_block=title_block)
    # the record as the endpoint writes it (api.execution.tasks.design_file), made here without the request's
    # deadline: four designs and the record take longer than it on a busy machine
    spec = machine_from(body, 4)
    record = DesignRecord.of(body.model_dump(mode="json"), name=body.name, version="0.0-test")
    pdf = design_report_pdf(synth.design_machine(spec), synth.alternatives(spec), record=record)
    reader = PdfReader(io.BytesIO(pdf))
    # A4 landscape on every page: 297 x 210 mm in points
    for page in reader.pages:
        assert float(page.mediabox.width) == pytest.approx(297 / 25.4 * 72, abs=1.0)
        assert float(page.mediabox.height) == pytest.approx(210 / 25.4 * 72, abs=1.0)
    text = _pdf_text(pdf)
    # title block: name, date, version and the hash of the request as sent (canonical JSON, computed here), which
    # leaves the title block out: signing a revision does not change the design's identity
    design = {k: v for k, v in body.model_dump(mode="json").items() if k != "title_block"}
    canonical = json.dumps(design, sort_keys=True, separators=(",", ":"), ensure_ascii=False)
    digest = hashlib.sha256(canonical.encode()).hexdigest()
    assert "four-bar at 300 rpm" in text and digest in text and "mechsynth 0.0-test" in text
    first = reader.pages[0].extract_text()
    for value in title_block.values():
        assert value in first, value
    single = _body(FOURBAR_MACHINE, title_block=title_block)
    alone = {k: v for k, v in single.model_dump(mode="json").items() if k != "title_block"}
    assert "approved" in first and client.design_machine(single).request_sha256 == hashlib.sha256(
        json.dumps(alone, sort_keys=True, separators=(",", ":"), ensure_ascii=False).encode()).hexdigest()
    # wording and units: the family in words, a one-stage train ratio once, every check with its unit
    assert re.search(r"mechanism\s+four-bar", text) and "FourBar" not in text
    ratio = re.search(r"train ratio \(teeth\)\s+(\S+)\s", text)
    assert ratio is not None and not text[ratio.end():ratio.end() + 3].startswith("=")
    for label, unit in [("motor torque, RMS (heating)", "N·m"), ("motor torque, peak", "N·m"),
                        ("motor starts the machine", "N·m"), ("start-up time", "s")]:
        assert re.search(rf"{re.escape(label)}\s+[-\d.e]+ {re.escape(unit)}\s+≤ [-\d.e]+ {re.escape(unit)}", text), label
    assert re.search(r"\d{4}-\d\d-\d\d \d\d:\d\d:\d\d UTC", text)
    # every input with its unit
    for path, value, unit in [("mechanism.crank_length_m", "0.1", "m"), ("speed_rpm", "300", "rpm"),
                              ("loads[0].torque_Nm", "40", "N·m"), ("drive.synchronous_rpm", "1500", "rpm"),
                              ("mechanism.links.coupler.inertia_kgm2", "0.02", "kg·m²"), ("delta", "0.01", "-")]:
        assert re.search(rf"{re.escape(path)}\s+{re.escape(value)}\s+{re.escape(unit)}", text), path
    # stages with their check figures, counterweights with their discs, the gear table, flywheel, motor
    for words in ["Stages and their check figures", "virtual power", "steel disc diameter", "pinion teeth",
                  "Gear train", "inertia on its shaft", "crank-equivalent inertia", "operating speed under the mean "
                  "load", "What each balancing choice costs", "on the motor shaft"]:
        assert words in re.sub(r"\s+", " ", text), words   # a table's header may wrap inside its cell
    assert "flywheel on crank" not in text
    # a full balance leaves solver noise (1e-13 N) in the residual: printed as 0, never as 1.954e-13
    assert not re.search(r"\de-1[0-9]", text)
    assert re.search(r"shaking force / moment re-analysed\s+0 N / 0 N·m", text)


def test_failing_stage_is_named_with_its_cause(client: SynthClient) -> None:
    # a fixed stage ratio the motor's operating point cannot use: the drive stage says so, with the ratio that
    # would give the working speed
    body = _body(FOURBAR_MACHINE, drive={"stages": [{"type": "helical", "ratio": 4}], "synchronous_rpm": 1500})
    with pytest.raises(InfeasibleError) as err:
        client.design_machine(body)
    p = err.value.problem
    assert p["stage"] == "drive" and p["detail"].startswith("drive stage:")
    # the ratio that would: the operating speed of the chosen motor over 300 rpm (formula above)
    free = client.design_machine(_body(FOURBAR_MACHINE))
    assert p["total_ratio"] == pytest.approx(free.drive.total_ratio, rel=1e-9)
    assert p["reachable_max"] == pytest.approx(4.0, rel=1e-12)


def test_solver_words_become_the_stage_cause() -> None:
    with pytest.raises(synth.SolverFailed) as err:
        with stage("simulation"):
            raise synth.SolverFailed("no_periodic_motion", "shooting for the periodic motion did not converge")
    assert err.value.stage == "simulation" and err.value.status == "no_periodic_motion"
    message = str(err.value)
    assert message.startswith("simulation stage: the assembled machine finds no steady motion")
    assert "larger motor" in message and "(the solver said: shooting" in message
    # an inner stage's mark stays when an outer stage passes the error on
    with pytest.raises(synth.InvalidInput) as inner:
        with stage("flywheel"), stage("simulation"):
            raise synth.InvalidInput("x", field="f")
    assert inner.value.stage == "simulation" and str(inner.value) == "simulation stage: x"


def test_the_answers_one_check_list_holds_the_start_up_and_decides_the_verdict(client: SynthClient) -> None:
    # The README press asked to run up within half a second: it cannot, and the one list of checks says so.
    out = client.design_machine(_body(PRESS_EXAMPLE, max_startup_time_s=0.5))
    startup = next(c for c in out.checks if c.name == "startup_time")
    assert out.running is not None and out.running.startup.steady_time_s is not None
    # the check's value is the run-up time the answer reports, held against the 0.5 s asked for
    assert startup.value == pytest.approx(out.running.startup.steady_time_s, rel=1e-12) and startup.limit == 0.5
    assert startup.value > 0.5 and not startup.passed and startup.unit == "s" and startup.label == "start-up time"
    assert out.passed is False and out.passed == all(c.passed for c in out.checks)
    assert [c.name for c in out.checks if not c.passed] == ["startup_time"]
    assert "checks" not in out.running.model_dump()


def test_every_input_unit_of_the_record_is_the_one_its_description_gives() -> None:
    """The inputs table reads a unit off each field name; the manual states it in the description's last bracket.
    The two agree for every field of a machine request that has both (degrees and rev/min spelled either way)."""
    from synth.machine.record import unit_of

    same = {"deg": "°", "rev/min": "rpm"}
    seen: dict[str, str] = {}

    def walk(node: Any) -> None:
        if isinstance(node, dict):
            for key, prop in (node.get("properties") or {}).items():
                found = re.findall(r"\[([^\]]+)\]", prop.get("description", "")) if isinstance(prop, dict) else []
                if found and unit_of(key) and re.fullmatch(r"[\w·/²³°-]+", found[-1]):
                    seen[key] = found[-1]
            for v in node.values():
                walk(v)
        elif isinstance(node, list):
            for v in node:
                walk(v)

    walk(MachineIn.model_json_schema())
    assert {"oil_viscosity_40C_mm2_s", "life_h", "torque_Nm", "speed_rpm"} <= set(seen)
    for key, unit in seen.items():
        assert unit_of(key) == same.get(unit, unit), key
