"""Scatter of a study's variants over two metrics, with the Pareto front drawn."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from numpy.typing import NDArray

from ..model import FloatArray
from ..plots import figure_png, literal_text


def pareto_png(x: FloatArray, y: FloatArray, feasible: NDArray[np.bool_], front: NDArray[np.bool_],
               x_label: str, y_label: str, title: str, staircase: str | None = None) -> bytes:
    """Every variant that gave both metrics: feasible ones, infeasible ones (crossed) and the Pareto front.

    Parameters
    ----------
    x, y
        The two metrics per variant, shape (n,) [unit of each metric].
    feasible
        Variant within every constraint, shape (n,) [-].
    front
        Variant on the Pareto front, shape (n,) [-].
    x_label, y_label, title
        Axis labels (metric names, which carry their units) and the figure title [-].
    staircase
        ``minmin``, ``minmax``, ``maxmin`` or ``maxmax`` when the front is over exactly these two metrics: its
        points are joined by the staircase of the region they dominate [-].
    """
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    fig, ax = plt.subplots(figsize=(7.5, 5.5))
    others = feasible & ~front
    ax.scatter(x[others], y[others], s=14, color="tab:blue", alpha=0.55, label=f"feasible ({int(others.sum())})")
    if (~feasible).any():
        ax.scatter(x[~feasible], y[~feasible], s=16, marker="x", color="0.6", alpha=0.7,
                   label=f"outside the constraints ({int((~feasible).sum())})")
    order = np.argsort(x[front], kind="stable")
    fx, fy = x[front][order], y[front][order]
    if staircase is not None and len(fx) > 1:
        ax.step(fx, fy, where="post" if staircase.startswith("min") else "pre", color="tab:red", lw=1.2)
    label = "Pareto front" if staircase is not None else "on the Pareto front of the objectives"
    ax.scatter(fx, fy, s=36, color="tab:red", edgecolor="black", lw=0.6, zorder=3, label=f"{label} ({len(fx)})")
    ax.set_xlabel(x_label)
    ax.set_ylabel(y_label)
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize=9)
    literal_text(fig).tight_layout()
    return figure_png(fig)
