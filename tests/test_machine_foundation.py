"""The machine around its linkage in one design request: the foundation, elastic-drive and regulation blocks of
POST /v1/machines/design answer what their own endpoints answer for the same inputs, and their limits join the
one list of checks that decides the verdict."""

from __future__ import annotations

import copy
import io
import math
from typing import Any

import numpy as np
import pytest

import synth
from api.translate.machine import machine_from
from mechsynth_client.client import InvalidInputError, SynthClient
from mechsynth_client.schemas.foundation import (
    FRAME_EXAMPLE,
    ISOLATORS_EXAMPLE,
    ElasticDriveIn,
    IsolationIn,
    RegulationIn,
)
from mechsynth_client.schemas.machine import PRESS_EXAMPLE, MachineDesignOut, MachineIn
from synth.machine.elastic_drive import ElasticDrive, ElasticRun, LoadHarmonic
from synth.machine.foundation_chain import elastic_shaft_torques

SAMPLES = 120
#: The link's stiffness at the crank [N·m/rad]: its natural frequency (about 46 Hz) sits between the 5th and 6th
#: harmonics of the crank's 8 Hz.
STIFFNESS = 1e4
#: The README's press unbalanced, so the standalone endpoints see the very linkage the chain designs with.
MACHINE: dict[str, Any] = {
    **PRESS_EXAMPLE, "samples": SAMPLES, "balancing": {"mode": "none"},
    "foundation": {"frame": FRAME_EXAMPLE, "isolators": ISOLATORS_EXAMPLE, "max_force_N": 1e4},
    "elastic_drive": {"stiffness_Nm_rad": STIFFNESS, "damping_ratio": 0.1, "start": False},
    "regulation": {"load_step_Nm": 40, "max_settling_time_s": 5.0},
}
SAME = 1e-9


@pytest.fixture(scope="module")
def design(client: SynthClient) -> MachineDesignOut:
    return client.design_machine(MachineIn.model_validate(MACHINE))


def _linkage_fields() -> dict[str, Any]:
    return {k: copy.deepcopy(MACHINE[k]) for k in ("mechanism", "loads", "speed_rpm", "samples")}


def _close(a: Any, b: Any) -> None:
    x, y = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert x.shape == y.shape
    assert np.max(np.abs(x - y)) <= SAME * max(float(np.max(np.abs(y))), 1e-300)


def _motor(d: MachineDesignOut) -> dict[str, Any]:
    """The design's motor through its real train, as the standalone endpoints take a motor."""
    return {"name": d.motor.motor.name, "gear_ratio": d.motor.train_ratio, "efficiency": d.motor.train_efficiency}


def test_foundation_block_answers_as_the_isolation_endpoint(client: SynthClient, design: MachineDesignOut) -> None:
    assert design.foundation is not None
    alone = client.isolate_machine(IsolationIn.model_validate(
        {**_linkage_fields(), "frame": FRAME_EXAMPLE, "isolators": ISOLATORS_EXAMPLE}))
    mine = design.foundation
    _close(mine.force_N, alone.force_N)
    _close(mine.displacement_m, alone.displacement_m)
    _close([m.frequency_Hz for m in mine.modes], [m.frequency_Hz for m in alone.modes])
    _close([h.transmitted_force_N for h in mine.harmonics], [h.transmitted_force_N for h in alone.harmonics])
    assert mine.peak_force_N == pytest.approx(alone.peak_force_N, rel=SAME)
    # its own check: the time integration agrees with the harmonic answer
    assert mine.checks.relative_diff < 1e-5
    check = next(c for c in design.checks if c.name == "foundation_force")
    assert check.value == pytest.approx(mine.peak_force_N, rel=1e-12) and check.passed


