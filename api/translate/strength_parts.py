"""Translation between the wire models of the machine's parts (joints, crank shaft, keys) and the engine."""

from __future__ import annotations

import math

import numpy as np

import synth
from synth.strength import bearings, joints, keys, parts, pins, shafts
from synth.strength.checks import PartCheck
from synth.strength.crank_shaft import CrankShaftLayout
from synth.strength.materials import Material

from mechsynth_client.schemas.common import WarningOut
from mechsynth_client.schemas.strength_parts import (
    BushingOut,
    CrankShaftIn,
    CrankShaftOut,
    JointBearingIn,
    JointPartsOut,
    KeyOut,
    PartCheckOut,
    PartsIn,
    PartsOut,
    PinIn,
    PinOut,
    RollingBearingOut,
    ShaftSectionOut,
)

from .strength import material_from

MPA, MM = 1e6, 1e-3


def _pin(p: PinIn) -> pins.PinJoint:
    return pins.PinJoint(p.shear_planes, p.fit,
                         None if p.rod_thickness_mm is None else p.rod_thickness_mm * MM,
                         None if p.fork_thickness_mm is None else p.fork_thickness_mm * MM,
                         p.rod_ratio, p.fork_ratio, p.application_factor)


def _joint_spec(pin: PinIn, bearing: JointBearingIn, material: Material, member: float | None) -> joints.JointPartSpec:
    bushing: str | bearings.BushingMaterial = bearing.bushing_material
    if bearing.bushing_limits is not None:
        b = bearing.bushing_limits
        bushing = bearings.BushingMaterial(b.name, b.pressure_limit_MPa * MPA, b.speed_limit_m_s,
                                           b.pv_limit_MPa_m_s * MPA)
    return joints.JointPartSpec(
        material, _pin(pin), member, None, pin.fixed_in, bearing.kind, bushing,
        None if bearing.bushing_length_mm is None else bearing.bushing_length_mm * MM, bearing.life_hours,
        bearing.static_safety, None if bearing.types is None else tuple(bearing.types))


def _crank_shaft(c: CrankShaftIn, prefix: str) -> parts.CrankShaftSpec:
    layout = CrankShaftLayout(
        c.span_mm * MM, c.crank_position_mm * MM, c.drive_position_mm * MM, c.drive,
        (c.pitch_radius_mm or 0.0) * MM, math.radians(c.mesh_angle_deg), math.radians(c.pressure_angle_deg),
        math.radians(c.helix_angle_deg), None if c.flywheel_position_mm is None else c.flywheel_position_mm * MM,
        c.flywheel_mass_kg)
    spec = shafts.ShaftSpec(c.span_mm * MM, 1.0, c.design_factor, c.surface, float(c.reliability), c.bearing_notch)
    hubs = tuple(parts.HubKeySpec(k.hub, k.hub_length_mm * MM, k.allowed_pressure_MPa * MPA, k.form, k.count,
                                  k.application_factor) for k in c.keys)
    if len({k.hub for k in hubs}) != len(hubs):
        raise synth.InvalidInput("a hub is keyed once", field=f"{prefix}crank_shaft.keys")
    return parts.CrankShaftSpec(layout, material_from(c.material, f"{prefix}crank_shaft.material"), spec,
                                c.bearing_life_hours, hubs)


def parts_spec(block: PartsIn, prefix: str = "parts.") -> parts.PartsSpec:
    """The engine's spec of the parts block; ``prefix`` names its fields in errors."""
    member = None if block.member_strength_MPa is None else block.member_strength_MPa * MPA
    material = material_from(block.pin_material, f"{prefix}pin_material")
    default = _joint_spec(block.pin, block.bearing, material, member)
    own: dict[str, joints.JointPartSpec] = {}
    for i, j in enumerate(block.joints or []):
        if j.joint in own:
            raise synth.InvalidInput(f"joint {j.joint!r} is listed twice", field=f"{prefix}joints[{i}].joint")
        pin_material = material if j.pin_material is None else material_from(
            j.pin_material, f"{prefix}joints[{i}].pin_material")
        own[j.joint] = _joint_spec(j.pin or block.pin, j.bearing or block.bearing, pin_material, member)
    catalogue = None
    if block.bearing_catalogue is not None:
        catalogue = tuple(bearings.rolling_bearing_from_row(r.model_dump()) for r in block.bearing_catalogue)
    crank = None if block.crank_shaft is None else _crank_shaft(block.crank_shaft, prefix)
    return parts.PartsSpec(default, own, catalogue, crank)


def _finite(value: float) -> float | None:
    return value if math.isfinite(value) else None


