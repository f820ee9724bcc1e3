"""POST /v1/cams/*: the cam's segments, follower, loads and limits in; its motion, profile, forces and least cam
out."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from synth import cams

from api.translate.linkage import validity_out, warnings_out
from mechsynth_client.schemas.cams import (
    CamAnalysisIn,
    CamAnalysisOut,
    CamChecksOut,
    CamConstraintOut,
    CamFollowerIn,
    CamForcesOut,
    CamProfileOut,
    CamSynthesisIn,
    CamSynthesisOut,
    CoilSpringOut,
    LawCheckOut,
    LeastCamCertificateOut,
    MotionLawOut,
    OptimisedLawOut,
    OscillatingMotionOut,
    TranslatingMotionOut,
    _CamFields,
)


def cam_follower_from(follower: CamFollowerIn) -> cams.Follower:
    """Engine follower."""
    return cams.Follower(follower.motion, follower.contact,
                         follower.roller_radius_m if follower.contact == "roller" else 0.0, follower.offset_m,
                         follower.pivot_distance_m or 0.0, follower.arm_length_m or 0.0, follower.face_offset_m)


def _segments(cam: _CamFields) -> tuple[cams.Segment, ...]:
    out = []
    for i, s in enumerate(cam.segments):
        if s.kind != "dwell":
            lift = s.lift_m if cam.follower.motion == "translating" else s.lift_deg
            if lift is None:
                want = "lift_m" if cam.follower.motion == "translating" else "lift_deg"
                raise cams.InvalidInput(f"segment {i} ({s.kind}) of a {cam.follower.motion} follower needs "
                                        f"{want}", field=f"segments.{i}.{want}")
            lift = lift if cam.follower.motion == "translating" else math.radians(lift)
        else:
            lift = 0.0
        out.append(cams.Segment(s.kind, math.radians(s.angle_deg), lift, s.law))
    return tuple(out)


def _loads(cam: _CamFields) -> cams.PairLoads | None:
    ld = cam.loads
    if ld is None:
        return None
    translating = cam.follower.motion == "translating"
    inertia = ld.mass_kg if translating else ld.inertia_kgm2
    stiffness = ld.spring_stiffness_N_m if translating else ld.spring_stiffness_Nm_rad
    preload = ld.spring_preload_N if translating else ld.spring_preload_Nm
    wrong = [n for n in (("inertia_kgm2", "spring_stiffness_Nm_rad", "spring_preload_Nm") if translating
                         else ("mass_kg", "spring_stiffness_N_m", "spring_preload_N"))
             if getattr(ld, n) is not None]
    if wrong:
        raise cams.InvalidInput(f"{wrong[0]} is for the other kind of follower", field=f"loads.{wrong[0]}")
    process = []
    for i, p in enumerate(ld.process):
        value = p.force_N if translating else p.moment_Nm
        if value is None:
            want = "force_N" if translating else "moment_Nm"
            raise cams.InvalidInput(f"a {cam.follower.motion} follower's process load needs {want}",
                                    field=f"loads.process.{i}.{want}")
        process.append(cams.ProcessLoad(math.radians(p.from_deg), math.radians(p.to_deg), value))
    return cams.PairLoads(inertia or 0.0, cam.omega_rad_s, stiffness, preload, tuple(process),
                          ld.contact_margin, ld.rolling_resistance_m, ld.max_initial_compression_m,
                          ld.spring_wire, ld.spring_index)


def cam_spec(cam: _CamFields, base_radius: float = 0.0, min_curvature_radius: float = 0.002) -> cams.CamSpec:
    """Engine spec; degrees and rev/min become radians and rad/s here."""
    o = cam.law_options
    options = cams.LawOptions(o.objective, o.knot_intervals, 2.0 * math.pi * (o.natural_frequency_hz or 0.0),
                              o.max_acceleration_coefficient)
    return cams.CamSpec(_segments(cam), cam_follower_from(cam.follower), cam.omega_rad_s, base_radius,
                        cam.samples, _loads(cam), options, math.radians(cam.max_pressure_angle_rise_deg),
                        math.radians(cam.max_pressure_angle_return_deg), min_curvature_radius)


def cam_analysis_spec(body: CamAnalysisIn) -> cams.CamSpec:
    """Engine spec of the cam."""
    return cam_spec(body, body.base_radius_m, body.min_curvature_radius_m)


def limits_from(body: CamSynthesisIn) -> cams.CamLimits:
    """Engine limits; degrees become radians here."""
    lo, hi = body.base_radius_bounds_m
    offsets = None if body.offset_bounds_m is None else (body.offset_bounds_m[0], body.offset_bounds_m[1])
    return cams.CamLimits(math.radians(body.max_pressure_angle_rise_deg),
                          math.radians(body.max_pressure_angle_return_deg), body.min_curvature_radius_m,
                          (lo, hi), offsets, body.hub_radius_m)


def _deg(x: Any) -> Any:
    return np.degrees(x).tolist()


def _l(x: Any) -> Any:
    """An engine array as the nested lists the answer's fields hold."""
    return np.asarray(x, dtype=float).tolist()


