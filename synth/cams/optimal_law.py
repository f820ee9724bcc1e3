"""A rise law optimised over a B-spline: least peak acceleration, least peak jerk, or least residual vibration.

The normalised rise f(u), u in [0, 1], is a quintic B-spline on uniform knots, f = B(u) c. Its value, slope and
curvature at both ends are fixed (f = 0, 1; f' = f'' = 0), so the law joins dwells with continuous position,
velocity and acceleration. Every derivative is linear in the coefficients c, so each objective is a convex program:

* peak acceleration: minimise t subject to |B''(u_i) c| <= t at the constraint samples u_i (a linear program);
* peak jerk: the same with B''';
* residual vibration of a follower with natural frequency omega_n: after a rise of duration T the undamped
  follower keeps vibrating with amplitude h |int_0^1 f''(u) exp(i lambda u) du| / lambda, lambda = omega_n T;
  that integral is linear in c (a second-order cone), minimised under a cap on the peak acceleration.

Each program is built once per (objective, knot count) and solved with Clarabel; the caller's data enter as
parameters. Lower bounds state how good the answer is: no rest-to-rest rise with zero end accelerations has peak
acceleration below 4 h/beta**2 (constant +-a over halves) or peak jerk below 32 h/beta**3 (constant +-j over
quarters).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Any, Literal, NamedTuple

import cvxpy as cp
import numpy as np
from scipy.interpolate import BSpline

from ..errors import InvalidInput, SolverFailed
from ..model import FloatArray
from .laws import Derivatives

Objective = Literal["peak_acceleration", "peak_jerk", "residual_vibration"]
OBJECTIVES: tuple[Objective, ...] = ("peak_acceleration", "peak_jerk", "residual_vibration")
DEGREE = 5
MAX_INTERVALS = 64
#: Constraint samples per knot interval: the peak between samples exceeds the sampled one by a fraction of a percent.
SAMPLES_PER_INTERVAL = 12
#: The least peaks any admissible law can have (see the module's docstring).
LOWER_BOUND = {"peak_acceleration": 4.0, "peak_jerk": 32.0}


def _knots(intervals: int) -> FloatArray:
    inner = np.linspace(0.0, 1.0, intervals + 1)
    return np.concatenate([np.zeros(DEGREE), inner, np.ones(DEGREE)])


@functools.lru_cache(maxsize=16)
def _basis(intervals: int) -> tuple[Any, ...]:
    """Values and first three derivatives of every basis function at the constraint samples, (M, n) each, and the
    samples."""
    t = _knots(intervals)
    n = len(t) - DEGREE - 1
    spline = BSpline(t, np.eye(n), DEGREE)
    u = np.linspace(0.0, 1.0, SAMPLES_PER_INTERVAL * intervals + 1)
    return (u, spline(u), spline.derivative(1)(u), spline.derivative(2)(u), spline.derivative(3)(u))


class _Program(NamedTuple):
    problem: cp.Problem
    c: cp.Variable
    residual: cp.Parameter   # (2, n): real and imaginary parts of the residual-vibration map
    cap: cp.Parameter        # peak acceleration allowed with the residual-vibration objective


@functools.lru_cache(maxsize=16)
def _program(objective: Objective, intervals: int) -> _Program:
    u, B0, B1, B2, B3 = _basis(intervals)
    n = B0.shape[1]
    c = cp.Variable(n)
    residual = cp.Parameter((2, n))
    cap = cp.Parameter(nonneg=True)
    ends = [B0[0] @ c == 0.0, B0[-1] @ c == 1.0, B1[0] @ c == 0.0, B1[-1] @ c == 0.0,
            B2[0] @ c == 0.0, B2[-1] @ c == 0.0]
    peak = cp.Variable(nonneg=True)
    # |x| <= t as two one-sided inequalities: one vector constraint each, never one per sample
    if objective == "peak_acceleration":
        problem = cp.Problem(cp.Minimize(peak), [*ends, B2 @ c <= peak, -(B2 @ c) <= peak])
    elif objective == "peak_jerk":
        problem = cp.Problem(cp.Minimize(peak), [*ends, B3 @ c <= peak, -(B3 @ c) <= peak])
    else:
        amplitude = cp.Variable(nonneg=True)
        problem = cp.Problem(cp.Minimize(amplitude), [*ends, cp.SOC(amplitude, residual @ c), B2 @ c <= cap,
                                                      -(B2 @ c) <= cap])
    return _Program(problem, c, residual, cap)


@dataclass(frozen=True, slots=True)
class SplineLaw:
    """A normalised rise law as a quintic B-spline on uniform knots in u in [0, 1]; callable like the standard
    laws."""

    coefficients: FloatArray
    intervals: int

    def __call__(self, u: FloatArray) -> Derivatives:
        spline = BSpline(_knots(self.intervals), self.coefficients, DEGREE)
        return (spline(u), spline.derivative(1)(u), spline.derivative(2)(u), spline.derivative(3)(u))


@dataclass(frozen=True, slots=True)
class OptimisedLaw:
    """The optimised law and its check figures, each recomputed on a grid ten times finer than the program's.

    ``peak_acceleration`` and ``peak_jerk`` are the coefficients C_a, C_j (peak = C h/beta**k);
    ``residual_vibration`` is the residual amplitude over the lift at ``frequency_ratio`` lambda = omega_n T
    (0 when no frequency was given); ``lower_bound`` the least peak any admissible law could have (None for the
    residual objective); ``end_error`` the largest error in the six end conditions.
    """

    law: SplineLaw
    objective: Objective
    status: str
    objective_value: float
    peak_velocity: float
    peak_acceleration: float
    peak_jerk: float
    residual_vibration: float
    frequency_ratio: float
    lower_bound: float | None
    end_error: float


def residual_map(intervals: int, frequency_ratio: float) -> FloatArray:
    """(2, n) map from coefficients to (Re, Im) of int_0^1 f''(u) exp(i lambda u) du / lambda, by Simpson's rule
    on the constraint samples."""
    u, _, _, B2, _ = _basis(intervals)
    lam = frequency_ratio
    w = np.ones_like(u)
    w[1:-1:2], w[2:-1:2] = 4.0, 2.0
    w *= (u[1] - u[0]) / 3.0
    kernel = np.stack([np.cos(lam * u), np.sin(lam * u)]) * w / lam
    return np.asarray(kernel @ B2)


def residual_vibration(law: SplineLaw | None, frequency_ratio: float, samples: int = 4001,
                       second: FloatArray | None = None) -> float:
    """|int_0^1 f''(u) exp(i lambda u) du| / lambda by Simpson's rule on ``samples`` points (odd)."""
    u = np.linspace(0.0, 1.0, samples)
    f2 = law(u)[2] if law is not None else second
    assert f2 is not None
    w = np.ones_like(u)
    w[1:-1:2], w[2:-1:2] = 4.0, 2.0
    w *= (u[1] - u[0]) / 3.0
    z = np.sum(w * f2 * np.exp(1j * frequency_ratio * u))
    return float(abs(z) / frequency_ratio)


