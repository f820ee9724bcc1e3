"""Figures of a flywheel sizing: the energy-mass (Wittenbauer) diagram with its tangents (or, for a constant
reduced inertia, the excess-work curve with its largest swing), and w(phi) with the target band and the mean."""

from __future__ import annotations

from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402

from ..plots import FigureFormat, literal_text, render  # noqa: E402
from .problem import FlywheelResult  # noqa: E402

_STYLE: dict[str, dict[str, Any]] = {
    "exact": {"lw": 2.4, "ls": "-", "color": "tab:red", "zorder": 5},
    "mertsalov": {"lw": 1.4, "ls": "--", "color": "tab:blue", "zorder": 6},
    "energy": {"lw": 1.4, "ls": ":", "color": "tab:green", "zorder": 7},
    "motor_nlp": {"lw": 1.8, "ls": "-.", "color": "tab:purple", "zorder": 8},
}


def constant_inertia(result: FlywheelResult) -> bool:
    """True when the cycle's reduced inertia does not vary: the energy-mass diagram is then a vertical line."""
    j = result.cycle.inertia
    return bool(np.ptp(j) <= 1e-9 * max(float(np.abs(j).max()), 1e-300))


def _energy_mass(ax: Axes, result: FlywheelResult) -> None:
    cycle, tan = result.cycle, result.tangents
    inertia, _, work = cycle.evaluate(cycle.dense(4000))
    ax.plot(inertia, work, lw=1.5, label="energy-mass curve A(J_red)")
    ax.plot(inertia[:1], work[:1], "ko", ms=4, label="start of cycle")
    x = np.linspace(min(0.0, float(inertia.min())), float(inertia.max()) * 1.05, 50)
    ax.plot(x, tan.slope_max * x + tan.intercept_max, "r--", lw=1, label="tangent at w_max²/2")
    ax.plot(x, tan.slope_min * x + tan.intercept_min, "b--", lw=1, label="tangent at w_min²/2")
    ax.plot([0, 0], [tan.intercept_min, tan.intercept_max], "k-", lw=3, alpha=0.5, label="AB = J_c·delta·w_m²")
    ax.set_xlabel("reduced inertia J_red [kg·m²]")
    ax.set_ylabel("excess work A [J]")
    ax.set_title("energy-mass diagram (Wittenbauer)")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)


def _excess_work(ax: Axes, result: FlywheelResult) -> None:
    cycle = result.cycle
    phi = cycle.dense(4000)
    _, _, work = cycle.evaluate(phi)
    deg = np.degrees(phi)
    i_max, i_min = int(np.argmax(work)), int(np.argmin(work))
    swing = float(work[i_max] - work[i_min])
    ax.plot(deg, work, lw=1.8, color="tab:red", label="excess work A(phi)")
    ax.axhline(work[i_max], color="0.4", ls=":", lw=1)
    ax.axhline(work[i_min], color="0.4", ls=":", lw=1)
    x = float(deg[i_max])
    ax.annotate("", (x, work[i_min]), (x, work[i_max]), arrowprops={"arrowstyle": "<->", "color": "k"})
    right = x > 0.6 * float(deg[-1])
    ax.annotate(f"ΔA_max = {swing:.4g} J", (x, (work[i_max] + work[i_min]) / 2), xytext=(-6 if right else 6, 0),
                textcoords="offset points", fontsize=8, ha="right" if right else "left")
    ax.axhline(0.0, color="0.5", lw=0.6)
    ax.set_xlabel("crank angle [deg]")
    ax.set_ylabel("excess work A [J]")
    period = np.degrees(cycle.period)
    ax.set_xticks(np.arange(0, period + 1, 90 if period > 360 else 60))
    title = "excess work over the cycle"
    if constant_inertia(result):
        title += " (constant J_red: J = ΔA_max/(delta·w_m²))"
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)


def _speed(ax: Axes, result: FlywheelResult) -> None:
    w_min, w_max = result.speed_band
    ax.axhspan(w_min, w_max, color="tab:orange", alpha=0.12, label=f"target band, delta {result.target_delta:.4g}")
    ax.axhline(result.mean_speed, color="k", ls="--", lw=1, label=f"mean w_m = {result.mean_speed:.4g} rad/s")
    for m in result.methods:
        style: dict[str, Any] = _STYLE.get(m.method, {"lw": 1.2})
        mark = " (design)" if m.method == result.design_method else ""
        ax.plot(np.degrees(m.speed.phi), m.speed.omega, label=f"{m.method}{mark}: delta {m.achieved_delta:.4g}",
                **style)
    ax.set_xlabel("crank angle [deg]")
    period = np.degrees(result.cycle.period)
    ax.set_xticks(np.arange(0, period + 1, 90 if period > 360 else 60))
    ax.set_ylabel("crank speed w [rad/s]")
    ax.set_title("steady speed over the cycle, simulated with each method's flywheel")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)


def flywheel_figure(result: FlywheelResult, fmt: FigureFormat = "png") -> bytes:
    """Energy-mass diagram with its tangents (left out for a constant J_red), the excess-work curve, and the
    simulated speed of every method with the target band and the mean, as PNG, SVG or PDF."""
    panels = 2 if constant_inertia(result) else 3
    fig, axes = plt.subplots(1, panels, figsize=(6.5 * panels, 5.0))
    if panels == 3:
        _energy_mass(axes[0], result)
    _excess_work(axes[-2], result)
    _speed(axes[-1], result)
    literal_text(fig).tight_layout()
    return render(fig, fmt)


def flywheel_png(result: FlywheelResult) -> bytes:
    """The flywheel figure as PNG (see flywheel_figure)."""
    return flywheel_figure(result, "png")