def motion_out(an: cams.CamAnalysis) -> TranslatingMotionOut | OscillatingMotionOut:
    """The motion block of an analysis."""
    m, w = an.motion, an.spec.speed
    cols = [_l(c) for c in (m.s, m.v, m.a, m.j, m.v * w, m.a * w * w, m.j * w**3)]
    if an.spec.follower.motion == "translating":
        return TranslatingMotionOut(s_m=cols[0], v_m_per_rad=cols[1], a_m_per_rad2=cols[2], jerk_m_per_rad3=cols[3],
                                    v_m_s=cols[4], a_m_s2=cols[5], jerk_m_s3=cols[6])
    return OscillatingMotionOut(psi_rad=cols[0], v_rad_per_rad=cols[1], a_rad_per_rad2=cols[2],
                                jerk_rad_per_rad3=cols[3], omega_rad_s=cols[4], alpha_rad_s2=cols[5],
                                jerk_rad_s3=cols[6])


def profile_out(an: cams.CamAnalysis) -> CamProfileOut:
    """The profile block of an analysis."""
    g, m = an.geometry, an.motion
    kinds = np.array([s.kind for s in an.spec.segments])[m.segment]
    alpha = np.abs(g.pressure_angle)
    convex = np.where(g.kappa > 0, g.kappa, 0.0)
    k = int(np.argmax(convex))
    flat = an.spec.follower.contact == "flat_faced"
    return CamProfileOut(base_radius_m=g.base_radius, prime_radius_m=g.prime_radius, offset_m=an.spec.follower.offset,
                         pitch_m=_l(g.pitch), profile_m=_l(g.profile), pressure_angle_deg=_deg(g.pressure_angle),
                         curvature_1_m=_l(g.kappa),
                         max_pressure_angle_rise_deg=float(np.degrees(alpha[kinds == "rise"].max(initial=0.0))),
                         max_pressure_angle_return_deg=float(np.degrees(alpha[kinds == "return"].max(initial=0.0))),
                         min_curvature_radius_m=float(1.0 / convex[k]) if convex[k] > 0 else 0.0,
                         min_curvature_radius_at_deg=float(np.degrees(m.theta[k])),
                         face_width_m=float(np.ptp(g.face)) if flat else 0.0,
                         face_extent_m=[float(g.face.min()), float(g.face.max())] if flat else [0.0, 0.0])


def forces_out(an: cams.CamAnalysis) -> CamForcesOut | None:
    """The forces block of an analysis."""
    f = an.forces
    if f is None:
        return None
    tr = an.spec.follower.motion == "translating"
    return CamForcesOut(
        spring_designed=f.spring_designed,
        spring_stiffness_N_m=f.stiffness if tr else None, spring_preload_N=f.preload if tr else None,
        spring_stiffness_Nm_rad=None if tr else f.stiffness, spring_preload_Nm=None if tr else f.preload,
        least_contact_margin=f.least_margin if math.isfinite(f.least_margin) else None,
        contact_force_N=_l(f.contact), min_contact_force_N=float(f.contact.min()),
        max_contact_force_N=float(f.contact.max()), driving_torque_Nm=_l(f.torque),
        driving_torque_virtual_power_Nm=_l(f.torque_virtual_power), rolling_loss_torque_Nm=_l(f.rolling_loss),
        peak_driving_torque_Nm=float(np.max(np.abs(f.torque))), mean_driving_torque_Nm=float(np.mean(f.torque)),
        rms_driving_torque_Nm=float(np.sqrt(np.mean(f.torque**2))), reduced_inertia_kgm2=_l(f.reduced_inertia),
        load_torque_Nm=_l(f.load_torque))


