"""The Pareto front of a study: the variants no other variant beats in every objective at once."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from ..errors import InvalidInput
from ..model import FloatArray


def round_significant(values: FloatArray, digits: int) -> FloatArray:
    """``values`` rounded to ``digits`` significant digits, as their shortest decimal form would show them."""
    flat = [float(f"{v:.{digits}g}") for v in np.asarray(values, dtype=float).ravel()]
    return np.array(flat, dtype=float).reshape(np.shape(values))


def pareto_mask(points: FloatArray, senses: Sequence[str], digits: int | None = None) -> NDArray[np.bool_]:
    """True for each row of ``points`` that no other row dominates.

    Parameters
    ----------
    points
        Objective values, one row per variant, shape (n, k) [unit of each metric].
    senses
        ``min`` or ``max`` per column [-].
    digits
        Compare objectives to this many significant digits, so that solver noise (a budget met to 1e-11) does
        not decide between designs that are equal; None compares the values exactly [-].

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
    cost = (points if digits is None else round_significant(points, digits)) * sign
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
