"""Figures of an analysis as the textbooks draw them, headless with matplotlib, as PNG, SVG or PDF bytes.

The mechanism is drawn to scale: the crank circle, frame pivots, guides, sliding blocks, the shaper's ram with
its slot, counterweights (area in proportion to mass) and the traced paths of coupler points. The shaking force
is drawn as a polar diagram (the tip of the force vector over the cycle) with crank-angle ticks.
"""

from __future__ import annotations

import functools
import io
import math
import unicodedata
from collections.abc import Callable, Iterator, Sequence
from typing import Any, Literal

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.artist import Artist  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.axis import Axis  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.font_manager import findfont, get_font  # noqa: E402
from matplotlib.patches import Circle, Polygon, Rectangle  # noqa: E402
from matplotlib.text import Text  # noqa: E402

from .analysis import Analysis  # noqa: E402
from .kinematics import SlottedLever  # noqa: E402
from .kinematics import motion as solve_motion  # noqa: E402
from .model import Counterweight, FloatArray, Linkage  # noqa: E402

FigureFormat = Literal["png", "svg", "pdf"]
FIGURE_FORMATS: tuple[FigureFormat, ...] = ("png", "svg", "pdf")
# Colours kept apart for "before" and "after" in every balancing panel.
BEFORE, AFTER = "tab:blue", "tab:red"


@functools.cache
def _drawable(font_path: str) -> Callable[[str], bool]:
    font = get_font(font_path)
    return functools.cache(lambda ch: ch == "\n" or (unicodedata.category(ch) != "Cc"
                                                     and font.get_char_index(ord(ch)) != 0))


def _as_drawn(text: Text) -> str:
    """The text with every character its font cannot draw (control characters, scripts it lacks) as U+FFFD."""
    drawable = _drawable(findfont(text.get_fontproperties()))
    return "".join(ch if drawable(ch) else "\ufffd" for ch in text.get_text())


def _own_texts(artist: Artist) -> Iterator[Text]:
    """The texts under ``artist`` that the figure's code set: an axis gives its label, never its tick labels."""
    for child in artist.get_children():
        if isinstance(child, Axis):
            yield child.label
            continue
        if isinstance(child, Text):
            yield child
        yield from _own_texts(child)


def literal_text(fig: Figure) -> Figure:
    """``fig`` with every text drawn as written: names from a request (trace points, links, machines) may hold
    ``$`` or ``\\``, which matplotlib would otherwise read as mathtext and fail on, and characters the font
    lacks, drawn as U+FFFD. The tick labels matplotlib formats itself keep their mathtext (a log axis writes its
    powers of ten with it)."""
    for text in _own_texts(fig):
        text.set_parse_math(False)
        if not all(" " <= ch <= "~" or ch == "\n" for ch in text.get_text()):
            text.set_text(_as_drawn(text))
    return fig


def close_figures() -> None:
    """Close every open figure: an export that failed half-way leaves its figure open, and pyplot keeps it."""
    plt.close("all")


def render(fig: Figure, fmt: FigureFormat = "png", dpi: int = 110) -> bytes:
    """Render a figure as PNG, SVG or PDF bytes and close it; its texts are drawn as written (literal_text).

    SVG and PDF carry no creation date, so the same figure gives the same bytes.
    """
    literal_text(fig)
    buf = io.BytesIO()
    metadata: dict[str, Any] = {"png": {}, "svg": {"Date": None}, "pdf": {"CreationDate": None}}[fmt]
    fig.savefig(buf, format=fmt, dpi=dpi, bbox_inches="tight", metadata=metadata)
    plt.close(fig)
    return buf.getvalue()


def figure_png(fig: Figure, dpi: int = 110) -> bytes:
    """Render and close a figure as PNG."""
    return render(fig, "png", dpi)


def _machine_size(points: Sequence[FloatArray]) -> float:
    cloud = np.vstack([p.reshape(-1, 2) for p in points])
    return float(max(np.ptp(cloud[:, 0]), np.ptp(cloud[:, 1]), 1e-9))


