"""Steady periodic speed over the cycle from the equation of motion, and the delta it actually gives.

The equation of motion J(phi)·w·dw/dphi + J'(phi)·w²/2 = M is the exact differential d(J·w²/2)/dphi = M. With a
torque independent of speed the kinetic energy is E0 + A(phi) and the speed follows from the work alone; E0 is
set by the mean speed. With a motor the periodic solution of the energy form is found directly: the trapezoidal
rule over a dense grid closed on itself, solved by Newton's method, on two grids with Richardson's
extrapolation and its error estimate. Both paths look at the speed densely over the cycle and never use a
sizing formula.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg.lapack import dtbtrs
from scipy.optimize import brentq

from ..errors import InvalidInput, SolverFailed
from ..model import FloatArray
from .cycle import ReducedCycle
from .motor import ReducedMotor

_NEWTON_ITERATIONS = 60
_MAX_REFINEMENTS = 3
# The speed fluctuation is reported to about 1e-8; the two grids' deltas must agree to that.
_DELTA_TOLERANCE = 1e-8


@dataclass(frozen=True, slots=True)
class SpeedProfile:
    """Steady crank speed over one cycle: ``phi`` [rad] and ``omega`` [rad/s] on a dense grid, (M,) each.

    ``delta`` = (w_max - w_min)/w_mean with w_mean = (w_max + w_min)/2 [-]; ``stalls`` when the speed falls to
    zero within the cycle (no steady motion at this mean speed; delta is then its limit 2).
    """

    phi: FloatArray
    omega: FloatArray
    omega_min: float
    omega_max: float
    delta: float
    stalls: bool = False

    @property
    def mean_speed(self) -> float:
        """(w_max + w_min)/2 [rad/s]."""
        return 0.5 * (self.omega_max + self.omega_min)

    def thinned(self, points: int = 721) -> tuple[FloatArray, FloatArray]:
        """At most ``points`` of the dense (angle [rad], speed [rad/s]) pairs, evenly picked, ends kept."""
        keep = np.unique(np.linspace(0, self.phi.size - 1, min(points, self.phi.size)).round().astype(int))
        return self.phi[keep], self.omega[keep]


def speed_fluctuation(omega: FloatArray) -> tuple[float, float, float]:
    """w_min, w_max [rad/s] and delta = (w_max - w_min)/w_mean with w_mean = (w_max + w_min)/2 of speeds [rad/s].

    Notes
    -----
    The seeds' definition (003:433-445).
    """
    w = np.asarray(omega, dtype=float)
    lo, hi = float(w.min()), float(w.max())
    if not lo >= 0 or not hi > 0:
        raise InvalidInput("speeds must be non-negative and not all zero", field="omega")
    return lo, hi, (hi - lo) / (0.5 * (hi + lo))


def _profile(phi: FloatArray, omega: FloatArray, stalls: bool = False) -> SpeedProfile:
    lo, hi, delta = speed_fluctuation(omega)
    return SpeedProfile(phi, omega, lo, hi, 2.0 if stalls else delta, stalls)


def _total_inertia(inertia: FloatArray, constant_inertia: float) -> FloatArray:
    total = inertia + constant_inertia
    if not np.all(total > 0):
        raise InvalidInput(
            "the machine has no inertia at some crank angles; give constant_inertia_kgm2", field="constant_inertia_kgm2"
        )
    return total


def steady_speed(cycle: ReducedCycle, constant_inertia: float, mean_speed: float, points: int = 20_000) -> SpeedProfile:
    """Steady speed of a balanced cycle under a speed-independent torque, with (w_max + w_min)/2 = ``mean_speed``.

    Parameters
    ----------
    cycle
        Reduced cycle whose torque does zero work over the cycle [N·m].
    constant_inertia
        Constant inertia on the crank on top of J_red(phi) [kg·m²].
    mean_speed
        (w_max + w_min)/2 [rad/s].
    points
        Least number of angles at which the speed is evaluated.
    """
    scale = float(np.sum(np.abs(cycle.torque))) * cycle.period / cycle.samples
    if abs(cycle.cycle_work) > 1e-9 * max(scale, 1e-300):
        raise InvalidInput("the cycle's work does not balance; steady motion needs zero net work", field="torque")
    phi = cycle.dense(points)
    inertia, _, work = cycle.evaluate(phi)
    total = _total_inertia(inertia, constant_inertia)
    floor = -float(work.min())

    def speeds(e0: float) -> FloatArray:
        return np.asarray(np.sqrt(np.maximum(2 * (e0 + work) / total, 0.0)), dtype=float)

    def excess(e0: float) -> float:
        w = speeds(e0)
        return 0.5 * (float(w.max()) + float(w.min())) - mean_speed

    if excess(floor) >= 0:
        return _profile(phi, speeds(floor), stalls=True)
    top = max(floor, 0.0) + 0.5 * float(total.max()) * mean_speed**2
    while excess(top) < 0:
        top *= 2
    e0 = brentq(excess, floor, top, xtol=1e-14 * top, rtol=4 * np.finfo(float).eps, maxiter=200)
    return _profile(phi, speeds(e0))


def _periodic_energy(phi: FloatArray, total: FloatArray, load: FloatArray, motor: ReducedMotor,
                     guess: FloatArray) -> FloatArray:
    """Periodic kinetic energy at the angles ``phi`` (the last one period after the first) by the trapezoidal
    rule closed on itself, solved by Newton's method.

    Residuals E_(i+1) - E_i - h_i/2 (f_i + f_(i+1)) with f = M_load + slope·(w0 - sqrt(2E/J)) and E at the
    end equal to E at the start. The rule is A-stable, so a machine with almost no inertia (a stiff equation)
    takes as few steps as any other. Each Newton step solves the cyclic bidiagonal system as a banded one plus
    a rank-one corner (Sherman-Morrison); its diagonal 1 + h/2·slope/(J·w) is at least one.

    Raises SolverFailed when the energy would have to reach zero (the machine stalls) or Newton's method does
    not settle.
    """
    h = np.diff(phi)
    j_now, j_next = total[:-1], total[1:]
    m_now, m_next = load[:-1], load[1:]
    e = guess[:-1].copy()
    scale = float(np.max(e))
    for _ in range(_NEWTON_ITERATIONS):
        e_next = np.roll(e, -1)
        w_now, w_next = np.sqrt(2 * e / j_now), np.sqrt(2 * e_next / j_next)
        f_now = m_now + motor.slope * (motor.no_load_speed - w_now)
        f_next = m_next + motor.slope * (motor.no_load_speed - w_next)
        residual = e_next - e - 0.5 * h * (f_now + f_next)
        # d residual_i / d E_(i+1) = 1 + h/2·slope/(J w) (the diagonal, unknown i+1), d / d E_i = -(1 - ...).
        diag = 1 + 0.5 * h * motor.slope / (j_next * w_next)
        sub = -(1 - 0.5 * h * motor.slope / (j_now * w_now))
        step = _cyclic_bidiagonal(diag, sub, -residual)      # corrections to E_1 .. E_m (E_m is E_0)
        step = np.roll(step, 1)
        size = 1.0
        while np.any(e + size * step <= 0):
            size *= 0.5
            if size < 1e-6:
                raise SolverFailed("no_periodic_motion", "the machine stalls: no periodic motion with this motor")
        e = e + size * step
        if size == 1.0 and float(np.max(np.abs(step))) <= 1e-13 * scale:
            return np.append(e, e[0])
    raise SolverFailed("no_periodic_motion", "the periodic motion with this motor did not settle")


def _cyclic_bidiagonal(diag: FloatArray, sub: FloatArray, rhs: FloatArray) -> FloatArray:
    """Solve diag_i x_i + sub_i x_(i-1) = rhs_i for all i, with x_(-1) = x_(m-1) (cyclic)."""
    m = len(diag)
    banded = np.zeros((2, m))
    banded[0] = diag
    banded[1, :-1] = sub[1:]
    corner = np.zeros(m)
    corner[0] = sub[0]
    both, info = dtbtrs(banded, np.stack([rhs, corner], axis=1), uplo="L")
    if info != 0:
        raise SolverFailed("no_periodic_motion", "the periodic motion with this motor has a singular Newton system")
    y, z = both[:, 0], both[:, 1]
    return np.asarray(y - z * (y[-1] / (1 + z[-1])), dtype=float)


def steady_speed_motor(
    cycle: ReducedCycle,
    constant_inertia: float,
    motor: ReducedMotor,
    points: int = 8_000,
) -> SpeedProfile:
    """Steady periodic speed with a motor characteristic: the periodic solution of the energy equation.

    ``cycle.torque`` is the load torque alone [N·m]; ``constant_inertia`` [kg·m²] on top of J_red(phi), the
    rotor's reduced inertia included by the caller. The trapezoidal rule on ``cycle.dense(points / 2)`` and on
    the grid with every step halved, closed on itself and solved by Newton's method (``_periodic_energy``), then
    Richardson's extrapolation of the two (fourth order: J and M are linear between the cycle's samples, and
    every sample is a grid angle). The difference of the two grids' deltas is the error estimate; a grid is
    refined (up to ``_MAX_REFINEMENTS`` times) until it is below ``_DELTA_TOLERANCE``.
    """
    omega0 = motor.mean_speed(cycle)
    for _ in range(_MAX_REFINEMENTS):
        phi = cycle.dense(points // 2)
        fine = np.empty(2 * phi.size - 1)
        fine[0::2] = phi
        fine[1::2] = 0.5 * (phi[1:] + phi[:-1])
        inertia, load, _ = cycle.evaluate(fine)
        # the period's end is the start again: take the first sample's values there, not the wrap-around's
        inertia[-1], load[-1] = inertia[0], load[0]
        total_fine = _total_inertia(inertia, constant_inertia)
        total = total_fine[0::2]
        coarse = _periodic_energy(phi, total, load[0::2], motor, 0.5 * total * omega0**2)
        guess = np.interp(fine, phi, coarse)
        refined = _periodic_energy(fine, total_fine, load, motor, guess)
        energy = (4 * refined[0::2] - coarse) / 3
        omega = np.sqrt(np.maximum(2 * energy / total, 0.0))
        estimate = abs(speed_fluctuation(np.sqrt(2 * coarse / total))[2] - speed_fluctuation(omega)[2])
        if estimate <= _DELTA_TOLERANCE:
            return _profile(phi, omega)
        points *= 4
    raise SolverFailed("no_periodic_motion", "the periodic motion with this motor did not converge on any grid")
