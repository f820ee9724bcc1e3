"""The assembled machine run to its periodic steady state: the independent check of a whole design.

The equation of motion is integrated in its velocity form, J(phi)·w·dw/dphi = M_load(phi) + M_motor(w) -
J'(phi)·w²/2, with J'(phi) the analytic slope of the linkage's reduced inertia (not the finite differences of
the energy form the flywheel NLP and its own check use), the motor's characteristic through the real train
ratio and efficiency, and the constant inertia of rotor, train and flywheel, by classical Runge-Kutta steps
between the samples (compiled once per step count with CasADi). Newton shooting on the initial speed, with the
variational equation for the slope, finds the motion that repeats after one revolution.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import casadi as ca
import numpy as np

from ..errors import InvalidInput, SolverFailed
from ..flywheel import Motor
from ..model import FloatArray


#: A shooting step below this fraction of the speed is applied along the motion by its sensitivity [-].
LINEAR_STEP = 1e-5
#: Steps up to which the stepper is expanded into one flat expression: a fifth faster a call, for a build of
#: tens of milliseconds once per process (any sample count up to 1440 gives fewer steps than this).
EXPAND_STEPS = 2880


@dataclass(frozen=True, slots=True)
class MachineCycle:
    """The linkage reduced to its crank at ``phi`` [rad] over one revolution: ``inertia`` J_red [kg·m²], its
    analytic ``inertia_slope`` dJ_red/dphi [kg·m²/rad], ``load_torque`` [N·m] (positive drives), (N,) each."""

    phi: FloatArray
    inertia: FloatArray
    inertia_slope: FloatArray
    load_torque: FloatArray


@dataclass(frozen=True, slots=True)
class MachineMotion:
    """Steady periodic motion of the assembled machine over one revolution.

    ``phi`` [rad], ``omega`` crank speed [rad/s], ``alpha`` crank acceleration [rad/s²], ``motor_torque`` on the
    motor shaft [N·m], ``dt`` time per angle step weight 1/w [s/rad], all (M,); ``delta`` (w_max - w_min)/w_mean
    [-]; ``mean_speed`` 2·pi over the period [rad/s]; ``period`` [s]; ``motor_peak_torque`` and
    ``motor_rms_torque`` (over time) [N·m]; ``breakdown_margin`` 1 - peak/breakdown torque [-] (None when the
    motor has no breakdown torque).
    """

    phi: FloatArray
    omega: FloatArray
    alpha: FloatArray
    motor_torque: FloatArray
    delta: float
    mean_speed: float
    period: float
    motor_peak_torque: float
    motor_rms_torque: float
    breakdown_margin: float | None

    def time_mean(self, values: FloatArray) -> float:
        """Mean over time of ``values`` given at ``phi`` (weights dt = dphi/w)."""
        return float(np.trapezoid(values / self.omega, self.phi) / self.period)

    def time_rms(self, values: FloatArray) -> float:
        """RMS over time of ``values`` given at ``phi``."""
        return math.sqrt(self.time_mean(values**2))


def _closed(values: FloatArray) -> FloatArray:
    """A table with its first value repeated one revolution later."""
    return np.append(values, values[0])


@lru_cache(maxsize=16)
def _cycle_stepper(steps: int) -> ca.Function:
    """Classical Runge-Kutta over ``steps`` steps of dw/dphi = f(phi, w), compiled once per step count.

    f = (M(phi) + c·(w_free - w) - J'(phi)·w²/2) / (J(phi)·w). The state carries the variational equation
    ds/dphi = df/dw · s, s(0) = 1, for Newton's shooting. Each step's column of parameters holds its length, J,
    J' and M at its start, middle and end, and c, w_free; the answer is the state after every step.
    """
    x = ca.SX.sym("x", 2)
    p = ca.SX.sym("p", 12)
    h, ja, jm, jb, da, dm, db, ma, mm, mb, c, w_free = (p[i] for i in range(12))

    def f(j: ca.SX, dj: ca.SX, m: ca.SX, w: ca.SX, sv: ca.SX) -> ca.SX:
        r = (m + c * (w_free - w) - 0.5 * dj * w * w) / (j * w)
        return ca.vertcat(r, ((-c - dj * w) / (j * w) - r / w) * sv)

    k1 = f(ja, da, ma, x[0], x[1])
    k2 = f(jm, dm, mm, x[0] + 0.5 * h * k1[0], x[1] + 0.5 * h * k1[1])
    k3 = f(jm, dm, mm, x[0] + 0.5 * h * k2[0], x[1] + 0.5 * h * k2[1])
    k4 = f(jb, db, mb, x[0] + h * k3[0], x[1] + h * k3[1])
    step = ca.Function("step", [x, p], [x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)])
    accumulated = step.mapaccum("cycle", steps)
    return accumulated.expand() if steps <= EXPAND_STEPS else accumulated


def _step_parameters(nodes: FloatArray, tables: tuple[FloatArray, FloatArray, FloatArray], c: float,
                     w_free: float, substeps: int) -> FloatArray:
    """The (12, N·substeps) parameter columns of :func:`_cycle_stepper`: tables linear between samples."""
    t = np.arange(substeps) / substeps
    frac = [t, t + 0.5 / substeps, t + 1.0 / substeps]
    h = np.repeat(np.diff(nodes) / substeps, substeps)
    rows = [h]
    for v in tables:
        start, rise = v[:-1, None], np.diff(v)[:, None]
        rows += [(start + f[None, :] * rise).reshape(-1) for f in frac]
    rows += [np.full(h.size, c), np.full(h.size, w_free)]
    return np.vstack(rows)


def simulate_machine(cycle: MachineCycle, constant_inertia: float, motor: Motor, *,
                     substeps: int | None = None, start: float | None = None) -> MachineMotion:
    """Integrate the assembled machine to its periodic steady state.

    Parameters
    ----------
    cycle
        The linkage reduced to its crank (counter-rotors and counterweights included) [kg·m², N·m].
    constant_inertia
        Rotor, train and flywheel reduced to the crank [kg·m²].
    motor
        Catalogue characteristic with the real train ratio and the train's efficiency [-].
    substeps
        Runge-Kutta steps per sample interval; default enough for about 1440 steps per revolution (four at
        360 samples). The tables are linear between samples, so the integration error stays far below the
        1e-3 the checks ask.
    start
        Crank speed at ``phi[0]`` to start the shooting from [rad/s]; the periodic motion found does not
        depend on it. Default the characteristic's steady mean speed.

    Raises SolverFailed (``no_periodic_motion``) when the machine stalls or the shooting does not converge.
    """
    if not (math.isfinite(constant_inertia) and constant_inertia >= 0):
        raise InvalidInput("constant inertia must not be negative", field="constant_inertia_kgm2")
    nodes = np.append(cycle.phi, cycle.phi[0] + 2 * math.pi)
    j = _closed(cycle.inertia + constant_inertia)
    dj = _closed(cycle.inertia_slope)
    load = _closed(cycle.load_torque)
    if not np.all(j > 0):
        raise InvalidInput("the machine has no inertia at some crank angles", field="constant_inertia_kgm2")
    red = motor.reduced()
    if substeps is None:
        substeps = max(1, math.ceil(1440 / cycle.phi.size))
    if substeps < 1:
        raise InvalidInput("substeps must be at least 1", field="substeps")
    params = _step_parameters(nodes, (j, dj, load), red.slope, red.no_load_speed, substeps)
    stepper = _cycle_stepper(params.shape[1])
    if start is None:
        # the linear characteristic's steady angle-average speed starts the shooting close to the answer
        start = red.no_load_speed + float(np.trapezoid(load, nodes)) / (red.slope * 2 * math.pi)
    w0 = float(start)
    for _ in range(40):
        states = np.asarray(stepper(np.array([w0, 1.0]), params), dtype=float)
        if not (np.all(np.isfinite(states)) and np.all(states[0] > 0)):
            raise SolverFailed("no_periodic_motion", "the machine stalls: the motor cannot keep it turning")
        speeds, sens = np.concatenate(([w0], states[0])), float(states[1, -1])
        gap, slope = float(speeds[-1]) - w0, sens - 1.0
        step = -gap / slope if slope != 0 else 0.0
        if abs(step) <= 1e-11 * w0:
            break
        if abs(step) <= LINEAR_STEP * w0:
            # the last Newton step moves the whole motion by step·dw/dw0, which the variational state holds at
            # every step; what that leaves out is of order step²/w0, about 1e-10 of the speed and of delta
            # (measured against shooting to 1e-11), and one integration less
            speeds = speeds + step * np.concatenate(([1.0], states[1]))
            w0 += step
            break
        while w0 + step <= 0:
            step *= 0.5
        w0 += step
    else:
        raise SolverFailed("no_periodic_motion", "shooting for the periodic motion did not converge")
    omega = np.asarray(speeds, dtype=float)
    # every Runge-Kutta step is reported, so the extremes between samples are seen
    t = np.arange(substeps) / substeps
    phi = np.append((nodes[:-1, None] + t[None, :] * np.diff(nodes)[:, None]).reshape(-1), nodes[-1])
    j, dj, load = (np.interp(phi, nodes, v) for v in (j, dj, load))
    alpha = (load + red.slope * (red.no_load_speed - omega) - 0.5 * dj * omega**2) / j
    torque = motor.torque_at(motor.gear_ratio * omega)
    period = float(np.trapezoid(1.0 / omega, phi))
    lo, hi = float(omega.min()), float(omega.max())
    peak = float(np.abs(torque).max())
    rms = math.sqrt(float(np.trapezoid(torque**2 / omega, phi)) / period)
    margin = None if motor.breakdown_torque is None else 1.0 - peak / motor.breakdown_torque
    return MachineMotion(phi, omega, alpha, torque, (hi - lo) / (0.5 * (hi + lo)), 2 * math.pi / period, period,
                         peak, rms, margin)