def _rolling_out(r: bearings.RollingBearingResult) -> RollingBearingOut:
    b = r.bearing
    return RollingBearingOut(
        designation=b.designation, type=b.type, bore_mm=b.bore / MM, outer_mm=b.outer / MM, width_mm=b.width / MM,
        dynamic_rating_kN=b.dynamic_rating / 1e3, static_rating_kN=b.static_rating / 1e3, mean_load_N=r.mean_load,
        peak_load_N=r.peak_load, revolutions_per_cycle=r.rotation.revolutions, oscillating=r.rotation.oscillating,
        swing_deg=math.degrees(r.rotation.swing), life_million_revolutions=_finite(r.life),
        life_hours=_finite(r.life_hours), static_safety=_finite(r.static_safety))


def _check_out(c: PartCheck) -> PartCheckOut:
    scale = {"Pa": (MPA, "MPa"), "Pa·m/s": (MPA, "MPa·m/s"), "m": (MM, "mm")}.get(c.unit, (1.0, c.unit))
    value = _finite(c.value)
    return PartCheckOut(part=c.part, name=c.name, value=None if value is None else value / scale[0],
                        limit=c.limit / scale[0], unit=scale[1], at_least=c.at_least, passed=c.passed,
                        meaning=c.meaning)


def _joint_out(j: joints.JointParts) -> JointPartsOut:
    p = j.pin
    pin = PinOut(diameter_mm=p.diameter / MM, diameter_required_mm=p.diameter_required / MM, governing=p.governing,
                 force_max_N=p.force_max, load_kind=p.load_kind, max_shear_MPa=float(p.shear_stress.max()) / MPA,
                 max_bending_MPa=float(p.bending_stress.max()) / MPA,
                 max_rod_pressure_MPa=float(p.rod_pressure.max()) / MPA,
                 max_fork_pressure_MPa=float(p.fork_pressure.max()) / MPA)
    bushing = None
    if j.bushing is not None:
        b = j.bushing
        bushing = BushingOut(material=b.material.name, bore_mm=b.diameter / MM, length_mm=b.length / MM,
                             max_pressure_MPa=float(b.pressure.max()) / MPA,
                             max_sliding_speed_m_s=float(b.sliding_speed.max()), mean_pv_MPa_m_s=b.pv_mean / MPA)
    return JointPartsOut(joint=j.joint, links=[x or "frame" for x in j.links], pin=pin, bushing=bushing,
                         rolling=None if j.rolling is None else _rolling_out(j.rolling),
                         max_relative_speed_rad_s=float(abs(j.relative_speed).max()), passed=j.passed)


def _key_out(k: keys.KeyResult) -> KeyOut:
    s = k.section
    return KeyOut(hub=k.hub, designation=f"DIN 6885 {k.form} {s.b / MM:g}x{s.h / MM:g}x{k.length / MM:g}",
                  b_mm=s.b / MM, h_mm=s.h / MM, t1_mm=s.t1 / MM, t2_mm=s.t2 / MM, length_mm=k.length / MM,
                  max_pressure_MPa=float(k.pressure.max()) / MPA, max_shear_MPa=float(k.shear.max()) / MPA)


def _shaft_out(c: parts.CrankShaftParts) -> CrankShaftOut:
    s = c.shaft
    sections = [ShaftSectionOut(name=x.name, position_mm=x.position / MM, kf=x.kf, kfs=x.kfs,
                                max_moment_Nm=float(np.hypot(x.moment[:, 0], x.moment[:, 1]).max()),
                                max_torque_Nm=float(abs(x.torque).max()), diameter_required_mm=x.diameter_required / MM,
                                fatigue_safety=_finite(x.fatigue_safety), yield_safety=_finite(x.yield_safety))
                for x in s.sections]
    return CrankShaftOut(diameter_mm=s.diameter / MM, diameter_required_mm=s.diameter_required / MM,
                         endurance_limit_MPa=s.endurance_limit / MPA, fatigue_safety=_finite(s.fatigue_safety),
                         yield_safety=_finite(s.yield_safety),
                         method="DE-Goodman with Marin factors (Shigley, Mechanical Engineering Design, eq. 7-8)",
                         sections=sections, bearings=[_rolling_out(b) for b in c.bearings],
                         keys=[_key_out(k) for k in c.keys.values()])


def parts_out(result: parts.Parts) -> PartsOut:
    """Wire form of the sized parts."""
    return PartsOut(
        joints=[_joint_out(j) for j in result.joints.values()],
        crank_shaft=None if result.crank_shaft is None else _shaft_out(result.crank_shaft),
        passed=result.passed, checks=[_check_out(c) for c in result.checks],
        warnings=[_warning_out(w) for w in result.warnings])


def _warning_out(w: synth.DesignWarning) -> WarningOut:
    if w.unit == "rad" and w.value is not None:
        return WarningOut(code=w.code, field=w.field, value=round(math.degrees(w.value), 6), unit="deg",
                          message=w.message)
    return WarningOut(code=w.code, field=w.field, value=w.value, unit=w.unit, message=w.message)
