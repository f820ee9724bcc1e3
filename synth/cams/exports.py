"""A cam's answer as files: the point table (CSV), the profile as a DXF drawing at a chord tolerance, and the
figure of the motion, the pressure angle and the cam with its follower (PNG, SVG, PDF)."""

from __future__ import annotations

import io
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import InvalidInput
from ..exports import csv_text
from ..model import FloatArray
from ..plots import FIGURE_FORMATS, FigureFormat, render
from .design import CamAnalysis
from .laws import follower_motion
from .profile import cam_geometry, to_follower_frame

_MM = 1000.0
#: Profile points per turn the DXF's polyline is chosen from; the chord tolerance is met against these.
DENSE = 8192
MIN_CHORD_TOLERANCE_M = 1e-7


def _units(an: CamAnalysis) -> tuple[str, str]:
    """(lift unit, per-second stem) of the follower's coordinate."""
    return ("m", "m") if an.spec.follower.motion == "translating" else ("rad", "rad")


def cam_table(an: CamAnalysis) -> dict[str, FloatArray]:
    """Every curve of the answer, one row per cam angle; column names carry their units."""
    m, g, w = an.motion, an.geometry, an.spec.speed
    u, _ = _units(an)
    cols: dict[str, FloatArray] = {
        "cam_angle_deg": np.degrees(m.theta),
        f"s_{u}": m.s, f"v_{u}_per_rad": m.v, f"a_{u}_per_rad2": m.a, f"jerk_{u}_per_rad3": m.j,
        f"v_{u}_s": m.v * w, f"a_{u}_s2": m.a * w**2, f"jerk_{u}_s3": m.j * w**3,
        "pressure_angle_deg": np.degrees(g.pressure_angle), "curvature_radius_m": g.rho,
        "pitch_x_m": g.pitch[:, 0], "pitch_y_m": g.pitch[:, 1],
        "profile_x_m": g.profile[:, 0], "profile_y_m": g.profile[:, 1],
    }
    if an.forces is not None:
        f = an.forces
        gen = "N" if u == "m" else "Nm"
        cols |= {"contact_force_N": f.contact, f"spring_{gen}": f.spring, f"inertia_{gen}": f.inertia,
                 f"process_{gen}": f.process, "driving_torque_Nm": f.torque,
                 "driving_torque_virtual_power_Nm": f.torque_virtual_power}
    return cols


def cam_csv(an: CamAnalysis) -> bytes:
    """The point table as CSV."""
    return csv_text(cam_table(an)).encode("utf-8")


def _chord_deviation(points: FloatArray, i: int, j: int) -> float:
    """Largest distance of points[i..j] from the chord points[i] -> points[j]."""
    a, b = points[i], points[j]
    x = points[i:j + 1]
    d = b - a
    length2 = float(d @ d)
    if length2 == 0.0:
        return float(np.max(np.hypot(*(x - a).T)))
    t = np.clip(((x - a) @ d) / length2, 0.0, 1.0)
    return float(np.max(np.hypot(*(x - a - t[:, None] * d).T)))


@dataclass(frozen=True, slots=True)
class Polyline:
    """The profile as a closed polyline: vertices [m] (cam frame) and the largest distance of the dense profile
    from it [m]."""

    vertices: FloatArray
    max_deviation: float
    tolerance: float


