"""Steady periodic speed over the cycle from the equation of motion, and the delta it actually gives.

The equation of motion J(phi)·w·dw/dphi + J'(phi)·w²/2 = M is the exact differential d(J·w²/2)/dphi = M. With a
torque independent of speed the kinetic energy is E0 + A(phi) and the speed follows from the work alone; E0 is
set by the mean speed. With a motor the energy form is integrated with scipy's ``solve_ivp`` and the initial
energy is shot until the motion repeats after one cycle. Both paths look at the speed densely over the cycle
and never use a sizing formula.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from ..errors import InvalidInput, SolverFailed
from ..model import FloatArray
from .cycle import ReducedCycle
from .motor import ReducedMotor


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


def steady_speed_motor(
    cycle: ReducedCycle,
    constant_inertia: float,
    motor: ReducedMotor,
    points: int = 20_000,
    *,
    method: str = "RK45",
    rtol: float = 1e-9,
) -> SpeedProfile:
    """Steady periodic speed with a motor characteristic, by shooting on the initial kinetic energy.

    ``cycle.torque`` is the load torque alone [N·m]; ``constant_inertia`` [kg·m²] on top of J_red(phi), the
    rotor's reduced inertia included by the caller.
    """
    nodes, inertia_n, torque_n = cycle.closed()
    total_n = _total_inertia(inertia_n, constant_inertia)
    start, end = float(nodes[0]), float(nodes[-1])

    def rhs(phi: float, y: FloatArray) -> FloatArray:
        # y = (energy, d energy / d initial energy): the sensitivity drives Newton's shooting
        j = np.interp(phi, nodes, total_n)
        w = np.sqrt(max(2 * y[0] / j, 1e-300))
        load = np.interp(phi, nodes, torque_n)
        return np.array([load + motor.slope * (motor.no_load_speed - w), -motor.slope / (j * w) * y[1]])

    def stall(phi: float, y: FloatArray) -> float:
        return float(y[0])

    stall.terminal = True  # type: ignore[attr-defined]

    def run(e0: float, dense: bool = False) -> Any:
        sol = solve_ivp(
            rhs, (start, end), [e0, 1.0], method=method, rtol=rtol, atol=[rtol * 1e-2 * e0, rtol * 1e-2],
            events=stall, dense_output=dense,
        )
        if sol.status == -1:
            raise SolverFailed("solve_ivp_failed", str(sol.message))
        return sol

    e0 = 0.5 * float(total_n[0]) * motor.mean_speed(cycle) ** 2
    for _ in range(50):
        sol = run(e0)
        if sol.status == 1:
            raise SolverFailed("no_periodic_motion", "the machine stalls: no periodic motion with this motor")
        gap, slope = float(sol.y[0, -1]) - e0, float(sol.y[1, -1]) - 1.0
        step = -gap / slope
        while e0 + step <= 0:
            step *= 0.5
        e0 += step
        # the integration's own error sets a floor under the gap; 1e-6 of the energy is 5e-7 of the speed
        if abs(step) <= 1e-6 * e0:
            break
    else:
        raise SolverFailed("no_periodic_motion", "shooting for the periodic motion did not converge")
    sol = run(e0, dense=True)
    phi = cycle.dense(points)
    energy = sol.sol(phi)[0]
    inertia, _, _ = cycle.evaluate(phi)
    omega = np.sqrt(np.maximum(2 * energy / (inertia + constant_inertia), 0.0))
    return _profile(phi, omega)
