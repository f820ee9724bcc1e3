"""Before/after figure of a balancing answer: shaking force polar diagrams, shaking moment, driving torque, the
balanced mechanism with its counterweights, and the trade-off curve of a sweep."""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.patches import Circle

from ..model import FloatArray
from ..plots import AFTER, BEFORE, FigureFormat, _curve, draw_linkage, literal_text, render, shaking_polar
from .fourbar import BalanceResult, counter_rotor_loads

# Below this share of the peak before, the after-curve would be a dot under the origin: it gets its own scale.
_ZOOM_BELOW = 0.05


def moment_after(result: BalanceResult) -> FloatArray:
    """Shaking moment after balancing [N·m], (N,), counter-rotors included."""
    moment = result.analysis_after.kinetostatics.shaking_moment
    if result.counter_rotors:
        moment = moment + counter_rotor_loads(result.analysis_before, result.counter_rotors)[0]
    return moment


def torque_after(result: BalanceResult) -> FloatArray:
    """Driving torque after balancing [N·m], (N,), counter-rotors included."""
    if result.driving_torque_after is not None:
        return result.driving_torque_after
    return result.analysis_after.kinetostatics.driving_torque


def polar_before_after(ax: Axes, before: FloatArray, after: FloatArray, phi: FloatArray, label: str) -> None:
    """Shaking force polar diagrams [N] before and after balancing on one axes; an after-curve too small to read
    on the before's scale gets an inset of its own, or a marker at the origin when it is round-off."""
    peak_before = float(np.hypot(*before.T).max())
    peak_after = float(np.hypot(*after.T).max())
    shaking_polar(ax, before, "before", phi, color=BEFORE, lw=1.2)
    if peak_after >= _ZOOM_BELOW * peak_before:
        shaking_polar(ax, after, label, phi, 90.0, color=AFTER, lw=2.2, zorder=5)
    elif peak_after <= 1e-6 * max(peak_before, 1e-300):
        ax.plot(0, 0, "o", color=AFTER, ms=8, zorder=6, label=f"{label}: {peak_after:.2g} N, a point")
    else:
        ax.plot(*np.vstack([after, after[:1]]).T, color=AFTER, lw=2.2, zorder=5, label=label)
        inset = ax.inset_axes((0.64, 0.6, 0.34, 0.34))
        shaking_polar(inset, after, "after", phi, 90.0, color=AFTER, lw=1.5)
        inset.set_title(f"after, own scale (peak {peak_after:.3g} N)", fontsize=7)
        inset.set_xlabel("")
        inset.set_ylabel("")
        inset.tick_params(labelsize=6)
    ax.set_title(f"shaking force polar diagram (peak {peak_before:.4g} → {peak_after:.3g} N)")
    ax.legend(fontsize=7, loc="lower left")


def _polar(ax: Axes, result: BalanceResult) -> None:
    polar_before_after(ax, result.analysis_before.kinetostatics.shaking_force,
                       result.analysis_after.kinetostatics.shaking_force, result.analysis_before.motion.phi,
                       f"after ({result.mode})")


def _tradeoff(ax: Axes, results: Sequence[BalanceResult]) -> None:
    """RMS shaking force against the other objective that moves most over the sweep; labels give added mass."""
    before = results[0].before
    force = np.array([r.after.rms_shaking_force for r in results])
    moment = np.array([r.after.rms_shaking_moment for r in results])
    torque = np.array([r.after.rms_driving_torque for r in results])

    def spread(v: FloatArray) -> float:
        return float(np.ptp(v) / max(float(np.abs(v).max()), 1e-300))

    y, name, y0 = (moment, "RMS shaking moment [N·m]", before.rms_shaking_moment)
    if spread(torque) > spread(moment):
        y, name, y0 = (torque, "RMS driving torque [N·m]", before.rms_driving_torque)
    order = np.argsort(force)
    ax.plot(force[order], y[order], "-", color="0.5", lw=1, zorder=1)
    ax.scatter(force, y, c=[r.total_added_mass for r in results], cmap="viridis", s=40, zorder=3)
    ax.plot(force[0], y[0], "*", ms=16, mfc="none", mec=AFTER, mew=1.5, zorder=4, label="design (weights)")
    ax.plot(before.rms_shaking_force, y0, "s", color=BEFORE, ms=7, label="before balancing")
    for r, fx, fy in zip(results, force, y, strict=True):
        ax.annotate(f"{r.total_added_mass:.3g} kg", (fx, fy), xytext=(4, 4), textcoords="offset points", fontsize=7)
    ax.set_xlabel("RMS shaking force [N]")
    ax.set_ylabel(name)
    ax.set_title(f"trade-off over the sweep ({len(results)} designs)")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)


