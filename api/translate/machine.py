"""POST /v1/machines: the machine description in (drive, balancing, flywheel, foundation, regulation), the
design and its alternatives out."""

from __future__ import annotations

import numpy as np

import synth

from api.translate.analysis import analysis_out
from api.translate.balancing import balance_out, slider_crank_balance_out, weights_from
from api.translate.flywheel import flywheel_out
from api.translate.foundation import (
    isolation_out,
    machine_elastic_drive_from,
    machine_elastic_drive_out,
    machine_foundation_from,
    machine_regulation_from,
    machine_regulation_out,
)
from api.translate.gearing import catalogue_motor_from, drive_out, motor_out, stage_specs, teeth_out
from api.translate.linkage import ensure_finite, linkage_from, pair_frictions, summary_out, warnings_out
from api.translate.rating import sized_stages_out, strength_from
from mechsynth_client.schemas.gearing import RPM
from mechsynth_client.schemas.machine import (
    AlternativeOut,
    EfficiencyOut,
    IntegratorOut,
    MachineBalancingIn,
    MachineCheckOut,
    MachineDesignOut,
    MachineDriveIn,
    MachineFlywheelBodyOut,
    MachineGeometryIn,
    MachineIn,
    MachineMotorOut,
    MachineShaftOut,
    ReducedOut,
    RunDownOut,
    RunningOut,
    SimulationOut,
    StartUpOut,
    TRANSIENT_POINTS,
)


def machine_drive_from(drive: MachineDriveIn, max_stages: int) -> synth.DriveSpec:
    """Engine drive (rpm become rad/s here)."""
    stages = synth.make_stages(stage_specs(drive.stages), max_stages=max_stages, field="drive.stages")
    return synth.DriveSpec(
        stages=stages, motor=drive.motor,
        catalogue=None if drive.motor_catalogue is None else tuple(
            catalogue_motor_from(m) for m in drive.motor_catalogue),
        synchronous_speed=None if drive.synchronous_rpm is None else drive.synchronous_rpm * RPM,
        reserve_factor=drive.reserve_factor, objective=drive.objective,
        inertia=synth.InertiaModel(drive.pinion_inertia_kgm2, drive.load_inertia_kgm2,
                                   tuple(drive.shaft_inertias_kgm2 or ())),
        tooth_rules=synth.ToothRules(min_teeth=drive.min_teeth, max_teeth=drive.max_teeth),
        tooth_tolerance=drive.tooth_tolerance,
        strength=strength_from(drive.strength) if drive.size_gears else None,
    )


def machine_balancing_from(balancing: MachineBalancingIn) -> synth.BalancingChoice:
    """Engine balancing choice."""
    return synth.BalancingChoice(
        balancing.mode,
        synth.CounterweightSpec(tuple(balancing.counterweight_links or ()), dict(balancing.max_radius_m)),
        None if balancing.weights is None else weights_from(balancing.weights), balancing.mass_budget_kg,
        tuple(balancing.rotor_ratios.items()))


def machine_geometry_from(geometry: MachineGeometryIn) -> synth.GeometrySpec:
    """Engine geometry specification."""
    return synth.GeometrySpec(shape=geometry.shape, density=geometry.density_kg_m3,
                              max_rim_speed=geometry.max_rim_speed_m_s, allowable_stress=geometry.allowable_stress_Pa,
                              max_diameter=geometry.max_diameter_m,
                              thickness_ratio=(geometry.thickness_ratio[0], geometry.thickness_ratio[1]),
                              width_ratio=(geometry.width_ratio[0], geometry.width_ratio[1]))


def machine_from(body: MachineIn, max_stages: int) -> synth.MachineSpec:
    """Engine machine (degrees and rpm become radians and rad/s here)."""
    if body.crank_angle_deg is not None:
        raise synth.InvalidInput("a machine is designed over the whole cycle: use samples", field="crank_angle_deg")
    if body.crank_acceleration_rad_s2 != 0:
        raise synth.InvalidInput("steady motion has no mean crank acceleration", field="crank_acceleration_rad_s2")
    if (body.delta is None) == (body.machine_type is None):
        raise synth.InvalidInput("give delta or machine_type (one of them)", field="delta")
    delta = body.delta if body.delta is not None else synth.admissible_delta(str(body.machine_type))
    return synth.MachineSpec(
        linkage=linkage_from(body), speed=body.omega_rad_s, drive=machine_drive_from(body.drive, max_stages),
        delta=delta, balancing=machine_balancing_from(body.balancing),
        flywheel=synth.FlywheelChoice(body.flywheel.placement, machine_geometry_from(body.flywheel.geometry)),
        samples=body.samples, speed_tolerance=body.speed_tolerance, friction=pair_frictions(body.friction),
        brake_torque=body.brake_torque_Nm, start_under_load=body.start_under_load,
        max_startup_time=body.max_startup_time_s, max_rundown_time=body.max_rundown_time_s,
        foundation=None if body.foundation is None else machine_foundation_from(body.foundation),
        elastic_drive=None if body.elastic_drive is None else machine_elastic_drive_from(body.elastic_drive),
        regulation=None if body.regulation is None else machine_regulation_from(body.regulation))


