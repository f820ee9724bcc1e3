"""The run-up integrator against the closed form of a start with constant inertia and a linear characteristic.

Independent derivation (written here, not taken from the engine): at the crank the motor gives
k·(w_s - w) with k = i²·eta·T_rated/(n_s - n_rated) and w_s = n_s/i; with J constant and a constant load M,
J·dw/dt = k·(w_s - w) + M from rest gives w(t) = (w_s + M/k)·(1 - exp(-k·t/J)), 99 % of the final speed at
t = J·ln(100)/k.
"""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

import synth
from api.translate.machine import machine_from
from mechsynth_client.schemas.machine import FOURBAR_MACHINE_EXAMPLE, MachineIn
from synth.flywheel import Motor
from synth.machine.simulate import MachineCycle
from synth.machine.startup import simulate_startup

SAMPLES = 120
MOTOR = Motor(157.08, 148.0, 20.0, gear_ratio=10.0, efficiency=0.9)   # linear branch down to standstill
LINKAGE_INERTIA, CONSTANT_INERTIA = 0.5, 1.5


def _closed_form(t: np.ndarray, load: float) -> tuple[np.ndarray, float, float]:
    i, eta = MOTOR.gear_ratio, MOTOR.efficiency
    k = i * i * eta * MOTOR.rated_torque / (MOTOR.synchronous_speed - MOTOR.rated_speed)
    j = LINKAGE_INERTIA + CONSTANT_INERTIA
    final = MOTOR.synchronous_speed / i + load / k
    return final * (1 - np.exp(-k * t / j)), final, j * math.log(100) / k


@pytest.mark.parametrize("load", [0.0, -60.0], ids=["no load", "constant load torque"])
def test_the_simulated_start_is_the_closed_form(load: float) -> None:
    phi = np.linspace(0, 2 * math.pi, SAMPLES, endpoint=False)
    cycle = MachineCycle(phi, np.full(SAMPLES, LINKAGE_INERTIA), np.zeros(SAMPLES), np.full(SAMPLES, load))
    up = simulate_startup(cycle, CONSTANT_INERTIA, MOTOR)
    assert up.run is not None and up.steady_time is not None
    exact, final, t99 = _closed_form(up.run.time, load)
    assert np.max(np.abs(up.run.omega - exact)) / final < 1e-6
    # "steady" is 1 % of the mean speed to stay: the closed form's 99 % time, to one time step
    dt = float(up.run.time[1] - up.run.time[0])
    assert up.steady_time == pytest.approx(t99, abs=dt)
    # the answer's own check: the same integrator against the same closed form
    assert up.integrator is not None
    assert up.integrator.time_step == pytest.approx(dt, rel=1e-12)
    assert up.integrator.reference_inertia == pytest.approx(LINKAGE_INERTIA + CONSTANT_INERTIA, rel=1e-12)
    assert up.integrator.reference_load == pytest.approx(load, abs=1e-12)
    assert up.integrator.closed_form_error < 1e-6


def test_a_designed_machine_states_its_integrator_and_check() -> None:
    body = copy.deepcopy(FOURBAR_MACHINE_EXAMPLE)
    body.update(samples=72, alternatives=False)
    body["drive"]["size_gears"] = False
    design = synth.design_machine(machine_from(MachineIn.model_validate(body), max_stages=4))
    up = design.running.startup
    assert up.run is not None and up.integrator is not None
    assert up.integrator.time_step == pytest.approx(float(up.run.time[1] - up.run.time[0]), rel=1e-12)
    assert 0 < up.integrator.closed_form_error < 1e-6
    # the reference inertia is the cycle's mean plus the constant part the design reports
    assert up.integrator.reference_inertia > design.running.constant_inertia
