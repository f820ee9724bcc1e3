"""Exports for people and for other programs: curves as CSV tables (one row per crank angle, named columns with
units) and the mechanism with its counterweights as a DXF or SVG drawing at a chosen crank angle.

Numbers leave here with 12 significant digits, so 119.99999999999999° reads 120.
"""

from __future__ import annotations

import io
import math
from collections.abc import Mapping, Sequence
from typing import Any, cast

import numpy as np

from .analysis import Analysis
from .balancing.fourbar import BalanceResult
from .balancing.plots import balance_figure, moment_after, torque_after
from .balancing.slider_crank import SliderCrankBalance
from .balancing.slider_crank_plots import slider_crank_balance_figure
from .errors import InvalidInput
from .flywheel.plots import flywheel_figure
from .flywheel.problem import FlywheelResult
from .kinematics import SlottedLever
from .kinematics import motion as solve_motion
from .model import Counterweight, FloatArray, Linkage
from .plots import FigureFormat, analysis_figure, trace_points

Columns = dict[str, FloatArray]
# Drawings are in millimetres, the unit of machine drawings; $INSUNITS 4 tells CAD so.
_MM = 1000.0


def people_number(value: float) -> str:
    """A float as people read it: 12 significant digits, no trailing noise (120, not 119.99999999999999)."""
    if not math.isfinite(value):
        return ""
    text = f"{value:.12g}"
    return "0" if text == "-0" else text


def csv_text(columns: Mapping[str, FloatArray]) -> str:
    """Columns of equal length as CSV: a header of the names, then one row per sample."""
    names = list(columns)
    data = np.column_stack([np.asarray(columns[n], dtype=float) for n in names])
    lines = [",".join(names)]
    lines += [",".join(people_number(float(v)) for v in row) for row in data]
    return "\n".join(lines) + "\n"


def analysis_table(an: Analysis) -> Columns:
    """Every curve of an analysis, one row per crank angle; column names carry their units."""
    m, k, r = an.motion, an.kinetostatics, an.reduced
    cols: Columns = {
        "crank_angle_deg": np.degrees(m.phi),
        "driving_torque_Nm": k.driving_torque,
        "virtual_power_torque_Nm": an.virtual_power_torque,
        "shaking_force_x_N": k.shaking_force[:, 0],
        "shaking_force_y_N": k.shaking_force[:, 1],
        "shaking_moment_Nm": k.shaking_moment,
        "reduced_inertia_kgm2": r.inertia,
        "reduced_inertia_slope_kgm2_per_rad": r.inertia_slope,
        "reduced_load_torque_Nm": r.load_torque,
        "kinetic_energy_J": r.kinetic_energy,
    }
    tau = an.transmission_angle
    if tau is not None:
        cols["transmission_angle_deg"] = np.degrees(tau)
    crank = an.linkage.mechanism.topology.crank
    for link in an.linkage.mechanism.topology.links:
        if link != crank:   # the crank's angle is the first column
            cols[f"{link}_angle_deg"] = np.degrees(m.link_angle[link])
        cols[f"{link}_angular_velocity_rad_s"] = m.link_omega[link]
        cols[f"{link}_angular_acceleration_rad_s2"] = m.link_alpha[link]
    for name in m.point_pos:
        for quantity, values, unit in (("", m.point_pos, "m"), ("velocity_", m.point_vel, "m_s"),
                                       ("acceleration_", m.point_acc, "m_s2")):
            cols[f"{name}_{quantity}x_{unit}"] = values[name][:, 0]
            cols[f"{name}_{quantity}y_{unit}"] = values[name][:, 1]
    for joint, force in k.reactions.items():
        cols[f"{joint}_reaction_x_N"] = force[:, 0]
        cols[f"{joint}_reaction_y_N"] = force[:, 1]
    if an.friction is not None:
        fr = an.friction
        kinds = {j.name: j.kind for j in an.linkage.mechanism.topology.joints}
        cols["driving_torque_with_friction_Nm"] = fr.driving_torque
        cols["friction_loss_torque_Nm"] = fr.loss_torque
        for joint, value in fr.friction.items():
            cols[f"{joint}_friction_{'moment_Nm' if kinds[joint] == 'revolute' else 'force_N'}"] = value
            cols[f"{joint}_friction_power_loss_W"] = fr.power_loss[joint]
    return cols