def _block(ax: Axes, at: FloatArray, angle: float, length: float, height: float, **style: Any) -> None:
    """A sliding block: a rectangle centred at ``at`` [m] with its long side at ``angle`` [rad]."""
    c, s = math.cos(angle), math.sin(angle)
    u, v = np.array([c, s]) * length / 2, np.array([-s, c]) * height / 2
    corners = np.array([at - u - v, at + u - v, at + u + v, at - u + v])
    ax.add_patch(Polygon(corners, closed=True, **{"fc": "0.85", "ec": "k", "lw": 1.2, "zorder": 4, **style}))


def _pivot(ax: Axes, at: FloatArray, size: float) -> None:
    """A frame pivot: a triangle under the joint and the hatched ground line."""
    x, y = at
    ax.add_patch(Polygon([[x, y], [x - size, y - 1.6 * size], [x + size, y - 1.6 * size]], closed=True,
                         fc="white", ec="k", lw=1, zorder=2))
    ax.plot([x - 1.6 * size, x + 1.6 * size], [y - 1.6 * size] * 2, "k-", lw=1.2, zorder=2)
    for k in np.linspace(-1.4, 1.2, 6):
        ax.plot([x + k * size, x + (k + 0.4) * size], [y - 2.2 * size, y - 1.6 * size], "k-", lw=0.6, zorder=2)


def _guide(ax: Axes, p0: FloatArray, p1: FloatArray, half_gap: float) -> None:
    """A fixed straight guide from ``p0`` to ``p1`` [m]: two rails ``half_gap`` either side, hatched outside."""
    d = p1 - p0
    n = np.array([-d[1], d[0]]) / max(float(np.hypot(*d)), 1e-12)
    for side in (1.0, -1.0):
        a, b = p0 + side * half_gap * n, p1 + side * half_gap * n
        ax.plot([a[0], b[0]], [a[1], b[1]], "k-", lw=1.2, zorder=1)
        for t in np.linspace(0.0, 1.0, 12):
            q = a + t * (b - a)
            r = q + side * 0.6 * half_gap * n + 0.4 * half_gap * d / max(float(np.hypot(*d)), 1e-12)
            ax.plot([q[0], r[0]], [q[1], r[1]], "k-", lw=0.5, zorder=1)


def _world(origin: FloatArray, angle: float, local: tuple[float, float]) -> FloatArray:
    c, s = math.cos(angle), math.sin(angle)
    return np.asarray(origin + np.array([c * local[0] - s * local[1], s * local[0] + c * local[1]]), dtype=float)