def profile_polyline(an: CamAnalysis, tolerance: float) -> Polyline:
    """Vertices of the profile chosen from :data:`DENSE` profile points so that no point is farther than
    ``tolerance`` [m] from its chord (greedy: each chord reaches as far as a bisection finds it may)."""
    if not tolerance >= MIN_CHORD_TOLERANCE_M:
        raise InvalidInput(f"the chord tolerance must be at least {MIN_CHORD_TOLERANCE_M:g} m",
                           field="chord_tolerance_m")
    theta = np.linspace(0.0, 2.0 * math.pi, DENSE + 1)
    motion = follower_motion(an.spec.segments, theta)
    dense = cam_geometry(an.geometry.follower, an.spec.base_radius, motion).profile
    keep = [0]
    i = 0
    while i < DENSE:
        # gallop out from i until a chord breaks the tolerance, then bisect between the last good and the bad one
        step, good = 1, i + 1
        while good < DENSE and _chord_deviation(dense, i, min(i + 2 * step, DENSE)) <= tolerance:
            step *= 2
            good = min(i + step, DENSE)
        lo, hi = good, min(i + 2 * step, DENSE)
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if _chord_deviation(dense, i, mid) <= tolerance:
                lo = mid
            else:
                hi = mid
        if hi == DENSE and _chord_deviation(dense, i, hi) <= tolerance:
            lo = hi
        keep.append(lo)
        i = lo
    worst = max(_chord_deviation(dense, a, b) for a, b in zip(keep[:-1], keep[1:]))
    return Polyline(dense[keep[:-1]], worst, tolerance)


def cam_dxf_document(an: CamAnalysis, tolerance: float) -> Any:
    """The cam in millimetres: layer ``PROFILE`` (closed polyline within ``tolerance``), ``PITCH`` (the pitch
    curve, a closed polyline of the sampled points), ``BASE_CIRCLE``, ``CENTRE`` and ``TEXT``."""
    from ezdxf.document import Drawing
    from ezdxf.filemanagement import new

    doc: Drawing = new("R2010", setup=True)
    doc.header["$INSUNITS"] = 4
    for name, colour in {"PROFILE": 7, "PITCH": 5, "BASE_CIRCLE": 8, "CENTRE": 1, "TEXT": 7}.items():
        doc.layers.add(name, color=colour)
    msp = doc.modelspace()
    poly = profile_polyline(an, tolerance)
    msp.add_lwpolyline([tuple(p) for p in poly.vertices * _MM], close=True, dxfattribs={"layer": "PROFILE"})
    msp.add_lwpolyline([tuple(p) for p in an.geometry.pitch * _MM], close=True, dxfattribs={"layer": "PITCH"})
    msp.add_circle((0.0, 0.0), an.spec.base_radius * _MM, dxfattribs={"layer": "BASE_CIRCLE"})
    r = 0.05 * an.spec.base_radius * _MM
    msp.add_line((-r, 0.0), (r, 0.0), dxfattribs={"layer": "CENTRE"})
    msp.add_line((0.0, -r), (0.0, r), dxfattribs={"layer": "CENTRE"})
    size = float(np.ptp(poly.vertices, axis=0).max()) * _MM
    msp.add_text(f"cam profile, chord tolerance {tolerance * _MM:g} mm, {len(poly.vertices)} vertices, "
                 f"base radius {an.spec.base_radius * _MM:.4g} mm", height=0.03 * size,
                 dxfattribs={"layer": "TEXT"}).set_placement((-0.5 * size, -0.65 * size))
    return doc


def cam_dxf(an: CamAnalysis, tolerance: float) -> bytes:
    """The drawing of :func:`cam_dxf_document` as DXF bytes."""
    stream = io.StringIO()
    cam_dxf_document(an, tolerance).write(stream)
    return stream.getvalue().encode("utf-8")


def _rot(theta: float, pts: FloatArray) -> FloatArray:
    c, s = math.cos(theta), math.sin(theta)
    return np.asarray(pts @ np.array([[c, s], [-s, c]]))


