"""The motor check (periodic speed under a motor characteristic) against scipy's solve_ivp with shooting, and
its limits: a machine with almost no inertia, and one the motor cannot keep turning."""

from __future__ import annotations

import bisect
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import synth
from synth.flywheel.motor import ReducedMotor

MOTOR = ReducedMotor(no_load_speed=60.0, slope=5.0, max_torque=1e9, inertia=0.0)


def _cycle(inertia_scale: float) -> synth.ReducedCycle:
    phi = np.linspace(0, 2 * np.pi, 72, endpoint=False)
    return synth.ReducedCycle(phi, inertia_scale * (1 + 0.5 * np.sin(phi)), -40 - 25 * np.sin(2 * phi) + 8 * np.cos(phi),
                              2 * np.pi)


def _shooting_delta(cycle: synth.ReducedCycle, constant_inertia: float) -> float:
    """Independent: d(J w²/2)/dphi = M_load + slope (w0 - w) integrated by solve_ivp (DOP853, rtol 1e-10) with
    the sensitivity to the initial energy, which Newton's method shoots until the motion repeats."""
    nodes, inertia, torque = cycle.closed()
    nodes_l, inertia_l, torque_l = nodes.tolist(), (inertia + constant_inertia).tolist(), torque.tolist()

    def rhs(phi: float, y: np.ndarray) -> list[float]:
        i = min(max(bisect.bisect_right(nodes_l, phi) - 1, 0), len(nodes_l) - 2)
        t = (phi - nodes_l[i]) / (nodes_l[i + 1] - nodes_l[i])
        j = inertia_l[i] + t * (inertia_l[i + 1] - inertia_l[i])
        w = math.sqrt(max(2 * y[0] / j, 1e-300))
        load = torque_l[i] + t * (torque_l[i + 1] - torque_l[i])
        return [load + MOTOR.slope * (MOTOR.no_load_speed - w), -MOTOR.slope / (j * w) * y[1]]

    def run(e0: float, t_eval: np.ndarray | None = None) -> object:
        return solve_ivp(rhs, (nodes_l[0], nodes_l[-1]), [e0, 1.0], method="DOP853", rtol=1e-10,
                         atol=[1e-12 * e0, 1e-12], t_eval=t_eval)

    e0 = 0.5 * inertia_l[0] * MOTOR.mean_speed(cycle) ** 2
    for _ in range(20):
        y = run(e0).y  # type: ignore[attr-defined]
        step = -(y[0, -1] - e0) / (y[1, -1] - 1.0)
        e0 += step
        if abs(step) <= 1e-12 * e0:
            break
    phi = cycle.dense(2000)
    j, _, _ = cycle.evaluate(phi)
    energy = run(e0, phi).y[0]  # type: ignore[attr-defined]
    return synth.speed_fluctuation(np.sqrt(2 * energy / (j + constant_inertia)))[2]


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
