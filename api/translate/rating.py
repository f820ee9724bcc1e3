"""Gear rating (ISO 6336) and sizing: the pair, duty and load spectrum in; the rating and sized stages out."""

from __future__ import annotations

import math

import numpy as np

import synth

from api.translate.linkage import validity_out, warnings_out
from api.translate.strength_parts import MM, MPA
from mechsynth_client.schemas.rating import (
    FactorOut,
    GearMaterialOut,
    PairGeometryOut,
    RatingChecksOut,
    RatingIn,
    RatingOut,
    SizedStageOut,
    SpectrumOut,
    StrengthIn,
    UM,
    _DutyFields,
    mpa,
)


def _mm(v: tuple[float, float]) -> list[float]:
    return [v[0] / MM, v[1] / MM]


def _finite_or_none(v: tuple[float, float]) -> list[float | None]:
    return [x if math.isfinite(x) else None for x in v]


def duty_from(request: _DutyFields) -> synth.Duty:
    """Engine service conditions."""
    return synth.Duty(request.application_factor, request.life_h, request.min_safety_contact, request.min_safety_root,
                      request.pitting_permitted)


def rating_from(body: RatingIn) -> synth.GearPairSpec:
    """Engine pair (mm, µm, deg and mm²/s become SI here)."""
    return synth.GearPairSpec(
        body.pinion_teeth, body.gear_teeth, body.normal_module_mm * MM, body.face_width_mm * MM,
        math.radians(body.helix_angle_deg), (body.pinion_profile_shift, body.gear_profile_shift),
        None if body.centre_distance_mm is None else body.centre_distance_mm * MM, body.accuracy_grade,
        (body.pinion_material, body.gear_material), body.oil_viscosity_40C_mm2_s * 1e-6,
        body.flank_roughness_Ra_um * UM, body.root_roughness_Rz_um * UM,
        None if body.tip_relief_um is None else body.tip_relief_um * UM, body.face_load_factor,
        synth.BasicRack(1.0, body.rack_dedendum, body.rack_root_radius,
                        math.radians(body.normal_pressure_angle_deg)),
        body.max_face_width_ratio,
        (None if body.pinion_rim_thickness_mm is None else body.pinion_rim_thickness_mm * MM,
         None if body.gear_rim_thickness_mm is None else body.gear_rim_thickness_mm * MM))


def spectrum_from(body: RatingIn) -> np.ndarray:
    """The spectrum's torques [N·m]."""
    assert body.load_spectrum is not None
    return np.asarray(body.load_spectrum.torque_Nm, dtype=float)


def pair_geometry_out(g: synth.PairGeometry) -> PairGeometryOut:
    """Schema from engine geometry (m and rad become mm and deg here)."""
    return PairGeometryOut(transverse_pressure_angle_deg=math.degrees(g.alpha_t),
                           working_pressure_angle_deg=math.degrees(g.alpha_wt),
                           base_helix_angle_deg=math.degrees(g.beta_b), centre_distance_mm=g.a / MM,
                           centre_distance_from_shifts_mm=g.a_shift / MM, ratio=g.ratio,
                           reference_diameters_mm=_mm(g.d), base_diameters_mm=_mm(g.db), tip_diameters_mm=_mm(g.da),
                           root_diameters_mm=_mm(g.df), working_diameters_mm=_mm(g.dw),
                           transverse_contact_ratio=g.eps_alpha, overlap_ratio=g.eps_beta,
                           total_contact_ratio=g.eps_gamma, virtual_teeth=list(g.zn))


