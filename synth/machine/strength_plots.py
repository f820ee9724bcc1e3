"""The design record's parts: tables of the links, joints, crank shaft and keys as built, and a page drawing each
link to scale with its section and the points where its checks are least."""

from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.patches import Circle, Polygon, Rectangle  # noqa: E402

from ..strength.links import LinkSizing  # noqa: E402
from ..strength.sections import Section  # noqa: E402
from .strength import MachineStrength  # noqa: E402

#: A4 landscape [in].
A4 = (11.69, 8.27)
_MARKS = {"static": ("v", "tab:red"), "fatigue": ("s", "tab:orange"), "buckling_in_plane": ("D", "tab:blue"),
          "buckling_out_of_plane": ("^", "tab:purple")}


def _n(value: float) -> str:
    return "inf" if not math.isfinite(value) or value > 1e12 else f"{value:.3g}"


def link_rows(s: MachineStrength) -> list[list[str]]:
    """One row per link: material, section, length, mass and each check's least factor of safety."""
    rows = []
    for link in s.links.values():
        by = {c.name: c for c in link.checks}
        rows.append([link.link, link.material.name, link.section.label, f"{link.forces.length * 1e3:.0f}",
                     f"{link.mass:.3g}", *(_n(by[k].safety) for k in _MARKS),
                     "yes" if link.passed else "NO"])
    return rows


def joint_rows(s: MachineStrength) -> list[list[str]]:
    """One row per revolute joint: pin, its governing check, the bearing and its figure, passed."""
    rows = []
    for j in s.parts.joints.values():
        if j.rolling is not None:
            bearing = f"{j.rolling.bearing.designation}, L10h {_n(j.rolling.life_hours)} h"
        elif j.bushing is not None:
            bearing = (f"{j.bushing.material.name} {j.bushing.diameter * 1e3:.0f}x{j.bushing.length * 1e3:.0f} mm, "
                       f"p·v {j.bushing.pv_mean / 1e6:.3g} MPa·m/s")
        else:
            bearing = "-"
        rows.append([j.joint, f"{j.pin.diameter * 1e3:.0f}", j.pin.governing, j.pin.load_kind, bearing,
                     "yes" if j.passed else "NO"])
    return rows


def shaft_rows(s: MachineStrength) -> list[list[str]]:
    """The crank shaft, its bearings and each hub's key."""
    c = s.parts.crank_shaft
    if c is None:
        return []
    sh = c.shaft
    rows = [["crank shaft", f"d = {sh.diameter * 1e3:.0f} mm (needs {sh.diameter_required * 1e3:.1f})",
             f"DE-Goodman n = {_n(sh.fatigue_safety)}, yield n = {_n(sh.yield_safety)}",
             "yes" if all(x.passed for x in sh.checks) else "NO"]]
    for name, b in zip("AB", c.bearings):
        rows.append([f"bearing {name}", b.bearing.designation, f"L10h {_n(b.life_hours)} h",
                     "yes" if all(x.passed for x in b.checks) else "NO"])
    for hub, k in c.keys.items():
        rows.append([f"key, {hub} hub", f"DIN 6885 {k.form} {k.section.b * 1e3:.0f}x{k.section.h * 1e3:.0f}x"
                     f"{k.length * 1e3:.0f}", f"p max {float(k.pressure.max()) / 1e6:.3g} MPa",
                     "yes" if all(x.passed for x in k.checks) else "NO"])
    return rows


