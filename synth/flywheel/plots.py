"""Figures of a flywheel sizing: the energy-mass (Wittenbauer) diagram with its tangents, and w(phi)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ..plots import figure_png  # noqa: E402
from .problem import FlywheelResult  # noqa: E402


def flywheel_png(result: FlywheelResult) -> bytes:
    """Energy-mass diagram (work over J_red, the limit tangents) and the simulated speed of every method [PNG]."""
    fig, (ax_e, ax_w) = plt.subplots(1, 2, figsize=(13, 4.8))
    cycle, tan = result.cycle, result.tangents
    phi = cycle.dense(4000)
    inertia, _, work = cycle.evaluate(phi)
    ax_e.plot(inertia, work, lw=1.5, label="energy-mass curve")
    ax_e.plot(inertia[:1], work[:1], "ko", ms=4, label="start of cycle")
    x = np.linspace(min(0.0, float(inertia.min())), float(inertia.max()) * 1.05 + 1e-12, 50)
    ax_e.plot(x, tan.slope_max * x + tan.intercept_max, "r--", lw=1, label="tangent w_max²/2")
    ax_e.plot(x, tan.slope_min * x + tan.intercept_min, "b--", lw=1, label="tangent w_min²/2")
    ax_e.plot([0, 0], [tan.intercept_min, tan.intercept_max], "k-", lw=3, alpha=0.5, label="AB = J_c·delta·w_m²")
    ax_e.set_xlabel("reduced inertia J_red [kg·m²]")
    ax_e.set_ylabel("excess work A [J]")
    ax_e.set_title("energy-mass diagram (Wittenbauer)")
    ax_e.legend(fontsize=7)
    ax_e.grid(alpha=0.3)
    w_min, w_max = result.speed_band
    for m in result.methods:
        ax_w.plot(np.degrees(m.speed.phi), m.speed.omega, lw=1.2, label=f"{m.method}: delta {m.achieved_delta:.4g}")
    ax_w.axhline(w_min, color="k", ls=":", lw=1)
    ax_w.axhline(w_max, color="k", ls=":", lw=1, label="target band")
    ax_w.set_xlabel("crank angle [deg]")
    ax_w.set_ylabel("crank speed [rad/s]")
    ax_w.set_title(f"steady speed over the cycle (target delta {result.target_delta:.4g})")
    ax_w.legend(fontsize=7)
    ax_w.grid(alpha=0.3)
    fig.tight_layout()
    return figure_png(fig)