def balance_table(result: BalanceResult) -> Columns:
    """Shaking force, shaking moment and driving torque before and after balancing, one row per crank angle."""
    before, after = result.analysis_before.kinetostatics, result.analysis_after.kinetostatics
    return {
        "crank_angle_deg": np.degrees(result.analysis_before.motion.phi),
        "shaking_force_x_before_N": before.shaking_force[:, 0],
        "shaking_force_y_before_N": before.shaking_force[:, 1],
        "shaking_force_x_after_N": after.shaking_force[:, 0],
        "shaking_force_y_after_N": after.shaking_force[:, 1],
        "shaking_moment_before_Nm": before.shaking_moment,
        "shaking_moment_after_Nm": moment_after(result),
        "driving_torque_before_Nm": before.driving_torque,
        "driving_torque_after_Nm": torque_after(result),
    }


def flywheel_table(result: FlywheelResult) -> Columns:
    """The cycle as sized (J_red, balanced reduced torque, excess work) and every method's simulated speed,
    one row per sample of the cycle.

    The speeds come from the dense simulated profiles (tens of thousands of points per cycle), read at the
    cycle's samples by linear interpolation.
    """
    cycle = result.cycle
    cols: Columns = {
        "crank_angle_deg": np.degrees(cycle.phi),
        "reduced_inertia_kgm2": cycle.inertia,
        "reduced_torque_Nm": cycle.torque,
        "excess_work_J": cycle.work_nodes()[:-1],
    }
    for m in result.methods:
        cols[f"omega_{m.method}_rad_s"] = np.interp(cycle.phi, m.speed.phi, m.speed.omega, period=cycle.period)
    return cols


def _rotate(angle: float, local: tuple[float, float] | FloatArray) -> FloatArray:
    c, s = math.cos(angle), math.sin(angle)
    x, y = float(local[0]), float(local[1])
    return np.array([c * x - s * y, s * x + c * y])


def _rect(at: FloatArray, angle: float, length: float, height: float) -> list[tuple[float, float]]:
    u, v = _rotate(angle, (length / 2, 0.0)), _rotate(angle, (0.0, height / 2))
    return [tuple(p) for p in (at - u - v, at + u - v, at + u + v, at - u + v)]


