"""Constant inertia that keeps the speed fluctuation of a balanced cycle within delta: three textbook methods.

Every method returns the *required constant inertia* J_c: the constant part of the reduced inertia (motor rotor,
gears, flywheel) that the machine needs on top of its variable J_red(phi). The flywheel to add is J_c minus the
constant inertia already on the shaft.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InvalidInput
from ..model import FloatArray
from .cycle import ReducedCycle


# The narrowest speed band the sizing resolves: w_m(1 ± delta/2) keeps about four digits of delta here.
MIN_DELTA = 1e-12


def speed_band(mean_speed: float, delta: float) -> tuple[float, float]:
    """Extreme speeds w_min, w_max = w_m (1 ∓ delta/2) [rad/s] whose mean is w_m and whose spread is delta·w_m."""
    if not mean_speed > 0:
        raise InvalidInput("mean speed must be positive", field="mean_speed_rad_s")
    if not 0 < delta < 2:
        raise InvalidInput("delta must lie in (0, 2)", field="delta")
    if delta < MIN_DELTA:
        # w_max² - w_min² = 2·delta·w_m²: below this it is lost in the rounding of w_m² (16 digits), and the
        # sizing's tangents would coincide
        raise InvalidInput(f"delta {delta:g} is below {MIN_DELTA:g}: a speed band this narrow cannot be told from "
                           "rounding in double precision", field="delta")
    return mean_speed * (1 - delta / 2), mean_speed * (1 + delta / 2)


def energy_extremes(cycle: ReducedCycle, c: float, *, samples_only: bool = False) -> tuple[float, float]:
    """Largest and smallest value over the whole cycle of A(phi) - c·J(phi) [J], for ``c`` [J/(kg·m²)].

    On a piece of the cycle A is quadratic and J linear in the angle, so each piece's extreme is at an end or at
    the vertex of its parabola: evaluated for all pieces at once. ``samples_only`` looks at the samples alone,
    as the seeds' graphical method does with its few positions.
    """
    return _EnergyPieces.of(cycle).extremes(c, samples_only=samples_only)


@dataclass(frozen=True, slots=True)
class _EnergyPieces:
    """What A(phi) - c·J(phi) is made of on each piece of the cycle whatever ``c``: the work and inertia at the
    closed samples, the pieces' work slope at their start times their length and their inertia rise, and the
    coefficient of the work's parabola, so that both Wittenbauer tangents read the cycle once."""

    work: FloatArray
    inertia: FloatArray
    slope_work: FloatArray
    rise: FloatArray
    quad: FloatArray

    @staticmethod
    def of(cycle: ReducedCycle) -> _EnergyPieces:
        phi, inertia, torque = cycle.closed()
        h = np.diff(phi)
        return _EnergyPieces(cycle.work_nodes(), inertia, h * torque[:-1], np.diff(inertia), 0.5 * h * np.diff(torque))

    def extremes(self, c: float, *, samples_only: bool = False) -> tuple[float, float]:
        """Largest and smallest A - c·J [J] (see :func:`energy_extremes`)."""
        f0 = self.work - c * self.inertia
        lin = self.slope_work - c * self.rise
        quad = self.quad
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(quad != 0, -lin / (2 * quad), -1.0)
        inside = (t > 0) & (t < 1)
        vertex = f0[:-1] + lin * t + quad * t**2
        candidates = f0 if samples_only else np.concatenate((f0, vertex[inside]))
        return float(candidates.max()), float(candidates.min())


@dataclass(frozen=True, slots=True)
class Tangents:
    """The two limit tangents of the energy-mass (Wittenbauer) diagram, work [J] over J_red [kg·m²].

    Tangent k is ``work = slope_k * inertia + intercept_k``; ``slope_max`` = w_max²/2, ``slope_min`` = w_min²/2
    [J/(kg·m²)]. Their intercepts on the work axis differ by J_c·delta·w_m² (seed 002:154-194).
    """

    slope_max: float
    intercept_max: float
    slope_min: float
    intercept_min: float

    @property
    def constant_inertia(self) -> float:
        """The constant inertia whose speed band the tangents bound [kg·m²]: their intercepts' gap over their
        slopes' (see :func:`exact_constant_inertia`)."""
        return (self.intercept_max - self.intercept_min) / (self.slope_max - self.slope_min)


def wittenbauer_tangents(cycle: ReducedCycle, mean_speed: float, delta: float) -> Tangents:
    """Limit tangents of the energy-mass curve (A(phi), J_red(phi)) of a balanced cycle for speeds w_m(1 ± delta/2)."""
    w_min, w_max = speed_band(mean_speed, delta)
    c_max, c_min = 0.5 * w_max**2, 0.5 * w_min**2
    pieces = _EnergyPieces.of(cycle)
    return Tangents(c_max, pieces.extremes(c_max)[0], c_min, pieces.extremes(c_min)[1])


def exact_constant_inertia(cycle: ReducedCycle, mean_speed: float, delta: float) -> float:
    """Constant inertia [kg·m²] for which the speed spans exactly w_m(1 ± delta/2): Wittenbauer in closed form.

    J_c = [max(A - J·w_max²/2) - min(A - J·w_min²/2)] / (delta·w_m²), since w_max² - w_min² = 2·delta·w_m²
    (seed_formulas 7). Exact for the piecewise-linear cycle at any inertia variation.
    """
    return wittenbauer_tangents(cycle, mean_speed, delta).constant_inertia


def mertsalov_constant_inertia(cycle: ReducedCycle, mean_speed: float, delta: float) -> float:
    """Mertsalov's approximation [kg·m²]: the variable group's energy at the mean speed taken off the work.

    The variable group II is J_red less its mean, its kinetic energy taken at w_m; the mean of J_red joins the
    constant group I: J_c = [max - min of (A - J_red·w_m²/2)] / (delta·w_m²) - mean J_red. Exact for constant
    J; for variable J it errs by about the variation of J_red between the extremes of the speed.
    """
    speed_band(mean_speed, delta)
    hi, lo = energy_extremes(cycle, 0.5 * mean_speed**2)
    return (hi - lo) / (delta * mean_speed**2) - cycle.mean_inertia


def energy_method_constant_inertia(
    cycle: ReducedCycle, mean_speed: float, delta: float, *, samples_only: bool = False
) -> float:
    """Plain energy method [kg·m²]: the largest work swing over delta·w_m², less the mean J_red.

    J_total = (max A - min A)/(delta·w_m²) treats the whole machine as one constant inertia (seed 003:457-473);
    the mechanism supplies its mean J_red of it. Exact for constant J.
    """
    speed_band(mean_speed, delta)
    hi, lo = energy_extremes(cycle, 0.0, samples_only=samples_only)
    return (hi - lo) / (delta * mean_speed**2) - cycle.mean_inertia
