"""Figures of an analysis, drawn headless with matplotlib and returned as PNG bytes."""

from __future__ import annotations

import io
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from .analysis import Analysis  # noqa: E402
from .kinematics import motion as solve_motion  # noqa: E402


def figure_png(fig: Figure, dpi: int = 110) -> bytes:
    """Render and close a figure."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, bbox_inches="tight")
    plt.close(fig)
    return buf.getvalue()


def draw_mechanism(ax: Axes, an: Analysis, phi: float) -> None:
    """The linkage at ``phi`` [rad]: links between their joints, frame pivots as triangles, guides dashed, centres of mass as x."""
    mech = an.linkage.mechanism
    m = solve_motion(mech, np.array([phi]), an.motion.omega_crank)
    pos = {k: v[0] for k, v in m.point_pos.items()}
    drawn = set()
    for joint in mech.topology.joints:
        giver, receiver = joint.bodies
        for body in (giver, receiver):
            if body is None or body in drawn:
                continue
            origin = pos[mech.origins[body]]
            ends = [pos[j.point] for j in mech.topology.joints if body in j.bodies]
            far = max(ends, key=lambda p: float(np.hypot(*(p - origin))))
            ax.plot([origin[0], far[0]], [origin[1], far[1]], "-o", lw=3, ms=5, label=body)
            drawn.add(body)
        if giver is None and joint.kind == "revolute":
            p = pos[joint.point]
            ax.plot(p[0], p[1], "k^", ms=10)
        elif giver is None:
            # A guide fixed in the frame: drawn along its axis over the output's travel.
            p = pos[joint.point]
            axis = np.array([np.cos(joint.axis_angle), np.sin(joint.axis_angle)])
            travel = an.motion.point_pos[joint.point] @ axis
            lo, hi = travel.min() - 0.1 * np.ptp(travel), travel.max() + 0.1 * np.ptp(travel)
            base = p - (p @ axis) * axis
            guide = np.array([base + lo * axis, base + hi * axis])
            ax.plot(guide[:, 0], guide[:, 1], "k--", lw=1)
    for link in mech.topology.links:
        props = an.linkage.mass_props(link)
        if props.mass > 0:
            at = m.point_on(link, props.com).pos[0]
            ax.plot(at[0], at[1], "kx", ms=6)
    ax.set_aspect("equal")
    ax.set_title(f"mechanism at {np.degrees(phi):.1f}°")
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)


def shaking_polar(ax: Axes, force: np.ndarray, label: str, **style: Any) -> None:
    """Polar diagram of the shaking force: the tip of the force vector over the cycle [N]."""
    closed = np.vstack([force, force[:1]])
    ax.plot(closed[:, 0], closed[:, 1], label=label, **style)
    ax.plot(0, 0, "k+")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("Fx [N]")
    ax.set_ylabel("Fy [N]")
    ax.set_title("shaking force polar diagram")
    ax.grid(alpha=0.3)


def analysis_png(an: Analysis, phi: float = 0.0) -> bytes:
    """Driving torque over the cycle, shaking force polar diagram, and the mechanism at ``phi`` [rad]."""
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6))
    deg = np.degrees(an.motion.phi)
    axes[0].plot(deg, an.kinetostatics.driving_torque, label="kinetostatics")
    axes[0].plot(deg, an.virtual_power_torque, "--", label="virtual power")
    axes[0].set_xlabel("crank angle [deg]")
    axes[0].set_ylabel("driving torque [N·m]")
    axes[0].set_title("driving torque")
    axes[0].legend()
    axes[0].grid(alpha=0.3)
    shaking_polar(axes[1], an.kinetostatics.shaking_force, "shaking force")
    draw_mechanism(axes[2], an, phi)
    fig.tight_layout()
    return figure_png(fig)
