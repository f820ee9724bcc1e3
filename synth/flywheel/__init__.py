"""Flywheel sizing for a target coefficient of speed fluctuation: methods, checks, geometry and figures."""

from .cycle import ReducedCycle, cycle_from_reduced, cycle_from_tables
from .geometry import FlywheelBody, FlywheelDesign, GeometrySpec, PlacementMiss, Shaft, design_flywheel, rim_diameter
from .machine_types import MachineType, admissible_delta, machine_types
from .motor import Motor, MotorSizing, ReducedMotor, motor_constant_inertia, motor_speed_limits
from .problem import FlywheelResult, MethodResult, size_flywheel
from .simulate import SpeedProfile, speed_fluctuation, steady_speed, steady_speed_motor
from .sizing import (
    Tangents,
    energy_extremes,
    energy_method_constant_inertia,
    exact_constant_inertia,
    mertsalov_constant_inertia,
    speed_band,
    wittenbauer_tangents,
)

__all__ = [
    "FlywheelBody",
    "FlywheelDesign",
    "FlywheelResult",
    "GeometrySpec",
    "MachineType",
    "MethodResult",
    "Motor",
    "MotorSizing",
    "PlacementMiss",
    "ReducedCycle",
    "ReducedMotor",
    "Shaft",
    "SpeedProfile",
    "Tangents",
    "admissible_delta",
    "cycle_from_reduced",
    "cycle_from_tables",
    "design_flywheel",
    "energy_extremes",
    "energy_method_constant_inertia",
    "exact_constant_inertia",
    "machine_types",
    "mertsalov_constant_inertia",
    "motor_constant_inertia",
    "motor_speed_limits",
    "rim_diameter",
    "size_flywheel",
    "speed_band",
    "speed_fluctuation",
    "steady_speed",
    "steady_speed_motor",
    "wittenbauer_tangents",
]
