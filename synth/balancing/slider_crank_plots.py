"""Figure of a slider-crank balance: shaking force before and after the counterweight and Lanchester pairs, its
harmonics by crank order, the shaking moment, and the mechanism with the balancer shafts on the slide axis."""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.patches import Circle

from ..plots import AFTER, BEFORE, FigureFormat, _curve, _frame_to_scale, draw_linkage, literal_text, render
from .plots import polar_before_after
from .slider_crank import RESIDUAL_ORDERS, SliderCrankBalance, _peak_by_order, balancer_loads


def _orders(ax: Axes, result: SliderCrankBalance) -> None:
    """Largest force of each crank order before and after, on a log scale so the cancelled orders show."""
    after = np.array(result.residual_by_order)
    before = np.array(_peak_by_order(result.analysis_before.kinetostatics.shaking_force, len(after)))
    k = np.arange(1, len(after) + 1)
    # a log scale has no 0: exact zeros drawn below round-off (of 1 N when nothing moves a mass)
    floor = 1e-16 * (float(before.max()) if before.max() > 0 else 1.0)
    ax.bar(k - 0.2, np.maximum(before, floor), 0.4, color=BEFORE, label="before")
    ax.bar(k + 0.2, np.maximum(after, floor), 0.4, color=AFTER, label="after")
    ax.set_yscale("log")
    ax.set_xticks(k)
    ax.set_xlabel("crank order")
    ax.set_ylabel("largest force of the order [N]")
    ax.set_title(f"shaking force by crank order (first {RESIDUAL_ORDERS})")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3, axis="y")


def _shafts(ax: Axes, result: SliderCrankBalance, phi: float) -> None:
    """Each pair's two shafts in mirror image about the slide axis, on the far side of the crank from the slider,
    masses at crank angle ``phi`` [rad]: the force and moment do not depend on where along the axis they sit."""
    an = result.analysis_after
    r = float(np.hypot(*an.motion.point_pos["A"][0]))
    away = -1.0 if float(np.mean(an.motion.point_pos["B"][:, 0])) >= 0 else 1.0
    x = away * (max(r, float(np.hypot(*result.crank_counterweight.position))) + 0.03 * r)
    y0 = result.balancer_line_y
    clouds = [an.motion.point_pos[p] for p in an.motion.point_pos]
    heaviest = max(p.mass for p in result.pairs)
    ax.axhline(y0, color="tab:green", ls="--", lw=0.9, zorder=1, label=f"balancer line y = {y0:.4g} m (slide axis)")
    for p in result.pairs:
        x += away * 1.4 * p.radius
        for turn, side in ((1.0, -1.0), (-1.0, 1.0)):
            centre = np.array([x, y0 + side * 1.15 * p.radius])
            angle = turn * (p.order * phi - p.phase)
            mass_at = centre + p.radius * np.array([math.cos(angle), math.sin(angle)])
            ax.add_patch(Circle(tuple(centre), p.radius, fill=False, ls=":", ec="tab:green", lw=1, zorder=2))
            ax.plot(*centre, "+", color="tab:green", ms=8, zorder=3)
            ax.plot([centre[0], mass_at[0]], [centre[1], mass_at[1]], "-", color="tab:green", lw=1.8, zorder=3)
            # a massless mechanism needs massless balancers: drawn as points
            share = math.sqrt(p.mass / heaviest) if heaviest > 0 else 0.0
            ax.add_patch(Circle(tuple(mass_at), 0.25 * p.radius * share, fc="tab:green",
                                ec="k", zorder=4, label=None if side < 0 else
                                f"order {p.order}: 2 × {p.mass:.3g} kg at {p.radius:.3g} m, "
                                f"phase {math.degrees(p.phase):.2f}°"))
            ax.annotate(f"{'+' if turn > 0 else '−'}{p.order}ω", (float(centre[0]), float(centre[1]) + side * p.radius),
                        xytext=(0, 6 * side), textcoords="offset points", fontsize=8, color="tab:green",
                        ha="center", va="bottom" if side > 0 else "top")
            clouds.append(np.array([centre - 1.5 * p.radius, centre + 1.5 * p.radius]))
        x += away * (1.4 * p.radius + 0.3 * r)
    _frame_to_scale(ax, clouds)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=3)


def _table(ax: Axes, result: SliderCrankBalance) -> None:
    b = result.before
    rows = [
        ("peak shaking force [N]", f"{b.max_shaking_force:.4g}", f"{result.residual:.3g}"),
        ("peak shaking moment about O [N·m]", f"{b.max_shaking_moment:.4g}", f"{result.residual_moment:.4g}"),
        ("balancers' moment about O [N·m]", "", f"{result.balancer_moment:.4g}"),
        ("rotating mass at A [kg]", f"{result.rotating_mass:.4g}", ""),
        ("reciprocating mass at B [kg]", f"{result.reciprocating_mass:.4g}", ""),
        ("crank counterweight [kg]", "", f"{result.crank_counterweight.mass:.4g}"),
    ]
    by_order = _peak_by_order(result.analysis_before.kinetostatics.shaking_force, len(result.pairs))
    rows += [(f"order {p.order} shaking force [N]", f"{f:.4g}", f"{result.residual_by_order[p.order - 1]:.2g}")
             for p, f in zip(result.pairs, by_order, strict=True)]
    ax.axis("off")
    table = ax.table(cellText=[list(row) for row in rows], colLabels=["", "before", "after"], loc="center",
                     colWidths=[0.6, 0.2, 0.2])
    table.auto_set_font_size(False)
    table.set_fontsize(8)
    table.scale(1.0, 1.5)
    ax.set_title("before and after")


def slider_crank_balance_figure(result: SliderCrankBalance, fmt: FigureFormat = "png", phi: float = 0.0) -> bytes:
    """Shaking force polar diagram and harmonics by crank order before and after, shaking moment before and
    after (the balancers' share too), and the mechanism at ``phi`` [rad] with its counterweight and the
    Lanchester shafts, as PNG, SVG or PDF."""
    fig = plt.figure(figsize=(17, 10.5))
    grid = fig.add_gridspec(2, 3)
    before = result.analysis_before
    deg = np.degrees(before.motion.phi)
    _, balancers = balancer_loads(result.pairs, before.motion.phi, before.motion.omega_crank, result.balancer_line_y)
    polar_before_after(fig.add_subplot(grid[0, 0]), before.kinetostatics.shaking_force, result.after_force,
                       before.motion.phi, "after (counterweight + Lanchester)")
    _orders(fig.add_subplot(grid[0, 1]), result)
    _curve(fig.add_subplot(grid[0, 2]), deg, [
        (before.kinetostatics.shaking_moment, "before", {"color": BEFORE, "lw": 1.2}),
        (result.after_moment, "after", {"color": AFTER, "lw": 2.2}),
        (balancers, "the balancers' share", {"color": "tab:green", "lw": 1, "ls": "--"}),
    ], "shaking moment [N·m]", "shaking moment about O")
    drawing = fig.add_subplot(grid[1, 0:2])
    draw_linkage(drawing, result.analysis_after.linkage, result.analysis_after, phi)
    _shafts(drawing, result, phi)
    _table(fig.add_subplot(grid[1, 2]), result)
    fig.suptitle(f"slider-crank balancing: crank counterweight and Lanchester pairs of orders "
                 f"{', '.join(str(p.order) for p in result.pairs)} on the slide axis y = offset = "
                 f"{result.balancer_line_y:.4g} m", fontsize=11)
    literal_text(fig).tight_layout()
    return render(fig, fmt)
