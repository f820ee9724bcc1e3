"""Figures of a synthesised linkage: both dead-centre positions, or the coupler curve through its targets."""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes

from ..kinematics import FourBar, SliderCrank, motion
from ..model import FloatArray, Linkage
from ..plots import figure_png
from .checks import LinkageCheck
from .path import PathResult, coupler_curve

_JOINTS = {"fourbar": ("O", "A", "B", "Q"), "slider_crank": ("O", "A", "B")}


def _positions(linkage: Linkage, phi: FloatArray) -> dict[str, FloatArray]:
    return dict(motion(linkage.mechanism, phi, 1.0).point_pos)


def _chain(ax: Axes, pos: dict[str, FloatArray], i: int, names: tuple[str, ...], style: str, label: str) -> None:
    xy = np.array([pos[n][i] for n in names])
    ax.plot(xy[:, 0], xy[:, 1], style, lw=2.5, ms=6, label=label)


def extremes_png(linkage: Linkage, check: LinkageCheck, title: str) -> bytes:
    """The linkage at the start and the end of its slow stroke, with the crank circle and the output's travel."""
    mech = linkage.mechanism
    fig, ax = plt.subplots(figsize=(7.5, 6))
    phi = np.array(check.slow_stroke)
    pos = _positions(linkage, phi)
    names = _JOINTS[mech.family]
    _chain(ax, pos, 0, names, "-o", f"start of slow stroke, crank {math.degrees(phi[0]):.2f}°")
    _chain(ax, pos, 1, names, "--o", f"end of slow stroke, crank {math.degrees(phi[1]):.2f}°")
    turn = np.linspace(0.0, 2 * math.pi, 361)
    full = _positions(linkage, turn[:-1])
    ax.plot(full["A"][:, 0], full["A"][:, 1], ":", color="grey", lw=1, label="crank pin circle")
    ax.plot(full["B"][:, 0], full["B"][:, 1], "-", color="tab:red", lw=1.2, label="output travel")
    ax.plot(0.0, 0.0, "k^", ms=11)
    ax.annotate("O", (0.0, 0.0), textcoords="offset points", xytext=(8, -12), fontsize=9)
    if isinstance(mech, FourBar):
        ax.plot(mech.ground, 0.0, "k^", ms=11)
        ax.annotate("Q", (mech.ground, 0.0), textcoords="offset points", xytext=(8, -12), fontsize=9)
        travel = f"swing {math.degrees(check.travel):.4f}°"
    else:
        assert isinstance(mech, SliderCrank)
        xb = full["B"][:, 0]
        span = float(np.ptp(xb))
        ax.plot([xb.min() - 0.15 * span, xb.max() + 0.15 * span], [mech.offset] * 2, "k--", lw=0.8, label="guide")
        travel = f"stroke {check.travel:.6g} m"
    ax.set_title(
        f"{title}\n{travel}, time ratio {check.time_ratio:.6f}, transmission angle "
        f"{math.degrees(check.min_transmission_angle):.2f}°–{math.degrees(check.max_transmission_angle):.2f}°",
        fontsize=10,
    )
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    return figure_png(fig)


def path_png(result: PathResult, targets: FloatArray) -> bytes:
    """Targets, the coupler curve of the answer and the linkage at the first target, in the targets' frame."""
    fig, ax = plt.subplots(figsize=(7.5, 6))
    curve = coupler_curve(result)
    ax.plot(curve[:, 0], curve[:, 1], "-", color="tab:blue", lw=1.2, label="coupler curve")
    ax.plot(targets[:, 0], targets[:, 1], "o", mfc="none", mec="tab:red", ms=9, label="targets")
    for k, (x, y) in enumerate(targets):
        ax.annotate(str(k + 1), (x, y), textcoords="offset points", xytext=(6, 4), fontsize=8)
    g, o = result.ground_angle, np.asarray(result.crank_pivot)
    rot = np.array([[math.cos(g), -math.sin(g)], [math.sin(g), math.cos(g)]])
    pos = _positions(result.linkage, result.crank_angles[:1])
    world = {k: v[0] @ rot.T + o for k, v in pos.items()}
    fb = result.fourbar
    e2 = (world["B"] - world["A"]) / fb.coupler
    p = world["A"] + result.coupler_point[0] * e2 + result.coupler_point[1] * np.array([-e2[1], e2[0]])
    xy = np.array([world[n] for n in ("O", "A", "B", "Q")])
    ax.plot(xy[:, 0], xy[:, 1], "-o", color="k", lw=2.5, ms=5, label="linkage at target 1")
    tri = np.array([world["A"], p, world["B"]])
    ax.fill(tri[:, 0], tri[:, 1], color="tab:orange", alpha=0.35, label="coupler")
    for name in ("O", "Q"):
        ax.plot(*world[name], "k^", ms=11)
        ax.annotate(f"{name} (crank pivot)" if name == "O" else f"{name} (rocker pivot)", world[name],
                    textcoords="offset points", xytext=(8, -12), fontsize=8)
    ax.set_title(f"path generation: largest residual {result.residuals.max():.3g} m, "
                 f"{result.starts_at_best} of {result.start_objectives.size} starts at the best", fontsize=10)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    return figure_png(fig)