def machine_check_out(c: synth.MachineCheck) -> MachineCheckOut:
    """Schema from an engine check."""
    return MachineCheckOut(name=c.name, label=c.label or c.name.replace("_", " "), value=c.value, limit=c.limit,
                           passed=c.passed, detail=c.detail, unit=c.unit)


def _picked(size: int) -> np.ndarray:
    return np.unique(np.linspace(0, size - 1, min(TRANSIENT_POINTS, size)).round().astype(int))


def running_out(r: synth.MachineRunning) -> RunningOut:
    """Schema from the engine's running figures (radians become degrees here)."""
    up, down, e = r.startup, r.rundown, r.efficiency
    run = up.run
    pick_up = _picked(run.time.size) if run is not None else np.zeros(0, dtype=int)
    pick_down = _picked(down.run.time.size)
    return RunningOut(
        efficiency=EfficiencyOut(linkage=e.linkage, gears=e.gears, overall=e.overall),
        startup=StartUpOut(
            starts=up.check.starts, starting_torque_Nm=up.check.starting_torque,
            max_resisting_torque_Nm=float(up.check.resisting_torque.max()),
            worst_crank_angle_deg=float(np.degrees(up.check.worst_angle)),
            start_crank_angle_deg=None if run is None else float(np.degrees(run.phi[0])),
            steady_time_s=up.steady_time,
            motor_peak_torque_Nm=up.peak_motor_torque, motor_rms_torque_Nm=up.rms_motor_torque,
            energy_residual=None if run is None else run.energy_residual,
            time_s=[] if run is None else run.time[pick_up].tolist(),
            omega_rad_s=[] if run is None else run.omega[pick_up].tolist(),
            motor_torque_Nm=[] if run is None else run.motor_torque[pick_up].tolist(),
            integrator=None if up.integrator is None else IntegratorOut(
                method=up.integrator.method, time_step_s=up.integrator.time_step,
                reference_inertia_kgm2=up.integrator.reference_inertia,
                reference_load_Nm=up.integrator.reference_load,
                reference_time_s=up.integrator.reference_time,
                closed_form_error=up.integrator.closed_form_error)),
        rundown=RunDownOut(
            stop_time_s=down.stop_time, brake_torque_Nm=down.brake_torque,
            energy_residual=down.run.energy_residual, time_error=down.time_error,
            time_s=down.run.time[pick_down].tolist(),
            omega_rad_s=np.maximum(down.run.omega[pick_down], 0.0).tolist()),
    )


def machine_flywheel_body_out(b: synth.FlywheelBody) -> MachineFlywheelBodyOut:
    """Schema from the body on its shaft."""
    return MachineFlywheelBodyOut(shaft=b.shaft, speed_ratio=b.speed_ratio, inertia_on_shaft_kgm2=b.inertia,
                                  crank_equivalent_inertia_kgm2=b.inertia * b.speed_ratio**2, shape=b.shape,
                                  mean_diameter_m=b.diameter, outer_diameter_m=b.outer_diameter,
                                  rim_thickness_m=b.thickness, width_m=b.width, mass_kg=b.mass,
                                  rim_speed_m_s=b.rim_speed, inertia_check_kgm2=b.inertia_check)


def alternative_out(a: synth.Alternative) -> AlternativeOut:
    """Schema from an engine alternative."""
    d = a.design
    if d is None:
        return AlternativeOut(mode=a.mode, available=False, reason=a.reason)
    return AlternativeOut(
        mode=a.mode, available=True, rms_shaking_force_N=d.balancing.after.rms_shaking_force,
        rms_shaking_moment_Nm=d.balancing.after.rms_shaking_moment, flywheel_inertia_kgm2=d.flywheel_inertia,
        flywheel_mass_kg=None if d.placement is None else d.placement.mass,
        flywheel_inertia_on_shaft_kgm2=None if d.placement is None else d.placement.inertia,
        flywheel_shaft=None if d.placement is None else d.placement.shaft, motor=d.drive.motor.name,
        peak_shaft_torque_Nm=max(s.peak_torque for s in d.shafts), achieved_delta=d.motion.delta,
        passed=d.passed,
    )


