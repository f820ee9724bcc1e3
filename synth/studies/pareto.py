"""The Pareto front of a study: the variants no other variant beats in every objective at once."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from ..errors import InvalidInput
from ..model import FloatArray


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


def pareto_mask(points: FloatArray, senses: Sequence[str], digits: int | None = None) -> NDArray[np.bool_]:
    """True for each row of ``points`` that no other row dominates.

    Parameters
    ----------
    points
        Objective values, one row per variant, shape (n, k) [unit of each metric].
    senses
        ``min`` or ``max`` per column [-].
    digits
        Compare each objective to this many significant digits of its largest magnitude (:func:`quantise`), so
        that solver noise (a budget met to 1e-11, a residual force of 1e-12 N) does not decide between designs
        that are equal; None compares the values exactly [-].

    Notes
    -----
    Row q dominates row p when q is no worse in every objective and better in one. After sorting the rows
    lexicographically (every objective turned into one to minimise), a row can only be dominated by rows before
    it, so one pass against the front found so far decides each row: O(n log n + n * front size). Equal rows do
    not dominate each other and are all kept.
    """
    points = np.asarray(points, dtype=float)
    if points.ndim != 2 or points.shape[1] != len(senses):
        raise InvalidInput(f"points of shape {points.shape} do not match {len(senses)} objectives")
    if bad := [s for s in senses if s not in ("min", "max")]:
        raise InvalidInput(f"objective senses must be 'min' or 'max', got {bad}")
    sign = np.array([1.0 if s == "min" else -1.0 for s in senses])
    cost = (points if digits is None else quantise(points, digits)) * sign
    order = np.lexsort(cost.T[::-1]) if len(cost) else np.arange(0)
    mask = np.zeros(len(cost), dtype=bool)
    front = np.empty((0, cost.shape[1]))
    for i in order:
        p = cost[i]
        if front.size and np.any(np.all(front <= p, axis=1) & np.any(front < p, axis=1)):
            continue
        mask[i] = True
        front = np.vstack([front, p])
    return mask