def optimise_law(objective: Objective, intervals: int = 16, frequency_ratio: float = 0.0,
                 max_acceleration: float = 2.0 * math.pi) -> OptimisedLaw:
    """The rise law of least peak acceleration, least peak jerk, or (``frequency_ratio`` lambda = omega_n T > 0)
    least residual vibration with the peak acceleration coefficient at most ``max_acceleration``."""
    if objective not in OBJECTIVES:
        raise InvalidInput(f"unknown objective {objective!r}", field="objective")
    if not 4 <= intervals <= MAX_INTERVALS:
        raise InvalidInput(f"knot intervals must be within 4..{MAX_INTERVALS}", field="knot_intervals")
    if objective == "residual_vibration":
        if not frequency_ratio > 0.0:
            raise InvalidInput("the residual-vibration objective needs the follower's natural frequency",
                               field="natural_frequency_hz")
        if not max_acceleration > LOWER_BOUND["peak_acceleration"]:
            raise InvalidInput("the acceleration cap must exceed 4, the least peak any rise can have",
                               field="max_acceleration_coefficient")
    prog = _program(objective, intervals)
    n = prog.c.size
    prog.residual.value = residual_map(intervals, frequency_ratio) if frequency_ratio > 0 else np.zeros((2, n))
    prog.cap.value = max_acceleration
    try:
        prog.problem.solve(solver=cp.CLARABEL)  # type: ignore[no-untyped-call]
    except cp.SolverError as exc:
        raise SolverFailed("solver_error", f"the motion-law program failed: {exc}") from exc
    if prog.problem.status != cp.OPTIMAL or prog.c.value is None:
        raise SolverFailed(str(prog.problem.status))
    law = SplineLaw(np.asarray(prog.c.value, dtype=float), intervals)
    u = np.linspace(0.0, 1.0, 10 * SAMPLES_PER_INTERVAL * intervals + 1)
    f, f1, f2, f3 = law(u)
    ends = np.array([f[0], f[-1] - 1.0, f1[0], f1[-1], f2[0], f2[-1]])
    return OptimisedLaw(
        law, objective, str(prog.problem.status), float(prog.problem.value),
        float(np.max(np.abs(f1))), float(np.max(np.abs(f2))), float(np.max(np.abs(f3))),
        residual_vibration(law, frequency_ratio) if frequency_ratio > 0 else 0.0, frequency_ratio,
        LOWER_BOUND.get(objective), float(np.max(np.abs(ends))))
