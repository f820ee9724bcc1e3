"""Speed regulation after a step in the process load: self-regulation through the motor's characteristic, and a
PI controller on a frequency-converter drive.

The machine is rigid, reduced to its crank (seed 003 §5.5, seed 001 §7.3):
J(phi)·w' + J'(phi)·w²/2 = M_d + M_load(phi) - dM·[t >= t_step], with the motor's linear characteristic reduced
to the crank, M_d = s·(w_0 + u - w). Without a controller u = 0 and the machine regulates itself: for a constant
inertia J and load the speed falls exponentially, w(t) = w_b + (w_a - w_b)·exp(-(t - t_step)/tau), tau = J/s,
by dw = dM/s, and comes within the band delta·w_b/2 of w_b after tau·ln(dw/(delta·w_b/2)). A frequency converter
shifts the characteristic's no-load speed by u; a PI controller sets u = k_p·e + k_i·∫e from the error
e = w_ref - w_m of the speed measured through a first-order filter T_f. The closed loop's characteristic equation
(constant J) is J·T_f·p³ + (J + s·T_f)·p² + s·(1 + k_p)·p + s·k_i = 0. Tuning places its dominant pair at the
damping ratio of the asked overshoot and, with a filter, the third pole where the filter leaves it
(J·T_f·(p² + 2·zeta·w_n·p + w_n²)·(p + a)), then picks w_n numerically so that the linear loop's answer to a
load step settles within the asked time; the achieved overshoot and settling of the simulated machine are
reported against what was asked.

The motor's whole characteristic drives the run: the linear branch down to the breakdown speed, below it the
torque falls to the starting torque at standstill (held at the breakdown torque when no starting torque is
given, an upper bound). A mean load beyond the breakdown torque at the crank stalls the motor and is refused.

Where the model stops (each a named warning and a failed check, or a refusal): ``motor_stalls`` (the mean load
beyond the breakdown torque: refused with the torque it lacks), ``motor_breakdown`` (the speed falls below the
breakdown speed during the run: the motor pulls out for a while), ``regulator_underdamped`` (damping below
:data:`MIN_DAMPING`: refused at once with the poles), ``regulator_lightly_damped`` (below
:data:`LIGHT_DAMPING`), ``regulator_overshoot`` and ``regulator_settling_time`` (a tuned loop missing what was
asked), ``settling_band_wide`` (a band wider than the step's dip).

Settling is judged on the speed with the cycle's own fluctuation taken off: w(t) - (w_ss(phi) - mean w_ss), w_ss
the periodic steady motion after the step without a controller (with one: the run's last revolution), in a band
of ``band_fraction`` (default 2 %) of the step's dip, or delta·w/2 when ``delta`` is given and narrower than
the dip.
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
from ..warnings import DesignWarning, ValidityCheck
from .simulate import MachineCycle, simulate_machine

#: Output points of a regulation run.
POINTS = 2000
#: Revolutions run before the step.
BEFORE = 2
#: A closed loop damped less than this rings for tens of periods and is refused with its poles [-].
MIN_DAMPING = 0.05
#: Below this a loop answers with a warning: each swing loses less than half its size [-].
LIGHT_DAMPING = 0.2
#: Settling band as a fraction of the step's dip, by default [-].
BAND_FRACTION = 0.02
#: A tuned loop's simulated overshoot may exceed the asked one by this much [-], its settling time the asked
#: one by this fraction, before the target counts as missed (the simulated machine is not the linear model).
OVERSHOOT_TOLERANCE = 0.02
SETTLING_TOLERANCE = 0.15
#: Revolutions after the step the run may take at most.
MAX_REVOLUTIONS = 3000


@dataclass(frozen=True, slots=True)
class PIController:
    """A PI controller on the converter: ``kp`` [-] and ``ki`` [1/s] on the crank speed's error, ``filter_time``
    of the speed measurement [s], ``reference`` speed [rad/s] (None: the mean speed before the step)."""

    kp: float
    ki: float
    filter_time: float = 0.0
    reference: float | None = None


def _zeta(overshoot: float) -> float:
    return 1.0 if overshoot == 0 else -math.log(overshoot) / math.sqrt(math.pi**2 + math.log(overshoot) ** 2)


def _placed(inertia: float, slope: float, zeta: float, wn: float, filter_time: float) -> tuple[float, float]:
    """Gains (k_p >= 0, k_i) placing the dominant pair at ``zeta``, ``wn``; with a filter the third pole goes
    where the p² coefficient leaves it, a = (J + s·T_f)/(J·T_f) - 2·zeta·w_n."""
    if filter_time == 0:
        kp = 2 * zeta * wn * inertia / slope - 1
        ki = inertia * wn * wn / slope
    else:
        a = (inertia + slope * filter_time) / (inertia * filter_time) - 2 * zeta * wn
        kp = inertia * filter_time * (wn * wn + 2 * zeta * wn * a) / slope - 1
        ki = inertia * filter_time * wn * wn * a / slope
    # a negative k_p would soften the drive: the characteristic alone already answers faster than asked
    return max(kp, 0.0), ki


def step_response(inertia: float, slope: float, c: PIController) -> tuple[float, float, float]:
    """The linear loop's answer to a load step (constant J): dip, overshoot past the reference over the dip [-]
    and the time to stay within 2 % of the dip [s]. dw(p) = -dM·(T_f·p + 1)/(J·T_f·p³ + (J + s·T_f)·p² +
    s·(1 + k_p)·p + s·k_i), the impulse response of that transfer function; the dip per unit dM [rad/s/N·m]."""
    poles = closed_loop_poles(inertia, slope, c)
    decay = float(np.min(-poles.real))
    if not decay > 0:
        return math.inf, math.inf, math.inf
    coeffs = np.array([inertia * c.filter_time, inertia + slope * c.filter_time, slope * (1 + c.kp), slope * c.ki])
    if coeffs[0] == 0:
        coeffs = coeffs[1:]
    # impulse response by residues, sum of N(p_k)/D'(p_k)·exp(p_k·t) (the poles are distinct unless placed on
    # each other exactly; a hair's perturbation of a double pole changes the response by as little)
    p = poles + 1e-9 * np.abs(poles) * np.arange(poles.size)
    residues = np.polyval([c.filter_time, 1.0], p) / np.polyval(np.polyder(coeffs), p)
    t = np.linspace(0.0, 12.0 / decay, 4000)
    dw = -np.real(np.exp(np.outer(t, p)) @ residues)
    low = int(np.argmin(dw))
    dip = -float(dw[low])
    overshoot = max(0.0, float(dw[low:].max())) / dip
    outside = np.flatnonzero(np.abs(dw) > BAND_FRACTION * dip)
    return dip, overshoot, float(t[min(outside[-1] + 1, t.size - 1)])


def tune_pi(inertia: float, slope: float, settling_time: float, overshoot: float,
            filter_time: float = 0.0) -> PIController:
    """Gains for the real loop with its filter: the dominant pair at damping zeta = -ln(OS)/sqrt(pi² + ln²OS)
    (1 for no overshoot), the third pole where the filter leaves it, and the natural frequency the least on a
    grid from 0.5 to 12 × 4/(zeta·t_s) whose linear answer to a load step settles (2 % of the dip) within
    ``settling_time`` [s] without passing the asked ``overshoot`` [-] by more than 2 %; with a filter w_n stays
    below (1/T_f + s/J)/(5·zeta), where the third pole is still at least as fast as the pair's decay. When no
    grid point meets both, the one settling soonest is taken (the answer then reports the miss). ``inertia``
    [kg·m²], ``slope`` of the characteristic at the crank [N·m·s/rad], ``filter_time`` [s]."""
    if not (math.isfinite(settling_time) and settling_time > 0):
        raise InvalidInput("the settling time must be positive", field="regulator.settling_time_s")
    if not 0 <= overshoot < 1:
        raise InvalidInput("the overshoot must lie in [0, 1)", field="regulator.overshoot")
    if not (math.isfinite(filter_time) and filter_time >= 0):
        raise InvalidInput("the filter time must not be negative", field="regulator.filter_time_s")
    zeta = _zeta(overshoot)
    estimate = 4.0 / (zeta * settling_time)
    top = 12 * estimate
    if filter_time > 0:
        top = min(top, (1 / filter_time + slope / inertia) / (5 * zeta))
    grid = np.geomspace(min(0.5 * estimate, top), top, 64)
    best: tuple[float, PIController] | None = None
    for wn in grid:
        c = PIController(*_placed(inertia, slope, zeta, float(wn), filter_time), filter_time)
        if not routh_stable(inertia, slope, c):
            continue
        _, os_, ts = step_response(inertia, slope, c)
        if ts <= settling_time and os_ <= overshoot + OVERSHOOT_TOLERANCE:
            return c
        if best is None or ts < best[0]:
            best = (ts, c)
    if best is None:
        raise Infeasible("no PI gains make the loop with this filter stable", constraint="regulator.filter_time_s")
    return best[1]


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
    ``time_constant`` J_mean/s [s]; ``band`` the settling band [rad/s] (``band_fraction`` of the dip, or
    delta·w/2); ``settling_time`` after the step until the smoothed speed stays in the band [s] (None: not within
    the run); ``settling_closed_form`` tau·ln(dw/band) (or None with a controller); ``overshoot`` the smoothed
    speed's largest excursion past the final speed over the step's change [-]; ``controller`` and its ``poles``
    [1/s] (None without one); ``max_deviation`` the largest |smoothed - final| after the step [rad/s];
    ``breakdown_torque`` the motor's at the crank [N·m] (inf without one); ``target`` the tuning's (settling
    time [s], overshoot [-]) or None; ``warnings`` and ``checks`` where the model stops.
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
    breakdown_torque: float = math.inf
    target: tuple[float, float] | None = None
    warnings: tuple[DesignWarning, ...] = ()
    checks: tuple[ValidityCheck, ...] = ()


def damping_ratio(poles: FloatArray) -> float:
    """Least damping ratio -Re(p)/|p| over the complex poles [-]; 1 when every pole is real."""
    pairs = poles[np.abs(poles.imag) > 1e-12 * np.abs(poles)]
    return float(np.min(-pairs.real / np.abs(pairs))) if pairs.size else 1.0


class _Characteristic:
    """The motor's whole characteristic at the crank, shifted by the converter's u: the linear branch
    s·(w_0 + u - w) down to the breakdown speed, below it the line to the starting torque at standstill (the
    breakdown torque held when no starting torque is given)."""

    def __init__(self, motor: Motor) -> None:
        red = motor.reduced()
        factor = motor.gear_ratio * motor.efficiency
        self.s, self.w0, self.top = red.slope, red.no_load_speed, red.max_torque
        start = motor.starting_torque if motor.starting_torque is not None else motor.breakdown_torque
        self.start = math.inf if start is None else factor * start

    def breakdown_speed(self, u: float | FloatArray) -> FloatArray:
        """Crank speed where the linear branch reaches the breakdown torque [rad/s] (-inf without one)."""
        return np.asarray(self.w0 + u - self.top / self.s)

    def torque(self, w: float, u: float) -> float:
        """Torque at the crank [N·m] at crank speed ``w`` [rad/s] with the shift ``u`` [rad/s]."""
        wb = self.w0 + u - self.top / self.s
        if not math.isfinite(self.top) or w >= wb:
            return self.s * (self.w0 + u - w)
        if wb <= 0:
            return self.top
        return self.start + (self.top - self.start) * max(w, 0.0) / wb

    def torques(self, w: FloatArray, u: FloatArray) -> FloatArray:
        """:meth:`torque` over arrays."""
        wb = self.breakdown_speed(u)
        linear = self.s * (self.w0 + u - w)
        if not math.isfinite(self.top):
            return np.asarray(linear)
        low = np.where(wb > 0, self.start + (self.top - self.start) * np.maximum(w, 0.0) / np.maximum(wb, 1e-300),
                       self.top)
        return np.asarray(np.where(w >= wb, linear, low))


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


def regulate(cycle: MachineCycle, constant_inertia: float, motor: Motor, load_step: float, *,
             delta: float | None = None, band_fraction: float = BAND_FRACTION,
             controller: PIController | None = None, horizon: float | None = None,
             target: tuple[float, float] | None = None) -> Regulation:
    """The machine in its steady cycle, then a step ``load_step`` [N·m at the crank, positive resists] in the
    process load; self-regulated, or with ``controller`` on a frequency converter.

    Parameters
    ----------
    cycle
        The linkage reduced to its crank, uniform samples [kg·m², N·m].
    constant_inertia
        Rotor, train and flywheel reduced to the crank [kg·m²] (the rotor included, as for the start-up).
    motor
        The motor through its train; its whole characteristic drives.
    delta
        A settling band delta·w/2 [-] instead of ``band_fraction`` of the dip; a band wider than the dip is
        replaced by the default one, with the warning ``settling_band_wide``.
    band_fraction
        The settling band as a fraction of the step's dip [-].
    horizon
        Time simulated after the step [s]; default enough for the slower of 8 time constants and 3 of the
        controller's settling estimates.
    target
        The (settling time [s], overshoot [-]) a tuned controller was asked for: checked against the run.

    Raises Infeasible ``motor_stalls`` when the mean load before or after the step reaches the motor's breakdown
    torque at the crank (with the torque it lacks), ``regulator_underdamped`` when the closed loop's damping is
    below :data:`MIN_DAMPING` (with its poles), ``regulator`` when it is unstable.
    """
    if not (math.isfinite(load_step)):
        raise InvalidInput("the load step must be finite", field="load_step_Nm")
    if delta is not None and not 0 < delta < 1:
        raise InvalidInput("delta must lie in (0, 1)", field="delta")
    if not 0 < band_fraction < 1:
        raise InvalidInput("the settling band must lie in (0, 1) of the dip", field="settling_band")
    red = motor.reduced()
    s, w0 = red.slope, red.no_load_speed
    drive = _Characteristic(motor)
    top = red.max_torque
    for label, load in (("before", -float(np.mean(cycle.load_torque))),
                        ("after", -float(np.mean(cycle.load_torque)) + load_step)):
        if load >= top:
            raise Infeasible(
                f"the motor stalls {label} the load step: the mean load torque at the crank, {load:.4g} N·m, "
                f"reaches the motor's breakdown torque there, {top:.4g} N·m (breakdown × ratio × efficiency); "
                "a larger motor, a larger ratio or a smaller step", constraint="load_step_Nm",
                condition="motor_stalls", mean_load_torque_Nm=load, breakdown_torque_at_crank_Nm=top,
                torque_lacking_Nm=load - top)
    machine = _Machine(cycle, constant_inertia)
    j_mean = float(np.mean(cycle.inertia)) + constant_inertia
    tau = j_mean / s
    before = simulate_machine(cycle, constant_inertia, _linear(motor))
    stepped = MachineCycle(cycle.phi, cycle.inertia, cycle.inertia_slope, cycle.load_torque - load_step)
    try:
        after = simulate_machine(stepped, constant_inertia, _linear(motor))
    except SolverFailed as exc:
        raise Infeasible("the motor cannot carry the stepped load: the machine stalls", constraint="load_step_Nm",
                         condition="motor_stalls", solver_status=exc.status) from None
    ripple_phi, ripple = after.phi, after.omega - after.mean_speed
    period = 2 * math.pi / before.mean_speed
    t_step = BEFORE * period
    poles = None
    final = after.mean_speed
    notes: list[DesignWarning] = []
    checks: list[ValidityCheck] = []
    if controller is not None:
        ref = controller.reference if controller.reference is not None else before.mean_speed
        controller = PIController(controller.kp, controller.ki, controller.filter_time, ref)
        if not routh_stable(j_mean, s, controller):
            raise Infeasible(
                "the regulator is unstable: the closed loop J·T_f·p³ + (J + s·T_f)·p² + s·(1 + k_p)·p + s·k_i "
                "fails Routh's conditions", constraint="regulator",
                poles_real_1_s=[float(p.real) for p in closed_loop_poles(j_mean, s, controller)])
        poles = closed_loop_poles(j_mean, s, controller)
        zeta = damping_ratio(poles)
        if zeta < MIN_DAMPING:
            raise Infeasible(
                f"the regulator barely damps the loop: damping ratio {zeta:.3g}, below {MIN_DAMPING:g}; the speed "
                "would ring for tens of periods after every step. Lower k_i, raise k_p or shorten the filter",
                constraint="regulator", condition="regulator_underdamped", damping_ratio=zeta,
                poles_real_1_s=[float(p.real) for p in poles], poles_imag_1_s=[float(p.imag) for p in poles])
        checks.append(ValidityCheck("regulator_damping", zeta, LIGHT_DAMPING, zeta >= LIGHT_DAMPING,
                                    "least damping ratio -Re(p)/|p| of the closed loop's poles against the "
                                    "lightly damped limit"))
        if zeta < LIGHT_DAMPING:
            notes.append(DesignWarning(
                "regulator_lightly_damped", "regulator", zeta,
                f"the closed loop's damping ratio is {zeta:.3g} (below {LIGHT_DAMPING:g}): the speed swings several "
                "times after a step; the filter or the gains need another look", "1"))
        final = ref
    slowest = 1.0 / float(np.min(-poles.real)) if poles is not None else tau
    span = horizon if horizon is not None else max(8 * slowest, 6 * period)
    if not (math.isfinite(span) and span > 0) or span > MAX_REVOLUTIONS * period:
        raise InvalidInput(f"the run after the step would be longer than {MAX_REVOLUTIONS} revolutions: the "
                           "regulator is too slow for this machine", field="regulator")
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
        m_d = drive.torque(w, u)
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

    def stopped(t: float, y: FloatArray) -> float:
        return float(y[1])

    stopped.terminal = True  # type: ignore[attr-defined]
    # two runs, so that no step straddles the load's jump
    for a, b in ((0.0, t_step), (t_step, t_end)):
        sol = solve_ivp(rhs, (a, b), y, method="RK45", dense_output=True, rtol=1e-9,
                        atol=1e-10 * max(w_start, 1.0), max_step=period / 32, events=stopped)
        if sol.status == 1:
            raise Infeasible(f"the machine stops {float(sol.t[-1]) - t_step:.4g} s after the load step: the motor "
                             "pulls out past its breakdown torque and cannot bring the speed back",
                             constraint="load_step_Nm", condition="motor_stalls",
                             breakdown_torque_at_crank_Nm=top)
        if not sol.success:
            raise SolverFailed("integration_failed", f"the regulation run failed: {sol.message}")
        pieces.append(sol)
        y = sol.y[:, -1]
    ys = np.where(t_out < t_step, pieces[0].sol(np.minimum(t_out, t_step)), pieces[1].sol(np.maximum(t_out, t_step)))
    phi, w, integral, wf = ys
    if not np.all(w > 0):
        raise Infeasible("the machine stalls after the load step", constraint="load_step_Nm",
                         condition="motor_stalls")
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
    motor_torque = drive.torques(w, shift)
    if math.isfinite(top):
        margin = float(np.min(w - drive.breakdown_speed(shift)))
        checks.append(ValidityCheck(
            "motor_breakdown", margin, 0.0, margin > 0,
            "least margin of the crank speed above the breakdown speed of the characteristic over the run: below "
            "it the motor pulls out and its torque falls [rad/s]", "rad/s"))
        if margin <= 0:
            below = (w < drive.breakdown_speed(shift)) & (t_out >= t_step)
            when = float(t_out[np.flatnonzero(below)[0]] - t_step) if below.any() else 0.0
            notes.append(DesignWarning(
                "motor_breakdown", "load_step_Nm", margin,
                f"the speed falls below the motor's breakdown speed {when:.4g} s after the step: the motor pulls "
                f"out, its torque held at most at the breakdown torque ({top:.4g} N·m at the crank) and falling "
                "toward the starting torque; a linear characteristic would have answered with more torque than "
                "the motor has", "rad/s"))
        mean_after = -float(np.mean(stepped.load_torque))
        checks.append(ValidityCheck(
            "motor_stalls", mean_after, top, mean_after < top,
            "mean load torque at the crank after the step against the motor's breakdown torque there [N·m]",
            "N·m"))
    load = np.interp(phi, cycle.phi, cycle.load_torque, period=2 * math.pi) - np.where(t_out >= t_step, load_step,
                                                                                      0.0)
    late = t_out >= t_step
    dip = float(np.max(np.abs(smoothed[late] - final)))
    if controller is None:
        dip = max(dip, abs(before.mean_speed - final))
    band = band_fraction * dip
    if delta is not None:
        wide = delta * final / 2
        if wide < dip:
            band = wide
        else:
            notes.append(DesignWarning(
                "settling_band_wide", "delta", wide,
                f"the band delta·w/2 = {wide:.4g} rad/s is as wide as the step's whole dip ({dip:.4g} rad/s): the "
                f"speed would count as settled at once; settling is judged in {band_fraction:.3g} of the dip "
                "instead", "rad/s"))
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
    if target is not None:
        asked_ts, asked_os = target
        got_ts = settle if settle is not None else math.inf
        checks.append(ValidityCheck(
            "regulator_settling_time", got_ts, asked_ts * (1 + SETTLING_TOLERANCE),
            got_ts <= asked_ts * (1 + SETTLING_TOLERANCE),
            f"simulated settling after the step against the asked {asked_ts:.4g} s (with "
            f"{SETTLING_TOLERANCE:.0%} room) [s]", "s"))
        checks.append(ValidityCheck(
            "regulator_overshoot", overshoot, asked_os + OVERSHOOT_TOLERANCE,
            overshoot <= asked_os + OVERSHOOT_TOLERANCE,
            f"simulated rise past the reference over the dip against the asked {asked_os:.3g} (with "
            f"{OVERSHOOT_TOLERANCE:g} room)"))
        for c in checks[-2:]:
            if not c.passed:
                notes.append(DesignWarning(
                    c.name, "regulator.settling_time_s" if c.name.endswith("time") else "regulator.overshoot",
                    c.value, f"the tuned regulator misses what was asked: {c.detail.split(' against')[0]} is "
                    f"{c.value:.4g}, the target {c.limit:.4g}; with this filter and motor the loop cannot do it "
                    "(shorten the filter, or ask less)", c.unit or "1"))
    drop_cf = load_step / s
    settle_cf = None
    if controller is None and abs(drop_cf) > band:
        settle_cf = tau * math.log(abs(drop_cf) / band)
    return Regulation(t_out, w, smoothed, motor_torque, load, shift, t_step, load_step, before.mean_speed,
                      after.mean_speed, before.mean_speed - after.mean_speed, drop_cf, tau, band, settle, settle_cf,
                      overshoot, float(np.max(np.abs(smoothed[late] - final))), controller, poles, top, target,
                      tuple(notes), tuple(checks))


def _linear(motor: Motor) -> Motor:
    """The motor's linear branch alone (no breakdown or starting torque): the regulation model's."""
    return Motor(motor.synchronous_speed, motor.rated_speed, motor.rated_torque, motor.gear_ratio, motor.efficiency,
                 motor.rotor_inertia)


def regulate_linkage(linkage: Linkage, speed: float, motor: Motor, load_step: float, *, constant_inertia: float = 0.0,
                     delta: float | None = None, band_fraction: float = BAND_FRACTION, controller: PIController | None = None,
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
    target = None if tuning is None else (tuning[0], tuning[1])
    return regulate(cycle, constant_inertia, motor, load_step, delta=delta, band_fraction=band_fraction,
                    controller=controller, target=target)