def mechanism_dxf_document(an: Analysis, phi: float, counterweights: Sequence[Counterweight] | None = None) -> Any:
    """The linkage at crank angle ``phi`` [rad] as an ezdxf document in millimetres.

    Layers: ``FRAME`` (pivots, guides), ``LINKS`` (centre lines between joints), ``JOINTS``, ``BLOCKS`` (sliders
    and the shaper's ram), ``CRANK_CIRCLE``, ``COUNTERWEIGHTS`` (arm, disc, mass label), ``CENTRES_OF_MASS``,
    ``TRACES`` (paths of the trace points over the analysed cycle) and ``TEXT``.
    """

    linkage: Linkage = an.linkage
    mech = linkage.mechanism
    topo = mech.topology
    single = solve_motion(mech, np.array([phi]), an.motion.omega_crank)
    pos = {k: v[0] * _MM for k, v in single.point_pos.items()}
    angle = {k: float(v[0]) for k, v in single.link_angle.items()}
    cloud = np.vstack(list(an.motion.point_pos.values())) * _MM
    size = float(np.ptp(cloud, axis=0).max())
    from ezdxf.document import Drawing
    from ezdxf.filemanagement import new

    doc: Drawing = new("R2010", setup=True)
    doc.header["$INSUNITS"] = 4
    colours = {"FRAME": 7, "LINKS": 5, "JOINTS": 7, "BLOCKS": 3, "CRANK_CIRCLE": 8, "COUNTERWEIGHTS": 1,
               "CENTRES_OF_MASS": 7, "TRACES": 6, "TEXT": 7}
    for name, colour in colours.items():
        doc.layers.add(name, color=colour)
    msp = doc.modelspace()
    joint_r, block_l, block_h = 0.012 * size, 0.09 * size, 0.05 * size
    riding = trace_points(an)

    crank_pin = pos[next(j.point for j in topo.joints if j.bodies[0] == topo.crank)]
    centre = pos[mech.origins[topo.crank]]
    msp.add_circle(tuple(centre), float(np.hypot(*(crank_pin - centre))),
                   dxfattribs={"layer": "CRANK_CIRCLE", "linetype": "CENTER"})
    for link in topo.links:
        points = sorted({j.point for j in topo.joints if link in j.bodies})
        origin = pos[mech.origins[link]]
        if len(points) == 1:
            msp.add_lwpolyline(_rect(origin, angle[link], block_l, block_h), close=True, dxfattribs={"layer": "BLOCKS"})
        elif isinstance(mech, SlottedLever) and link == "ram":
            travel = an.motion.point_pos["R"][:, 0] * _MM
            length = max(1.4 * float(np.ptp(travel)), 0.5 * size)
            msp.add_lwpolyline(_rect(pos["R"], 0.0, length, 1.6 * block_h), close=True,
                               dxfattribs={"layer": "BLOCKS"})
            slot_lo = min(float(pos["B"][1]), float(pos["R"][1])) - 1.5 * block_h
            msp.add_lwpolyline(_rect(np.array([pos["R"][0], (slot_lo + pos["R"][1]) / 2]), 0.0, 1.8 * block_h,
                                     float(pos["R"][1]) - slot_lo), close=True, dxfattribs={"layer": "BLOCKS"})
        else:
            far = max((pos[p] for p in points), key=lambda p: float(np.hypot(*(p - origin))))
            plate = [origin + _rotate(angle[link], local) * _MM for on, local in riding.values() if on == link]
            msp.add_lwpolyline([tuple(q) for q in (origin, *plate, far)], close=bool(plate),
                               dxfattribs={"layer": "LINKS"})
        msp.add_text(link, height=0.02 * size, dxfattribs={"layer": "TEXT"}).set_placement(
            tuple(origin + np.array([0.02 * size, 0.02 * size])))
    for joint in topo.joints:
        p = pos[joint.point]
        if joint.kind == "revolute":
            msp.add_circle(tuple(p), joint_r, dxfattribs={"layer": "JOINTS"})
            if joint.bodies[0] is None:
                s = 2.5 * joint_r
                msp.add_lwpolyline([(p[0], p[1]), (p[0] - s, p[1] - 1.6 * s), (p[0] + s, p[1] - 1.6 * s)], close=True,
                                   dxfattribs={"layer": "FRAME"})
        elif joint.bodies[0] is None:
            axis = np.array([math.cos(joint.axis_angle), math.sin(joint.axis_angle)])
            travel = an.motion.point_pos[joint.point] @ axis * _MM
            base = p - (p @ axis) * axis
            gap = (1.6 * block_h if isinstance(mech, SlottedLever) else block_h) / 2 + 0.004 * size
            extra = 0.75 * size if isinstance(mech, SlottedLever) else block_l
            normal = np.array([-axis[1], axis[0]])
            for side in (1.0, -1.0):
                a = base + (float(travel.min()) - extra) * axis + side * gap * normal
                b = base + (float(travel.max()) + extra) * axis + side * gap * normal
                msp.add_line(tuple(a), tuple(b), dxfattribs={"layer": "FRAME"})
    for name, path in an.motion.point_pos.items():
        if name in {j.point for j in topo.joints} or name.startswith("S_"):
            continue
        msp.add_lwpolyline([tuple(q) for q in path * _MM], close=True, dxfattribs={"layer": "TRACES"})
        if name in riding:
            link, local = riding[name]
            at = pos[mech.origins[link]] + _rotate(angle[link], local) * _MM
            msp.add_circle(tuple(at), 0.6 * joint_r, dxfattribs={"layer": "TRACES"})
            msp.add_text(name, height=0.02 * size, dxfattribs={"layer": "TEXT"}).set_placement(
                tuple(at + np.array([0.015 * size, 0.015 * size])))
    for link in topo.links:
        props = linkage.links.get(link)
        if props is not None and props.mass > 0:
            at = pos[mech.origins[link]] + _rotate(angle[link], props.com) * _MM
            s = joint_r
            msp.add_line(tuple(at - s), tuple(at + s), dxfattribs={"layer": "CENTRES_OF_MASS"})
            msp.add_line((at[0] - s, at[1] + s), (at[0] + s, at[1] - s), dxfattribs={"layer": "CENTRES_OF_MASS"})
    cws = list(linkage.counterweights if counterweights is None else counterweights)
    heaviest = max((c.mass for c in cws), default=0.0)
    for cw in cws:
        if cw.mass <= 0:
            continue
        joint = pos[mech.origins[cw.link]]
        at = joint + _rotate(angle[cw.link], cw.position) * _MM
        radius = math.hypot(*cw.position)
        bearing = math.degrees(math.atan2(cw.position[1], cw.position[0]))
        msp.add_line(tuple(joint), tuple(at), dxfattribs={"layer": "COUNTERWEIGHTS"})
        msp.add_circle(tuple(at), 0.06 * size * math.sqrt(cw.mass / heaviest), dxfattribs={"layer": "COUNTERWEIGHTS"})
        label = f"{cw.link}: {people_number(round(cw.mass, 4))} kg at r {people_number(round(radius * _MM, 2))} mm, " \
                f"{people_number(round(bearing, 2))} deg"
        msp.add_text(label, height=0.018 * size, dxfattribs={"layer": "TEXT"}).set_placement(
            tuple(at + np.array([0.07 * size, -0.02 * size])))
    msp.add_text(f"crank angle {people_number(round(math.degrees(phi), 6))} deg, lengths in mm", height=0.025 * size,
                 dxfattribs={"layer": "TEXT"}).set_placement((float(cloud[:, 0].min()), float(cloud[:, 1].min()) - 0.12 * size))
    return doc


