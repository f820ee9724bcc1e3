"""The machine as it really runs: friction losses in the motor's power, each stage's efficiency, the start-up and
run-down checks of the machine answer."""

from __future__ import annotations

import copy
import dataclasses
import math
from typing import Any

import numpy as np
import pytest

import synth
from api.translate.machine import machine_from
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.machine import PRESS_EXAMPLE, MachineIn

SAMPLES = 120
FRICTION = (synth.PairFriction("guide", 0.15, static_coefficient=0.6), synth.PairFriction("O", 0.1, 0.02),
            synth.PairFriction("A", 0.1, 0.015))


def _spec(**changes: Any) -> synth.MachineSpec:
    spec = machine_from(MachineIn.model_validate({**PRESS_EXAMPLE, "samples": SAMPLES}), 6)
    return dataclasses.replace(spec, **changes)


@pytest.fixture(scope="module")
def plain() -> synth.MachineDesign:
    return synth.design_machine(_spec())


@pytest.fixture(scope="module")
def rubbing() -> synth.MachineDesign:
    return synth.design_machine(_spec(friction=FRICTION))


def test_motor_power_carries_the_friction_losses(plain: synth.MachineDesign, rubbing: synth.MachineDesign) -> None:
    # the same balanced linkage with and without friction: the mean crank power differs by the mean power loss
    # of the friction analysis (identity), and the linkage's efficiency is P0 / (P0 + P_loss)
    fr = rubbing.balanced.friction
    assert fr is not None and plain.balanced.friction is None
    speed = rubbing.spec.speed
    loss = speed * float(np.mean(fr.loss_torque))
    assert rubbing.output_power == pytest.approx(plain.output_power + loss, rel=1e-9)
    assert rubbing.running is not None and plain.running is not None
    eff = rubbing.running.efficiency
    assert eff.linkage == pytest.approx(plain.output_power / (plain.output_power + loss), rel=1e-9)
    assert eff.overall == pytest.approx(eff.linkage * rubbing.drive.chain_efficiency, rel=1e-12)
    assert plain.running.efficiency.linkage == 1.0
    assert rubbing.drive.required_power > plain.drive.required_power


def test_start_up_and_run_down_are_checks_of_the_design(rubbing: synth.MachineDesign) -> None:
    r = rubbing.running
    assert r is not None and r.startup.run is not None
    names = [c.name for c in rubbing.running_checks]
    assert names == ["motor_starts", "startup_time"]
    # one list of checks holds them with the steady motion's, and it alone decides the verdict
    assert [c.name for c in rubbing.checks][-2:] == names
    assert rubbing.passed == all(c.passed for c in rubbing.checks)
    # the run-up keeps the energy balance (motor work = kinetic energy gained + losses + process work) to 1e-6
    assert abs(r.startup.run.energy_residual) < 1e-6 and abs(r.rundown.run.energy_residual) < 1e-6
    # idling, the machine runs up faster than its loaded steady speed; the run-down starts from the loaded
    # steady motion the design was checked on
    assert r.startup.steady.mean_speed > rubbing.motion.mean_speed
    assert r.rundown.run.omega[0] == pytest.approx(rubbing.motion.omega[0], rel=1e-9)
    # the constant inertia of the run is rotor, train and flywheel, as the steady simulation has it
    assert r.constant_inertia == pytest.approx(
        rubbing.train_inertia + rubbing.motor.reduced().inertia + rubbing.flywheel_inertia, rel=1e-12)
    assert r.rundown.stop_time is not None and r.rundown.stop_time > 0


def test_a_motor_that_cannot_start_the_machine_is_a_failed_check_and_a_warning() -> None:
    # started under load, the static guide friction (f0 = 0.6) and the pressing force hold the crank harder than
    # the chosen motor's starting torque at its worst angle
    spec = _spec(friction=FRICTION, start_under_load=True, drive=dataclasses.replace(_spec().drive, motor="4A100L4"))
    d = synth.design_machine(spec)
    check = next(c for c in d.running_checks if c.name == "motor_starts")
    assert not check.passed and not d.passed
    assert d.running is not None and d.running.startup.run is None
    cat = synth.find_motor("4A100L4")
    # the limit is the catalogue's starting torque through the real train (written here)
    assert check.limit == pytest.approx(cat.starting_ratio * cat.rated_torque * d.train_ratio
                                        * d.drive.chain_efficiency, rel=1e-12)
    assert "motor_cannot_start" in [w.code for w in d.warnings]


def test_loaded_start_runs_up_to_the_designed_steady_motion() -> None:
    # started under load (a motor big enough), the run-up ends on the steady motion the design was checked on
    d = synth.design_machine(_spec(start_under_load=True, drive=dataclasses.replace(_spec().drive, motor="4A132M4")))
    assert d.running is not None and d.running.startup.steady_time is not None
    assert d.running.startup.steady.mean_speed == pytest.approx(d.motion.mean_speed, rel=1e-9)
    assert abs(d.running.startup.run.energy_residual) < 1e-6  # type: ignore[union-attr]


def test_rundown_time_checked_when_asked() -> None:
    d = synth.design_machine(_spec(brake_torque=20.0, max_rundown_time=0.01))
    check = next(c for c in d.running_checks if c.name == "rundown_time")
    assert d.running is not None and d.running.rundown.stop_time == pytest.approx(check.value, rel=1e-12)
    assert not check.passed  # no press stops in 10 ms


def test_machine_answer_carries_friction_and_running(client: SynthClient) -> None:
    body = copy.deepcopy(PRESS_EXAMPLE) | {"samples": SAMPLES, "friction": {"guide": {"coefficient": 0.15}},
                                           "brake_torque_Nm": 10.0}
    out = client.design_machine(MachineIn.model_validate(body))
    assert out.running is not None and out.analysis.friction is not None
    up = out.running.startup
    assert up.starts and up.steady_time_s is not None and len(up.time_s) == len(up.omega_rad_s) <= 1001
    assert up.energy_residual is not None and abs(up.energy_residual) < 1e-6
    assert out.running.rundown.brake_torque_Nm == 10.0
    assert [c.name for c in out.checks][-2:] == ["motor_starts", "startup_time"] and out.passed
    # the mean crank power is that of the load torque less the friction torque the answer reports (identity)
    assert out.reduced.friction_torque_Nm is not None
    resisting = np.array(out.reduced.reduced_load_torque_Nm) - np.array(out.reduced.friction_torque_Nm)
    speed = body["speed_rpm"] * math.pi / 30
    assert out.reduced.mean_power_W == pytest.approx(-float(np.mean(resisting)) * speed, rel=1e-9)
    assert 0 < out.running.efficiency.overall < out.running.efficiency.gears < 1  # type: ignore[operator]
    assert math.isclose(up.time_s[0], 0.0)


def test_machine_friction_problems_name_the_pair(client: SynthClient) -> None:
    body = copy.deepcopy(PRESS_EXAMPLE) | {"samples": SAMPLES, "friction": {"A": {"coefficient": 0.1,
                                                                               "journal_radius_m": 0.5}}}
    r = client.http.post("/v1/machines/design", json=body)
    assert r.status_code == 422 and r.json()["field"] == "friction.A.journal_radius_m"
