"""The assembled machine run to its periodic steady state: the independent check of a whole design.

The equation of motion is integrated in its velocity form, J(phi)·w·dw/dphi = M_load(phi) + M_motor(w) -
J'(phi)·w²/2, with J'(phi) the analytic slope of the linkage's reduced inertia (not the finite differences of
the energy form the flywheel NLP and its own check use), the motor's characteristic through the real train
ratio and efficiency, and the constant inertia of rotor, train and flywheel, by classical Runge-Kutta steps
between the samples. Newton shooting on the initial speed, with the variational equation for the slope, finds
the motion that repeats after one revolution.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InvalidInput, SolverFailed
from ..flywheel import Motor
from ..model import FloatArray


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


def _periodic(phi: FloatArray, values: FloatArray) -> FloatArray:
    return np.append(values, values[0])


def _rk4_cycle(tables: tuple[list[float], list[float], list[float], list[float]], w0: float, c: float, w_free: float,
               substeps: int) -> tuple[list[float], float]:
    """One revolution of dw/dphi = f(phi, w) from ``w0`` by classical Runge-Kutta, ``substeps`` per sample.

    f = (M(phi) + c·(w_free - w) - J'(phi)·w²/2) / (J(phi)·w) with J, J', M linear between samples. Carries the
    variational equation ds/dphi = df/dw · s, s(0) = 1, for Newton's shooting. Returns the speed at every
    sample (closed, N+1) and s after one revolution. An ODE is sequential in the angle: this loop is the
    stepper itself, over plain floats.
    """
    nodes, inertia, slope, load = tables

    def f(j: float, dj: float, m: float, w: float, sv: float) -> tuple[float, float]:
        r = (m + c * (w_free - w) - 0.5 * dj * w * w) / (j * w)
        return r, ((-c - dj * w) / (j * w) - r / w) * sv

    out = [w0]
    w, sv = w0, 1.0
    for k in range(len(nodes) - 1):
        h = (nodes[k + 1] - nodes[k]) / substeps
        j0, j1 = inertia[k], inertia[k + 1]
        d0, d1 = slope[k], slope[k + 1]
        m0, m1 = load[k], load[k + 1]
        for i in range(substeps):
            ta, tm, tb = i / substeps, (i + 0.5) / substeps, (i + 1) / substeps
            ja, jm, jb = j0 + ta * (j1 - j0), j0 + tm * (j1 - j0), j0 + tb * (j1 - j0)
            da, dm, db = d0 + ta * (d1 - d0), d0 + tm * (d1 - d0), d0 + tb * (d1 - d0)
            ma, mm, mb = m0 + ta * (m1 - m0), m0 + tm * (m1 - m0), m0 + tb * (m1 - m0)
            k1, l1 = f(ja, da, ma, w, sv)
            k2, l2 = f(jm, dm, mm, w + 0.5 * h * k1, sv + 0.5 * h * l1)
            k3, l3 = f(jm, dm, mm, w + 0.5 * h * k2, sv + 0.5 * h * l2)
            k4, l4 = f(jb, db, mb, w + h * k3, sv + h * l3)
            w += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
            sv += h / 6 * (l1 + 2 * l2 + 2 * l3 + l4)
            if not w > 0:
                raise SolverFailed("no_periodic_motion", "the machine stalls: the motor cannot keep it turning")
        out.append(w)
    return out, sv


def simulate_machine(cycle: MachineCycle, constant_inertia: float, motor: Motor, *, substeps: int = 4) -> MachineMotion:
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
        Runge-Kutta steps per sample interval; the tables are linear between samples, so four keep the
        integration error far below the 1e-3 the checks ask.

    Raises SolverFailed (``no_periodic_motion``) when the machine stalls or the shooting does not converge.
    """
    if not (math.isfinite(constant_inertia) and constant_inertia >= 0):
        raise InvalidInput("constant inertia must not be negative", field="constant_inertia_kgm2")
    nodes = np.append(cycle.phi, cycle.phi[0] + 2 * math.pi)
    j = _periodic(cycle.phi, cycle.inertia + constant_inertia)
    dj = _periodic(cycle.phi, cycle.inertia_slope)
    load = _periodic(cycle.phi, cycle.load_torque)
    if not np.all(j > 0):
        raise InvalidInput("the machine has no inertia at some crank angles", field="constant_inertia_kgm2")
    red = motor.reduced()
    tables = (nodes.tolist(), j.tolist(), dj.tolist(), load.tolist())
    # the linear characteristic's steady angle-average speed starts the shooting close to the answer
    w0 = red.no_load_speed + float(np.trapezoid(load, nodes)) / (red.slope * 2 * math.pi)
    for _ in range(40):
        speeds, sens = _rk4_cycle(tables, w0, red.slope, red.no_load_speed, substeps)
        gap, slope = speeds[-1] - w0, sens - 1.0
        step = -gap / slope if slope != 0 else 0.0
        while w0 + step <= 0:
            step *= 0.5
        w0 += step
        if abs(step) <= 1e-12 * w0:
            break
    else:
        raise SolverFailed("no_periodic_motion", "shooting for the periodic motion did not converge")
    omega = np.asarray(_rk4_cycle(tables, w0, red.slope, red.no_load_speed, substeps)[0], dtype=float)
    phi = nodes
    alpha = (load + red.slope * (red.no_load_speed - omega) - 0.5 * dj * omega**2) / j
    torque = motor.torque_at(motor.gear_ratio * omega)
    period = float(np.trapezoid(1.0 / omega, phi))
    lo, hi = float(omega.min()), float(omega.max())
    peak = float(np.abs(torque).max())
    rms = math.sqrt(float(np.trapezoid(torque**2 / omega, phi)) / period)
    margin = None if motor.breakdown_torque is None else 1.0 - peak / motor.breakdown_torque
    return MachineMotion(phi, omega, alpha, torque, (hi - lo) / (0.5 * (hi + lo)), 2 * math.pi / period, period,
                         peak, rms, margin)