def _section_shape(ax: Axes, sec: Section) -> None:
    """The cross-section to scale [mm], height in the plane of motion upward."""
    h, b = sec.height * 1e3, sec.width * 1e3
    if sec.kind == "round":
        ax.add_patch(Circle((0, 0), h / 2, fc="0.75", ec="k", lw=0.8))
    elif sec.kind == "tube":
        ax.add_patch(Circle((0, 0), h / 2, fc="0.75", ec="k", lw=0.8))
        ax.add_patch(Circle((0, 0), h / 2 - sec.dimensions["wall_m"] * 1e3, fc="w", ec="k", lw=0.8))
    elif sec.kind == "ipe":
        tw, tf = sec.dimensions["web_m"] * 1e3, sec.dimensions["flange_m"] * 1e3
        pts = [(-b / 2, h / 2), (b / 2, h / 2), (b / 2, h / 2 - tf), (tw / 2, h / 2 - tf), (tw / 2, -h / 2 + tf),
               (b / 2, -h / 2 + tf), (b / 2, -h / 2), (-b / 2, -h / 2), (-b / 2, -h / 2 + tf),
               (-tw / 2, -h / 2 + tf), (-tw / 2, h / 2 - tf), (-b / 2, h / 2 - tf)]
        ax.add_patch(Polygon(pts, closed=True, fc="0.75", ec="k", lw=0.8))
    else:
        ax.add_patch(Rectangle((-b / 2, -h / 2), b, h, fc="0.75", ec="k", lw=0.8))
    r = 0.65 * max(h, b)
    ax.set_xlim(-r, r)
    ax.set_ylim(-r, r)
    ax.set_aspect("equal", adjustable="box")
    ax.set_title(f"{sec.label}\nA = {sec.area * 1e6:.4g} mm²", fontsize=7)
    ax.tick_params(labelsize=6)


def _link_elevation(ax: Axes, link: LinkSizing) -> None:
    """The bar along its x-axis [mm] (lengths to scale, its height in the plane exaggerated), its load points,
    the envelope of its bending moment over the cycle and where each check is least."""
    f = link.forces
    h = link.section.height * 1e3
    x0, x1 = f.start * 1e3, f.end * 1e3
    ax.add_patch(Rectangle((x0, -h / 2), x1 - x0, h, fc="0.85", ec="k", lw=0.8))
    for name, x in f.points.items():
        if name == "process_force":
            continue
        ax.plot([x * 1e3], [0.0], marker="o", ms=7, mfc="w", mec="k", ls="none", zorder=3)
        ax.annotate(name, (x * 1e3, h / 2), xytext=(0, 4), textcoords="offset points", ha="center", fontsize=7)
    envelope = np.abs(f.moment).max(axis=0)
    scale = 1.5 * h / max(float(envelope.max()), 1e-30)
    ax.plot(f.x * 1e3, -h / 2 - envelope * scale, color="tab:green", lw=1.0,
            label=f"|M| over the cycle (max {float(envelope.max()):.3g} N·m)")
    for c in link.checks:
        marker, colour = _MARKS[c.name]
        ax.plot([c.x * 1e3], [0.0], marker=marker, color=colour, ms=6, ls="none", zorder=4,
                label=f"{c.name.replace('_', ' ')}: n = {_n(c.safety)} (≥ {c.required:g}) at "
                      f"{math.degrees(c.phi):.0f}°")
    span = x1 - x0
    ax.set_xlim(x0 - 0.08 * span, x1 + 0.08 * span)
    ax.set_ylim(-h / 2 - 2.0 * h, h * 1.6)
    ax.set_aspect("auto")
    ax.set_yticks([])
    ax.set_xlabel("along the link [mm]", fontsize=7)
    ax.tick_params(labelsize=6)
    ax.set_title(f"{link.link}: {link.material.name}, {link.mass:.3g} kg, "
                 f"{'passes' if link.passed else 'FAILS'} every check", fontsize=8, loc="left")


def strength_record_page(s: MachineStrength) -> Figure:
    """One page: each link drawn along its axis with its section beside it and its least factors of safety."""
    links = list(s.links.values())
    fig = plt.figure(figsize=A4)
    grid = fig.add_gridspec(max(len(links), 1), 3, width_ratios=(4, 1.9, 1), hspace=0.9, wspace=0.1)
    for i, link in enumerate(links):
        ax = fig.add_subplot(grid[i, 0])
        _link_elevation(ax, link)
        key = fig.add_subplot(grid[i, 1])
        key.axis("off")
        key.legend(*ax.get_legend_handles_labels(), fontsize=6, loc="center left", frameon=False)
        _section_shape(fig.add_subplot(grid[i, 2]), link.section)
    return fig