def rating_out(r: synth.RatingResult | synth.SpectrumRating) -> RatingOut:
    """Schema from an engine rating or spectrum rating."""
    spectrum = None
    if isinstance(r, synth.SpectrumRating):
        s = r
        spectrum = SpectrumOut(
            samples=s.samples, rms_torque_Nm=s.rms_torque, mean_torque_Nm=s.mean_torque,
            damage_contact=list(s.damage_contact), damage_root=list(s.damage_root),
            life_contact_h=_finite_or_none(s.life_contact), life_root_h=_finite_or_none(s.life_root),
            safety_contact=list(s.safety_contact), safety_root=list(s.safety_root),
            equivalent_torque_contact_Nm=list(s.equivalent_torque_contact),
            equivalent_torque_root_Nm=list(s.equivalent_torque_root))
        rating = s.peak
        sh, sf = s.safety_contact, s.safety_root
    else:
        rating, sh, sf = r, r.safety_contact, r.safety_root
    d = rating.duty
    return RatingOut(
        geometry=pair_geometry_out(rating.geometry), pinion_torque_Nm=rating.pinion_torque,
        tangential_force_N=rating.tangential_force, pitch_line_velocity_m_s=rating.pitch_line_velocity,
        load_cycles=list(rating.load_cycles), nominal_contact_stress_MPa=rating.nominal_contact_stress / MPA,
        contact_stress_MPa=mpa(rating.contact_stress), contact_limit_MPa=mpa(rating.contact_limit),
        permissible_contact_stress_MPa=mpa(rating.permissible_contact),
        nominal_root_stress_MPa=mpa(rating.nominal_root_stress), root_stress_MPa=mpa(rating.root_stress),
        root_limit_MPa=mpa(rating.root_limit), permissible_root_stress_MPa=mpa(rating.permissible_root),
        safety_contact=list(rating.safety_contact), safety_root=list(rating.safety_root),
        meets_minimum=min(sh) >= d.min_safety_contact and min(sf) >= d.min_safety_root,
        factors=[FactorOut(symbol=f.symbol, name=f.name, pinion=f.pinion, gear=f.gear, unit=f.unit)
                 for f in rating.factors],
        spectrum=spectrum,
        checks=RatingChecksOut(hertz_contact_stress_MPa=rating.checks.hertz_contact_stress / MPA,
                               power_balance=rating.checks.power_balance),
        warnings=warnings_out(rating.warnings), validity=validity_out(rating.validity))


def gear_material_out(m: synth.GearMaterial) -> GearMaterialOut:
    """Schema from an engine grade."""
    return GearMaterialOut(name=m.name, group=m.group, description=m.description, sigma_Hlim_MPa=m.sigma_Hlim / MPA,
                           sigma_Flim_MPa=m.sigma_Flim / MPA, hardness_HB=m.hardness_HB,
                           elastic_modulus_MPa=m.elastic_modulus / MPA, poisson=m.poisson, density_kg_m3=m.density)


def strength_from(body: StrengthIn) -> synth.SizingRules:
    """Engine sizing rules."""
    return synth.SizingRules(
        (body.pinion_material, body.gear_material),
        None if body.helix_angle_deg is None else math.radians(body.helix_angle_deg), body.pinion_teeth,
        body.accuracy_grade, body.oil_viscosity_40C_mm2_s * 1e-6, duty=duty_from(body), series=body.module_series,
        min_face_width_ratio=body.min_face_width_ratio, max_face_width_ratio=body.max_face_width_ratio,
        objective=body.objective)


def sized_stage_out(s: synth.SizedStage) -> SizedStageOut:
    """Schema from an engine sized stage (m become mm here)."""
    return SizedStageOut(stage=s.stage, module_mm=round(s.module / MM, 9), pinion_teeth=s.pinion_teeth,
                         gear_teeth=s.gear_teeth, ratio=s.ratio, helix_angle_deg=math.degrees(s.helix_angle),
                         face_width_mm=s.face_width / MM, centre_distance_mm=s.centre_distance / MM,
                         reference_diameters_mm=[d / MM for d in s.diameters],
                         tip_diameters_mm=[d / MM for d in s.tip_diameters], mass_kg=s.mass,
                         safety_contact=list(s.safety_contact), safety_root=list(s.safety_root),
                         pinion_torque_Nm=s.rating.pinion_torque, binding=s.binding, margins=dict(s.margins),
                         smaller_module_mm=None if s.smaller_module is None else round(s.smaller_module[0] / MM, 9),
                         smaller_module_fails=None if s.smaller_module is None else s.smaller_module[1])


def sized_stages_out(t: synth.TrainSizing | None) -> list[SizedStageOut | None] | None:
    """Per-stage schemas of a sized train (null for a stage that is not a cylindrical pair)."""
    if t is None:
        return None
    return [None if s is None else sized_stage_out(s) for s in t.stages]
