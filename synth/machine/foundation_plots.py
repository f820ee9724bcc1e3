"""Figures of the machine on its foundation: the force it passes on, the frame's orbit, the transmissibility per
harmonic; the speed and torque of a regulated machine after a load step."""

from __future__ import annotations

import io
from collections.abc import Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from ..model import FloatArray  # noqa: E402

from .foundation import Isolation  # noqa: E402
from .elastic_drive import ElasticDrive, ElasticRun  # noqa: E402
from .foundation_design import IsolationDesign  # noqa: E402
from .regulation import Regulation  # noqa: E402


def _bytes(fig: Figure, fmt: str) -> bytes:
    buffer = io.BytesIO()
    fig.savefig(buffer, format=fmt, dpi=110)
    plt.close(fig)
    return buffer.getvalue()


def isolation_figure(r: Isolation, fmt: str = "png") -> bytes:
    """Force to the foundation against the shaking force over the cycle, the frame centre's orbit, and the force
    transmissibility per harmonic, as PNG, SVG or PDF."""
    if r.run_up is None:
        fig, grid = plt.subplots(1, 3, figsize=(14, 4.4), layout="constrained")
        axes = list(grid)
    else:
        fig, grid = plt.subplots(2, 2, figsize=(12, 8.5), layout="constrained")
        axes = list(grid.reshape(-1))
    deg = np.degrees(r.phi)
    ax = axes[0]
    ax.plot(deg, np.linalg.norm(r.shaking_force, axis=1), lw=1.2, label="shaking force (rigid floor)")
    ax.plot(deg, np.linalg.norm(r.force, axis=1), lw=1.2, label="force to the foundation")
    ax.set(xlabel="crank angle [deg]", ylabel="|F| [N]", title="Force the foundation feels")
    ax.legend(fontsize=8)
    ax = axes[1]
    ax.plot(r.displacement[:, 0] * 1e3, r.displacement[:, 1] * 1e3, lw=1.2)
    ax.plot(r.displacement[0, 0] * 1e3, r.displacement[0, 1] * 1e3, "o", ms=4, label="first sample")
    ax.set(xlabel="x [mm]", ylabel="y [mm]", title=f"Frame centre's orbit (peak {r.peak_displacement * 1e3:.3g} mm)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=8)
    ax = axes[2]
    orders = [h.order for h in r.harmonics if h.force_transmissibility is not None]
    values = [h.force_transmissibility for h in r.harmonics if h.force_transmissibility is not None]
    ax.bar(orders, values, color="C1")
    ax.axhline(1.0, color="k", lw=0.8, ls="--")
    crank_hz = 1.0 / (r.time[1] * r.time.size)
    for m in r.modes:
        ax.axvline(m.frequency / crank_hz, color="C3", lw=0.8, ls=":")
    ax.set(xlabel="harmonic order (modes dotted)", ylabel="transmitted / shaking [-]", yscale="log",
           title="Force transmissibility per harmonic")
    if r.run_up is not None:
        ru = r.run_up
        ax = axes[3]
        ax.plot(ru.time, ru.amplitude * 1e3, lw=0.8, label="frame centre")
        ax.axhline(ru.steady_amplitude * 1e3, color="g", ls="--", lw=1, label="steady peak")
        ax.plot(ru.peak_time, ru.peak_amplitude * 1e3, "o", color="C3", ms=5,
                label=f"peak {ru.peak_amplitude * 1e3:.3g} mm at {ru.peak_speed * 30 / np.pi:.4g} rpm")
        twin = ax.twinx()
        twin.plot(ru.time, ru.speed * 30 / np.pi, color="0.5", lw=1)
        twin.set_ylabel("crank speed [rpm]", color="0.4")
        ax.set(xlabel="time [s]", ylabel="displacement [mm]", title="Run-up: the frame through resonance")
        ax.legend(fontsize=8, loc="upper right")
    return _bytes(fig, fmt)


def design_figure(d: IsolationDesign, fmt: str = "png") -> bytes:
    """The figure of the frame on the designed isolators (see :func:`isolation_figure`)."""
    return isolation_figure(d.isolation, fmt)


def elastic_drive_figure(d: ElasticDrive, fmt: str = "png") -> bytes:
    """Torque in the elastic link against the rigid model's over the steady cycle, and the run-up with the link."""
    fig, axes = plt.subplots(1, 2 if d.start is not None else 1, figsize=(13 if d.start else 7, 4.6),
                             layout="constrained", squeeze=False)
    link_torque(axes[0][0], d, f"Steady cycle; link at {d.natural_frequency:.4g} Hz", 8)
    if d.start is not None:
        run_up(axes[0][1], d.start, 8)
    return _bytes(fig, fmt)


def link_torque(ax: Axes, d: ElasticDrive, title: str, fontsize: float) -> None:
    """The torque in the elastic link over the steady cycle against the rigid model's."""
    deg = np.degrees(d.phi)
    ax.plot(deg, d.rigid_torque, lw=1.2, label="rigid model, M_d − J₁α")
    ax.plot(deg, d.steady.elastic_torque, lw=1.2, label=f"elastic link (factor {d.dynamic_factor:.3g})")
    ax.set(xlabel="crank angle [deg]", ylabel="torque at the crank [N·m]", title=title)
    ax.legend(fontsize=fontsize)


def run_up(ax: Axes, start: ElasticRun, fontsize: float) -> None:
    """The run-up from rest with the elastic link: the torque in it and the crank's speed."""
    ax.plot(start.time, start.elastic_torque, lw=0.8, color="C1", label="torque in the link")
    ax.set(xlabel="time [s]", ylabel="torque at the crank [N·m]", title="Run-up from rest with the link")
    twin = ax.twinx()
    twin.plot(start.time, start.crank_speed * 30 / np.pi, color="0.4", lw=1)
    twin.set_ylabel("crank speed [rpm]", color="0.4")
    ax.legend(fontsize=fontsize, loc="lower right")


def regulation_figure(r: Regulation, fmt: str = "png") -> bytes:
    """Speed and torques over time around the load step, with the settling band."""
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(10, 7.5), sharex=True, layout="constrained")
    rpm = 30 / np.pi
    final = r.controller.reference if r.controller is not None and r.controller.reference else r.speed_after
    top.plot(r.time, r.omega * rpm, lw=0.7, color="0.6", label="crank speed")
    top.plot(r.time, r.smoothed * rpm, lw=1.4, color="C0", label="without the cycle's fluctuation")
    top.axhspan((final - r.band) * rpm, (final + r.band) * rpm, color="C2", alpha=0.15, label="settling band")
    top.axvline(r.step_time, color="k", lw=0.8, ls=":")
    if r.settling_time is not None:
        top.axvline(r.step_time + r.settling_time, color="C3", lw=0.8, ls="--",
                    label=f"settled after {r.settling_time:.3g} s")
    mode = "self-regulation" if r.controller is None else (f"PI: k_p {r.controller.kp:.3g}, "
                                                           f"k_i {r.controller.ki:.3g} 1/s")
    top.set(ylabel="speed [rpm]", title=f"Load step of {r.load_step:.4g} N·m at the crank, {mode}")
    top.legend(fontsize=8)
    bottom.plot(r.time, r.motor_torque, lw=1.0, label="motor (at the crank)")
    bottom.plot(r.time, -r.load_torque, lw=1.0, label="load (resisting)")
    bottom.axvline(r.step_time, color="k", lw=0.8, ls=":")
    bottom.set(xlabel="time [s]", ylabel="torque [N·m]")
    bottom.legend(fontsize=8)
    return _bytes(fig, fmt)


