"""The Pareto front of a study: the variants no other variant beats in every objective at once, beyond noise.

Two objective values closer than :data:`SOLVER_NOISE` of their column's largest magnitude are the same design
as far as the solvers can tell. The convex programs run Clarabel to 1e-10 on their scaled problems (gap and
feasibility) and the nonconvex ones IPOPT to 1e-9, but what a study compares is recovered from their solutions:
an added mass summed over counterweights, a shaking force re-analysed with the plain model, a flywheel checked by
simulation. Those carry errors of up to about 1e-7 of their scale (the mass budgets of the crank-length and
mass-budget study are met to 1e-7 kg of 1-4 kg), so the front compares to 1e-6 of each objective's largest
magnitude: ten times the largest noise seen, and still a thousand times finer than any difference a designer
would weigh.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from ..errors import InvalidInput
from ..model import FloatArray

#: Objective values closer than this fraction of their column's largest magnitude are equal [-].
SOLVER_NOISE = 1e-6
#: Values compared at once in the final check of the front against every row (block × rows × objectives).
_CHUNK = 4_000_000


def quantise(points: FloatArray, digits: int) -> FloatArray:
    """Each column of ``points`` rounded to ``digits`` significant digits of its largest magnitude.

    A shaking force of 1e-12 N next to 250 N is zero to nine digits; rounding each value to its own digits would
    keep solver noise near zero and rank designs by it.
    """
    points = np.asarray(points, dtype=float)
    scale = np.max(np.abs(points), axis=0, initial=0.0)
    with np.errstate(divide="ignore"):
        exponent = np.where(scale > 0, np.floor(np.log10(np.where(scale > 0, scale, 1.0))), 0.0)
    quantum = 10.0 ** (exponent - digits + 1)
    return np.asarray(np.round(points / quantum) * quantum, dtype=float)


def tolerances(points: FloatArray, digits: int | None = None, noise: float = SOLVER_NOISE) -> FloatArray:
    """Per objective, the difference below which two values are equal [unit of each metric], shape (k,).

    ``noise`` of the column's largest magnitude, or half a unit of the ``digits``-th significant digit of it
    when that is coarser (a study asking for fewer digits); never finer than the solvers' noise.
    """
    points = np.asarray(points, dtype=float)
    scale = np.max(np.abs(points), axis=0, initial=0.0)
    tol = noise * scale
    if digits is not None:
        with np.errstate(divide="ignore"):
            exponent = np.where(scale > 0, np.floor(np.log10(np.where(scale > 0, scale, 1.0))), 0.0)
        tol = np.maximum(tol, np.where(scale > 0, 0.5 * 10.0 ** (exponent - digits + 1), 0.0))
    return np.asarray(tol, dtype=float)


def pareto_mask(points: FloatArray, senses: Sequence[str], digits: int | None = None, *,
                noise: float = SOLVER_NOISE) -> NDArray[np.bool_]:
    """True for each row of ``points`` that no other row beats beyond noise.

    Parameters
    ----------
    points
        Objective values, one row per variant, shape (n, k) [unit of each metric].
    senses
        ``min`` or ``max`` per column [-].
    digits
        Compare each objective to this many significant digits of its largest magnitude when that is coarser
        than ``noise`` (:func:`tolerances`); None: to ``noise`` [-].
    noise
        Relative difference, of each objective's largest magnitude, within which values are equal [-]: by
        default :data:`SOLVER_NOISE`, tied to the solvers' accuracy (see the module docstring); 0 compares the
        values exactly.

    Notes
    -----
    Row q beats row p when q is no worse than p by more than the tolerance in every objective and better by
    more than it in one. Values within the tolerance of each other are equal, so designs that differ only by
    solver noise do not beat each other and are all kept. With a tolerance, beating is not transitive (q may
    beat p through a row that is itself beaten), so a row is kept only when no row at all beats it. A first
    pass over the rows sorted lexicographically drops every row the front found so far beats, in
    O(n log n + n * front size); the rows left are then checked against every row in blocks, O(front * n).
    """
    points = np.asarray(points, dtype=float)
    if points.ndim != 2 or points.shape[1] != len(senses):
        raise InvalidInput(f"points of shape {points.shape} do not match {len(senses)} objectives")
    if bad := [s for s in senses if s not in ("min", "max")]:
        raise InvalidInput(f"objective senses must be 'min' or 'max', got {bad}")
    if not (np.isfinite(noise) and noise >= 0):
        raise InvalidInput(f"noise must be a finite non-negative fraction, got {noise}", field="noise")
    sign = np.array([1.0 if s == "min" else -1.0 for s in senses])
    cost = points * sign
    tol = tolerances(points, digits, noise)

    def beaten_by(q: FloatArray, p: FloatArray) -> NDArray[np.bool_]:
        # q (rows, 1 or m, k) beats p (1 or m, rows, k): no worse beyond tol anywhere, better beyond it somewhere
        return np.asarray(np.all(q <= p + tol, axis=-1) & np.any(q < p - tol, axis=-1))

    order = np.lexsort(cost.T[::-1]) if len(cost) else np.arange(0)
    kept = np.zeros(len(cost), dtype=bool)
    front = np.empty((0, cost.shape[1]))
    for i in order:
        p = cost[i]
        if front.size and np.any(beaten_by(front, p[None, :])):
            continue
        kept[i] = True
        front = np.vstack([front, p])
    survivors = np.flatnonzero(kept)
    block = max(1, _CHUNK // max(1, cost.size))
    for start in range(0, survivors.size, block):
        rows = survivors[start:start + block]
        beaten = beaten_by(cost[None, :, :], cost[rows][:, None, :]).any(axis=1)
        kept[rows[beaten]] = False
    return kept