def cam_figure(an: CamAnalysis, at: float, fmt: FigureFormat = "png") -> bytes:
    """s, v, a, jerk and the pressure angle over the turn, and the cam drawn at cam angle ``at`` [rad] with its
    follower."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle

    m, g, spec = an.motion, an.geometry, an.spec
    u, _ = _units(an)
    scale, unit = (1000.0, "mm") if u == "m" else (180.0 / math.pi, "deg")
    deg = np.degrees(m.theta)
    fig = plt.figure(figsize=(12.5, 8.0))
    grid = fig.add_gridspec(5, 2, width_ratios=[1.15, 1.0], hspace=0.12, wspace=0.18)
    rows = [(m.s * scale, f"s [{unit}]"), (m.v * scale, f"ds/dθ [{unit}/rad]"),
            (m.a * scale, f"d²s/dθ² [{unit}/rad²]"), (m.j * scale, f"d³s/dθ³ [{unit}/rad³]"),
            (np.degrees(g.pressure_angle), "pressure angle [deg]")]
    axes = [fig.add_subplot(grid[k, 0]) for k in range(5)]
    for k, (ax, (y, label)) in enumerate(zip(axes, rows)):
        ax.plot(deg, y, lw=1.3, color="tab:blue")
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.axvline(math.degrees(at) % 360.0, color="tab:red", lw=0.8, ls="--")
        for b in np.degrees(m.bounds[1:-1]):
            ax.axvline(b, color="0.85", lw=0.6)
        ax.set_ylabel(label, fontsize=8)
        ax.set_xlim(0.0, 360.0)
        ax.tick_params(labelsize=7, labelbottom=k == 4)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("cam angle θ [deg]")
    speed_rpm = spec.speed * 30.0 / math.pi
    axes[0].set_title(f"follower motion at {speed_rpm:.4g} rev/min (per radian of cam turn)", fontsize=9)

    ax = fig.add_subplot(grid[:, 1])
    prof, pitch = _rot(at, g.profile) * 1000.0, _rot(at, g.pitch) * 1000.0
    ax.fill(prof[:, 0], prof[:, 1], color="0.88", zorder=1)
    ax.plot(*np.vstack([prof, prof[:1]]).T, color="k", lw=1.4, label="profile", zorder=2)
    if spec.follower.contact != "flat_faced":
        ax.plot(*np.vstack([pitch, pitch[:1]]).T, color="tab:blue", lw=0.8, ls="--", label="pitch curve")
    ax.add_patch(Circle((0, 0), spec.base_radius * 1000.0, fill=False, color="0.5", lw=0.7, ls=":",
                        label="base circle"))
    ax.plot([0], [0], "k+", ms=10)
    # the follower at `at`, from the analytic state at the nearest sample
    i = int(np.argmin(np.abs(np.angle(np.exp(1j * (m.theta - at))))))
    C = g.contact[i] * 1000.0
    P = to_follower_frame(g.pitch[i:i + 1], m.theta[i:i + 1])[0] * 1000.0
    size = float(np.ptp(prof, axis=0).max())
    f = spec.follower
    if f.motion == "translating":
        top = P + np.array([0.0, 0.45 * size])
        ax.plot([P[0], top[0]], [P[1], top[1]], color="tab:red", lw=3, solid_capstyle="butt")
    else:
        A = np.array([f.pivot_distance, 0.0]) * 1000.0
        ax.plot([A[0], P[0]], [A[1], P[1]], color="tab:red", lw=3)
        ax.plot(*A, "o", color="tab:red", ms=7, mfc="white")
    if f.contact == "roller":
        ax.add_patch(Circle(tuple(P), f.roller_radius * 1000.0, color="tab:red", fill=False, lw=1.5))
    elif f.contact == "flat_faced":
        # the face from its reference point (on the axis, or the foot of the pivot's perpendicular) past the
        # contact point, at least as long as the contact travels along it over the turn
        along = np.array([-g.normal[i, 1], g.normal[i, 0]])
        reach = np.array([float(g.face.min()), float(g.face.max()), 0.0]) * 1000.0
        ref = C - along * g.face[i] * 1000.0
        margin = 0.05 * size
        ends = np.array([ref + along * (reach.min() - margin), ref + along * (reach.max() + margin)])
        ax.plot(ends[:, 0], ends[:, 1], color="tab:red", lw=3)
    ax.annotate("", xy=tuple(C + g.normal[i] * 0.18 * size), xytext=tuple(C),
                arrowprops=dict(arrowstyle="->", color="tab:green", lw=1.3))
    ax.plot(*C, "o", color="tab:green", ms=4)
    ax.set_aspect("equal")
    ax.grid(alpha=0.3)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.legend(loc="lower left", fontsize=7)
    ax.set_title(f"cam at θ = {math.degrees(m.theta[i]):.1f}°, turning counter-clockwise\npressure angle "
                 f"{math.degrees(g.pressure_angle[i]):.1f}° (green: contact normal)", fontsize=9)
    if fmt not in FIGURE_FORMATS:
        raise InvalidInput(f"format {fmt!r} is not a figure format", field="format")
    return render(fig, fmt)


def cam_export(an: CamAnalysis, fmt: str, at: float, tolerance: float, title: RecordTitle | None = None) -> bytes:
    """The answer as a figure (png, svg; pdf: the design record when ``title`` is given) at cam angle ``at``
    [rad], the point table (csv) or the drawing (dxf) within chord ``tolerance`` [m]."""
    if fmt == "pdf" and title is not None:
        return cam_record_pdf(an, at, title)
    if fmt == "csv":
        return cam_csv(an)
    if fmt == "dxf":
        return cam_dxf(an, tolerance)
    if fmt in FIGURE_FORMATS:
        return cam_figure(an, at, fmt)
    raise InvalidInput(f"format {fmt!r} is not offered for cams", field="format")


@dataclass(frozen=True, slots=True)
class RecordTitle:
    """The title block of a cam's design record: a name, the UTC time, the service's version, the SHA-256 of the
    request's canonical JSON and every input as (JSON path, value, unit)."""

    name: str
    created: str
    version: str
    request_sha256: str
    inputs: tuple[tuple[str, str, str], ...]
    least: tuple[str, ...] = ()