def foundation_record_page(isolation: Isolation | None = None, drive: ElasticDrive | None = None,
                           regulation: Regulation | None = None) -> Figure:
    """One A4 landscape page of the design record on the machine around the linkage: the frame on its isolators
    (modes, peaks, the force the foundation feels), the elastic drive (natural frequency, dynamic factor, the
    link's torque) and the speed after a load step; whichever are given. The caller saves and closes it."""
    fig = plt.figure(figsize=(11.69, 8.27))
    fig.suptitle("The machine on its foundation, its elastic drive and its speed regulation", fontsize=13)
    grid = fig.add_gridspec(2, 3, height_ratios=[1.0, 1.3], hspace=0.35, wspace=0.3, left=0.06, right=0.97,
                            bottom=0.12, top=0.9)
    rows: list[list[str]] = []
    if isolation is not None:
        r = isolation
        rows += [["isolation", "natural frequencies", ", ".join(f"{m.frequency:.3g}" for m in r.modes) + " Hz"],
                 ["", "peak force to the foundation", f"{r.peak_force:.4g} N (shaking {r.peak_shaking_force:.4g} N)"],
                 ["", "frame amplitude", f"{r.peak_displacement * 1e3:.3g} mm, {r.peak_rotation * 1e3:.3g} mrad"],
                 ["", "check: time integration", f"{r.check.relative_diff:.1e} of the peaks"]]
        if r.run_up is not None:
            rows.append(["", "run-up peak amplitude", f"{r.run_up.peak_amplitude * 1e3:.3g} mm at "
                         f"{r.run_up.peak_speed * 30 / np.pi:.4g} rpm"])
    if drive is not None:
        rows += [["elastic drive", "link stiffness, frequency", f"{drive.stiffness:.4g} N·m/rad, "
                  f"{drive.natural_frequency:.4g} Hz"],
                 ["", "dynamic factor", f"{drive.dynamic_factor:.4f}"],
                 ["", "harmonics near resonance", ", ".join(str(h.order) for h in drive.harmonics if h.near) or "none"],
                 ["", "check: energy balance", f"{drive.steady.energy_residual:.1e}"]]
    if regulation is not None:
        g = regulation
        mode = ("self-regulation" if g.controller is None
                else f"PI k_p {g.controller.kp:.3g}, k_i {g.controller.ki:.3g}")
        settle = "not within the run" if g.settling_time is None else f"{g.settling_time:.3g} s"
        rows += [["regulation", "load step, mode", f"{g.load_step:.4g} N·m, {mode}"],
                 ["", "speed drop (closed form)",
                  f"{g.drop * 30 / np.pi:.4g} rpm ({g.drop_closed_form * 30 / np.pi:.4g})"],
                 ["", "settling in the band", settle]]
    table_ax = fig.add_subplot(grid[0, :])
    table_ax.axis("off")
    if rows:
        table = table_ax.table(cellText=rows, colLabels=["", "figure", "value"], loc="center", cellLoc="left",
                               colWidths=[0.15, 0.3, 0.55])
        table.auto_set_font_size(False)
        table.set_fontsize(8.5)
        table.scale(1, 1.25)
    if isolation is not None:
        ax = fig.add_subplot(grid[1, 0])
        deg = np.degrees(isolation.phi)
        ax.plot(deg, np.linalg.norm(isolation.shaking_force, axis=1), lw=1, label="shaking force")
        ax.plot(deg, np.linalg.norm(isolation.force, axis=1), lw=1, label="to the foundation")
        ax.set(xlabel="crank angle [deg]", ylabel="|F| [N]", title="Force the foundation feels")
        ax.legend(fontsize=7)
    if drive is not None:
        ax = fig.add_subplot(grid[1, 1])
        deg = np.degrees(drive.phi)
        ax.plot(deg, drive.rigid_torque, lw=1, label="rigid model")
        ax.plot(deg, drive.steady.elastic_torque, lw=1, label="elastic link")
        ax.set(xlabel="crank angle [deg]", ylabel="torque [N·m]", title="Torque in the link")
        ax.legend(fontsize=7)
    if regulation is not None:
        ax = fig.add_subplot(grid[1, 2])
        ax.plot(regulation.time, regulation.smoothed * 30 / np.pi, lw=1)
        ax.axvline(regulation.step_time, color="k", lw=0.8, ls=":")
        ax.set(xlabel="time [s]", ylabel="speed [rpm]", title="Speed after the load step")
    return fig


