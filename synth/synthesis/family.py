"""Global maximisation over a one-parameter family of linkages: exhaustive Lipschitz bracketing, then a polish.

A family of designs that meet the kinematic targets exactly is a curve u -> design, u in [lo, hi]. The objective
(minimum transmission angle, peak driving torque...) is evaluated over a uniform grid of the whole parameter range;
intervals whose upper bound (the mean of their end values plus L·h/2, with L twice the steepest slope seen on the
interval and its neighbours) could still beat the best value are bisected until none can by more than the tolerance.
The best bracket is then polished by a bounded scalar search, and the first-order optimality conditions of the
answer are checked with one-sided slopes: both zero (stationary point), an increase from the left and a decrease to
the right (a kink of a max-min objective), or a binding constraint with the objective rising toward it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from scipy.optimize import minimize_scalar

from ..errors import Infeasible
from ..model import FloatArray


class FamilyValues(NamedTuple):
    """Objective to maximise at each parameter value (n,) and named constraint slacks (n,), feasible when > 0."""

    value: FloatArray
    slack: Mapping[str, FloatArray]


@dataclass(frozen=True, slots=True)
class Optimality:
    """How the answer is known to be the global optimum of its one-parameter family.

    ``evaluations``: family members evaluated in all (grid, bisections and polish); ``gap_bound``: largest amount
    by which any member between the evaluated ones could still beat the answer, from the Lipschitz estimate
    ``lipschitz`` [objective unit per unit parameter]; ``kind``: ``stationary``, ``kink`` or ``bound``;
    ``binding``: the constraint active at a bound; ``left_slope``/``right_slope``: one-sided derivatives of the
    objective at the answer; ``conditions_met``: the first-order conditions of ``kind`` hold.
    """

    evaluations: int
    grid_points: int
    gap_bound: float
    lipschitz: float
    kind: str
    binding: str | None
    left_slope: float
    right_slope: float
    conditions_met: bool


# Slacks are normalised (by a length of the linkage, or radians); one this small is a degenerate linkage
# (a change point, a dead centre on a pivot) that only rounding makes look feasible.
MARGIN = 1e-12


def feasible(slack: Mapping[str, FloatArray]) -> FloatArray:
    """Members whose every slack exceeds the degeneracy margin."""
    return np.asarray(np.all(np.stack(list(slack.values())) > MARGIN, axis=0))


def _feasible(fv: FamilyValues) -> FloatArray:
    return np.asarray(np.isfinite(fv.value) & feasible(fv.slack))


def _scores(fv: FamilyValues) -> FloatArray:
    return np.where(_feasible(fv), fv.value, -np.inf)


def _infeasible_reason(fv: FamilyValues) -> Infeasible:
    names = list(fv.slack)
    slack = np.stack([fv.slack[n] for n in names])
    best_compromise = int(np.argmax(slack.min(axis=0)))
    worst = names[int(np.argmin(slack[:, best_compromise]))]
    return Infeasible(
        f"no member of the design family satisfies every bound; closest miss on {worst!r}",
        constraint=worst,
        normalised_shortfall=max(0.0, float(-slack[:, best_compromise].min())),
    )


def maximise_family(
    evaluate: Callable[[FloatArray], FamilyValues],
    lo: float,
    hi: float,
    *,
    grid: int,
    tol: float,
    max_evaluations: int,
    rel_tol: float = 0.0,
) -> tuple[float, Optimality]:
    """Global maximiser of ``evaluate`` over [lo, hi] with its certificate; Infeasible when no member is feasible.

    Bisection stops when no interval can beat the best value by more than ``tol + rel_tol·|best|`` (objective
    units) or after ``max_evaluations`` members.
    """
    u = np.linspace(lo, hi, grid + 1)
    fv = evaluate(u)
    f = _scores(fv)
    if not np.isfinite(f).any():
        raise _infeasible_reason(fv)
    evaluations = u.size
    us, fs = u, f
    lipschitz = 0.0
    while True:
        order = np.argsort(us)
        us, fs = us[order], fs[order]
        h = np.diff(us)
        both = np.isfinite(fs[:-1]) & np.isfinite(fs[1:])
        slope = np.zeros(h.size)
        slope[both] = np.abs((fs[1:][both] - fs[:-1][both]) / h[both])
        lipschitz = max(lipschitz, 2.0 * float(slope.max()))
        # Each interval's own constant: twice the steepest slope over it and its neighbours, never below a
        # hundredth of the global one, so flat stretches close fast and steep ones keep their margin.
        near = np.maximum(slope, np.maximum(np.r_[slope[1:], 0.0], np.r_[0.0, slope[:-1]]))
        local = np.where(both, np.maximum(2.0 * near, 0.01 * lipschitz), lipschitz)
        best = float(fs.max())
        left, right = fs[:-1], fs[1:]
        finite_end = np.maximum(left, right)
        with np.errstate(invalid="ignore"):
            bound = np.where(both, 0.5 * (left + right) + 0.5 * local * h, finite_end + local * h)
        open_ = np.isfinite(finite_end) & (bound > best + tol + rel_tol * abs(best)) & (h > 1e-14 * (hi - lo))
        if not open_.any() or evaluations >= max_evaluations:
            break
        mids = 0.5 * (us[:-1] + us[1:])[open_]
        mids = mids[: max(1, max_evaluations - evaluations)]
        fm = _scores(evaluate(mids))
        evaluations += mids.size
        us, fs = np.concatenate([us, mids]), np.concatenate([fs, fm])
    gap = max(0.0, float(np.max(np.where(np.isfinite(finite_end), bound, -np.inf))) - best)

    i = int(np.argmax(fs))
    a, b = us[max(i - 1, 0)], us[min(i + 1, us.size - 1)]

    def negative(x: float) -> float:
        s = _scores(evaluate(np.array([x])))[0]
        return -s if np.isfinite(s) else 1e300

    if b > a:
        res = minimize_scalar(negative, bounds=(a, b), method="bounded", options={"xatol": 1e-13 * (hi - lo)})
        evaluations += int(res.nfev)
        x = float(res.x) if -float(res.fun) >= fs[i] else float(us[i])
    else:
        x = float(us[i])
    return x, _conditions(evaluate, x, lo, hi, evaluations, grid + 1, gap, lipschitz, tol)


def _conditions(
    evaluate: Callable[[FloatArray], FamilyValues],
    x: float,
    lo: float,
    hi: float,
    evaluations: int,
    grid_points: int,
    gap: float,
    lipschitz: float,
    tol: float,
) -> Optimality:
    eta = 1e-7 * (hi - lo)
    pts = np.array([x - eta, x, x + eta])
    fv = evaluate(pts)
    f = _scores(fv)
    # What a one-sided difference of step eta can resolve: rounding in f, and a millionth of the steepest slope.
    slope_tol = 1e-6 * max(1.0, lipschitz) + 1e4 * np.finfo(float).eps * max(1.0, abs(float(f[1]))) / eta
    left = (f[1] - f[0]) / eta if np.isfinite(f[0]) else math.nan
    right = (f[2] - f[1]) / eta if np.isfinite(f[2]) else math.nan
    binding: str | None = None
    if not (np.isfinite(f[0]) and np.isfinite(f[2])) or x - eta < lo or x + eta > hi:
        kind = "bound"
        side = 0 if not np.isfinite(f[0]) or x - eta < lo else 2
        names = [n for n, s in fv.slack.items() if s[side] <= MARGIN]
        binding = names[0] if names else "parameter range"
        inward = right if side == 0 else -left
        met = bool(np.isfinite(inward) and inward <= slope_tol)
    elif abs(left) <= slope_tol and abs(right) <= slope_tol:
        kind, met = "stationary", True
    else:
        kind = "kink"
        met = bool(left >= -slope_tol and right <= slope_tol)
    return Optimality(
        evaluations=evaluations + 3,
        grid_points=grid_points,
        gap_bound=gap,
        lipschitz=lipschitz,
        kind=kind,
        binding=binding,
        left_slope=float(left),
        right_slope=float(right),
        conditions_met=met,
    )