def mechanism_dxf(an: Analysis, phi: float, counterweights: Sequence[Counterweight] | None = None) -> bytes:
    """The drawing of :func:`mechanism_dxf_document` as DXF bytes (text, UTF-8)."""
    stream = io.StringIO()
    mechanism_dxf_document(an, phi, counterweights).write(stream)
    return stream.getvalue().encode("utf-8")


def mechanism_svg(an: Analysis, phi: float, counterweights: Sequence[Counterweight] | None = None) -> bytes:
    """The same drawing as the DXF, rendered to SVG by ezdxf at 1:1 in millimetres on a white page."""
    from ezdxf.addons.drawing import config, layout, svg
    from ezdxf.addons.drawing.frontend import Frontend
    from ezdxf.addons.drawing.properties import RenderContext

    doc = mechanism_dxf_document(an, phi, counterweights)
    backend = svg.SVGBackend()
    cfg = config.Configuration(background_policy=config.BackgroundPolicy.WHITE,
                               color_policy=config.ColorPolicy.BLACK)
    Frontend(RenderContext(doc), backend, config=cfg).draw_layout(doc.modelspace())
    page = layout.Page(0, 0, layout.Units.mm, margins=layout.Margins.all(10))
    return str(backend.get_string(page)).encode("utf-8")


def _figure_format(fmt: str, offered: Sequence[str]) -> FigureFormat:
    if fmt not in offered:
        raise InvalidInput(f"format {fmt!r} is not offered here; choose one of {list(offered)}", field="format")
    return cast(FigureFormat, fmt)


def analysis_export(an: Analysis, phi: float, fmt: str) -> bytes:
    """An analysis as ``png``/``svg``/``pdf`` (the figure, mechanism at ``phi`` [rad]), ``csv`` (every curve) or
    ``dxf`` (the mechanism drawing at ``phi``)."""
    if fmt == "csv":
        return csv_text(analysis_table(an)).encode("utf-8")
    if fmt == "dxf":
        return mechanism_dxf(an, phi)
    return analysis_figure(an, phi, _figure_format(fmt, ("png", "svg", "pdf", "csv", "dxf")))


def balance_export(result: BalanceResult, fmt: str, sweep: Sequence[BalanceResult] = ()) -> bytes:
    """A balance as ``png``/``svg``/``pdf`` (the before/after figure, with the trade-off curve of ``sweep``),
    ``csv`` (before/after curves) or ``dxf`` (the balanced mechanism with its counterweights at the first angle)."""
    if fmt == "csv":
        return csv_text(balance_table(result)).encode("utf-8")
    after = result.analysis_after
    if fmt == "dxf":
        return mechanism_dxf(after, float(after.motion.phi[0]))
    return balance_figure(result, _figure_format(fmt, ("png", "svg", "pdf", "csv", "dxf")), sweep=sweep)


def flywheel_export(result: FlywheelResult, fmt: str) -> bytes:
    """A flywheel sizing as ``png``/``svg``/``pdf`` (energy-mass or excess-work diagram and w(phi)) or ``csv``."""
    if fmt == "csv":
        return csv_text(flywheel_table(result)).encode("utf-8")
    return flywheel_figure(result, _figure_format(fmt, ("png", "svg", "pdf", "csv")))


def slider_crank_balance_export(result: SliderCrankBalance, fmt: str) -> bytes:
    """A slider-crank balance as ``png``/``svg``/``pdf``: force and moment before and after, the shafts drawn."""
    return slider_crank_balance_figure(result, _figure_format(fmt, ("png", "svg", "pdf")))