def draw_linkage(ax: Axes, linkage: Linkage, an: Analysis, phi: float,
                 counterweights: Sequence[Counterweight] | None = None) -> None:
    """The linkage at crank angle ``phi`` [rad], to scale, with the paths of its trace points over ``an``'s cycle.

    ``counterweights`` defaults to the linkage's own; they are drawn as discs of area in proportion to mass on
    an arm from their link's first joint.
    """
    mech = linkage.mechanism
    topo = mech.topology
    single = solve_motion(mech, np.array([phi]), an.motion.omega_crank)
    pos = {k: v[0] for k, v in single.point_pos.items()}
    angle = {k: float(v[0]) for k, v in single.link_angle.items()}
    full = an.motion.point_pos
    size = _machine_size(list(full.values()))
    block_len, block_h = 0.09 * size, 0.05 * size

    crank_pin = pos[next(j.point for j in topo.joints if j.bodies[0] == topo.crank)]
    centre = pos[mech.origins[topo.crank]]
    radius = float(np.hypot(*(crank_pin - centre)))
    ax.add_patch(Circle(tuple(centre), radius, fill=False, ls="-.", lw=0.8, ec="0.45", zorder=1))

    joints_of = {link: [j for j in topo.joints if link in j.bodies] for link in topo.links}
    riding = trace_points(an)
    extent: list[FloatArray] = []
    for name, (link, local) in riding.items():
        pos[name] = _world(pos[mech.origins[link]], angle[link], local)
    for link in topo.links:
        points = {j.point for j in joints_of[link]}
        origin = pos[mech.origins[link]]
        if len(points) == 1:
            # A block sliding in a slot or on a guide: drawn along its own axis.
            _block(ax, origin, angle[link], block_len, block_h)
            continue
        if isinstance(mech, SlottedLever) and link == "ram":
            extent.append(_draw_ram(ax, an, pos, size, block_h))
            continue
        ends = [pos[p] for p in points]
        plate = [pos[t] for t, (on, _) in riding.items() if on == link]
        far = max(ends, key=lambda p: float(np.hypot(*(p - origin))))
        outline = np.array([origin, *plate, far]) if plate else np.array([origin, far])
        if len(outline) > 2:
            ax.add_patch(Polygon(outline, closed=True, fc="tab:orange", alpha=0.25, ec="none", zorder=2))
        ax.plot(outline[:, 0], outline[:, 1], "-", lw=3.5, solid_capstyle="round", zorder=3, label=link)
    for joint in topo.joints:
        p = pos[joint.point]
        if joint.kind == "revolute":
            ax.plot(*p, "o", ms=6, mfc="white", mec="k", zorder=5)
            if joint.bodies[0] is None:
                _pivot(ax, p, 0.03 * size)
        elif joint.bodies[0] is None and not isinstance(mech, SlottedLever):
            axis = np.array([math.cos(joint.axis_angle), math.sin(joint.axis_angle)])
            travel = full[joint.point] @ axis
            base = p - (p @ axis) * axis
            lo, hi = float(travel.min()) - block_len, float(travel.max()) + block_len
            _guide(ax, base + lo * axis, base + hi * axis, block_h / 2 + 0.004 * size)
    for name in riding:
        path = full[name]
        ax.plot(path[:, 0], path[:, 1], ":", lw=1.2, color="tab:purple", zorder=2)
        ax.plot(*pos[name], "s", ms=5, color="tab:purple", zorder=6)
        ax.annotate(name, pos[name], xytext=(4, 4), textcoords="offset points", fontsize=8, color="tab:purple")
    for link in topo.links:
        props = linkage.links.get(link)
        if props is not None and props.mass > 0:
            at = _world(pos[mech.origins[link]], angle[link], props.com)
            ax.plot(*at, "kx", ms=6, zorder=6)
    cws = list(linkage.counterweights if counterweights is None else counterweights)
    heaviest = max((c.mass for c in cws), default=0.0)
    for cw in cws:
        if cw.mass <= 0:
            continue
        joint = pos[mech.origins[cw.link]]
        at = _world(joint, angle[cw.link], cw.position)
        ax.plot([joint[0], at[0]], [joint[1], at[1]], "-", color="0.3", lw=2, zorder=3)
        r = 0.06 * size * math.sqrt(cw.mass / heaviest)
        ax.add_patch(Circle(tuple(at), r, fc="0.25", ec="k", zorder=5))
        extent.append(np.array([at - r, at + r]))
        ax.annotate(f"{cw.mass:.3g} kg", at + np.array([r, -r]), xytext=(3, -6), textcoords="offset points", fontsize=8)
    extent.append(np.array([centre - radius, centre + radius]))
    _frame_to_scale(ax, [*full.values(), *extent])
    ax.set_title(f"mechanism at {round(math.degrees(phi), 6):g}°")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.25)


def trace_points(an: Analysis) -> dict[str, tuple[str, tuple[float, float]]]:
    """The analysis's extra points (not joints, not centres of mass) and the link each rides on, with its position
    in that link's frame [m], recovered from the motion: the link whose frame holds it still. Fewer than three
    analysed angles cannot tell the links apart, and give none."""
    mech = an.linkage.mechanism
    m = an.motion
    joints = {j.point for j in mech.topology.joints}
    out: dict[str, tuple[str, tuple[float, float]]] = {}
    if m.samples < 3:
        return out
    for name, path in m.point_pos.items():
        if name in joints or name.startswith("S_"):
            continue
        for link in mech.topology.links:
            rel = path - m.point_pos[mech.origins[link]]
            th = m.link_angle[link]
            local = np.stack([np.cos(th) * rel[:, 0] + np.sin(th) * rel[:, 1],
                              -np.sin(th) * rel[:, 0] + np.cos(th) * rel[:, 1]], axis=1)
            if float(np.ptp(local, axis=0).max()) < 1e-9 * (1.0 + float(np.abs(local).max())):
                out[name] = (link, (float(local[0, 0]), float(local[0, 1])))
                break
    return out


