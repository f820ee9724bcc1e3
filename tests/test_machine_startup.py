"""Start-up and run-down of a machine: analytic rigid-rotor cases, the start check and the energy balance."""

from __future__ import annotations

import json
import math
from importlib import resources

import numpy as np
import pytest

import synth
from synth.machine import MachineCycle, simulate_rundown, simulate_startup, start_check

N = 360
PHI = np.arange(N) * 2 * math.pi / N


def _rigid(load_torque: float) -> MachineCycle:
    """A rigid rotor: no linkage inertia, a constant resisting torque."""
    return MachineCycle(PHI, np.zeros(N), np.zeros(N), np.full(N, -load_torque))


def _linear_motor() -> synth.Motor:
    # no breakdown torque: the linear branch holds from standstill, so the rotor's motion is exponential
    return synth.Motor(synchronous_speed=50 * math.pi, rated_speed=0.95 * 50 * math.pi, rated_torque=20.0,
                       gear_ratio=10.0, efficiency=0.95, rotor_inertia=0.01)


def test_rigid_rotor_runs_up_on_the_analytic_exponential() -> None:
    # J dw/dt = c (w0 - w) - T_L  =>  w(t) = w_inf (1 - exp(-c t / J)), w_inf = w0 - T_L / c (written here)
    motor, load, inertia = _linear_motor(), 150.0, 20.0
    red = motor.reduced()
    c, w0 = red.slope, red.no_load_speed
    w_inf = w0 - load / c
    up = simulate_startup(_rigid(load), inertia, motor)
    assert up.run is not None and up.steady_time is not None
    expected = w_inf * (1 - np.exp(-c * up.run.time / inertia))
    assert np.max(np.abs(up.run.omega - expected)) / w_inf < 1e-9
    # the steady speed of the periodic simulation is the same w_inf
    assert up.steady.mean_speed == pytest.approx(w_inf, rel=1e-9)
    # within 1 % of w_inf from t = (J/c) ln(1/0.01) on, to one time step
    dt = float(up.run.time[1])
    assert abs(up.steady_time - inertia / c * math.log(1 / up.tolerance)) <= dt
    # the motor's peak torque is its torque at standstill, slope * synchronous speed (linear characteristic)
    assert up.peak_motor_torque == pytest.approx(motor.torque_at(0.0), rel=1e-12)
    assert abs(up.run.energy_residual) < 1e-9


def test_rigid_rotor_runs_down_linearly_to_rest() -> None:
    # motor off: J dw/dt = -(T_L + T_brake), so the crank stops after J w_steady / (T_L + T_brake)
    motor, load, brake, inertia = _linear_motor(), 150.0, 50.0, 20.0
    down = simulate_rundown(_rigid(load), inertia, motor, brake_torque=brake)
    w_steady = motor.reduced().no_load_speed - load / motor.reduced().slope
    assert down.stop_time == pytest.approx(inertia * w_steady / (load + brake), rel=1e-9)
    # the kinetic energy goes into the process load and the brake (friction_loss carries the brake)
    assert down.run.friction_loss == pytest.approx(0.5 * inertia * w_steady**2 * brake / (load + brake), rel=1e-6)
    assert down.run.motor_work == 0.0


def test_start_check_against_the_starting_torque() -> None:
    # a catalogue motor's starting torque through the train: i * eta * ratio * P / w_rated, written here
    cat = synth.find_motor("4A100L4")
    motor = synth.Motor.from_catalogue(cat, 20.0, 0.9)
    starting = 20.0 * 0.9 * cat.starting_ratio * cat.rated_power / cat.rated_speed
    cycle = MachineCycle(PHI, np.full(N, 0.5), np.zeros(N), -200.0 - 100.0 * np.sin(PHI))
    check = start_check(cycle, motor, breakaway_torque=np.full(N, 40.0))
    assert check.starting_torque == pytest.approx(starting, rel=1e-12)
    # the largest resistance 200 + 100 + 40 N·m is at 90 deg
    assert check.worst_angle == pytest.approx(math.pi / 2, abs=1e-12)
    assert check.margin == pytest.approx(starting / 340.0, rel=1e-12)
    weak = start_check(cycle, motor, breakaway_torque=np.full(N, starting))
    assert not weak.starts
    refused = simulate_startup(cycle, 2.0, motor, breakaway_torque=np.full(N, starting))
    assert refused.run is None and refused.steady_time is None