def _record_lines(an: CamAnalysis, title: RecordTitle) -> list[tuple[str, str]]:
    """(heading or label, value) lines of the record's first page; a heading has an empty value."""
    g, spec, f = an.geometry, an.spec, an.forces
    fol = spec.follower
    kinds = np.array([s.kind for s in spec.segments])[an.motion.segment]
    alpha = np.abs(g.pressure_angle)
    convex = np.where(g.kappa > 0, g.kappa, 0.0)
    k = int(np.argmax(convex))
    where = (f"offset {fol.offset * 1e3:.4g} mm" if fol.motion == "translating"
             else f"pivot {fol.pivot_distance * 1e3:.4g} mm from the cam centre, arm {fol.arm_length * 1e3:.4g} mm")
    lines: list[tuple[str, str]] = [("The cam", ""),
                                    ("follower", f"{fol.motion}, {fol.contact.replace('_', '-')}"
                                     + (f", roller {fol.roller_radius * 1e3:.4g} mm" if fol.contact == "roller" else "")
                                     + f", {where}"),
                                    ("base / prime radius", f"{spec.base_radius * 1e3:.5g} / {g.prime_radius * 1e3:.5g} mm"),
                                    ("cam speed", f"{spec.speed * 30 / math.pi:.5g} rev/min, counter-clockwise")]
    for c in an.laws:
        lift = f"{c.lift * 1e3:.4g} mm" if fol.motion == "translating" else f"{math.degrees(c.lift):.4g}°"
        lines.append((f"segment {c.index}: {c.kind}", f"{lift} over {math.degrees(c.angle):.4g}° by {c.law}; C_a "
                      f"{c.coefficient_acceleration:.4f}" + (f" (textbooks {c.textbook_acceleration:.4f})"
                                                            if c.textbook_acceleration else "")))
    lines += [("Profile", ""),
              ("largest pressure angle", f"{math.degrees(alpha[kinds == 'rise'].max(initial=0)):.3f}° in the rises, "
               f"{math.degrees(alpha[kinds == 'return'].max(initial=0)):.3f}° in the returns"),
              ("least radius of curvature", f"{1e3 / convex[k]:.4g} mm at {math.degrees(an.motion.theta[k]):.1f}°")]
    if fol.contact == "flat_faced":
        lines.append(("least face width", f"{float(np.ptp(g.face)) * 1e3:.4g} mm"))
    if f is not None:
        unit = ("N/m", "N") if fol.motion == "translating" else ("N·m/rad", "N·m")
        lines += [("Forces", ""),
                  ("spring", f"{f.stiffness:.5g} {unit[0]}, preload {f.preload:.5g} {unit[1]}"
                   + (" (designed: least largest force for the contact margin)" if f.spring_designed else "")),
                  ("contact force", f"{f.contact.min():.5g} .. {f.contact.max():.5g} N"),
                  ("driving torque", f"peak {np.abs(f.torque).max():.5g} N·m, mean {f.torque.mean():.5g} N·m")]
    if title.least:
        lines += [("The least cam", "")] + [("", text) for text in title.least]
    lines += [("Checks", ""),
              ("pressure angle from the point table", f"within {math.degrees(an.table.max_pressure_angle_error):.2g}°"),
              ("curvature from the point table", f"within {an.table.max_curvature_error:.2g} of the largest"),
              ("laws' derivatives by differences", f"within {an.derivative_check:.2g} of each peak")]
    if f is not None:
        lines.append(("torque by virtual power, T ω = Q q̇", f"within {f.torque_check:.2g} of the peak"))
    return lines