def _summary(ax: Axes, result: BalanceResult) -> None:
    """The before/after figures as a small table, for a balance without a sweep."""
    b, a = result.before, result.after
    rows = [
        ("RMS shaking force [N]", b.rms_shaking_force, a.rms_shaking_force),
        ("peak shaking force [N]", b.max_shaking_force, a.max_shaking_force),
        ("RMS shaking moment [N·m]", b.rms_shaking_moment, a.rms_shaking_moment),
        ("peak shaking moment [N·m]", b.max_shaking_moment, a.max_shaking_moment),
        ("RMS driving torque [N·m]", b.rms_driving_torque, a.rms_driving_torque),
        ("peak bearing force [N]", b.max_bearing_force, a.max_bearing_force),
    ]
    ax.axis("off")
    table = ax.table(cellText=[[n, f"{x:.4g}", f"{y:.3g}"] for n, x, y in rows],
                     colLabels=["", "before", "after"], loc="center", colWidths=[0.6, 0.2, 0.2])
    table.auto_set_font_size(False)
    table.set_fontsize(8)
    table.scale(1.0, 1.5)
    ax.set_title("before and after")


def _counter_rotors(ax: Axes, result: BalanceResult) -> None:
    """Each counter-rotor as a dashed ring about its link's frame pivot, turning the other way."""
    mech = result.analysis_after.linkage.mechanism
    size = float(np.ptp(np.vstack(list(result.analysis_after.motion.point_pos.values())), axis=0).max())
    for c in result.counter_rotors:
        at = result.analysis_after.motion.point_pos[mech.origins[c.link]][0]
        ax.add_patch(Circle(tuple(at), 0.07 * size, fill=False, ls="--", lw=1.5, ec="tab:purple", zorder=6))
        ax.annotate(f"counter-rotor {c.inertia:.3g} kg·m², -{c.ratio:g}×", at, xytext=(8, 14),
                    textcoords="offset points", fontsize=7, color="tab:purple")


def _headline(result: BalanceResult) -> str:
    parts = [f"{result.mode} balancing: added mass {result.total_added_mass:.3g} kg "
             f"in {len(result.counterweights)} counterweight(s), added inertia {result.added_inertia:.3g} kg·m²"]
    if result.counter_rotors:
        parts.append("counter-rotors " + ", ".join(
            f"{c.link} {c.inertia:.3g} kg·m² at -{c.ratio:g}×" for c in result.counter_rotors))
    if result.coupler_inertia is not None:
        own = result.analysis_before.linkage.mass_props("coupler").inertia
        parts.append(f"coupler inertia {own:.3g} → {result.coupler_inertia:.3g} kg·m²")
    return "; ".join(parts)


def balance_figure(result: BalanceResult, fmt: FigureFormat = "png", *, sweep: Sequence[BalanceResult] = (),
                   phi: float = 0.0) -> bytes:
    """Shaking force polar diagrams, shaking moment and driving torque before and after, the balanced mechanism
    at ``phi`` [rad] with its counterweights, and the trade-off curve of ``sweep`` (else a before/after table)."""
    fig = plt.figure(figsize=(17, 10.5))
    grid = fig.add_gridspec(2, 3)
    before = result.analysis_before
    deg = np.degrees(before.motion.phi)
    label = f"after ({result.mode})"
    _polar(fig.add_subplot(grid[0, 0]), result)
    _curve(fig.add_subplot(grid[0, 1]), deg, [
        (before.kinetostatics.shaking_moment, "before", {"color": BEFORE, "lw": 1.2}),
        (moment_after(result), label, {"color": AFTER, "lw": 2.2}),
    ], "shaking moment [N·m]", "shaking moment about O")
    _curve(fig.add_subplot(grid[0, 2]), deg, [
        (before.kinetostatics.driving_torque, "before", {"color": BEFORE, "lw": 1.2}),
        (torque_after(result), label, {"color": AFTER, "lw": 2.2}),
    ], "driving torque [N·m]", "driving torque on the crank")
    after = result.analysis_after
    drawing = fig.add_subplot(grid[1, 0:2])
    draw_linkage(drawing, after.linkage, after, phi)
    _counter_rotors(drawing, result)
    if sweep:
        _tradeoff(fig.add_subplot(grid[1, 2]), [result, *sweep])
    else:
        _summary(fig.add_subplot(grid[1, 2]), result)
    fig.suptitle(_headline(result), fontsize=11)
    literal_text(fig).tight_layout()
    return render(fig, fmt)


def balance_png(result: BalanceResult) -> bytes:
    """The balancing figure as PNG (see balance_figure)."""
    return balance_figure(result, "png")