def optimised_out(o: cams.OptimisedLaw) -> OptimisedLawOut:
    """Schema of an optimised law."""
    return OptimisedLawOut(objective=o.objective, solver_status=o.status, objective_value=o.objective_value,
                           velocity_coefficient=o.peak_velocity, acceleration_coefficient=o.peak_acceleration,
                           jerk_coefficient=o.peak_jerk, lower_bound=o.lower_bound,
                           residual_vibration=o.residual_vibration, frequency_ratio=o.frequency_ratio,
                           end_condition_error=o.end_error, knot_intervals=o.law.intervals,
                           coefficients=_l(o.law.coefficients))


def coil_out(c: Any) -> CoilSpringOut | None:
    """The coil block of an analysis, or None."""
    if c is None:
        return None
    return CoilSpringOut(
        wire=c.wire, wire_diameter_m=c.diameter, mean_coil_diameter_m=c.mean_diameter, spring_index=c.index,
        active_coils=c.active_coils, free_length_m=c.free_length, installed_length_m=c.installed_length,
        solid_length_m=c.solid_length, initial_compression_m=c.initial_compression, max_force_N=c.max_force,
        max_shear_stress_MPa=c.max_stress / 1e6, allowable_shear_stress_MPa=c.allowable_stress / 1e6,
        fatigue_factor=c.fatigue_factor, surge_frequency_Hz=c.surge_frequency, surge_order=c.surge_order)


def cam_analysis_out(an: cams.CamAnalysis) -> CamAnalysisOut:
    """Schema from an engine analysis."""
    f = an.forces
    laws = [LawCheckOut(
        segment=c.index, kind=c.kind, law=c.law, velocity_coefficient=c.coefficient_velocity,
        acceleration_coefficient=c.coefficient_acceleration, jerk_coefficient=c.coefficient_jerk,
        textbook_acceleration_coefficient=c.textbook_acceleration,
        sampled_peak_acceleration_ratio=c.peak_acceleration / (c.coefficient_acceleration * c.lift / c.angle**2))
            for c in an.laws]
    checks = CamChecksOut(table_pressure_angle_error_deg=math.degrees(an.table.max_pressure_angle_error),
                          table_curvature_error=an.table.max_curvature_error,
                          table_samples_compared=an.table.samples_compared, derivative_error=an.derivative_check,
                          torque_virtual_power_error=None if f is None else f.torque_check,
                          reduced_model_error=None if f is None else f.reduced_check, laws=laws)
    return CamAnalysisOut(cam_angle_deg=_deg(an.motion.theta), speed_rpm=an.spec.speed * 30.0 / math.pi,
                          motion=motion_out(an), profile=profile_out(an), forces=forces_out(an),
                          optimised_laws=[optimised_out(o) for o in an.optimised], checks=checks,
                          spring=coil_out(an.coil), warnings=warnings_out(an.warnings),
                          validity=validity_out(an.checks))


def cam_synthesis_out(r: cams.CamSynthesis) -> CamSynthesisOut:
    """Schema from an engine synthesis."""
    lc, lim = r.least, r.limits
    cons = [CamConstraintOut(name="max_pressure_angle_rise_deg", limit=math.degrees(lim.max_pressure_rise),
                             value=math.degrees(lc.pressure_rise), active=lc.active == "max_pressure_angle_rise_deg"),
            CamConstraintOut(name="max_pressure_angle_return_deg", limit=math.degrees(lim.max_pressure_return),
                             value=math.degrees(lc.pressure_return),
                             active=lc.active == "max_pressure_angle_return_deg"),
            CamConstraintOut(name="min_curvature_radius_m", limit=lim.min_curvature_radius,
                             value=lc.min_curvature_radius if math.isfinite(lc.min_curvature_radius) else 0.0,
                             active=lc.active == "min_curvature_radius_m")]
    cert = LeastCamCertificateOut(statement=lc.statement, grid_points=lc.grid_points, evaluations=lc.evaluations,
                                  bracket_width_m=lc.bracket_width, monotone=lc.monotone,
                                  just_below_fails=lc.just_below_fails, offsets_scanned=lc.offset_scan)
    return CamSynthesisOut(base_radius_m=lc.base_radius, offset_m=lc.offset, active_constraint=lc.active,
                           constraints=cons, certificate=cert, cam=cam_analysis_out(r.analysis))


def motion_law_out(c: cams.LawCoefficients) -> MotionLawOut:
    """Schema from the engine's coefficients."""
    return MotionLawOut(name=c.name, velocity_coefficient=c.velocity, acceleration_coefficient=c.acceleration,
                        jerk_coefficient=c.jerk,
                        textbook_acceleration_coefficient=cams.TEXTBOOK_PEAK_ACCELERATION[c.name])
