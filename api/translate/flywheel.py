"""POST /v1/flywheel: tables or a linkage, speeds, delta and geometry in; the flywheel and its checks out."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

import synth
from synth.machine import elastic_drive as drives

from api.translate.foundation import elastic_drive_out, elastic_element_from
from api.translate.linkage import degree_list, ensure_finite, warnings_out
from mechsynth_client.schemas.common import one_of
from mechsynth_client.schemas.flywheel import (
    EnergyMassOut,
    FLYWHEEL_SHAPES,
    FlywheelElasticDriveIn,
    FlywheelIn,
    FlywheelOut,
    FlywheelPlacementOut,
    FlywheelTablesIn,
    GeometryIn,
    GeometryOut,
    MACHINE_TYPES,
    MachineTypeOut,
    MethodOut,
    PlacementMissOut,
    SIZING_METHODS,
    SpeedOut,
)


def cycle_from(tables: FlywheelTablesIn, cycle_deg: float, max_samples: int) -> synth.ReducedCycle:
    """Engine cycle; degrees become radians here."""
    return synth.cycle_from_tables(
        [math.radians(a) for a in tables.crank_angle_deg],
        reduced_inertia=tables.reduced_inertia_kgm2,
        reduced_torque=tables.reduced_torque_Nm,
        driving_torque=tables.driving_torque_Nm,
        resisting_torque=tables.resisting_torque_Nm,
        period=math.radians(cycle_deg),
        max_samples=max_samples,
        balance=tables.constant_torque_role,
    )


def link_stiffness(drive: FlywheelElasticDriveIn) -> float:
    """The link's stiffness at the crank, given or from its elements; InvalidInput naming the field."""
    if (drive.stiffness_Nm_rad is None) == (not drive.elements):
        raise synth.InvalidInput("give the link's stiffness_Nm_rad or its elements, one of the two",
                                 field="elastic_drive.stiffness_Nm_rad")
    if drive.stiffness_Nm_rad is not None:
        return drive.stiffness_Nm_rad
    try:
        elements = tuple(elastic_element_from(e, k) for k, e in enumerate(drive.elements))
        return float(drives.link_stiffness(elements))
    except synth.InvalidInput as error:
        raise synth.InvalidInput(str(error), field=f"elastic_drive.{error.field}") from error


def geometry_from(geometry: GeometryIn) -> synth.GeometrySpec:
    """Engine geometry specification."""
    return synth.GeometrySpec(
        shape=geometry.shape,
        density=geometry.density_kg_m3,
        max_rim_speed=geometry.max_rim_speed_m_s,
        allowable_stress=geometry.allowable_stress_Pa,
        max_diameter=geometry.max_diameter_m,
        thickness_ratio=(geometry.thickness_ratio[0], geometry.thickness_ratio[1]),
        width_ratio=(geometry.width_ratio[0], geometry.width_ratio[1]),
        shafts=tuple(synth.Shaft(s.name, s.speed_ratio) for s in geometry.shafts),
    )


def mean_speed_of(body: FlywheelIn) -> float:
    """w_m [rad/s] from whichever mean speed is given (``speed_rpm`` for a linkage when it is the only one)."""
    given = [v for v in (body.mean_speed_rpm, body.mean_speed_rad_s) if v is not None]
    if len(given) > 1:
        raise synth.InvalidInput("give mean_speed_rpm or mean_speed_rad_s, not both", field="mean_speed_rad_s")
    if body.mean_speed_rad_s is not None:
        speed = body.mean_speed_rad_s
    elif body.mean_speed_rpm is not None:
        speed = body.mean_speed_rpm * math.pi / 30
    elif body.mechanism is not None and body.speed_rpm is not None:
        speed = body.speed_rpm * math.pi / 30
    else:
        raise synth.InvalidInput("give mean_speed_rpm or mean_speed_rad_s", field="mean_speed_rpm")
    if body.speed_rpm is not None and not math.isclose(speed, body.speed_rpm * math.pi / 30, rel_tol=1e-12):
        raise synth.InvalidInput("speed_rpm differs from the mean speed; give one of them", field="speed_rpm")
    return speed


def target_delta(body: FlywheelIn) -> float:
    """The target delta, or the tightest admissible value of the machine type."""
    if (body.delta is None) == (body.machine_type is None):
        raise synth.InvalidInput("give delta or machine_type (one of them)", field="delta")
    return body.delta if body.delta is not None else synth.admissible_delta(str(body.machine_type))


