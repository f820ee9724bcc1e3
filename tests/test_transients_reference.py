"""The start-up (LSODA, adaptive) and the run-down (closed form over the crank angle) against an independent
time-domain integration of the same equation of motion written here: J(phi)·dw/dt = M_motor(w) + M_load(phi)
- M_friction(phi) - J'(phi)·w²/2, J the cubic Hermite curve through the tables and their slopes, the load and
friction linear between samples, integrated by scipy's DOP853 at a relative tolerance of 1e-11 (a one-step
method of another family, far tighter than the engine's), the run-down stopped by an event at w = 0."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import synth
from synth.machine import MachineCycle, rundown, simulate_rundown, simulate_startup

N = 360
PHI = np.arange(N) * 2 * math.pi / N


def _press() -> tuple[MachineCycle, synth.Motor, float, np.ndarray]:
    """A slider-crank press with gravity and a window load (a steep rise and fall), reduced to its crank."""
    mech = synth.SliderCrank(crank=0.06, rod=0.24)
    links = {"crank": synth.MassProps(3.0, (0.02, 0.0), 0.004), "rod": synth.MassProps(4.0, (0.08, 0.0), 0.03),
             "slider": synth.MassProps(9.0)}
    load = synth.ProcessLoad(kind="window", magnitude=2500.0, start=0.0, end=math.pi)
    linkage = synth.Linkage(mech, links, gravity=synth.Gravity(), loads=(load,))
    red = synth.analyse(linkage, 50.0, samples=N).reduced
    cycle = MachineCycle(red.phi, red.inertia, red.inertia_slope, red.load_torque)
    motor = synth.Motor.from_catalogue(synth.find_motor("4A100L4"), 3.03, 0.98)
    return cycle, motor, 3.4, 2.0 + 1.0 * np.cos(PHI) ** 2


def _rhs(cycle: MachineCycle, constant: float, motor: synth.Motor | None, resisting: np.ndarray):
    n = cycle.phi.size
    h = 2 * math.pi / n
    j, dj = np.append(cycle.inertia, cycle.inertia[0]), np.append(cycle.inertia_slope, cycle.inertia_slope[0])
    load, res = np.append(cycle.load_torque, cycle.load_torque[0]), np.append(resisting, resisting[0])

    def f(_: float, y: np.ndarray) -> list[float]:
        phi, w = y
        u = (phi % (2 * math.pi)) / h
        k = min(int(u), n - 1)
        t = u - k
        jj = ((2 * t**3 - 3 * t**2 + 1) * j[k] + (t**3 - 2 * t**2 + t) * h * dj[k] + (3 * t**2 - 2 * t**3) * j[k + 1]
              + (t**3 - t**2) * h * dj[k + 1])
        djj = ((6 * t**2 - 6 * t) * (j[k] - j[k + 1]) / h + (3 * t**2 - 4 * t + 1) * dj[k]
               + (3 * t**2 - 2 * t) * dj[k + 1])
        drive = (0.0 if motor is None
                 else float(motor.start_torque_at(motor.gear_ratio * w)) * motor.gear_ratio * motor.efficiency)
        m = drive + load[k] + t * (load[k + 1] - load[k]) - (res[k] + t * (res[k + 1] - res[k]))
        return [w, (m - 0.5 * djj * w * w) / (jj + constant)]

    return f


def test_run_down_meets_the_time_domain_reference() -> None:
    cycle, motor, constant, friction = _press()
    down = simulate_rundown(cycle, constant, motor, friction_torque=friction, brake_torque=5.0)
    assert down.stop_time is not None
    w0 = float(down.run.omega[0])
    stop = lambda t, y: y[1]  # noqa: E731
    stop.terminal, stop.direction = True, -1  # type: ignore[attr-defined]
    ref = solve_ivp(_rhs(cycle, constant, None, friction + 5.0), (0.0, 60.0), [float(cycle.phi[0]), w0],
                    method="DOP853", rtol=1e-11, atol=1e-11, events=stop, dense_output=True,
                    max_step=2 * math.pi / 90 / w0)
    t_ref = float(ref.t_events[0][0])
    # the stop time to 1e-7 relative (the engine's own estimate of its time error says less)
    assert down.stop_time == pytest.approx(t_ref, rel=1e-7)
    assert down.time_error < 1e-7
    # the speed at the reported times, to 1e-6 of the starting speed
    inside = down.run.time < 0.999 * t_ref
    w_ref = ref.sol(down.run.time[inside])[1]
    assert np.max(np.abs(down.run.omega[inside] - w_ref)) / w0 < 1e-6
    # energy: the kinetic energy given up is the friction, brake and process work (identity, to rounding)
    assert abs(down.run.energy_residual) < 1e-12


def test_run_up_meets_the_time_domain_reference() -> None:
    cycle, motor, constant, friction = _press()
    up = simulate_startup(cycle, constant, motor, friction_torque=friction, breakaway_torque=1.5 * friction)
    assert up.run is not None and up.steady_time is not None
    run = up.run
    ref = solve_ivp(_rhs(cycle, constant, motor, friction), (0.0, float(run.time[-1])), [float(run.phi[0]), 0.0],
                    method="DOP853", rtol=1e-11, atol=1e-11, dense_output=True,
                    max_step=2 * math.pi / 90 / (motor.synchronous_speed / motor.gear_ratio))
    w_ref = ref.sol(run.time)[1]
    w_end = float(np.max(w_ref))
    assert np.max(np.abs(run.omega - w_ref)) / w_end < 1e-6
    # the peak motor torque, read from the reference's speeds, to 1e-6
    peak_ref = float(np.max(np.abs(motor.start_torque_at(motor.gear_ratio * w_ref[: np.searchsorted(
        run.time, up.steady_time) + 1]))))
    assert up.peak_motor_torque == pytest.approx(peak_ref, rel=1e-6)
    # motor work = kinetic energy gained + losses + process work (identity of the integrated states), to 1e-7
    assert abs(run.energy_residual) < 1e-7


def test_a_finer_grid_reports_no_more_states() -> None:
    # 3 600 samples a revolution are integrated on their own grid and reported on 360 a revolution: the answer
    # holds no more states than at 360, and the stop time moves by the tables' refinement only (1e-3)
    cycle, motor, constant, friction = _press()
    coarse = simulate_rundown(cycle, constant, motor, friction_torque=friction, brake_torque=5.0)
    fine_phi = np.arange(3600) * 2 * math.pi / 3600
    fine = MachineCycle(fine_phi, *(np.interp(fine_phi, PHI, v, period=2 * math.pi)
                                    for v in (cycle.inertia, cycle.inertia_slope, cycle.load_torque)))
    down = simulate_rundown(fine, constant, motor, friction_torque=np.interp(fine_phi, PHI, friction,
                                                                               period=2 * math.pi), brake_torque=5.0)
    assert down.stop_time is not None and coarse.stop_time is not None
    assert down.stop_time == pytest.approx(coarse.stop_time, rel=1e-3)
    assert down.run.time.size <= coarse.run.time.size + 2
    # the fine grid's time is integrated in panels of the reported spacing, each by the reported grid's rule: the
    # stop time it gives is the fine intervals' own rule (every interval by that rule) to 1e-9, and within the
    # panels' error estimate, which the lower-order rule makes larger than the error itself
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(rundown, "REPORTED_PER_REVOLUTION", 3600)
        patch.setattr(rundown, "_points", lambda samples: (rundown._POINTS, rundown._CHECK_POINTS))
        full = simulate_rundown(fine, constant, motor, friction_torque=np.interp(fine_phi, PHI, friction,
                                                                                 period=2 * math.pi),
                                brake_torque=5.0)
    assert full.stop_time is not None and down.stop_time == pytest.approx(full.stop_time, rel=1e-9)
    assert abs(down.stop_time - full.stop_time) / full.stop_time <= down.time_error < 1e-7


def test_a_steady_speed_to_start_from_changes_no_state() -> None:
    # the chain hands its working steady speed to the run-down and the start-up: their shooting starts there,
    # and what they find is what they find from their own guess, to the shooting's tolerance (1e-10)
    cycle, motor, constant, friction = _press()
    own = simulate_rundown(cycle, constant, motor, friction_torque=friction, brake_torque=5.0)
    given = simulate_rundown(cycle, constant, motor, friction_torque=friction, brake_torque=5.0,
                             steady_start=float(own.run.omega[0]) * (1 + 1e-3))
    assert own.stop_time is not None and given.stop_time == pytest.approx(own.stop_time, rel=1e-10)
    up = simulate_startup(cycle, constant, motor, friction_torque=friction, breakaway_torque=1.5 * friction)
    guided = simulate_startup(cycle, constant, motor, friction_torque=friction, breakaway_torque=1.5 * friction,
                              steady_start=float(own.run.omega[0]))
    assert np.max(np.abs(guided.steady.omega - up.steady.omega)) <= 1e-10 * float(np.max(up.steady.omega))
    assert guided.steady_time == pytest.approx(up.steady_time, rel=1e-9)