def test_catalogue_starting_ratio_and_the_whole_characteristic() -> None:
    # every catalogue row carries its starting torque ratio; the characteristic is continuous at breakdown
    rows = json.loads(resources.files("synth.gearing").joinpath("motors.json").read_text())["motors"]
    by_name = {m.name: m for m in synth.motor_catalogue()}
    for row in rows:
        assert by_name[row["name"]].starting_ratio == row["starting_torque_ratio"]
    m = synth.Motor.from_catalogue(by_name["4A132M4"])
    n_b = m.breakdown_speed
    assert float(m.start_torque_at(n_b * (1 - 1e-12))) == pytest.approx(m.breakdown_torque, rel=1e-9)
    assert float(m.start_torque_at(0.0)) == pytest.approx(m.starting_torque, rel=1e-12)
    assert float(m.start_torque_at(m.rated_speed)) == pytest.approx(m.rated_torque, rel=1e-12)


def _press_cycle() -> tuple[MachineCycle, synth.Motor, float]:
    """A slider-crank press with gravity and a smooth crank-angle load, reduced to its crank."""
    mech = synth.SliderCrank(crank=0.1, rod=0.4)
    links = {"crank": synth.MassProps(4.0, (0.03, 0.0), 0.01), "rod": synth.MassProps(6.0, (0.2, 0.0), 0.08),
             "slider": synth.MassProps(10.0)}
    table = np.linspace(0, 2 * math.pi, 13)
    load = synth.ProcessLoad(kind="crank_table", table_x=tuple(table), values=tuple(800 + 600 * np.sin(table) ** 2))
    linkage = synth.Linkage(mech, links, gravity=synth.Gravity(), loads=(load,))
    an = synth.analyse(linkage, 10.0, samples=N)
    red = an.reduced
    cycle = MachineCycle(red.phi, red.inertia, red.inertia_slope, red.load_torque)
    motor = synth.Motor.from_catalogue(synth.find_motor("4A80B4"), 14.2, 0.92)
    return cycle, motor, 3.0


def test_press_run_up_keeps_the_energy_balance() -> None:
    # motor work = kinetic energy gained + train and friction losses + process work (identity), to 1e-6
    cycle, motor, inertia = _press_cycle()
    friction = 2.0 + 1.0 * np.cos(PHI) ** 2
    up = simulate_startup(cycle, inertia, motor, friction_torque=friction, breakaway_torque=1.5 * friction)
    assert up.check.starts and up.run is not None and up.steady_time is not None
    r = up.run
    assert abs(r.energy_residual) < 1e-6
    assert r.motor_work == pytest.approx(r.kinetic_energy_change + r.gear_loss + r.friction_loss + r.process_work,
                                         rel=1e-6)
    # the run ends on the periodic steady state of the same machine, to the tolerance
    end = np.interp(r.phi[-1], up.steady.phi, up.steady.omega, period=2 * math.pi)
    assert abs(r.omega[-1] - end) <= up.tolerance * up.steady.mean_speed
    # the start draws more than the rated torque on the motor shaft
    assert up.peak_motor_torque > motor.rated_torque
    down = simulate_rundown(cycle, inertia, motor, friction_torque=friction, brake_torque=5.0)
    assert down.stop_time is not None and abs(down.run.energy_residual) < 1e-6


def test_bad_brake_and_friction_are_refused() -> None:
    cycle, motor, inertia = _press_cycle()
    with pytest.raises(synth.InvalidInput) as err:
        simulate_rundown(cycle, inertia, motor, brake_torque=-1.0)
    assert err.value.field == "brake_torque_Nm"
    with pytest.raises(synth.InvalidInput) as err:
        simulate_startup(cycle, inertia, motor, friction_torque=np.full(N, -1.0))
    assert err.value.field == "friction_torque"