def uses_tables(body: FlywheelIn) -> bool:
    """True for tables, False for a linkage; InvalidInput unless exactly one is given."""
    if (body.tables is None) == (body.mechanism is None):
        raise synth.InvalidInput("give tables or a mechanism (one of them)", field="tables")
    if body.tables is not None:
        for name in ("loads", "torques", "counterweights", "gravity", "speed_rpm", "crank_angle_deg", "friction"):
            if getattr(body, name):
                raise synth.InvalidInput(f"{name} belongs to a linkage; tables already hold the torques", field=name)
    if body.mechanism is not None:
        if body.cycle_deg != 360:
            raise synth.InvalidInput("a linkage's cycle is one crank revolution", field="cycle_deg")
        if body.crank_angle_deg is not None:
            raise synth.InvalidInput("a flywheel needs the whole cycle: use samples", field="crank_angle_deg")
        if body.crank_acceleration_rad_s2 != 0:
            raise synth.InvalidInput(
                "steady motion has no mean crank acceleration", field="crank_acceleration_rad_s2")
    return body.tables is not None


def machine_type_out(row: synth.MachineType) -> MachineTypeOut:
    """Schema from an engine table row."""
    return MachineTypeOut(
        machine_type=one_of(MACHINE_TYPES, row.name), label=row.label, delta_min=row.delta_min,
        delta_max=row.delta_max,
        default_delta=row.default_delta,
    )


def method_out(m: synth.MethodResult, target: float) -> MethodOut:
    """Schema from an engine method result."""
    return MethodOut(
        method=one_of(SIZING_METHODS, m.method),
        required_constant_inertia_kgm2=m.required_constant_inertia,
        flywheel_inertia_kgm2=m.flywheel_inertia,
        achieved_delta=m.achieved_delta,
        delta_error_rel=m.achieved_delta / target - 1,
        omega_min_rad_s=m.speed.omega_min,
        omega_max_rad_s=m.speed.omega_max,
        stalls=m.speed.stalls,
    )


def flywheel_placement_out(b: synth.FlywheelBody) -> FlywheelPlacementOut:
    """Schema from an engine flywheel body."""
    return FlywheelPlacementOut(
        shaft=b.shaft, speed_ratio=b.speed_ratio, shape=one_of(FLYWHEEL_SHAPES, b.shape), inertia_kgm2=b.inertia,
        diameter_m=b.diameter,
        outer_diameter_m=b.outer_diameter, rim_thickness_m=b.thickness, width_m=b.width, mass_kg=b.mass,
        rim_speed_m_s=b.rim_speed, inertia_check_kgm2=b.inertia_check,
    )


def flywheel_out(r: synth.FlywheelResult, warnings: list[synth.DesignWarning] | None = None,
                 drive: Any = None) -> FlywheelOut:
    """Schema from the engine result (radians become degrees here), with the elastic drive's when given."""
    elastic = None if drive is None else elastic_drive_out(drive)
    near = [] if elastic is None else [w.model_copy(update={"field": f"elastic_drive.{w.field}"})
                                       for w in elastic.warnings]
    design, tan = r.design, r.tangents
    w_min, w_max = r.speed_band
    phi, omega = design.speed.thinned()
    work = r.cycle.work_nodes()[:-1]
    ensure_finite(omega, work, np.array([m.required_constant_inertia for m in r.methods]))
    geometry = None
    if r.geometry is not None:
        geometry = GeometryOut(
            best=flywheel_placement_out(r.geometry.best),
            placements=[flywheel_placement_out(b) for b in r.geometry.bodies],
            misses=[
                PlacementMissOut(shaft=m.shaft, speed_ratio=m.speed_ratio, constraint=m.constraint,
                                 max_inertia_kgm2=m.max_inertia)
                for m in r.geometry.misses
            ],
        )
    return FlywheelOut(
        flywheel_inertia_kgm2=design.flywheel_inertia,
        required_constant_inertia_kgm2=design.required_constant_inertia,
        achieved_delta=design.achieved_delta,
        target_delta=r.target_delta,
        mean_speed_rad_s=r.mean_speed,
        omega_min_rad_s=w_min,
        omega_max_rad_s=w_max,
        constant_inertia_kgm2=r.constant_inertia,
        constant_driving_torque_Nm=r.driving_torque,
        constant_torque_role=r.cycle.balance,
        cycle_work_J=r.cycle_work,
        motor_mean_speed_rad_s=r.motor_mean_speed,
        design_method=one_of(SIZING_METHODS, r.design_method),
        methods=[method_out(m, r.target_delta) for m in r.methods],
        energy_mass=EnergyMassOut(
            crank_angle_deg=degree_list(r.cycle.phi),
            reduced_inertia_kgm2=r.cycle.inertia.tolist(),
            excess_work_J=work.tolist(),
            tangent_max_slope_J_per_kgm2=tan.slope_max,
            tangent_max_intercept_J=tan.intercept_max,
            tangent_min_slope_J_per_kgm2=tan.slope_min,
            tangent_min_intercept_J=tan.intercept_min,
        ),
        speed=SpeedOut(method=one_of(SIZING_METHODS, design.method), crank_angle_deg=degree_list(phi),
                       omega_rad_s=omega.tolist()),
        geometry=geometry,
        warnings=[*warnings_out(warnings or []), *near],
        elastic_drive=elastic,
    )