def _draw_ram(ax: Axes, an: Analysis, pos: dict[str, FloatArray], size: float, block_h: float) -> FloatArray:
    """The shaper's ram: a long bar on its horizontal guide with a slotted arm for the lever's block; returns
    the corners of the space it sweeps [m]."""
    r, b = pos["R"], pos["B"]
    travel = an.motion.point_pos["R"][:, 0]
    stroke = float(np.ptp(travel))
    length = max(1.4 * stroke, 0.5 * size)
    height = 1.6 * block_h
    ax.add_patch(Rectangle((r[0] - length / 2, r[1] - height / 2), length, height, fc="tab:green", alpha=0.35,
                           ec="k", lw=1.2, zorder=3, label="ram"))
    slot_lo = min(b[1], r[1]) - 1.5 * block_h
    slot_hi = r[1] + height / 2
    ax.add_patch(Rectangle((r[0] - block_h * 0.9, slot_lo), block_h * 1.8, slot_hi - slot_lo, fc="tab:green",
                           alpha=0.2, ec="k", lw=1, zorder=3))
    ax.plot([r[0] - block_h * 0.45, r[0] - block_h * 0.45], [slot_lo + 0.2 * block_h, slot_hi], "k-", lw=0.6, zorder=3)
    ax.plot([r[0] + block_h * 0.45, r[0] + block_h * 0.45], [slot_lo + 0.2 * block_h, slot_hi], "k-", lw=0.6, zorder=3)
    ax.add_patch(Polygon([[r[0] + length / 2, r[1] - height / 2], [r[0] + length / 2 + 0.3 * height, r[1] - height],
                          [r[0] + length / 2 + 0.3 * height, r[1] - height / 2]], closed=True, fc="0.3", zorder=3))
    lo, hi = float(travel.min()) - length / 2 - block_h, float(travel.max()) + length / 2 + block_h
    _guide(ax, np.array([lo, r[1]]), np.array([hi, r[1]]), height / 2 + 0.004 * size)
    low_b = float(an.motion.point_pos["B"][:, 1].min()) - 1.5 * block_h
    return np.array([[lo, low_b], [hi, r[1] + height]])


def _frame_to_scale(ax: Axes, clouds: Sequence[FloatArray]) -> None:
    """Equal scales on both axes, and a frame never flatter than 5:3 so a slider-crank is not a strip."""
    cloud = np.vstack([c.reshape(-1, 2) for c in clouds])
    lo, hi = cloud.min(axis=0), cloud.max(axis=0)
    span = np.maximum(hi - lo, 1e-9)
    mid = (lo + hi) / 2
    span = np.maximum(span, 0.6 * span.max()) * 1.25
    ax.set_xlim(mid[0] - span[0] / 2, mid[0] + span[0] / 2)
    ax.set_ylim(mid[1] - span[1] / 2, mid[1] + span[1] / 2)
    ax.set_aspect("equal", adjustable="box")


def draw_mechanism(ax: Axes, an: Analysis, phi: float) -> None:
    """The analysed linkage at ``phi`` [rad] with its counterweights and trace-point paths (see draw_linkage)."""
    draw_linkage(ax, an.linkage, an, phi)


def _tick_indices(phi: FloatArray, step_deg: float = 30.0) -> list[int]:
    """Samples nearest to every ``step_deg`` of crank angle (each at most half a step away)."""
    deg = np.degrees(phi) % 360.0
    out = []
    for target in np.arange(0.0, 360.0, step_deg):
        gap = np.abs((deg - target + 180.0) % 360.0 - 180.0)
        i = int(np.argmin(gap))
        if gap[i] <= step_deg / 2 and i not in out:
            out.append(i)
    return out


def shaking_polar(ax: Axes, force: FloatArray, label: str, phi: FloatArray | None = None, tick_deg: float = 30.0,
                  **style: Any) -> None:
    """Polar diagram of the shaking force [N]: the tip of the force vector over the cycle, with crank-angle ticks
    every ``tick_deg`` when ``phi`` [rad] is given."""
    closed = np.vstack([force, force[:1]])
    line, = ax.plot(closed[:, 0], closed[:, 1], label=label, **style)
    if phi is not None:
        idx = _tick_indices(phi, tick_deg)
        ax.plot(force[idx, 0], force[idx, 1], "o", ms=3.5, color=line.get_color(), zorder=line.get_zorder() + 1)
        for i in idx:
            ax.annotate(f"{round(math.degrees(phi[i])) % 360:d}°", force[i], xytext=(3, 3), textcoords="offset points",
                        fontsize=6.5, color=line.get_color())
    ax.plot(0, 0, "+", color="0.4", ms=7, zorder=0)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("Fx [N]")
    ax.set_ylabel("Fy [N]")
    ax.set_title("shaking force polar diagram")
    ax.grid(alpha=0.3)


