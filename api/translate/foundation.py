"""The machine on its foundation, its elastic drive and speed regulation: frames, isolators, elements and
regulators in, their answers out."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

import synth
from synth.machine import elastic_drive as drives
from synth.machine import foundation as frames
from synth.machine import foundation_chain as chain
from synth.machine import foundation_design as designs
from synth.machine import regulation as regulators

from api.translate.linkage import degree_array, ensure_finite, validity_out, warnings_out
from api.translate.motor import motor_from
from mechsynth_client.schemas.common import WarningOut
from mechsynth_client.schemas.foundation import (
    ElasticDriveChecksOut,
    ElasticDriveIn,
    ElasticDriveOut,
    ElasticElementIn,
    ElasticRunOut,
    FrameIn,
    HarmonicOut,
    IsolationChecksOut,
    IsolationDesignIn,
    IsolationDesignOut,
    IsolationIn,
    IsolationOut,
    IsolatorIn,
    IsolatorLoadOut,
    LoadHarmonicOut,
    MachineElasticDriveIn,
    MachineElasticDriveOut,
    MachineFoundationIn,
    MachineRegulationIn,
    MachineRegulationOut,
    ModeOut,
    RegulationOut,
    RegulatorIn,
    RunUpOut,
)


def frame_from(frame: FrameIn) -> Any:
    """Engine frame."""
    return frames.Frame(frame.mass_kg, frame.inertia_kgm2, (frame.centre_m[0], frame.centre_m[1]))


def isolator_from(isolator: IsolatorIn) -> Any:
    """Engine isolator."""
    return frames.Isolator((isolator.position_m[0], isolator.position_m[1]), isolator.kx_N_m, isolator.ky_N_m,
                           isolator.cx_Ns_m, isolator.cy_Ns_m, isolator.damping_ratio)


def run_up_from(body: IsolationIn) -> tuple[Any, float] | None:
    """Engine motor and constant inertia of the run-up, or None."""
    if body.run_up is None:
        return None
    return motor_from(body.run_up.motor), body.run_up.constant_inertia_kgm2


def frame_and_isolators_from(body: IsolationIn) -> tuple[Any, tuple[Any, ...]]:
    """Engine frame and isolators."""
    return frame_from(body.frame), tuple(isolator_from(i) for i in body.isolators)


def isolation_design_spec(body: IsolationDesignIn) -> Any:
    """Engine design spec."""
    return designs.IsolationDesignSpec(
        tuple((p[0], p[1]) for p in body.positions_m), body.objective, body.max_force_N, body.max_amplitude_m,
        body.stiffness_ratio, body.min_stiffness_N_m, body.max_stiffness_N_m, body.min_damping_ratio,
        body.max_damping_ratio, body.max_static_deflection_m, body.max_block_mass_kg, body.block_radius_m)


def isolation_out(r: Any) -> IsolationOut:
    """Schema from an engine isolation."""
    iso = [IsolatorLoadOut.model_construct(force_N=r.isolator_force[i],
                                           peak_force_N=float(r.peak_isolator_force[i]),
                                           static_deflection_m=[float(v) for v in r.static_deflection[i]],
                                           static_load_N=[float(v) for v in r.static_load[i]])
           for i in range(len(r.isolators))]
    c = r.check
    ensure_finite(r.displacement, r.rotation, r.force, r.moment, r.isolator_force)
    values: dict[str, Any] = dict(
        crank_angle_deg=degree_array(r.phi), time_s=r.time, displacement_m=r.displacement,
        rotation_rad=r.rotation, force_N=r.force, moment_Nm=r.moment, shaking_force_N=r.shaking_force,
        shaking_moment_Nm=r.shaking_moment, isolators=iso,
        modes=[ModeOut(frequency_Hz=m.frequency, shape_x_m=m.shape[0], shape_y_m=m.shape[1],
                       shape_theta_rad=m.shape[2], damping_ratio=m.damping_ratio) for m in r.modes],
        harmonics=[HarmonicOut(order=h.order, frequency_Hz=h.frequency, shaking_force_N=h.shaking_force,
                               shaking_moment_Nm=h.shaking_moment, transmitted_force_N=h.transmitted_force,
                               transmitted_moment_Nm=h.transmitted_moment,
                               force_transmissibility=h.force_transmissibility,
                               moment_transmissibility=h.moment_transmissibility) for h in r.harmonics],
        peak_displacement_m=r.peak_displacement, peak_rotation_rad=r.peak_rotation,
        peak_isolator_displacement_m=r.peak_isolator_displacement, peak_force_N=r.peak_force,
        peak_moment_Nm=r.peak_moment, peak_shaking_force_N=r.peak_shaking_force,
        force_ratio=r.peak_force / r.peak_shaking_force if r.peak_shaking_force > 0 else 0.0,
        settle_time_s=r.settle_time if math.isfinite(r.settle_time) else None,
        checks=IsolationChecksOut(max_displacement_diff_m=c.displacement_diff,
                                  max_rotation_diff_rad=c.rotation_diff,
                                  max_force_diff_N=c.force_diff, relative_diff=c.relative_diff,
                                  series_residual=c.series_residual, method=c.method),
        warnings=warnings_out(r.warnings), validity=validity_out(r.checks),
    )
    ru = r.run_up
    values["run_up"] = None if ru is None else RunUpOut.model_construct(
        time_s=ru.time, crank_speed_rpm=ru.speed * 30 / math.pi, amplitude_m=ru.amplitude,
        peak_amplitude_m=ru.peak_amplitude, peak_time_s=ru.peak_time, peak_speed_rpm=ru.peak_speed * 30 / math.pi,
        steady_amplitude_m=ru.steady_amplitude, ratio=ru.ratio, crossed_frequencies_Hz=list(ru.crossed))
    return IsolationOut.model_construct(**values)


def isolation_design_out(d: Any) -> IsolationDesignOut:
    """Schema from an engine design."""
    return IsolationDesignOut.model_construct(
        ky_N_m=d.ky, kx_N_m=d.kx, damping_ratio=d.damping_ratio, block_mass_kg=d.block_mass,
        amplitude_m=d.amplitude, peak_force_N=d.peak_force, static_deflection_m=d.static_deflection,
        objective=d.objective, objective_value=d.objective_value, grid_best=d.grid_best,
        candidates=d.candidates, refined=d.refined, method=d.method,
        isolation=isolation_out(d.isolation))


def elastic_element_from(element: ElasticElementIn, k: int) -> Any:
    """Engine element; InvalidInput naming a missing field."""
    if element.type == "shaft":
        if element.diameter_m is None or element.length_m is None:
            raise synth.InvalidInput("a shaft needs diameter_m and length_m", field=f"elements.{k}.diameter_m")
        return drives.ElasticElement("shaft", element.speed_ratio, element.diameter_m, element.length_m,
                                     element.shear_modulus_Pa)
    if element.stiffness_Nm_rad is None:
        raise synth.InvalidInput("a coupling needs stiffness_Nm_rad", field=f"elements.{k}.stiffness_Nm_rad")
    return drives.ElasticElement("coupling", element.speed_ratio, stiffness=element.stiffness_Nm_rad)


def elements_from(body: ElasticDriveIn) -> tuple[Any, ...]:
    """Engine elements."""
    return tuple(elastic_element_from(e, k) for k, e in enumerate(body.elements))


def elastic_drive_out(d: Any) -> ElasticDriveOut:
    """Schema from an engine elastic drive."""
    rpm = 30 / math.pi
    st = d.steady
    ensure_finite(st.elastic_torque, d.rigid_torque, st.crank_speed, st.rotor_speed)
    near = [h for h in d.harmonics if h.near]
    warnings = [WarningOut(code="load_harmonic_near_resonance", field="stiffness_Nm_rad", value=h.ratio, unit="",
                           message=f"harmonic {h.order} of the load torque ({h.frequency:.4g} Hz, "
                           f"{h.amplitude:.4g} N·m) lies within 15 % of the link's natural frequency "
                           f"({d.natural_frequency:.4g} Hz): change the stiffness or the inertias")
                for h in near]
    start = None
    if d.start is not None:
        r = d.start
        start = ElasticRunOut.model_construct(
            time_s=r.time, crank_speed_rpm=r.crank_speed * rpm, rotor_speed_rpm=r.rotor_speed * rpm,
            elastic_torque_Nm=r.elastic_torque, peak_elastic_torque_Nm=d.start_peak_torque,
            rigid_peak_torque_Nm=d.rigid_start_peak_torque, energy_residual=r.energy_residual)
    values: dict[str, Any] = dict(
        stiffness_Nm_rad=d.stiffness, damping_Nms_rad=d.damping, rotor_inertia_kgm2=d.rotor_inertia,
        machine_inertia_kgm2=list(d.machine_inertia), natural_frequency_Hz=d.natural_frequency,
        natural_frequency_range_Hz=list(d.natural_frequency_range),
        mean_speed_rpm=d.mean_speed * rpm,
        crank_angle_deg=degree_array(d.phi), elastic_torque_Nm=st.elastic_torque, rigid_torque_Nm=d.rigid_torque,
        crank_speed_rpm=st.crank_speed * rpm, rotor_speed_rpm=st.rotor_speed * rpm,
        peak_elastic_torque_Nm=float(np.max(np.abs(st.elastic_torque))),
        peak_rigid_torque_Nm=float(np.max(np.abs(d.rigid_torque))), dynamic_factor=d.dynamic_factor,
        harmonics=[LoadHarmonicOut(order=h.order, frequency_Hz=h.frequency, amplitude_Nm=h.amplitude,
                                   frequency_ratio=h.ratio, near_resonance=h.near) for h in d.harmonics],
        warnings=warnings,
        checks=ElasticDriveChecksOut(
            eigen_frequency_Hz=d.eigen_frequency,
            closed_form_diff=abs(d.eigen_frequency - d.natural_frequency) / d.natural_frequency,
            steady_energy_residual=st.energy_residual, revolutions=d.revolutions),
        start=start)
    return ElasticDriveOut.model_construct(**values)


def regulator_from(regulator: RegulatorIn) -> tuple[Any, tuple[float, float, float] | None]:
    """Engine controller (gains) or tuning targets; InvalidInput naming the missing field."""
    tuned = regulator.settling_time_s is not None or regulator.overshoot is not None
    given = regulator.kp is not None or regulator.ki is not None
    if tuned == given:
        raise synth.InvalidInput("give the regulator either settling_time_s and overshoot (tuned) or kp and ki",
                                 "regulator")
    if tuned:
        if regulator.settling_time_s is None or regulator.overshoot is None:
            raise synth.InvalidInput("tuning needs both settling_time_s and overshoot",
                                     field="regulator.settling_time_s")
        return None, (regulator.settling_time_s, regulator.overshoot, regulator.filter_time_s)
    if regulator.kp is None or regulator.ki is None:
        raise synth.InvalidInput("gains need both kp and ki", field="regulator.kp")
    ref = None if regulator.reference_speed_rpm is None else regulator.reference_speed_rpm * math.pi / 30
    return regulators.PIController(
        regulator.kp, regulator.ki, regulator.filter_time_s, ref), None


def regulation_out(r: Any) -> RegulationOut:
    """Schema from an engine regulation."""
    rpm = 30 / math.pi
    ensure_finite(r.omega, r.smoothed, r.motor_torque)
    c = r.controller
    values: dict[str, Any] = dict(
        time_s=r.time, crank_speed_rpm=r.omega * rpm, smoothed_speed_rpm=r.smoothed * rpm,
        motor_torque_Nm=r.motor_torque, load_torque_Nm=r.load_torque, converter_shift_rpm=r.shift * rpm,
        step_time_s=r.step_time, speed_before_rpm=r.speed_before * rpm, speed_after_rpm=r.speed_after * rpm,
        drop_rpm=r.drop * rpm, drop_closed_form_rpm=r.drop_closed_form * rpm, time_constant_s=r.time_constant,
        band_rpm=r.band * rpm, settling_time_s=r.settling_time, settling_closed_form_s=r.settling_closed_form,
        overshoot=r.overshoot, max_deviation_rpm=r.max_deviation * rpm,
        kp=None if c is None else c.kp, ki_1_s=None if c is None else c.ki,
        filter_time_s=None if c is None else c.filter_time,
        reference_speed_rpm=None if c is None or c.reference is None else c.reference * rpm,
        poles_real_1_s=None if r.poles is None else [float(p.real) for p in r.poles],
        poles_imag_1_s=None if r.poles is None else [float(p.imag) for p in r.poles],
        breakdown_torque_Nm=r.breakdown_torque if math.isfinite(r.breakdown_torque) else None,
        warnings=warnings_out(r.warnings), validity=validity_out(r.checks))
    return RegulationOut.model_construct(**values)


def machine_foundation_from(foundation: MachineFoundationIn) -> Any:
    """Engine foundation choice."""
    return chain.FoundationChoice(
        frame_from(foundation.frame), tuple(isolator_from(i) for i in foundation.isolators), foundation.max_force_N,
        foundation.max_amplitude_m, foundation.run_up)


def machine_elastic_drive_from(drive: MachineElasticDriveIn) -> Any:
    """Engine elastic-drive choice."""
    return chain.ElasticDriveChoice(
        drive.stiffness_Nm_rad, tuple(elastic_element_from(e, k) for k, e in enumerate(drive.elements)),
        drive.motor_side_inertia_kgm2, drive.damping_ratio, drive.start, drive.max_dynamic_factor)


def machine_regulation_from(regulation: MachineRegulationIn) -> Any:
    """Engine regulation choice."""
    controller, tuning = (None, None) if regulation.regulator is None else regulator_from(regulation.regulator)
    return chain.RegulationChoice(regulation.load_step_Nm, regulation.delta, controller, tuning,
                                  regulation.max_settling_time_s, regulation.max_speed_drop_rad_s)


def machine_elastic_drive_out(e: Any) -> MachineElasticDriveOut:
    """Schema from the engine's elastic drive of a design."""
    base = elastic_drive_out(e.drive)
    return MachineElasticDriveOut.model_construct(**dict(base), motor_side_inertia_kgm2=e.motor_side_inertia,
                                                  machine_constant_inertia_kgm2=e.machine_constant_inertia,
                                                  gear_torque_basis=e.gear_torque_basis)


def machine_regulation_out(g: Any) -> MachineRegulationOut:
    """Schema from the engine's load step of a design."""
    base = regulation_out(g.regulation)
    return MachineRegulationOut.model_construct(**dict(base), constant_inertia_kgm2=g.constant_inertia)
