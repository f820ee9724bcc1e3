"""Speed regulation after a step in the process load: self-regulation through the motor's characteristic, and a
PI controller on a frequency-converter drive.

The machine is rigid, reduced to its crank (seed 003 §5.5, seed 001 §7.3):
J(phi)·w' + J'(phi)·w²/2 = M_d + M_load(phi) - dM·[t >= t_step], with the motor's linear characteristic reduced
to the crank, M_d = s·(w_0 + u - w). Without a controller u = 0 and the machine regulates itself: for a constant
inertia J and load the speed falls exponentially, w(t) = w_b + (w_a - w_b)·exp(-(t - t_step)/tau), tau = J/s,
by dw = dM/s, and comes within the band delta·w_b/2 of w_b after tau·ln(dw/(delta·w_b/2)). A frequency converter
shifts the characteristic's no-load speed by u; a PI controller sets u = k_p·e + k_i·∫e from the error
e = w_ref - w_m of the speed measured through a first-order filter T_f. The closed loop's characteristic equation
(constant J) is J·T_f·p³ + (J + s·T_f)·p² + s·(1 + k_p)·p + s·k_i = 0; it is tuned (T_f = 0) for a damping
ratio from the overshoot and a natural frequency from the settling time, and refused when Routh's conditions
fail.

Settling is judged on the speed with the cycle's own fluctuation taken off: w(t) - (w_ss(phi) - mean w_ss), w_ss
the periodic steady motion after the step without a controller (with one: the run's last revolution).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from ..analysis import analyse
from ..counter_rotors import CounterRotor
from ..errors import Infeasible, InvalidInput, SolverFailed
from ..flywheel import Motor
from ..friction import PairFriction
from ..model import FloatArray, Linkage
from .simulate import MachineCycle, simulate_machine

#: Output points of a regulation run.
POINTS = 2000
#: Revolutions run before the step.
BEFORE = 2


@dataclass(frozen=True, slots=True)
class PIController:
    """A PI controller on the converter: ``kp`` [-] and ``ki`` [1/s] on the crank speed's error, ``filter_time``
    of the speed measurement [s], ``reference`` speed [rad/s] (None: the mean speed before the step)."""

    kp: float
    ki: float
    filter_time: float = 0.0
    reference: float | None = None


def tune_pi(inertia: float, slope: float, settling_time: float, overshoot: float,
            filter_time: float = 0.0) -> PIController:
    """Gains placing the closed loop's (T_f = 0) poles at damping zeta = -ln(OS)/sqrt(pi² + ln²OS) (1 for no
    overshoot) and natural frequency 4/(zeta·t_s) (the 2 % settling estimate): s·(1 + k_p) = 2·zeta·w_n·J,
    s·k_i = J·w_n². When that asks a negative k_p (the characteristic alone answers faster than asked), k_p = 0
    and k_i = 4/t_s. ``inertia`` [kg·m²], ``slope`` of the characteristic at the crank [N·m·s/rad]."""
    if not (math.isfinite(settling_time) and settling_time > 0):
        raise InvalidInput("the settling time must be positive", field="regulator.settling_time_s")
    if not 0 <= overshoot < 1:
        raise InvalidInput("the overshoot must lie in [0, 1)", field="regulator.overshoot")
    zeta = 1.0 if overshoot == 0 else -math.log(overshoot) / math.sqrt(math.pi**2 + math.log(overshoot) ** 2)
    wn = 4.0 / (zeta * settling_time)
    kp = 2 * zeta * wn * inertia / slope - 1
    if kp < 0:
        # the characteristic alone already answers faster than asked: no proportional action (a negative one would
        # soften the drive), and the integral's own pole, about -k_i while k_i << s/J, sets the recovery
        return PIController(0.0, 4.0 / settling_time, filter_time)
    return PIController(kp, inertia * wn * wn / slope, filter_time)


def closed_loop_poles(inertia: float, slope: float, c: PIController) -> FloatArray:
    """Roots of J·T_f·p³ + (J + s·T_f)·p² + s·(1 + k_p)·p + s·k_i [1/s] (complex)."""
    coeffs = [inertia * c.filter_time, inertia + slope * c.filter_time, slope * (1 + c.kp), slope * c.ki]
    while coeffs and coeffs[0] == 0:
        coeffs = coeffs[1:]
    return np.asarray(np.roots(coeffs))


def routh_stable(inertia: float, slope: float, c: PIController) -> bool:
    """Routh's conditions for the closed loop: every coefficient positive and, with a filter,
    (J + s·T_f)·s·(1 + k_p) > J·T_f·s·k_i."""
    a3, a2 = inertia * c.filter_time, inertia + slope * c.filter_time
    a1, a0 = slope * (1 + c.kp), slope * c.ki
    if a1 <= 0 or a0 <= 0:
        return False
    return a3 == 0 or a2 * a1 > a3 * a0


@dataclass(frozen=True, slots=True)
class Regulation:
    """A load step and the machine's answer to it.

    ``time`` [s], ``omega`` crank speed [rad/s], ``smoothed`` the speed with the cycle's own fluctuation taken off
    [rad/s], ``motor_torque`` at the crank [N·m], ``load_torque`` at the crank, the step included [N·m], ``shift``
    the converter's no-load speed shift u [rad/s], each (M,); ``step_time`` [s]; ``speed_before`` and
    ``speed_after`` the mean speeds [rad/s]; ``drop`` their difference [rad/s] and ``drop_closed_form`` dM/s;
    ``time_constant`` J_mean/s [s]; ``band`` delta·w/2 [rad/s]; ``settling_time`` after the step until the
    smoothed speed stays in the band [s] (None: not within the run); ``settling_closed_form`` tau·ln(dw/band) (or
    None with a controller); ``overshoot`` the smoothed speed's largest excursion past the final speed over the
    step's change [-]; ``controller`` and its ``poles`` [1/s] (None without one); ``max_deviation`` the largest
    |smoothed - final| after the step [rad/s].
    """

    time: FloatArray
    omega: FloatArray
    smoothed: FloatArray
    motor_torque: FloatArray
    load_torque: FloatArray
    shift: FloatArray
    step_time: float
    load_step: float
    speed_before: float
    speed_after: float
    drop: float
    drop_closed_form: float
    time_constant: float
    band: float
    settling_time: float | None
    settling_closed_form: float | None
    overshoot: float
    max_deviation: float
    controller: PIController | None
    poles: FloatArray | None


class _Machine:
    """Tables of the reduced machine for a scalar right-hand side."""

    def __init__(self, cycle: MachineCycle, constant_inertia: float) -> None:
        n = cycle.phi.size
        self.n, self.step, self.phi0 = n, 2 * math.pi / n, float(cycle.phi[0])
        self.j = (np.append(cycle.inertia, cycle.inertia[0]) + constant_inertia).tolist()
        self.dj = np.append(cycle.inertia_slope, cycle.inertia_slope[0]).tolist()
        self.load = np.append(cycle.load_torque, cycle.load_torque[0]).tolist()

    def at(self, phi: float) -> tuple[float, float, float]:
        """J, dJ/dphi (of the Hermite curve through the tables) and the load torque at ``phi``."""
        s = ((phi - self.phi0) % (2 * math.pi)) / self.step
        k = int(s)
        f = s - k
        k %= self.n
        j, dj, h = self.j, self.dj, self.step
        value = ((2 * f**3 - 3 * f**2 + 1) * j[k] + (f**3 - 2 * f**2 + f) * h * dj[k]
                 + (-2 * f**3 + 3 * f**2) * j[k + 1] + (f**3 - f**2) * h * dj[k + 1])
        slope = ((6 * f**2 - 6 * f) * (j[k] - j[k + 1]) / h + (3 * f**2 - 4 * f + 1) * dj[k]
                 + (3 * f**2 - 2 * f) * dj[k + 1])
        return value, slope, self.load[k] + f * (self.load[k + 1] - self.load[k])


def regulate(cycle: MachineCycle, constant_inertia: float, motor: Motor, load_step: float, *, delta: float = 0.02,
             controller: PIController | None = None, horizon: float | None = None) -> Regulation:
    """The machine in its steady cycle, then a step ``load_step`` [N·m at the crank, positive resists] in the
    process load; self-regulated, or with ``controller`` on a frequency converter.

    Parameters
    ----------
    cycle
        The linkage reduced to its crank, uniform samples [kg·m², N·m].
    constant_inertia
        Rotor, train and flywheel reduced to the crank [kg·m²] (the rotor included, as for the start-up).
    motor
        The motor through its train; its linear characteristic (reduced to the crank) drives.
    delta
        The band the settling is judged in, delta·w/2 [-].
    horizon
        Time simulated after the step [s]; default enough for the slower of 8 time constants and 3 of the
        controller's settling estimates.
    """
    if not (math.isfinite(load_step)):
        raise InvalidInput("the load step must be finite", field="load_step_Nm")
    if not 0 < delta < 1:
        raise InvalidInput("delta must lie in (0, 1)", field="delta")
    red = motor.reduced()
    s, w0 = red.slope, red.no_load_speed
    machine = _Machine(cycle, constant_inertia)
    j_mean = float(np.mean(cycle.inertia)) + constant_inertia
    tau = j_mean / s
    before = simulate_machine(cycle, constant_inertia, _linear(motor))
    stepped = MachineCycle(cycle.phi, cycle.inertia, cycle.inertia_slope, cycle.load_torque - load_step)
    try:
        after = simulate_machine(stepped, constant_inertia, _linear(motor))
    except SolverFailed as exc:
        raise Infeasible("the motor cannot carry the stepped load: the machine stalls", constraint="load_step_Nm",
                         solver_status=exc.status) from None
    ripple_phi, ripple = after.phi, after.omega - after.mean_speed
    period = 2 * math.pi / before.mean_speed
    t_step = BEFORE * period
    poles = None
    final = after.mean_speed
    if controller is not None:
        ref = controller.reference if controller.reference is not None else before.mean_speed
        controller = PIController(controller.kp, controller.ki, controller.filter_time, ref)
        if not routh_stable(j_mean, s, controller):
            raise Infeasible(
                "the regulator is unstable: the closed loop J·T_f·p³ + (J + s·T_f)·p² + s·(1 + k_p)·p + s·k_i "
                "fails Routh's conditions", constraint="regulator",
                poles_real_1_s=[float(p.real) for p in closed_loop_poles(j_mean, s, controller)])
        poles = closed_loop_poles(j_mean, s, controller)
        final = ref
    slowest = 1.0 / float(np.min(-poles.real)) if poles is not None else tau
    span = horizon if horizon is not None else max(8 * slowest, 6 * period)
    if not (math.isfinite(span) and span > 0) or span > 1e4 * period:
        raise InvalidInput("the run after the step would be longer than 10⁴ revolutions: the regulator is too "
                           "slow for this machine", field="regulator")
    kp = ki = tf = 0.0
    ref_speed = 0.0
    u0 = 0.0
    if controller is not None:
        kp, ki, tf = controller.kp, controller.ki, controller.filter_time
        ref_speed = float(controller.reference or before.mean_speed)
        # the integral state that holds the reference before the step: s·u0 moves the mean speed by u0
        u0 = ref_speed - before.mean_speed

    def rhs(t: float, y: FloatArray) -> FloatArray:
        phi, w, integral, wf = float(y[0]), float(y[1]), float(y[2]), float(y[3])
        j, dj, load = machine.at(phi)
        if t >= t_step:
            load -= load_step
        e = ref_speed - (wf if tf > 0 else w)
        u = kp * e + ki * integral if controller is not None else 0.0
        m_d = s * (w0 + u - w)
        dwf = (w - wf) / tf if tf > 0 else 0.0
        return np.array([w, (m_d + load - 0.5 * dj * w * w) / j, e if controller is not None else 0.0, dwf])

    phi0 = float(cycle.phi[0])
    w_start = float(before.omega[0])
    integral0 = (u0 - kp * (ref_speed - w_start)) / ki if controller is not None and ki != 0 else 0.0
    t_end = t_step + span
    t_out = np.linspace(0.0, t_end, POINTS)
    y = np.array([phi0, w_start, integral0, w_start])
    if controller is not None:
        # the controller reshapes the steady cycle: run into it before the record starts
        pre = solve_ivp(rhs, (-8 * slowest - 2 * period, 0.0), y, method="RK45", rtol=1e-8,
                        atol=1e-10 * max(w_start, 1.0), max_step=period / 32)
        if not pre.success or not np.all(pre.y[1] > 0):
            raise Infeasible("the machine does not run steadily under the regulator before the step",
                             constraint="regulator")
        y = pre.y[:, -1]
    pieces = []
    # two runs, so that no step straddles the load's jump
    for a, b in ((0.0, t_step), (t_step, t_end)):
        sol = solve_ivp(rhs, (a, b), y, method="RK45", dense_output=True, rtol=1e-9,
                        atol=1e-10 * max(w_start, 1.0), max_step=period / 32)
        if not sol.success:
            raise SolverFailed("integration_failed", f"the regulation run failed: {sol.message}")
        pieces.append(sol)
        y = sol.y[:, -1]
    ys = np.where(t_out < t_step, pieces[0].sol(np.minimum(t_out, t_step)), pieces[1].sol(np.maximum(t_out, t_step)))
    phi, w, integral, wf = ys
    if not np.all(w > 0):
        raise Infeasible("the machine stalls after the load step", constraint="load_step_Nm")
    if controller is not None:
        # the cycle's own fluctuation under the controller: the last revolution of the run
        t_last = float(np.interp(phi[-1] - 2 * math.pi, phi, t_out))
        grid = np.linspace(t_last, t_end, 8 * cycle.phi.size)
        last = pieces[1].sol(grid)
        ripple_phi = np.mod(last[0] - phi0, 2 * math.pi) + phi0
        order = np.argsort(ripple_phi)
        ripple_phi = ripple_phi[order]
        ripple = last[1][order] - 2 * math.pi / (t_end - t_last)
    smoothed = w - np.interp(phi, ripple_phi, ripple, period=2 * math.pi)
    if controller is not None:
        e = ref_speed - (wf if tf > 0 else w)
        shift = kp * e + ki * integral
    else:
        shift = np.zeros_like(w)
    motor_torque = s * (w0 + shift - w)
    load = np.interp(phi, cycle.phi, cycle.load_torque, period=2 * math.pi) - np.where(t_out >= t_step, load_step,
                                                                                      0.0)
    band = delta * final / 2
    late = t_out >= t_step
    outside = np.flatnonzero(late & (np.abs(smoothed - final) > band))
    settle = None
    if outside.size == 0:
        settle = 0.0
    elif outside[-1] < t_out.size - 1:
        # where the deviation crosses the band, between the last point outside and the first inside
        k = int(outside[-1])
        d0, d1 = abs(smoothed[k] - final) - band, abs(smoothed[k + 1] - final) - band
        settle = float(t_out[k] + (t_out[k + 1] - t_out[k]) * d0 / (d0 - d1) - t_step)
    change = final - before.mean_speed
    beyond = (smoothed[late] - final) * (1 if change >= 0 else -1)
    if controller is None:
        overshoot = float(max(0.0, beyond.max()) / abs(change)) if change != 0 else 0.0
    else:
        # with integral action the speed first falls and comes back: overshoot is the rise past the reference
        low = int(np.argmin(smoothed[late]))
        overshoot = float(max(0.0, (smoothed[late][low:] - final).max()) / max(final - smoothed[late][low], 1e-300))
    drop_cf = load_step / s
    settle_cf = None
    if controller is None and abs(drop_cf) > band:
        settle_cf = tau * math.log(abs(drop_cf) / band)
    return Regulation(t_out, w, smoothed, motor_torque, load, shift, t_step, load_step, before.mean_speed,
                      after.mean_speed, before.mean_speed - after.mean_speed, drop_cf, tau, band, settle, settle_cf,
                      overshoot, float(np.max(np.abs(smoothed[late] - final))), controller, poles)


def _linear(motor: Motor) -> Motor:
    """The motor's linear branch alone (no breakdown or starting torque): the regulation model's."""
    return Motor(motor.synchronous_speed, motor.rated_speed, motor.rated_torque, motor.gear_ratio, motor.efficiency,
                 motor.rotor_inertia)


def regulate_linkage(linkage: Linkage, speed: float, motor: Motor, load_step: float, *, constant_inertia: float = 0.0,
                     delta: float = 0.02, controller: PIController | None = None,
                     tuning: tuple[float, float, float] | None = None, samples: int = 360,
                     max_samples: int = 100_000, counter_rotors: tuple[CounterRotor, ...] = (),
                     friction: tuple[PairFriction, ...] = ()) -> Regulation:
    """Analyse ``linkage`` at crank ``speed`` [rad/s], reduce it to its crank and step its load (see
    :func:`regulate`); ``tuning`` (settling time [s], overshoot [-], filter time [s]) tunes a PI controller for
    the machine's mean inertia and the characteristic's slope instead of giving ``controller``."""
    an = analyse(linkage, speed, samples=samples, max_samples=max_samples, counter_rotors=counter_rotors,
                 friction=friction)
    red = an.reduced
    cycle = MachineCycle(red.phi, red.inertia, red.inertia_slope, red.resisting_torque)
    if tuning is not None:
        reduced = motor.reduced()
        j_mean = float(np.mean(red.inertia)) + constant_inertia
        controller = tune_pi(j_mean, reduced.slope, tuning[0], tuning[1], tuning[2])
    return regulate(cycle, constant_inertia, motor, load_step, delta=delta, controller=controller)