def machine_design_out(d: synth.MachineDesign, alternatives: tuple[synth.Alternative, ...] = (),
                       request_sha256: str | None = None) -> MachineDesignOut:
    """Schema from an engine design (radians and rad/s become degrees and rpm here)."""
    m, red, bal = d.motion, d.balanced.reduced, d.balancing
    ensure_finite(m.omega, m.motor_torque, red.inertia, red.load_torque)
    keep = np.unique(np.linspace(0, m.phi.size - 1, min(721, m.phi.size)).round().astype(int))
    motor = d.motor
    return MachineDesignOut(
        passed=d.passed,
        checks=[machine_check_out(c) for c in d.checks],
        analysis=analysis_out(d.before),
        balancing_mode=bal.mode,
        balancing=None if bal.result is None else balance_out(bal.result),
        slider_crank_balancing=None if bal.slider_crank is None else slider_crank_balance_out(
            bal.slider_crank),
        summary_after_balancing=summary_out(bal.after),
        reduced=ReducedOut(
            crank_angle_deg=np.degrees(red.phi).tolist(), reduced_inertia_kgm2=red.inertia.tolist(),
            reduced_load_torque_Nm=red.load_torque.tolist(),
            friction_torque_Nm=None if red.friction_torque is None else red.friction_torque.tolist(),
            driving_torque_Nm=d.balanced.kinetostatics.driving_torque.tolist(), mean_power_W=d.output_power,
            train_inertia_kgm2=d.train_inertia, rotor_inertia_kgm2=motor.reduced().inertia,
        ),
        motor=MachineMotorOut(
            motor=motor_out(d.drive.motor), rated_torque_Nm=motor.rated_torque,
            breakdown_torque_Nm=motor.breakdown_torque, train_ratio=d.train_ratio,
            train_efficiency=motor.efficiency, required_power_W=d.drive.required_power,
            operating_speed_rpm=d.drive.shafts[0].speed / RPM,
            simulated_mean_speed_rpm=motor.gear_ratio * m.mean_speed / RPM,
        ),
        drive=drive_out(d.drive, d.spec.drive.stages),
        teeth=None if d.teeth is None else teeth_out(d.teeth), gears=sized_stages_out(d.gears),
        stage_ratios=list(d.stage_ratios),
        flywheel=flywheel_out(d.flywheel),
        flywheel_shaft=None if d.placement is None else d.placement.shaft,
        flywheel_body=None if d.placement is None else machine_flywheel_body_out(d.placement),
        simulation=SimulationOut(
            achieved_delta=m.delta, target_delta=d.spec.delta, mean_crank_speed_rad_s=m.mean_speed,
            mean_crank_speed_rpm=m.mean_speed / RPM, period_s=m.period, motor_peak_torque_Nm=m.motor_peak_torque,
            motor_rms_torque_Nm=m.motor_rms_torque, breakdown_margin=m.breakdown_margin,
            crank_angle_deg=np.degrees(m.phi[keep]).tolist(), omega_rad_s=m.omega[keep].tolist(),
            motor_torque_Nm=m.motor_torque[keep].tolist(),
        ),
        shafts=[MachineShaftOut(name=s.name, speed_ratio=s.speed_ratio, mean_speed_rpm=s.mean_speed / RPM,
                                mean_power_W=s.mean_power, mean_torque_Nm=s.mean_torque,
                                peak_torque_Nm=s.peak_torque, rms_torque_Nm=s.rms_torque, inertia_kgm2=s.inertia,
                                carries_flywheel=s.carries_flywheel) for s in d.shafts],
        running=None if d.running is None else running_out(d.running),
        alternatives=[alternative_out(a) for a in alternatives],
        warnings=warnings_out(d.warnings),
        request_sha256=request_sha256,
        foundation=None if d.foundation is None else isolation_out(d.foundation),
        elastic_drive=None if d.elastic is None else machine_elastic_drive_out(d.elastic),
        regulation=None if d.regulation is None else machine_regulation_out(d.regulation),
    )