def _outline(r: Isolation) -> FloatArray:
    """The frame drawn as the rectangle around its centre, isolator points and the crank pivot, with a margin [m],
    closed (5, 2)."""
    pts = np.vstack([np.array([i.position for i in r.isolators], dtype=float), [r.frame.centre], [[0.0, 0.0]]])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = 0.08 * max(float(np.max(hi - lo)), 0.1)
    lo, hi = lo - pad, hi + pad
    return np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]], [lo[0], lo[1]]])


def _moved(points: FloatArray, centre: FloatArray, q: tuple[float, float, float], scale: float) -> FloatArray:
    """``points`` [m] after the frame's rigid motion (x, y, theta) of its centre, magnified by ``scale``."""
    x, y, theta = (scale * v for v in q)
    c, s = np.cos(theta), np.sin(theta)
    rel = points - centre
    return np.asarray(centre + np.column_stack([c * rel[:, 0] - s * rel[:, 1], s * rel[:, 0] + c * rel[:, 1]])
                      + [x, y], dtype=float)


def mode_shapes(axes: Sequence[Axes], r: Isolation) -> None:
    """Each natural mode drawn on the frame: the frame at rest (grey), its isolators (triangles) and the
    crank pivot O, and the frame moved along the mode's shape, magnified so its largest point moves a fifth of
    the frame's size (the shape's sign is arbitrary)."""
    outline = _outline(r)
    centre = np.asarray(r.frame.centre, dtype=float)
    size = float(np.max(np.ptp(outline, axis=0)))
    iso = np.array([i.position for i in r.isolators], dtype=float)
    for k, (ax, m, colour) in enumerate(zip(axes, r.modes, ("C0", "C1", "C3"), strict=False)):
        unit = _moved(outline, centre, m.shape, 1.0) - outline
        scale = 0.2 * size / max(float(np.max(np.linalg.norm(unit, axis=1))), 1e-300)
        ax.plot(outline[:, 0], outline[:, 1], color="0.6", lw=1)
        moved = _moved(outline, centre, m.shape, scale)
        ax.plot(moved[:, 0], moved[:, 1], color=colour, lw=1.6)
        ax.plot(iso[:, 0], iso[:, 1], "^", color="0.3", ms=7)
        shifted = _moved(iso, centre, m.shape, scale)
        for a, b in zip(iso, shifted, strict=True):
            ax.plot([a[0], b[0]], [a[1], b[1]], color=colour, lw=0.8, ls=":")
        ax.plot(*centre, "+", color="k", ms=8)
        ax.plot(0.0, 0.0, "o", color="k", ms=3)
        ax.annotate("O", (0.0, 0.0), textcoords="offset points", xytext=(3, 3), fontsize=7)
        both = np.vstack([outline, moved])
        middle = (both.min(axis=0) + both.max(axis=0)) / 2
        half = 0.55 * float(np.max(np.ptp(both, axis=0)))
        ax.set(xlim=(middle[0] - half, middle[0] + half), ylim=(middle[1] - half, middle[1] + half))
        ax.set_aspect("equal", adjustable="box")
        x, y, th = (0.0 if abs(v) < 1e-9 else v for v in m.shape)
        ax.set_title(f"mode {k + 1}: {m.frequency:.3g} Hz, "
                     f"ζ {m.damping_ratio:.3g}\nshape x {x:.2f}, y {y:.2f}, θ {th:.3g} rad", fontsize=8)
        ax.set_xlabel("x [m]", fontsize=8)
        ax.tick_params(labelsize=7)
    if axes:
        axes[0].set_ylabel("y [m]", fontsize=8)


