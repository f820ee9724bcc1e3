"""POST /v1/gearing/*: stages, tooth rules, inertia models and motor catalogues in; ratio splits, teeth and
drives out."""

from __future__ import annotations

import math

import synth

from api.translate.linkage import warnings_out
from api.translate.rating import sized_stages_out
from mechsynth_client.schemas.common import one_of
from mechsynth_client.schemas.gearing import (
    CatalogueMotorIn,
    DriveChecksOut,
    DriveIn,
    DriveOut,
    MeshOut,
    MotorOut,
    OBJECTIVES,
    RPM,
    STAGE_TYPES,
    ShaftOut,
    SplitChecksOut,
    SplitIn,
    SplitOut,
    StageIn,
    StageOut,
    StageType,
    StageTypeOut,
    TORQUE_BASES,
    TeethChecksOut,
    TeethIn,
    TeethOut,
    _InertiaFields,
)


def stage_spec(stage: StageIn) -> synth.StageSpec:
    """Engine stage spec."""
    return synth.StageSpec(stage.type, stage.ratio_min, stage.ratio_max, stage.efficiency, stage.ratio)


def stage_specs(stages: int | list[StageType | StageIn]) -> int | list[synth.StageSpec | str]:
    """Engine stage specs of a request's stages: a count, or each stage by type name or in full."""
    return stages if isinstance(stages, int) else [s if isinstance(s, str) else stage_spec(s) for s in stages]


def inertia_model(request: _InertiaFields, motor_inertia_kgm2: float = 0.0) -> synth.InertiaModel:
    """Engine reduced-inertia model data."""
    return synth.InertiaModel(request.pinion_inertia_kgm2, request.load_inertia_kgm2,
                              tuple(request.shaft_inertias_kgm2 or ()), motor_inertia_kgm2)


def split_ratio(body: SplitIn) -> float:
    """The total ratio, from the speeds when it is not given."""
    if body.total_ratio is not None:
        return body.total_ratio
    motor = body.motor_speed_rad_s if body.motor_speed_rpm is None else body.motor_speed_rpm * RPM
    output = body.output_speed_rad_s if body.output_speed_rpm is None else body.output_speed_rpm * RPM
    assert motor is not None and output is not None
    return synth.total_ratio(motor, output)


def stage_out(s: synth.Stage) -> StageOut:
    """Schema from an engine stage."""
    return StageOut(type=one_of(STAGE_TYPES, s.type), ratio_min=s.ratio_min, ratio_max=s.ratio_max,
                    efficiency=s.efficiency,
                    fixed_ratio=s.ratio)


def split_out(r: synth.SplitResult, stages: tuple[synth.Stage, ...]) -> SplitOut:
    """Schema from an engine split."""
    return SplitOut(
        total_ratio=r.total_ratio, objective=one_of(OBJECTIVES, r.objective), stage_ratios=list(r.stage_ratios),
        continuous_ratios=list(r.continuous_ratios), objective_value=r.objective_value,
        objective_unit="m3" if r.objective == "min_volume" else "kgm2",
        reduced_inertia_kgm2=r.reduced_inertia, gear_volume_m3=r.gear_volume,
        stages=[stage_out(s) for s in stages], snapped=r.snapped, snap_tolerance=r.snap_tolerance,
        solver=r.solver, solver_status=r.solver_status, solve_time_s=r.solve_time,
        checks=SplitChecksOut(objective_model=r.checks.objective_model,
                              ratio_product_error=r.checks.ratio_product_error,
                              kkt_residual=r.checks.kkt_residual),
        warnings=warnings_out(r.warnings),
    )


def teeth_rules(body: TeethIn) -> synth.ToothRules:
    """Engine tooth rules (degrees become radians here)."""
    return synth.ToothRules(math.radians(body.pressure_angle_deg), body.addendum_coefficient,
                            body.profile_shift, body.min_teeth, body.max_teeth, body.hunting_teeth, body.reverted)


