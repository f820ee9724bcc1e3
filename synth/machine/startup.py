"""The machine from standstill to its steady cycle, and from its steady cycle to standstill.

The run-up integrates the equation of motion in time, J(phi)·dw/dt = M_motor(w) + M_load(phi) - M_friction(phi)
- J'(phi)·w²/2 (seed 000:597-612: run-up with the motor on, run-down with -M_PC - M_T), from rest at the
crank angle where starting is hardest, with the motor's whole characteristic from its starting torque
(:meth:`synth.flywheel.Motor.start_torque_at`), until the speed lies on the periodic steady state that
:func:`synth.machine.simulate.simulate_machine` finds for the same machine. Between the samples J is the cubic
Hermite curve through the tables of J_red and its analytic slope, and J' is that curve's own derivative, so
the integrated motion keeps the energy balance (motor work = kinetic energy gained + losses + process work)
the answer reports as its check. LSODA (scipy's ``odeint``: Adams steps, BDF where the motion turns
stiff) sets the step by its error control to a relative tolerance of 1e-10, no step longer than 1/90 revolution
at the motor's no-load speed (no feature of the load wider than four degrees is stepped over); the states are
reported on a uniform grid of a quarter of a sample interval at that speed (of a 360-sample interval on finer
tables), and the start-up time, the peaks and the run-down time are read from it. The work integrals are states
of the same integration. Nothing is built per call but the list of the cycle's nodes the right-hand side reads.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import warnings
from collections.abc import Callable

import numpy as np
from scipy.integrate import ODEintWarning, odeint

from ..errors import InvalidInput, SolverFailed
from ..flywheel import Motor
from ..model import FloatArray
from .rundown import coast
from .simulate import MachineCycle, MachineMotion, simulate_machine

#: Relative distance from the periodic steady speed, (w - w_steady(phi))/w_mean, counted as steady [-].
STEADY_TOLERANCE = 0.01
#: Longest run-up or run-down simulated [s]: a machine not steady or stopped by then is reported as such.
MAX_TIME = 600.0
#: Most reported states of one run (a fast crank with a heavy flywheel would otherwise hold millions of them).
MAX_STEPS = 400_000
#: Reported states per sample interval at the no-load crank speed, on at most RESOLVED_SAMPLES intervals.
SUBSTEPS = 4
#: Finer tables than this many samples per revolution do not refine the reported grid: 1 440 states a revolution
#: show the motion (its speed varies over the revolution as the load and the inertia do), and a finer sample grid
#: only refines the tables the integration reads between their nodes.
RESOLVED_SAMPLES = 360
#: Reported states integrated between two looks at the speed (a few revolutions).
CHUNK_STEPS = 4096
#: Most reported states of the closed-form reference run that checks the integrator.
REFERENCE_STEPS = 1024
#: LSODA's relative tolerance; the absolute ones are this times a revolution (angle), the no-load speed (speed)
#: and one joule (work integrals).
RELATIVE_TOLERANCE = 1e-10
#: Least integration steps a revolution at the no-load speed (the longest step LSODA may take).
MIN_STEPS_PER_REVOLUTION = 90
#: Most integration steps LSODA may take between two reported states.
_MAX_INNER_STEPS = 100_000
#: The integration as the answer names it.
METHOD = ("LSODA (adaptive Adams/BDF, relative tolerance 1e-10, at least 90 steps a revolution), states reported "
          "at a fixed time step")


@dataclass(frozen=True, slots=True)
class StartCheck:
    """Can the motor start the machine from rest at every crank angle?

    ``starting_torque`` the motor's locked-rotor torque reduced to the crank (train ratio and efficiency)
    [N·m]; ``resisting_torque`` at every sample the torque that holds the crank at rest, the reduced load
    (process loads and gravity as they act when turning forward) plus breakaway friction [N·m], (N,);
    ``worst_angle`` where it is largest [rad]; ``margin`` starting over the largest resisting torque [-].
    """

    starting_torque: float
    resisting_torque: FloatArray
    worst_angle: float
    margin: float

    @property
    def starts(self) -> bool:
        """True when the starting torque exceeds the resistance at the worst crank angle."""
        return self.margin > 1.0


@dataclass(frozen=True, slots=True)
class Transient:
    """A simulated run-up or run-down: ``time`` [s], ``phi`` crank angle [rad, unwrapped], ``omega`` crank speed
    [rad/s] and ``motor_torque`` on the motor shaft [N·m] at every step, (M,) each.

    Energy over the run [J]: ``motor_work`` on the motor shaft, ``kinetic_energy_change`` of the whole machine,
    ``gear_loss`` in the train, ``friction_loss`` in the pairs and the brake, ``process_work`` done on the
    process loads and against gravity; ``energy_residual`` the balance motor work - kinetic energy gained -
    losses - process work over the largest of those terms [-] (the check of the integration).
    """

    time: FloatArray
    phi: FloatArray
    omega: FloatArray
    motor_torque: FloatArray
    motor_work: float
    kinetic_energy_change: float
    gear_loss: float
    friction_loss: float
    process_work: float
    energy_residual: float


@dataclass(frozen=True, slots=True)
class IntegratorCheck:
    """How the run-up was integrated and how well the same integrator meets a closed form.

    ``method`` in words; ``time_step`` the spacing of the reported states [s]; the reference is the same
    machine with its inertia held at the cycle's mean ``reference_inertia`` [kg·m²], its load at the mean
    ``reference_load`` [N·m] (zero when the motor could not turn against it) and the motor's linear branch down
    to standstill, whose run-up from rest is w(t) = w_inf·(1 - exp(-k·t/J)) (k the characteristic's slope at the
    crank, w_inf = w_s + M/k): the same integration from rest over ``reference_time`` [s] (three time constants,
    or the first ``REFERENCE_STEPS`` reported states of them) misses it by at most ``closed_form_error`` of
    w_inf [-].
    """

    method: str
    time_step: float
    reference_inertia: float
    reference_load: float
    reference_time: float
    closed_form_error: float


def run_up_closed_form(time: FloatArray, inertia: float, slope: float, no_load_speed: float,
                       load: float = 0.0) -> FloatArray:
    """Crank speed [rad/s] at ``time`` [s] of a run-up from rest with constant ``inertia`` [kg·m²], a linear
    characteristic of ``slope`` [N·m·s] through ``no_load_speed`` [rad/s] and a constant ``load`` [N·m]
    (positive drives): J·dw/dt = k·(w_s - w) + M, so w = (w_s + M/k)·(1 - exp(-k·t/J)); it reaches 99 % of
    its final speed at J·ln(100)/k."""
    final = no_load_speed + load / slope
    return np.asarray(final * -np.expm1(-slope * np.asarray(time, dtype=float) / inertia), dtype=float)


def _integrator_check(cycle: MachineCycle, constant_inertia: float, motor: Motor, friction: FloatArray,
                      dt: float) -> IntegratorCheck:
    inertia = float(np.mean(cycle.inertia)) + constant_inertia
    linear = Motor(motor.synchronous_speed, motor.rated_speed, motor.rated_torque, motor.gear_ratio,
                   motor.efficiency, motor.rotor_inertia)
    reduced = linear.reduced()
    load = float(np.mean(cycle.load_torque - friction))
    if reduced.no_load_speed + load / reduced.slope <= 0.05 * reduced.no_load_speed:
        load = 0.0
    n = cycle.phi.size
    flat = MachineCycle(cycle.phi, np.full(n, inertia - constant_inertia), np.zeros(n), np.full(n, load))
    # the run-up's own integration over three time constants, or the first 1024 reported states of them: the error
    # the integration makes is what is checked, and a short run keeps the check a small part of the start-up's cost
    steps = int(min(max(256, math.ceil(3 * inertia / reduced.slope / dt)), REFERENCE_STEPS))
    rates = _rates(flat, constant_inertia, linear, np.zeros(n), 0.0, True)
    states = _run(rates, np.zeros(6), dt, steps, motor)
    time: FloatArray = dt * np.arange(1, steps + 1, dtype=float)
    exact = run_up_closed_form(time, inertia, reduced.slope, reduced.no_load_speed, load)
    final = reduced.no_load_speed + load / reduced.slope
    error = float(np.max(np.abs(states[1] - exact)) / final)
    return IntegratorCheck(METHOD, dt, inertia, load,
                           float(time[-1]), error)


@dataclass(frozen=True, slots=True)
class StartUp:
    """The run-up from rest to the periodic steady state.

    ``check`` the start at the worst crank angle; ``run`` the simulated run-up (from there unless another
    start angle is given; None when the motor cannot start the machine); ``steady`` the periodic steady motion it runs into; ``steady_time`` when
    the speed comes within ``tolerance`` of it to stay [s] (None: not within ``MAX_TIME`` or ``MAX_STEPS``
    steps, or never started);
    ``peak_motor_torque`` the largest motor torque and ``rms_motor_torque`` its RMS over time until steady
    (the heating figure of the start) [N·m]; ``stalled`` True when the speed fell back to zero; ``integrator``
    the integration's method, step and its error against a closed-form run-up (None without a run-up).
    """

    check: StartCheck
    run: Transient | None
    steady: MachineMotion
    steady_time: float | None
    peak_motor_torque: float
    rms_motor_torque: float
    tolerance: float
    stalled: bool
    integrator: IntegratorCheck | None = None


@dataclass(frozen=True, slots=True)
class RunDown:
    """The run-down from the steady state at the first sample with the motor switched off.

    ``run`` the run-down on the sample grid, integrated over the crank angle by
    :func:`synth.machine.rundown.coast` (its motor work is zero, its energy balance holds by construction);
    ``stop_time`` when the crank comes to rest [s] (None: still turning after ``MAX_TIME`` or ``MAX_STEPS``
    samples); ``brake_torque`` at the crank [N·m]; ``time_error`` the time at the end by a quadrature rule of
    lower order, relative [-] (the check of the only integral approximated).
    """

    run: Transient
    stop_time: float | None
    brake_torque: float
    time_error: float


def _closed(values: FloatArray) -> FloatArray:
    return np.append(values, values[0])


def _uniform_step(phi: FloatArray) -> float:
    step = 2 * math.pi / phi.size
    if not np.allclose(np.diff(phi), step, rtol=1e-9, atol=1e-12):
        raise InvalidInput("the start-up simulation takes uniformly spaced crank angles over one revolution",
                           field="samples")
    return step


def _time_step(cycle: MachineCycle, speed: float) -> float:
    """The spacing of the reported states [s]: SUBSTEPS a sample interval (on at most RESOLVED_SAMPLES of them a
    revolution) at crank ``speed`` [rad/s]."""
    return 2 * math.pi / (SUBSTEPS * min(cycle.phi.size, RESOLVED_SAMPLES) * max(speed, 1e-300))


def _hermite(phi_rel: FloatArray, step: float, j: FloatArray, dj: FloatArray) -> FloatArray:
    """J on the Hermite curve through the closed tables at angles ``phi_rel`` from the first sample [rad]."""
    n = j.size - 1
    u = np.asarray(phi_rel) / step
    k = np.floor(u)
    t = u - k
    i = (k - n * np.floor(k / n)).astype(int)
    h00, h10, h01, h11 = 2 * t**3 - 3 * t**2 + 1, t**3 - 2 * t**2 + t, -2 * t**3 + 3 * t**2, t**3 - t**2
    return np.asarray(h00 * j[i] + h10 * step * dj[i] + h01 * j[i + 1] + h11 * step * dj[i + 1], dtype=float)


_Rates = Callable[[float, FloatArray], tuple[float, float, float, float, float, float]]


def _rates(cycle: MachineCycle, constant_inertia: float, motor: Motor, friction: FloatArray, brake: float,
           motor_on: bool) -> _Rates:
    """The time derivative of the state (phi - phi_0, w, motor work, gear loss, friction loss, process work).

    Plain floats throughout: LSODA calls it a few thousand times a run with one state, where an array's or a
    compiled graph's call costs more than the arithmetic. The node list is the only thing built per call.
    """
    step = 2 * math.pi / cycle.phi.size
    n = cycle.phi.size
    closed = np.column_stack([_closed(v) for v in (cycle.inertia, cycle.inertia_slope, cycle.load_torque,
                                                   friction)])
    # one look-up at a node gives the four tables there and at the next node
    nodes: list[tuple[float, ...]] = [tuple(r) for r in np.hstack([closed[:-1], closed[1:]]).tolist()]
    i_gear, eta = float(motor.gear_ratio), float(motor.efficiency)
    n_s = float(motor.synchronous_speed)
    slope = float(motor.rated_torque / (motor.synchronous_speed - motor.rated_speed))
    t_start, t_break = motor.starting_torque, motor.breakdown_torque
    whole = t_start is not None and t_break is not None
    n_b = float(motor.breakdown_speed) if whole else 0.0
    start_torque = float(t_start) if t_start is not None else 0.0
    start_rise = (float(t_break) - start_torque) / max(n_b, 1e-300) if t_break is not None else 0.0
    inv, c_j = 1.0 / step, float(constant_inertia)
    floor = math.floor

    def rates(_: float, state: FloatArray) -> tuple[float, float, float, float, float, float]:
        phi, w = float(state[0]), float(state[1])
        u = phi * inv
        k = floor(u)
        t = u - k
        j0, d0, l0, f0, j1, d1, l1, f1 = nodes[k % n]
        t2 = t * t
        t3 = t2 * t
        jj = (2 * t3 - 3 * t2 + 1) * j0 + (t3 - 2 * t2 + t) * step * d0 + (3 * t2 - 2 * t3) * j1 + (t3 - t2) * step * d1
        dj = (6 * t2 - 6 * t) * (j0 - j1) * inv + (3 * t2 - 4 * t + 1) * d0 + (3 * t2 - 2 * t) * d1
        load = l0 + t * (l1 - l0)
        fric = f0 + t * (f1 - f0) + brake
        speed = i_gear * w
        if not motor_on:
            torque = 0.0
        elif whole and speed < n_b:
            torque = start_torque + start_rise * speed
        else:
            torque = slope * (n_s - speed)
        power = torque * speed
        acc = (i_gear * eta * torque + load - fric - 0.5 * dj * w * w) / (jj + c_j)
        return w, acc, power, (1 - eta) * power, fric * w, -load * w

    return rates


def _run(rates: _Rates, start: FloatArray, dt: float, steps: int, motor: Motor) -> FloatArray:
    """The states (6, steps) at dt, 2·dt, ... steps·dt after ``start``, integrated by LSODA with steps of at most
    1/MIN_STEPS_PER_REVOLUTION revolution at the motor's no-load crank speed."""
    no_load = max(motor.synchronous_speed / motor.gear_ratio, 1e-300)
    max_step = 2 * math.pi / (MIN_STEPS_PER_REVOLUTION * no_load)
    scale = np.array([2 * math.pi, no_load, 1.0, 1.0, 1.0, 1.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error", ODEintWarning)
        try:
            states, info = odeint(rates, start, dt * np.arange(steps + 1, dtype=float), tfirst=True,
                                  rtol=RELATIVE_TOLERANCE, atol=RELATIVE_TOLERANCE * scale, hmax=max_step,
                                  mxstep=_MAX_INNER_STEPS, full_output=True)
        except ODEintWarning as exc:
            raise SolverFailed("integration_failed", f"the start-up's integration failed: {exc}") from exc
    if info["message"] != "Integration successful.":
        raise SolverFailed("integration_failed", f"the start-up's integration failed: {info['message']}")
    return np.asarray(states[1:].T, dtype=float)


def _integrate(cycle: MachineCycle, constant_inertia: float, motor: Motor, friction: FloatArray, brake: float,
               motor_on: bool, phi0: float, w0: float, dt: float,
               done: _Stop) -> tuple[FloatArray, bool]:
    """States (6, M) from (phi0, w0) until ``done`` says so, the speed reaches zero or MAX_TIME passes; and
    whether it ended by the speed reaching zero."""
    rates = _rates(cycle, constant_inertia, motor, friction, brake, motor_on)
    states = [np.array([[phi0 - float(cycle.phi[0])], [w0], [0.0], [0.0], [0.0], [0.0]])]
    max_chunks = max(1, min(math.ceil(MAX_TIME / (dt * CHUNK_STEPS)), MAX_STEPS // CHUNK_STEPS))
    for _ in range(max_chunks):
        chunk = _run(rates, states[-1][:, -1], dt, CHUNK_STEPS, motor)
        stop = np.flatnonzero(~(chunk[1] > 0))
        if stop.size:
            states.append(chunk[:, : stop[0] + 1])
            return np.hstack(states), True
        states.append(chunk)
        if done(np.hstack(states)):
            break
    return np.hstack(states), False


class _Stop:
    """Whether a run-up has reached its steady state: the speed within the tolerance over a whole revolution."""

    def __init__(self, steady: MachineMotion, tolerance: float, phi0: float) -> None:
        self.steady, self.tolerance, self.phi0 = steady, tolerance, phi0

    def errors(self, states: FloatArray) -> FloatArray:
        """|w - w_steady(phi)| / w_mean at every state."""
        s = self.steady
        target = np.interp(states[0] + self.phi0, s.phi, s.omega, period=2 * math.pi)
        return np.asarray(np.abs(states[1] - target) / s.mean_speed, dtype=float)

    def __call__(self, states: FloatArray) -> bool:
        bad = np.flatnonzero(self.errors(states) > self.tolerance)
        last = states[0, bad[-1]] if bad.size else states[0, 0]
        return bool(states[0, -1] - last >= 2 * math.pi)


def _transient(cycle: MachineCycle, constant_inertia: float, motor: Motor, states: FloatArray, dt: float,
               motor_on: bool) -> Transient:
    step = 2 * math.pi / cycle.phi.size
    j, dj = _closed(cycle.inertia), _closed(cycle.inertia_slope)
    phi_rel, w = states[0], states[1]
    energy = 0.5 * (_hermite(phi_rel, step, j, dj) + constant_inertia) * w**2
    gained = float(energy[-1] - energy[0])
    work, gear, fric, proc = (float(v) for v in states[2:, -1])
    scale = max(abs(work), abs(gained), abs(fric), abs(proc), 1e-300)
    torque = motor.start_torque_at(motor.gear_ratio * w) if motor_on else np.zeros_like(w)
    return Transient(np.arange(w.size) * dt, phi_rel + float(cycle.phi[0]), w, torque, work, gained, gear, fric,
                     proc, (work - gained - gear - fric - proc) / scale)


def _friction_table(cycle: MachineCycle, values: FloatArray | None, name: str) -> FloatArray:
    if values is None:
        return np.zeros(cycle.phi.size)
    arr = np.broadcast_to(np.asarray(values, dtype=float), cycle.phi.shape).copy()
    if not (np.all(np.isfinite(arr)) and np.all(arr >= 0)):
        raise InvalidInput(f"{name} must be finite and not negative at every crank angle", field=name)
    return arr


def start_check(cycle: MachineCycle, motor: Motor, breakaway_torque: FloatArray | None = None,
                standstill_load: FloatArray | None = None) -> StartCheck:
    """Starting torque against the torque that holds the crank at rest, at every sample.

    Parameters
    ----------
    cycle
        The linkage reduced to its crank [kg·m², N·m].
    motor
        The motor with the train's ratio and efficiency; its ``starting_torque`` (the linear branch's torque at
        standstill when it has none) [N·m].
    breakaway_torque
        Friction torque at the crank that must be overcome to break away from rest, per sample [N·m] (>= 0).
    standstill_load
        Reduced load torque at rest, per sample [N·m] (positive drives); default the cycle's own (process loads
        and gravity as they act when turning forward). A machine started without its process load passes its
        gravity and link torques alone.
    """
    breakaway = _friction_table(cycle, breakaway_torque, "breakaway_torque")
    start = float(motor.start_torque_at(0.0)) * motor.gear_ratio * motor.efficiency
    load = cycle.load_torque if standstill_load is None else np.asarray(standstill_load, dtype=float)
    resisting = -load + breakaway
    worst = int(np.argmax(resisting))
    top = float(resisting[worst])
    margin = math.inf if top <= 0 else start / top
    return StartCheck(start, resisting, float(cycle.phi[worst]), margin)


def simulate_startup(cycle: MachineCycle, constant_inertia: float, motor: Motor, *,
                     friction_torque: FloatArray | None = None, breakaway_torque: FloatArray | None = None,
                     standstill_load: FloatArray | None = None, start_angle: float | None = None,
                     tolerance: float = STEADY_TOLERANCE, steady_start: float | None = None) -> StartUp:
    """Run the machine up from rest to its periodic steady state.

    Parameters
    ----------
    cycle
        The linkage reduced to its crank (uniform samples over one revolution) [kg·m², N·m].
    constant_inertia
        Rotor, train and flywheel reduced to the crank [kg·m²].
    motor
        Characteristic with starting torque, through the train's ratio and efficiency.
    friction_torque
        Friction torque of the pairs reduced to the crank while turning, per sample [N·m] (>= 0, resists).
    breakaway_torque
        Friction torque reduced to the crank at rest, per sample [N·m] (>= 0).
    standstill_load
        Reduced load torque at rest for the start check (see :func:`start_check`) [N·m]; the run-up itself
        works against the cycle's load.
    start_angle
        Crank angle to start from [rad]; default the worst one of the start check. No run-up is simulated
        when the start check fails.
    tolerance
        Relative distance from the steady speed counted as steady [-].
    steady_start
        Crank speed at the first sample to start the steady state's shooting from [rad/s] (a nearby machine's
        steady speed saves integrations; the steady state found does not depend on it).

    The steady state is :func:`simulate_machine`'s, on the same cycle less the friction torque.
    """
    if not 0 < tolerance < 1:
        raise InvalidInput("the steady-state tolerance must lie in (0, 1)", field="tolerance")
    _uniform_step(cycle.phi)
    friction = _friction_table(cycle, friction_torque, "friction_torque")
    check = start_check(cycle, motor, breakaway_torque, standstill_load)
    loaded = MachineCycle(cycle.phi, cycle.inertia, cycle.inertia_slope, cycle.load_torque - friction)
    steady = simulate_machine(loaded, constant_inertia, motor, start=steady_start)
    phi0 = check.worst_angle if start_angle is None else float(start_angle)
    if not check.starts:
        return StartUp(check, None, steady, None, 0.0, 0.0, tolerance, True)
    dt = _time_step(cycle, motor.synchronous_speed / motor.gear_ratio)
    stop = _Stop(steady, tolerance, float(cycle.phi[0]))
    states, stalled = _integrate(cycle, constant_inertia, motor, friction, 0.0, True, phi0, 0.0, dt, stop)
    run = _transient(cycle, constant_inertia, motor, states, dt, True)
    steady_time: float | None = None
    upto = run.time.size
    if not stalled and stop(states):
        bad = np.flatnonzero(stop.errors(states) > tolerance)
        first = int(bad[-1]) + 1 if bad.size else 0
        steady_time = float(run.time[first])
        upto = first + 1
    torque = run.motor_torque[:upto]
    peak = float(np.abs(torque).max())
    rms = math.sqrt(float(np.trapezoid(torque**2, run.time[:upto])) / run.time[upto - 1]) if upto > 1 else peak
    return StartUp(check, run, steady, steady_time, peak, rms, tolerance, stalled,
                   _integrator_check(cycle, constant_inertia, motor, friction, dt))


def simulate_rundown(cycle: MachineCycle, constant_inertia: float, motor: Motor, *,
                     friction_torque: FloatArray | None = None, brake_torque: float = 0.0,
                     steady_start: float | None = None) -> RunDown:
    """Switch the motor off in the steady state at the first sample and let the machine run down.

    Parameters
    ----------
    cycle, constant_inertia, motor, friction_torque
        As for :func:`simulate_startup`; the motor's rotor still turns with the train.
    brake_torque
        Constant brake torque at the crank while turning [N·m] (>= 0).
    steady_start
        As for :func:`simulate_startup`.
    """
    if not (math.isfinite(brake_torque) and brake_torque >= 0):
        raise InvalidInput("the brake torque must be finite and not negative", field="brake_torque_Nm")
    _uniform_step(cycle.phi)
    friction = _friction_table(cycle, friction_torque, "friction_torque")
    loaded = MachineCycle(cycle.phi, cycle.inertia, cycle.inertia_slope, cycle.load_torque - friction)
    steady = simulate_machine(loaded, constant_inertia, motor, start=steady_start)
    down = coast(cycle.inertia, cycle.inertia_slope, cycle.load_torque, friction + brake_torque, constant_inertia,
                 float(steady.omega[0]), MAX_TIME, MAX_STEPS)
    energy = 0.5 * (_hermite(down.angle, 2 * math.pi / cycle.phi.size, _closed(cycle.inertia),
                             _closed(cycle.inertia_slope)) + constant_inertia) * down.omega**2
    gained = float(energy[-1] - energy[0])
    scale = max(abs(gained), abs(down.friction_loss), abs(down.process_work), 1e-300)
    run = Transient(down.time, down.angle + float(cycle.phi[0]), down.omega, np.zeros_like(down.omega), 0.0, gained,
                    0.0, down.friction_loss, down.process_work,
                    (-gained - down.friction_loss - down.process_work) / scale)
    return RunDown(run, down.stop_time, brake_torque, down.time_error)
