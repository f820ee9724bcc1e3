"""The linkage in a request as the engine takes it (mechanism, links, loads, counterweights, friction), and the
pieces every answer shares: warnings, summaries, degrees for people, the finite-number check."""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Any

import numpy as np

import synth

from mechsynth_client.schemas.analysis import AnalysisIn
from mechsynth_client.schemas.common import (
    CounterweightIn,
    CrankTableLoadIn,
    FourBarIn,
    LinkIn,
    LinkageFields,
    LinkageJointIn,
    LoadIn,
    MechanismIn,
    PairFrictionIn,
    PlanarLinkageIn,
    PositionTableLoadIn,
    SliderCrankIn,
    SlottedLeverIn,
    SummaryOut,
    ValidityCheckOut,
    WarningOut,
    WindowLoadIn,
    _LoadBase,
)


def props_from(link: LinkIn) -> synth.MassProps:
    """Engine mass properties."""
    return synth.MassProps(link.mass_kg, (link.com_m[0], link.com_m[1]), link.inertia_kgm2)


def four_bar_from(m: FourBarIn) -> synth.FourBar:
    """Engine mechanism."""
    return synth.FourBar(
        m.ground_length_m, m.crank_length_m, m.coupler_length_m, m.rocker_length_m, m.branch
    )


def slider_crank_from(m: SliderCrankIn) -> synth.SliderCrank:
    """Engine mechanism."""
    return synth.SliderCrank(m.crank_length_m, m.rod_length_m, m.offset_m, m.branch)


def slotted_lever_from(m: SlottedLeverIn) -> synth.SlottedLever:
    """Engine mechanism."""
    return synth.SlottedLever(m.crank_length_m, m.ground_length_m, m.rocker_length_m, m.ram_height_m)


def linkage_joint_from(joint: LinkageJointIn) -> synth.JointSpec:
    """Engine joint; degrees become radians."""
    return synth.JointSpec(joint.name, joint.kind, (joint.links[0], joint.links[1]), joint.point, joint.axis_link,
                           math.radians(joint.axis_deg), joint.through, math.radians(joint.slider_axis_deg))


def planar_linkage_from(m: PlanarLinkageIn) -> synth.PlanarLinkage:
    """Engine mechanism."""
    return synth.PlanarLinkage(
        frame_points=tuple((k, (v[0], v[1])) for k, v in m.frame_points_m.items()),
        links=tuple(synth.LinkSpec(k.name, tuple(k.joints), k.length_m,
                                   tuple((p, (xy[0], xy[1])) for p, xy in k.points_m.items()))
                    for k in m.links),
        joints=tuple(linkage_joint_from(j) for j in m.joints),
        crank_link=m.crank,
        output=m.output,
        branches=tuple(m.branches.items()),
        assembly=tuple((k, (v[0], v[1])) for k, v in m.assembly_m.items()),
    )


def mechanism_from(m: MechanismIn) -> synth.FourBar | synth.SliderCrank | synth.SlottedLever | synth.PlanarLinkage:
    """Engine mechanism of any family."""
    if isinstance(m, FourBarIn):
        return four_bar_from(m)
    if isinstance(m, SliderCrankIn):
        return slider_crank_from(m)
    if isinstance(m, SlottedLeverIn):
        return slotted_lever_from(m)
    return planar_linkage_from(m)


def link_props(m: PlanarLinkageIn) -> dict[str, synth.MassProps]:
    """Engine mass properties per link."""
    return {k.name: props_from(k) for k in m.links}


def counterweight_from(cw: CounterweightIn) -> synth.Counterweight:
    """Engine counterweight."""
    return synth.Counterweight(cw.link, cw.mass_kg, (cw.position_m[0], cw.position_m[1]), cw.inertia_kgm2)


def counterweight_in(cw: synth.Counterweight) -> CounterweightIn:
    """Schema from an engine counterweight."""
    return CounterweightIn(link=cw.link, mass_kg=cw.mass, position_m=list(cw.position), inertia_kgm2=cw.inertia)


