"""The motor check (periodic speed under a motor characteristic) against scipy's solve_ivp with shooting, and
its limits: a machine with almost no inertia, and one the motor cannot keep turning."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import synth
from synth.flywheel.motor import ReducedMotor

MOTOR = ReducedMotor(no_load_speed=60.0, slope=5.0, max_torque=1e9, inertia=0.0)


def _cycle(inertia_scale: float) -> synth.ReducedCycle:
    phi = np.linspace(0, 2 * np.pi, 72, endpoint=False)
    return synth.ReducedCycle(phi, inertia_scale * (1 + 0.5 * np.sin(phi)), -40 - 25 * np.sin(2 * phi) + 8 * np.cos(phi),
                              2 * np.pi)


def _shooting_delta(cycle: synth.ReducedCycle, constant_inertia: float) -> float:
    """Independent: d(J w²/2)/dphi = M_load + slope (w0 - w) integrated by solve_ivp (DOP853, rtol 1e-10),
    the initial energy found by brentq so that the motion repeats."""
    nodes, inertia, torque = cycle.closed()

    def rhs(phi: float, e: np.ndarray) -> np.ndarray:
        j = np.interp(phi, nodes, inertia) + constant_inertia
        w = math.sqrt(max(2 * e[0] / j, 0.0))
        return np.array([np.interp(phi, nodes, torque) + MOTOR.slope * (MOTOR.no_load_speed - w)])

    def end(e0: float) -> float:
        sol = solve_ivp(rhs, (nodes[0], nodes[-1]), [e0], method="DOP853", rtol=1e-10, atol=1e-11 * e0)
        return float(sol.y[0, -1]) - e0

    j0, w_m = inertia[0] + constant_inertia, MOTOR.mean_speed(cycle)
    e0 = brentq(end, 0.5 * j0 * (0.8 * w_m) ** 2, 0.5 * j0 * (1.2 * w_m) ** 2, rtol=1e-12)
    phi = cycle.dense(2000)
    sol = solve_ivp(rhs, (nodes[0], nodes[-1]), [e0], method="DOP853", rtol=1e-10, atol=1e-11 * e0, t_eval=phi)
    j, _, _ = cycle.evaluate(phi)
    return synth.speed_fluctuation(np.sqrt(2 * sol.y[0] / (j + constant_inertia)))[2]


def test_periodic_speed_agrees_with_shooting_on_solve_ivp() -> None:
    cycle, constant_inertia = _cycle(0.2), 0.1
    profile = synth.steady_speed_motor(cycle, constant_inertia, MOTOR)
    assert profile.delta == pytest.approx(_shooting_delta(cycle, constant_inertia), abs=1e-6)
    # the linear characteristic fixes the angle-average speed whatever the inertia (balance of work)
    assert np.trapezoid(profile.omega, profile.phi) / (2 * np.pi) == pytest.approx(MOTOR.mean_speed(cycle), rel=1e-6)


def test_almost_no_inertia_settles_to_the_quasi_static_speed() -> None:
    # J of 1e-8 kg·m² makes the equation stiff; the motion then follows the motor's static balance
    # slope (w0 - w) + M_load = 0 at every angle (independent closed form).
    cycle = _cycle(1e-8)
    profile = synth.steady_speed_motor(cycle, 0.0, MOTOR)
    _, load, _ = cycle.evaluate(profile.phi)
    quasi_static = MOTOR.no_load_speed + load / MOTOR.slope
    assert np.max(np.abs(profile.omega / quasi_static - 1)) < 1e-5


def test_a_motor_that_cannot_keep_it_turning_is_a_typed_failure() -> None:
    # With slope 0.5 the static balance asks for a negative speed where the load peaks: no periodic motion.
    weak = ReducedMotor(no_load_speed=60.0, slope=0.5, max_torque=1e9, inertia=0.0)
    with pytest.raises(synth.SolverFailed) as err:
        synth.steady_speed_motor(_cycle(1e-8), 0.0, weak)
    assert err.value.status == "no_periodic_motion"