def force_spectrum(ax: Axes, r: Isolation) -> None:
    """Amplitude of each harmonic of the shaking force and of the force to the foundation (log scale), with the
    natural frequencies as orders of the crank speed."""
    orders = np.array([h.order for h in r.harmonics])
    shaking = np.array([h.shaking_force for h in r.harmonics])
    passed = np.array([h.transmitted_force for h in r.harmonics])
    keep = shaking > 1e-9 * max(float(shaking.max(initial=0.0)), 1e-300)
    width = 0.38
    ax.bar(orders[keep] - width / 2, shaking[keep], width, label="shaking force (rigid floor)", color="C0")
    ax.bar(orders[keep] + width / 2, passed[keep], width, label="to the foundation", color="C1")
    crank_hz = 1.0 / (r.time[1] * r.time.size)
    for m in r.modes:
        ax.axvline(m.frequency / crank_hz, color="C3", lw=0.8, ls=":")
    ax.set_yscale("log")
    ax.set_xlim(0, min(float(orders[keep].max(initial=1.0)), 12.0) + 0.8)
    ax.set(xlabel="harmonic order (natural frequencies dotted)", ylabel="amplitude [N]",
           title="Spectrum of the force")
    ax.legend(fontsize=7)


def force_over_cycle(ax: Axes, r: Isolation) -> None:
    """The force to the foundation over the cycle, x and y and magnitude, against the shaking force's magnitude."""
    deg = np.degrees(r.phi)
    ax.plot(deg, np.linalg.norm(r.shaking_force, axis=1), lw=1, color="0.5", label="|shaking force|")
    ax.plot(deg, r.force[:, 0], lw=1, label="F_x to the foundation")
    ax.plot(deg, r.force[:, 1], lw=1, label="F_y to the foundation")
    ax.plot(deg, np.linalg.norm(r.force, axis=1), lw=1.4, color="k", label="|F| to the foundation")
    ax.set(xlabel="crank angle [deg]", ylabel="force [N]", title="Force the foundation feels over the cycle")
    ax.legend(fontsize=7)