def test_elastic_drive_block_answers_as_the_elastic_drive_endpoint(client: SynthClient,
                                                                   design: MachineDesignOut) -> None:
    e = design.elastic_drive
    assert e is not None
    alone = client.elastic_drive(ElasticDriveIn.model_validate(
        {**_linkage_fields(), "motor": _motor(design), "stiffness_Nm_rad": STIFFNESS,
         "machine_inertia_kgm2": e.machine_constant_inertia_kgm2,
         "motor_side_inertia_kgm2": e.motor_side_inertia_kgm2, "damping_ratio": 0.1, "start": False}))
    assert e.natural_frequency_Hz == pytest.approx(alone.natural_frequency_Hz, rel=SAME)
    assert e.dynamic_factor == pytest.approx(alone.dynamic_factor, rel=SAME)
    _close(e.elastic_torque_Nm, alone.elastic_torque_Nm)
    # the press's flywheel sits on the motor shaft, so it turns on the rotor's side of the link
    assert design.flywheel_shaft == "motor" and design.flywheel_body is not None
    assert e.motor_side_inertia_kgm2 == pytest.approx(design.flywheel_body.inertia_on_shaft_kgm2, rel=1e-12)
    # two-mass closed form sqrt(c (J1 + J2) / (J1 J2)) at the mean J2, independently of the engine
    j1, j2 = e.rotor_inertia_kgm2, e.machine_inertia_kgm2[0]
    assert e.natural_frequency_Hz == pytest.approx(math.sqrt(STIFFNESS * (j1 + j2) / (j1 * j2)) / (2 * math.pi),
                                                   rel=1e-12)
    assert e.checks.closed_form_diff < 1e-9
    # the rotor side: the catalogue rotor and the flywheel, reduced by the train ratio squared
    assert j1 == pytest.approx(design.motor.train_ratio**2 * (design.motor.motor.rotor_inertia_kgm2
                                                              + e.motor_side_inertia_kgm2), rel=1e-12)
    # the link passes more than the rigid machine at some angle, so the helical stage is sized for it
    assert e.dynamic_factor > 1 and e.gear_torque_basis == "elastic"


def test_regulation_block_answers_as_the_regulation_endpoint(client: SynthClient, design: MachineDesignOut) -> None:
    g = design.regulation
    assert g is not None
    # the constant inertia it ran with is rotor, train and flywheel at the crank, as the design reports them
    constant = design.reduced.train_inertia_kgm2 + design.reduced.rotor_inertia_kgm2 + \
        design.flywheel.flywheel_inertia_kgm2
    assert g.constant_inertia_kgm2 == pytest.approx(constant, rel=1e-12)
    alone = client.regulation(RegulationIn.model_validate(
        {**_linkage_fields(), "motor": _motor(design), "constant_inertia_kgm2": g.constant_inertia_kgm2,
         "load_step_Nm": 40}))
    assert g.drop_rpm == pytest.approx(alone.drop_rpm, rel=SAME)
    assert g.time_constant_s == pytest.approx(alone.time_constant_s, rel=SAME)
    assert g.settling_time_s is not None and alone.settling_time_s is not None
    assert g.settling_time_s == pytest.approx(alone.settling_time_s, rel=SAME)
    _close(g.crank_speed_rpm, alone.crank_speed_rpm)
    # self-regulation's closed form dM/s against the simulated drop (a constant inertia's would be exact; the
    # cycle's varying inertia and load leave a few per cent)
    assert g.drop_rpm == pytest.approx(g.drop_closed_form_rpm, rel=0.05)
    check = next(c for c in design.checks if c.name == "regulation_settling_time")
    assert check.value == pytest.approx(g.settling_time_s, rel=1e-12)
    assert design.passed == all(c.passed for c in design.checks)


def test_a_failing_limit_of_a_block_fails_the_machine() -> None:
    # the same machine's frame held to a peak force far below the one its isolators pass on: only that check
    # fails, and the verdict with it
    body = {**copy.deepcopy(MACHINE), "elastic_drive": None, "regulation": None}
    body["foundation"]["max_force_N"] = 1.0
    d = synth.design_machine(machine_from(MachineIn.model_validate(body), 6))
    failed = [c.name for c in d.checks if not c.passed]
    assert failed == ["foundation_force"] and not d.passed
    assert d.foundation is not None and d.checks[-1].value == d.foundation.peak_force
    w = next(w for w in d.warnings if w.code == "check_failed")
    assert (w.stage, w.field) == ("foundation", "foundation.max_force_N")


def test_elastic_torque_carried_to_the_shafts() -> None:
    # two shafts (motor r = 3, crank 1), a train of efficiency 0.9: the link's excess over the rigid torque at
    # the crank reaches the crank shaft whole and the motor shaft as a motor torque, excess / (0.9 · 3)
    phi = np.linspace(0, 2 * math.pi, 8, endpoint=False)
    excess = np.where(np.arange(8) < 4, 5.0, -5.0)
    run = ElasticRun(phi, phi, phi, phi, 10.0 + excess, 0.0, 0.0, 0.0, 0.0, 0.0)
    drive = ElasticDrive(1.0, 0.0, 1.0, (1.0, 1.0, 1.0), 1.0, (1.0, 1.0), 1.0, 1.0, phi, run, np.full(8, 10.0),
                         1.5, tuple[LoadHarmonic, ...](), 1, None, None, None)
    rigid = np.vstack([np.full(8, 10.0 / (0.9 * 3)), np.full(8, 10.0)])
    out = elastic_shaft_torques(rigid, phi, drive, np.array([3.0, 1.0]), np.array([1.0, 0.9]), 0.9)
    # where the excess adds, the elastic torque; where it takes away, the rigid one stays (the larger)
    np.testing.assert_allclose(out[1], np.where(excess > 0, 15.0, 10.0), rtol=1e-12)
    np.testing.assert_allclose(out[0], np.where(excess > 0, 15.0 / 2.7, 10.0 / 2.7), rtol=1e-12)