def _magnitude(load: _LoadBase, output_motion: str, table: bool) -> float | list[float]:
    turning = output_motion == "rotation" and load.direction != "frame"
    name, value = ("torque_Nm", load.torque_Nm) if turning else ("force_N", load.force_N)
    other = load.force_N if name == "torque_Nm" else load.torque_Nm
    if value is None or other is not None:
        what = ("a force of fixed direction in the frame" if load.direction == "frame" else
                f"this mechanism's output {'turns' if name == 'torque_Nm' else 'slides'}")
        raise synth.InvalidInput(f"{what}: give its load as {name}", field=f"loads.{name}")
    if table != isinstance(value, list):
        raise synth.InvalidInput(
            f"{name} must be {'a list matching the table' if table else 'a single number'}", field=f"loads.{name}"
        )
    return value


def _direction(load: _LoadBase) -> dict[str, Any]:
    return {"direction": load.direction, "angle": math.radians(load.frame_angle_deg)}


def window_load_from(load: WindowLoadIn, output_motion: str) -> synth.ProcessLoad:
    """Engine load."""
    mag = _magnitude(load, output_motion, table=False)
    assert isinstance(mag, float)
    return synth.ProcessLoad(
        "window", mag, math.radians(load.start_deg), math.radians(load.end_deg),
        stroke=load.stroke, point=(load.point_m[0], load.point_m[1]), **_direction(load),
    )


def crank_table_load_from(load: CrankTableLoadIn, output_motion: str) -> synth.ProcessLoad:
    """Engine load."""
    mag = _magnitude(load, output_motion, table=True)
    assert isinstance(mag, list)
    return synth.ProcessLoad(
        "crank_table", table_x=tuple(np.radians(load.crank_angle_deg)), values=tuple(mag),
        stroke=load.stroke, point=(load.point_m[0], load.point_m[1]), **_direction(load),
    )


def position_table_load_from(load: PositionTableLoadIn, output_motion: str) -> synth.ProcessLoad:
    """Engine load."""
    mag = _magnitude(load, output_motion, table=True)
    assert isinstance(mag, list)
    if output_motion == "rotation":
        if load.position_deg is None:
            raise synth.InvalidInput("a turning output's table needs position_deg", field="loads.position_deg")
        x = tuple(np.radians(load.position_deg))
    else:
        if load.position_m is None:
            raise synth.InvalidInput("a sliding output's table needs position_m", field="loads.position_m")
        x = tuple(load.position_m)
    return synth.ProcessLoad(
        "position_table", table_x=x, values=tuple(mag), stroke=load.stroke, point=(load.point_m[0], load.point_m[1]),
        **_direction(load),
    )


def load_from(load: LoadIn, output_motion: str) -> synth.ProcessLoad:
    """Engine process load of any kind, for an output that turns (``rotation``) or slides (``translation``)."""
    if isinstance(load, WindowLoadIn):
        return window_load_from(load, output_motion)
    if isinstance(load, CrankTableLoadIn):
        return crank_table_load_from(load, output_motion)
    return position_table_load_from(load, output_motion)


def pair_friction_from(pair: PairFrictionIn, joint: str) -> synth.PairFriction:
    """Engine pair friction for ``joint``."""
    return synth.PairFriction(joint, pair.coefficient, pair.journal_radius_m, pair.viscous,
                              pair.static_coefficient, pair.rolling_resistance_m, pair.roller_radius_m)


def pair_frictions(friction: dict[str, PairFrictionIn] | None) -> tuple[synth.PairFriction, ...]:
    """Engine pair frictions of a request's friction block."""
    return tuple(pair_friction_from(p, name) for name, p in (friction or {}).items())


def crank_angles(request: LinkageFields) -> np.ndarray | None:
    """Explicit crank angles [rad], or None for the uniform grid."""
    return None if request.crank_angle_deg is None else np.radians(request.crank_angle_deg)


def linkage_from(request: LinkageFields) -> synth.Linkage:
    """Engine linkage; degrees become radians here and nowhere else. An analysis request's (and those built on it)
    carries its coupler inertia and its balancing answer's counterweights too."""
    if request.mechanism is None:
        raise synth.InvalidInput("give the mechanism", field="mechanism")
    mech = mechanism_from(request.mechanism)
    output_motion = mech.topology.output_motion
    mechanism = request.mechanism
    if isinstance(mechanism, PlanarLinkageIn):
        links = link_props(mechanism)
    else:
        links = {name: props_from(link) for name, link in mechanism.links}
    gravity = None
    if request.gravity is not None:
        gravity = synth.Gravity(request.gravity.g_m_s2, math.radians(request.gravity.direction_deg))
    linkage = synth.Linkage(
        mechanism=mech,
        links=links,
        counterweights=tuple(counterweight_from(cw) for cw in request.counterweights),
        gravity=gravity,
        loads=tuple(load_from(load, output_motion) for load in request.loads),
        torques=tuple(synth.LinkTorque(t.link, t.torque_Nm) for t in request.torques),
    )
    return _with_balancing(request, linkage) if isinstance(request, AnalysisIn) else linkage