def isolation_record_page(r: Isolation) -> Figure:
    """A page of the design record: the force to the foundation over the cycle and its spectrum, the mode shapes
    drawn on the frame."""
    fig = plt.figure(figsize=(11.69, 8.27))
    fig.suptitle("The frame on its isolators: the force the foundation feels and the natural modes", fontsize=13)
    grid = fig.add_gridspec(2, 3, height_ratios=[1.0, 1.1], hspace=0.45, wspace=0.3, left=0.07, right=0.97,
                            bottom=0.12, top=0.9)
    force_over_cycle(fig.add_subplot(grid[0, :2]), r)
    force_spectrum(fig.add_subplot(grid[0, 2]), r)
    mode_shapes([fig.add_subplot(grid[1, k]) for k in range(3)], r)
    return fig


def drive_record_page(drive: ElasticDrive | None, regulation: Regulation | None) -> Figure:
    """A page of the design record: the elastic link's torque over the steady cycle (and the run-up with it), the
    speed and the torques after the load step; whichever are given."""
    fig = plt.figure(figsize=(11.69, 8.27))
    fig.suptitle("The elastic drive and the speed after a load step", fontsize=13)
    grid = fig.add_gridspec(2, 2, hspace=0.4, wspace=0.25, left=0.07, right=0.95, bottom=0.12, top=0.9)
    if drive is not None:
        link_torque(fig.add_subplot(grid[0, 0]), drive,
                    f"Torque in the link over the steady cycle; {drive.natural_frequency:.4g} Hz", 7)
        if drive.start is not None:
            run_up(fig.add_subplot(grid[0, 1]), drive.start, 7)
    if regulation is not None:
        g = regulation
        rpm = 30 / np.pi
        final = g.controller.reference if g.controller is not None and g.controller.reference else g.speed_after
        ax = fig.add_subplot(grid[1, 0])
        ax.plot(g.time, g.omega * rpm, lw=0.6, color="0.6", label="crank speed")
        ax.plot(g.time, g.smoothed * rpm, lw=1.3, color="C0", label="without the cycle's fluctuation")
        ax.axhspan((final - g.band) * rpm, (final + g.band) * rpm, color="C2", alpha=0.15, label="settling band")
        ax.axvline(g.step_time, color="k", lw=0.8, ls=":")
        if g.settling_time is not None:
            ax.axvline(g.step_time + g.settling_time, color="C3", lw=0.8, ls="--",
                       label=f"settled after {g.settling_time:.3g} s")
        mode = "self-regulation" if g.controller is None else f"PI k_p {g.controller.kp:.3g}, k_i {g.controller.ki:.3g}"
        ax.set(xlabel="time [s]", ylabel="speed [rpm]", title=f"Speed after a {g.load_step:.4g} N·m step, {mode}")
        ax.legend(fontsize=7)
        ax = fig.add_subplot(grid[1, 1])
        ax.plot(g.time, g.motor_torque, lw=1.0, label="motor (at the crank)")
        ax.plot(g.time, -g.load_torque, lw=1.0, label="load (resisting)")
        ax.axvline(g.step_time, color="k", lw=0.8, ls=":")
        ax.set(xlabel="time [s]", ylabel="torque [N·m]", title="Torques after the load step")
        ax.legend(fontsize=7)
    return fig


def foundation_record_pages(isolation: Isolation | None = None, drive: ElasticDrive | None = None,
                            regulation: Regulation | None = None) -> list[Figure]:
    """The design record's pages on the machine around the linkage: the summary page
    (:func:`foundation_record_page`), then the frame's page and the drive's page when there is something for
    them. The caller saves and closes them."""
    if isolation is None and drive is None and regulation is None:
        return []
    pages = [foundation_record_page(isolation, drive, regulation)]
    if isolation is not None:
        pages.append(isolation_record_page(isolation))
    if drive is not None or regulation is not None:
        pages.append(drive_record_page(drive, regulation))
    return pages
