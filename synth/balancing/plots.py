"""Before/after figure of a balancing answer: shaking force polar diagrams and driving torque."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ..plots import figure_png, shaking_polar
from .fourbar import BalanceResult


def balance_png(result: BalanceResult) -> bytes:
    """Shaking force polar diagram and driving torque over the cycle, before and after balancing."""
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    before, after = result.analysis_before, result.analysis_after
    shaking_polar(axes[0], before.kinetostatics.shaking_force, "before")
    shaking_polar(axes[0], after.kinetostatics.shaking_force, f"after ({result.mode})", lw=2)
    axes[0].legend()
    deg = np.degrees(before.motion.phi)
    torque_after = result.driving_torque_after
    if torque_after is None:
        torque_after = after.kinetostatics.driving_torque
    axes[1].plot(deg, before.kinetostatics.driving_torque, label="before")
    axes[1].plot(deg, torque_after, label=f"after ({result.mode})")
    axes[1].set_xlabel("crank angle [deg]")
    axes[1].set_ylabel("driving torque [N·m]")
    axes[1].set_title(f"added mass {result.total_added_mass:.3g} kg")
    axes[1].legend()
    axes[1].grid(alpha=0.3)
    fig.tight_layout()
    return figure_png(fig)


def first_balance_png(results: list[BalanceResult]) -> bytes:
    """The figure of the first design of a weight sweep (the one for the request's own weights)."""
    return balance_png(results[0])