def cam_record_pdf(an: CamAnalysis, at: float, title: RecordTitle) -> bytes:
    """The cam's design record: a page of the title block, the cam's figures, the checks and every input, then
    the figure of :func:`cam_figure`."""
    import textwrap

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.backends.backend_pdf import PdfPages

    buffer = io.BytesIO()
    with PdfPages(buffer, metadata={"CreationDate": None}) as pdf:
        fig = plt.figure(figsize=(8.27, 11.69))
        y = 0.955
        fig.text(0.07, y, f"Design record: {title.name}", fontsize=14, weight="bold")
        y -= 0.025
        for text in (f"{title.created} · service {title.version}", f"request SHA-256 {title.request_sha256}"):
            fig.text(0.07, y, text, fontsize=7.5, family="monospace")
            y -= 0.016
        for label, value in _record_lines(an, title):
            if not value:
                y -= 0.008
                fig.text(0.07, y, label, fontsize=10, weight="bold")
                y -= 0.018
                continue
            wrapped = textwrap.wrap(value, 70 if label else 100) or [""]
            fig.text(0.07, y, label, fontsize=8)
            for part in wrapped:
                fig.text(0.38 if label else 0.07, y, part, fontsize=8)
                y -= 0.0145
        y -= 0.008
        fig.text(0.07, y, "Inputs", fontsize=10, weight="bold")
        y -= 0.018
        rows = list(title.inputs)
        room = max(int((y - 0.04) / 0.0125), 0)
        if len(rows) > room:
            rows = rows[:max(room - 1, 0)] + [("…", f"{len(title.inputs) - room + 1} more in the request", "")]
        for path, value, unit in rows:
            fig.text(0.07, y, path, fontsize=7, family="monospace")
            fig.text(0.55, y, f"{value} {unit}".strip()[:60], fontsize=7, family="monospace")
            y -= 0.0125
        fig.text(0.5, 0.02, "page 1 of 2", fontsize=7, ha="center")
        pdf.savefig(fig)
        plt.close(fig)
        page = io.BytesIO(cam_figure(an, at, "png"))
        fig = plt.figure(figsize=(11.69, 8.27))
        ax = fig.add_axes((0.02, 0.04, 0.96, 0.92))
        ax.imshow(plt.imread(page))
        ax.axis("off")
        fig.text(0.5, 0.015, f"{title.name} · request SHA-256 {title.request_sha256[:16]}… · page 2 of 2",
                 fontsize=7, ha="center")
        pdf.savefig(fig)
        plt.close(fig)
    return buffer.getvalue()