def _curve(ax: Axes, deg: FloatArray, series: Sequence[tuple[FloatArray, str, dict[str, Any]]],
           ylabel: str, title: str) -> None:
    for y, label, style in series:
        ax.plot(deg, y, label=label, **style)
    ax.axhline(0.0, color="0.5", lw=0.6)
    ax.set_xlabel("crank angle [deg]")
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.set_xticks(np.arange(0, 361, 60))
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)


#: Below this fraction of a linkage's own force scale a shaking force (or moment) is rounding, not a quantity.
ZERO_FRACTION = 1e-9
#: The half-span of an axis that shows a zero: a thousandth of the scale, so rounding does not fill the plot.
ZERO_SPAN = 1e-3


def force_scale(an: Analysis) -> float:
    """The linkage's own inertia-force scale Σm·ω²·size [N]: links and counterweights, the cycle's extent."""
    lk = an.linkage
    mass = sum(p.mass for p in lk.links.values()) + sum(c.mass for c in lk.counterweights)
    return float(mass * an.motion.omega_crank ** 2 * _machine_size(list(an.motion.point_pos.values())))


def read_zero(ax: Axes, peak: float, scale: float, unit: str, polar: bool = False) -> bool:
    """When ``peak`` is below ZERO_FRACTION of ``scale``, show the axes as a zero: a span of ±ZERO_SPAN·scale
    (both axes of a polar diagram) and the words "≈ 0"; True when it did."""
    if not (scale > 0 and peak < ZERO_FRACTION * scale):
        return False
    half = ZERO_SPAN * scale
    ax.set_ylim(-half, half)
    if polar:
        ax.set_aspect("equal", adjustable="box")
        ax.set_xlim(-half, half)
    ax.text(0.02, 0.96, f"≈ 0 (largest |value| {peak:.2g} {unit})", transform=ax.transAxes, va="top", fontsize=8,
            color="tab:green", weight="bold")
    return True


def analysis_figure(an: Analysis, phi: float = 0.0, fmt: FigureFormat = "png") -> bytes:
    """Driving torque (with the virtual-power check, and with friction when the analysis has it), shaking
    moment, shaking force polar diagram and the mechanism at ``phi`` [rad], as PNG, SVG or PDF."""
    fig, axes = plt.subplots(2, 2, figsize=(13, 10))
    k = an.kinetostatics
    deg = np.degrees(an.motion.phi)
    torques: list[tuple[FloatArray, str, dict[str, Any]]] = [
        (k.driving_torque, "kinetostatics", {"lw": 2}),
        (an.virtual_power_torque, "virtual power (check)", {"ls": "--", "color": "k", "lw": 1})]
    if an.friction is not None:
        eta = an.friction.cycle_efficiency
        label = "with friction" + ("" if eta is None else f" (cycle efficiency {eta:.3g})")
        torques.append((an.friction.driving_torque, label, {"lw": 1.5, "color": "tab:red"}))
    _curve(axes[0, 0], deg, torques, "driving torque [N·m]", "driving torque on the crank")
    _curve(axes[0, 1], deg, [(k.shaking_moment, "shaking moment about O", {"lw": 2, "color": "tab:green"})],
           "shaking moment [N·m]", "shaking moment on the frame")
    shaking_polar(axes[1, 0], k.shaking_force, "shaking force", an.motion.phi, lw=1.5)
    # a balanced linkage's force and moment are rounding: read as zero, not autoscaled to fill the axes
    scale = force_scale(an)
    read_zero(axes[0, 1], float(np.abs(k.shaking_moment).max()), scale * _machine_size(
        list(an.motion.point_pos.values())), "N·m")
    read_zero(axes[1, 0], float(np.hypot(*k.shaking_force.T).max()), scale, "N", polar=True)
    draw_mechanism(axes[1, 1], an, phi)
    literal_text(fig).tight_layout()
    return render(fig, fmt)


def analysis_png(an: Analysis, phi: float = 0.0) -> bytes:
    """The analysis figure as PNG (see analysis_figure)."""
    return analysis_figure(an, phi, "png")