def mesh_out(m: synth.Mesh) -> MeshOut:
    """Schema from an engine mesh, simple or planetary."""
    if isinstance(m, synth.PlanetaryMesh):
        return MeshOut(pinion_teeth=m.pinion_teeth, gear_teeth=m.gear_teeth, ratio=m.ratio, sun_teeth=m.pinion_teeth,
                       planet_teeth=m.planet_teeth, ring_teeth=m.gear_teeth, planets=m.planets,
                       efficiency=m.efficiency, back_efficiency=m.back_efficiency)
    return MeshOut(pinion_teeth=m.pinion_teeth, gear_teeth=m.gear_teeth, ratio=m.ratio)


def teeth_out(r: synth.ToothResult) -> TeethOut:
    """Schema from an engine tooth result."""
    c = r.checks
    return TeethOut(
        stages=[mesh_out(m) for m in r.stages],
        total_ratio=r.total_ratio, target_ratio=r.target_ratio, ratio_error=r.ratio_error,
        total_teeth=r.total_teeth, tolerance=r.tolerance, method=r.method, search_time_s=r.search_time,
        products_examined=r.products_examined, undercut_limit=r.undercut_limit,
        min_pinion_teeth=r.min_pinion_teeth, min_gear_teeth=r.min_gear_teeth,
        checks=TeethChecksOut(enumeration_combinations=c.enumeration_combinations,
                              enumeration_ratio_error=c.enumeration_ratio_error,
                              enumeration_total_teeth=c.enumeration_total_teeth, agrees=c.agrees),
        warnings=warnings_out(r.warnings),
    )


def catalogue_motor_from(motor: CatalogueMotorIn) -> synth.CatalogueMotor:
    """Engine motor (rpm become rad/s here)."""
    return synth.CatalogueMotor(motor.name, motor.rated_power_W, motor.synchronous_rpm * RPM,
                                motor.rated_rpm * RPM, motor.rotor_inertia_kgm2, mass=motor.mass_kg)


def drive_catalogue(body: DriveIn) -> list[synth.CatalogueMotor] | None:
    """Engine motors of the request's own catalogue, if it has one."""
    return None if body.motor_catalogue is None else [catalogue_motor_from(m) for m in body.motor_catalogue]


def motor_out(m: synth.CatalogueMotor) -> MotorOut:
    """Schema from an engine motor (rad/s become rpm here)."""
    return MotorOut(name=m.name, rated_power_W=m.rated_power, synchronous_rpm=round(m.synchronous_speed / RPM, 9),
                    rated_rpm=round(m.rated_speed / RPM, 9), rotor_inertia_kgm2=m.rotor_inertia, mass_kg=m.mass)


def drive_out(r: synth.DriveResult, stages: tuple[synth.Stage, ...]) -> DriveOut:
    """Schema from an engine drive (rad/s become rpm here)."""
    return DriveOut(
        motor=motor_out(r.motor), required_power_W=r.required_power,
        drive_efficiency=r.drive_efficiency, chain_efficiency=r.chain_efficiency, total_ratio=r.total_ratio,
        stage_ratios=list(r.split.stage_ratios), stage_efficiencies=list(r.stage_efficiencies),
        shafts=[ShaftOut(speed_rpm=s.speed / RPM, speed_rad_s=s.speed, power_W=s.power, torque_Nm=s.torque,
                         inertia_kgm2=s.inertia, reduced_inertia_kgm2=s.reduced_inertia) for s in r.shafts],
        reduced_inertia_kgm2=r.reduced_inertia, output_speed_rpm=r.output_speed / RPM,
        torque_basis=one_of(TORQUE_BASES, r.torque_basis), split=split_out(r.split, stages),
        checks=DriveChecksOut(power_balance_error=r.checks.power_balance_error,
                              kinetic_energy_J=r.checks.kinetic_energy,
                              reduced_kinetic_energy_J=r.checks.reduced_kinetic_energy),
        warnings=warnings_out(r.warnings), gears=sized_stages_out(r.gears),
        gear_mass_kg=None if r.gears is None else r.gears.mass, volume_agreement=r.volume_agreement,
    )


def stage_type_out(t: synth.StageType) -> StageTypeOut:
    """Schema from an engine stage type."""
    return StageTypeOut(name=one_of(STAGE_TYPES, t.name), description=t.description, ratio_min=t.ratio_min,
                        ratio_max=t.ratio_max,
                        efficiency=t.efficiency, toothed=t.toothed, volume_coefficient_m3_per_Nm=t.volume_coefficient)