def _with_balancing(body: AnalysisIn, linkage: synth.Linkage) -> synth.Linkage:
    """An analysis request's linkage with its coupler inertia and its balancing answer's counterweights applied."""
    coupler = body.coupler_inertia_kgm2
    extra: list[synth.Counterweight] = []
    if body.balancing is not None:
        extra = [counterweight_from(c) for c in body.balancing.counterweights]
        if body.balancing.coupler_inertia_kgm2 is not None:
            if coupler is not None:
                raise synth.InvalidInput("give the coupler inertia once: here or in the balancing answer",
                                         field="coupler_inertia_kgm2")
            coupler = body.balancing.coupler_inertia_kgm2
    if coupler is not None:
        if "coupler" not in linkage.mechanism.topology.links:
            raise synth.InvalidInput("this mechanism has no coupler", field="coupler_inertia_kgm2")
        props = linkage.links.get("coupler", synth.MassProps())
        links = {**linkage.links, "coupler": synth.MassProps(props.mass, props.com, coupler)}
        linkage = synth.Linkage(linkage.mechanism, links, linkage.counterweights, linkage.gravity, linkage.loads,
                                linkage.torques)
    return linkage.with_counterweights(extra)


def warning_out(w: synth.DesignWarning) -> WarningOut:
    """Schema from an engine warning; radians become degrees, rounded for people."""
    value, unit = w.value, w.unit
    if unit == "rad" and value is not None:
        value, unit = round(math.degrees(value), 6), "deg"
    ranges = [[round(math.degrees(a) % 360, 6), round(math.degrees(b) % 360, 6)] for a, b in w.ranges]
    return WarningOut(code=w.code, field=w.field, value=value, unit=unit, message=w.message,
                      crank_angle_ranges_deg=ranges or None, stage=w.stage)


def warnings_out(warnings: Iterable[synth.DesignWarning]) -> list[WarningOut]:
    """Schemas of engine warnings."""
    return [warning_out(w) for w in warnings]


def validity_check_out(c: synth.ValidityCheck) -> ValidityCheckOut:
    """Schema from an engine check; radians become degrees."""
    value, limit, unit = c.value, c.limit, c.unit
    if unit == "rad":
        value, limit, unit = math.degrees(value), math.degrees(limit), "deg"
    return ValidityCheckOut(name=c.name, value=value, limit=limit, passed=c.passed, detail=c.detail, unit=unit)


def validity_out(checks: Iterable[synth.ValidityCheck]) -> list[ValidityCheckOut]:
    """Schemas of engine validity checks."""
    return [validity_check_out(c) for c in checks]


def degree_list(radians: np.ndarray) -> list[float]:
    """Radians as degrees for people: rounded to 1e-9°, so a sample at 2π/3 reads 120, not 119.99999999999999."""
    # Adding 0.0 turns -0.0 into 0.0.
    degrees: list[float] = np.asarray(np.round(np.degrees(radians), 9) + 0.0).tolist()
    return degrees


def degree_array(radians: np.ndarray) -> np.ndarray:
    """Radians as degrees for people, as an array for the JSON writer: rounded like :func:`degree_list`."""
    return np.asarray(np.round(np.degrees(radians), 9) + 0.0)


def ensure_finite(*arrays: np.ndarray) -> None:
    """Refuse to answer with NaN or infinity: that would be an engine bug, not a property of the input."""
    for a in arrays:
        if not np.all(np.isfinite(a)):
            raise RuntimeError("non-finite value in an engine result")


def summary_out(s: synth.Summary) -> SummaryOut:
    """Schema from the engine summary."""
    return SummaryOut(
        rms_shaking_force_N=s.rms_shaking_force,
        max_shaking_force_N=s.max_shaking_force,
        rms_shaking_moment_Nm=s.rms_shaking_moment,
        max_shaking_moment_Nm=s.max_shaking_moment,
        rms_driving_torque_Nm=s.rms_driving_torque,
        max_driving_torque_Nm=s.max_driving_torque,
        max_bearing_force_N=s.max_bearing_force,
    )
