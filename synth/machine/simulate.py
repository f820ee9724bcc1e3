"""The assembled machine run to its periodic steady state: the independent check of a whole design.

The equation of motion is integrated in its velocity form, J(phi)·w·dw/dphi = M_load(phi) + M_motor(w) -
J'(phi)·w²/2, with J'(phi) the analytic slope of the linkage's reduced inertia (not the finite differences of
the energy form the flywheel NLP and its own check use), the motor's characteristic through the real train
ratio and efficiency, and the constant inertia of rotor, train and flywheel, by classical Runge-Kutta steps
between the samples (one compiled loop, :mod:`synth.compiled`). Newton shooting on the initial speed, with the
variational equation for the slope, finds the motion that repeats after one revolution.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..compiled import compiled
from ..errors import InvalidInput, SolverFailed
from ..flywheel import Motor
from ..model import FloatArray


#: A shooting step below this fraction of the speed is applied along the motion by its sensitivity [-].
LINEAR_STEP = 1e-5


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


@compiled
def _march(w0: float, nodes: FloatArray, tables: FloatArray, frac: FloatArray, c: float,
           w_free: float) -> FloatArray:  # pragma: no cover - compiled; run through simulate_machine
    """Classical Runge-Kutta of dw/dphi = f(phi, w) with its variational state, ``frac.shape[1]`` steps between
    each two ``nodes`` [rad].

    f = (M(phi) + c·(w_free - w) - J'(phi)·w²/2) / (J(phi)·w). The state carries the variational equation
    ds/dphi = df/dw · s, s(0) = 1, for Newton's shooting. ``tables`` (3, N + 1) hold J, J' and M at the closed
    nodes, linear between them; a step reads them at the fractions ``frac`` (3, substeps) of its interval (its
    start, middle and end). The answer (2, N·substeps) is the state after every step.
    """
    substeps = frac.shape[1]
    out = np.empty((2, (nodes.shape[0] - 1) * substeps))
    w, s = w0, 1.0
    for n in range(nodes.shape[0] - 1):
        h = (nodes[n + 1] - nodes[n]) / substeps
        j0, d0, m0 = tables[0, n], tables[1, n], tables[2, n]
        rj, rd, rm = tables[0, n + 1] - j0, tables[1, n + 1] - d0, tables[2, n + 1] - m0
        for k in range(substeps):
            fa, fm, fb = frac[0, k], frac[1, k], frac[2, k]
            ja, jm, jb = j0 + fa * rj, j0 + fm * rj, j0 + fb * rj
            da, dm, db = d0 + fa * rd, d0 + fm * rd, d0 + fb * rd
            ma, mm, mb = m0 + fa * rm, m0 + fm * rm, m0 + fb * rm
            r1 = (ma + c * (w_free - w) - 0.5 * da * w * w) / (ja * w)
            s1 = ((-c - da * w) / (ja * w) - r1 / w) * s
            w2, v2 = w + 0.5 * h * r1, s + 0.5 * h * s1
            r2 = (mm + c * (w_free - w2) - 0.5 * dm * w2 * w2) / (jm * w2)
            s2 = ((-c - dm * w2) / (jm * w2) - r2 / w2) * v2
            w3, v3 = w + 0.5 * h * r2, s + 0.5 * h * s2
            r3 = (mm + c * (w_free - w3) - 0.5 * dm * w3 * w3) / (jm * w3)
            s3 = ((-c - dm * w3) / (jm * w3) - r3 / w3) * v3
            w4, v4 = w + h * r3, s + h * s3
            r4 = (mb + c * (w_free - w4) - 0.5 * db * w4 * w4) / (jb * w4)
            s4 = ((-c - db * w4) / (jb * w4) - r4 / w4) * v4
            w = w + h / 6 * (r1 + 2 * r2 + 2 * r3 + r4)
            s = s + h / 6 * (s1 + 2 * s2 + 2 * s3 + s4)
            out[0, n * substeps + k] = w
            out[1, n * substeps + k] = s
    return out


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
    # J, J' and M at the nodes, each closed on its first value: the march reads them as one (3, N + 1) table
    n = cycle.phi.size
    tables = np.empty((3, n + 1))
    tables[0, :n] = cycle.inertia + constant_inertia
    tables[1, :n] = cycle.inertia_slope
    tables[2, :n] = cycle.load_torque
    tables[:, n] = tables[:, 0]
    j, dj, load = tables
    if not np.all(j > 0):
        raise InvalidInput("the machine has no inertia at some crank angles", field="constant_inertia_kgm2")
    red = motor.reduced()
    if substeps is None:
        substeps = max(1, math.ceil(1440 / cycle.phi.size))
    if substeps < 1:
        raise InvalidInput("substeps must be at least 1", field="substeps")
    t = np.arange(substeps) / substeps
    frac = np.stack((t, t + 0.5 / substeps, t + 1.0 / substeps))
    if start is None:
        # the linear characteristic's steady angle-average speed starts the shooting close to the answer
        start = red.no_load_speed + float(np.trapezoid(load, nodes)) / (red.slope * 2 * math.pi)
    w0 = float(start)
    for _ in range(40):
        states = _march(w0, nodes, tables, frac, red.slope, red.no_load_speed)
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