@pytest.mark.parametrize(("change", "field"), [
    ({"foundation": {"frame": FRAME_EXAMPLE, "isolators": []}}, "foundation.isolators"),
    ({"foundation": {"frame": FRAME_EXAMPLE, "isolators": [ISOLATORS_EXAMPLE[0]]}}, "foundation.isolators"),
    ({"elastic_drive": {}}, "elastic_drive.stiffness_Nm_rad"),
])
def test_a_block_that_cannot_be_solved_is_refused_naming_its_field(client: SynthClient, change: dict[str, Any],
                                                                   field: str) -> None:
    # no isolator, or one that leaves the frame free to turn about it; a link with neither stiffness nor elements
    body = {**copy.deepcopy(PRESS_EXAMPLE), **change}
    with pytest.raises(InvalidInputError) as err:
        client.design_machine(MachineIn.model_validate(body))
    assert err.value.problem.get("field") == field


def test_the_design_record_has_pages_for_the_blocks() -> None:
    from pypdf import PdfReader

    from synth.machine.report import design_report_pdf

    d = synth.design_machine(machine_from(MachineIn.model_validate({**copy.deepcopy(MACHINE), "elastic_drive": None}), 6))
    texts = [p.extract_text() for p in PdfReader(io.BytesIO(design_report_pdf(d))).pages]
    # the blocks' summary page, the frame's page and the load step's page, once each, after the text pages
    for title in ("The machine on its foundation, its elastic drive", "The frame on its isolators: the force",
                  "The elastic drive and the speed after a load step"):
        assert sum(title in t for t in texts) == 1, title
    whole = "\n".join(texts)
    for words in ("Spectrum of the force", "mode 3:", "Speed after a 40 N·m step", "Torques after the load step",
                  "time integration against the harmonic answer", "force to the foundation, peak"):
        assert words in whole, words


def test_the_frame_feels_the_balanced_machine_lanchester_balancers_included() -> None:
    # the press fully balanced: a crank counterweight and Lanchester balancers, whose shafts act on the frame too;
    # the shaking force driving the frame is the balancing's own figure after balancing, not the linkage's alone
    body = {**copy.deepcopy(MACHINE), "balancing": {"mode": "full"}, "elastic_drive": None, "regulation": None}
    d = synth.design_machine(machine_from(MachineIn.model_validate(body), 6))
    assert d.foundation is not None and d.balancing.slider_crank is not None
    assert d.foundation.peak_shaking_force == pytest.approx(d.balancing.after.max_shaking_force, rel=1e-12)
    linkage_alone = float(np.max(np.linalg.norm(d.balanced.kinetostatics.shaking_force, axis=1)))
    assert d.foundation.peak_shaking_force < 0.1 * linkage_alone


def test_a_link_tuned_near_a_load_harmonic_is_solved_and_warned_about() -> None:
    # 3 kN·m/rad puts the link near 25 Hz, the press's third harmonic at 480 rpm (24 Hz) lightly damped: the
    # shooting settles at the integration's noise, the energy over the cycle still balances, and the harmonic is
    # named in a warning of the elastic-drive stage
    body = {**copy.deepcopy(MACHINE), "foundation": None, "regulation": None,
            "elastic_drive": {"stiffness_Nm_rad": 3e3, "damping_ratio": 0.05, "start": False}}
    d = synth.design_machine(machine_from(MachineIn.model_validate(body), 6))
    assert d.elastic is not None
    e = d.elastic.drive
    assert abs(e.steady.energy_residual) < 1e-6
    crank_hz = e.mean_speed / (2 * math.pi)
    near = [k for k in range(1, 10) if abs(k * crank_hz / e.natural_frequency - 1) <= 0.15]
    assert near == [3]
    warned = [w for w in d.warnings if w.code == "load_harmonic_near_resonance"]
    assert [w.stage for w in warned] == ["elastic_drive"] and "harmonic 3 " in warned[0].message
    assert e.dynamic_factor > 1.3
