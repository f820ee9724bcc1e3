"""One machine described once: the linkage and its load, the working speed, the drive, the target, the choices."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

from ..balancing import CounterweightSpec, Weights
from ..errors import InvalidInput
from ..flywheel import GeometrySpec
from ..friction import PairFriction
from ..gearing import CatalogueMotor, InertiaModel, SizingRules, Stage, ToothRules
from ..model import Linkage
from .foundation_chain import ElasticDriveChoice, FoundationChoice, RegulationChoice
from .strength import StrengthChoice

BalancingMode = Literal["none", "static", "full", "optimal"]
Placement = Literal["crank", "motor", "lightest"]
BALANCING_MODES: tuple[BalancingMode, ...] = ("none", "static", "full", "optimal")
#: Finest coefficient of speed fluctuation a machine design takes [-]; 30 times finer than any machine type.
MIN_DELTA = 1e-4


@dataclass(frozen=True, slots=True)
class BalancingChoice:
    """How to balance the linkage: ``mode`` none, static, full or optimal; where counterweights may go
    (``spec``); the optimal mode's dimensionless ``weights`` and ``mass_budget`` [kg]; full mode's counter-rotor
    ``rotor_ratios`` [-]."""

    mode: BalancingMode = "none"
    spec: CounterweightSpec | None = None
    weights: Weights | None = None
    mass_budget: float | None = None
    rotor_ratios: tuple[tuple[str, float], ...] = ()


@dataclass(frozen=True, slots=True)
class FlywheelChoice:
    """Where the flywheel goes: on the ``crank`` shaft, the ``motor`` shaft, or the ``lightest`` shaft that holds
    it; ``geometry`` its shape, material and limits (the candidate shafts are the drive's)."""

    placement: Placement = "lightest"
    geometry: GeometrySpec = field(default_factory=GeometrySpec)


@dataclass(frozen=True, slots=True)
class DriveSpec:
    """The drive from motor to crank: ``stages`` motor side first; a catalogue ``motor`` by name or the smallest
    that covers the power (from ``catalogue``, default the shipped one, within ``synchronous_speed`` [rad/s] if
    given); ``reserve_factor`` [-] on the mean power; the split ``objective``; pinion, load and shaft inertias
    (``inertia`` [kg·m²]); tooth ``rules`` and the relative ratio ``tooth_tolerance`` [-] of the tooth search;
    ``strength`` how the cylindrical stages are sized for the cyclic torque each pinion shaft passes on (None:
    not sized)."""

    stages: tuple[Stage, ...]
    motor: str | None = None
    catalogue: tuple[CatalogueMotor, ...] | None = None
    synchronous_speed: float | None = None
    reserve_factor: float = 1.1
    objective: str = "min_inertia"
    inertia: InertiaModel | None = None
    tooth_rules: ToothRules | None = None
    tooth_tolerance: float | None = None
    strength: SizingRules | None = None


@dataclass(frozen=True, slots=True)
class MachineSpec:
    """A whole machine: a motor drives a train that drives a linkage with a process load.

    ``speed`` the crank's working speed [rad/s]; ``delta`` the target coefficient of speed fluctuation [-];
    ``speed_tolerance`` how far the simulated mean crank speed may lie from ``speed`` [-]; ``samples`` crank
    angles per revolution for every stage of the chain; ``friction`` per pair of the linkage; ``brake_torque``
    at the crank during the run-down [N·m]; ``start_under_load`` the start check holds the process load too;
    ``max_startup_time`` and ``max_rundown_time`` (None: not checked)
    the limits of the start-up and run-down checks [s]; ``foundation``, ``elastic_drive`` and ``regulation`` the
    machine around its linkage (None: not asked).
    """

    linkage: Linkage
    speed: float
    drive: DriveSpec
    delta: float
    balancing: BalancingChoice = field(default_factory=BalancingChoice)
    flywheel: FlywheelChoice = field(default_factory=FlywheelChoice)
    samples: int = 360
    speed_tolerance: float = 0.05
    friction: tuple[PairFriction, ...] = ()
    brake_torque: float = 0.0
    start_under_load: bool = False
    max_startup_time: float = 60.0
    max_rundown_time: float | None = None
    foundation: FoundationChoice | None = None
    elastic_drive: ElasticDriveChoice | None = None
    strength: StrengthChoice | None = None
    regulation: RegulationChoice | None = None

    def validate(self) -> None:
        """InvalidInput naming the field for a speed, target or tolerance out of range, or no stages."""
        if not (math.isfinite(self.speed) and self.speed > 0):
            raise InvalidInput("the crank speed must be positive", field="speed_rpm")
        if not MIN_DELTA <= self.delta < 1:
            raise InvalidInput(f"delta must lie in [{MIN_DELTA:g}, 1): the finest machines of the seeds' table ask "
                               "1/300", field="delta")
        if not 0 < self.speed_tolerance < 1:
            raise InvalidInput("speed_tolerance must lie in (0, 1)", field="speed_tolerance")
        if not (math.isfinite(self.max_startup_time) and self.max_startup_time > 0):
            raise InvalidInput("max_startup_time must be positive", field="max_startup_time_s")
        if self.max_rundown_time is not None and not (math.isfinite(self.max_rundown_time)
                                                      and self.max_rundown_time > 0):
            raise InvalidInput("max_rundown_time must be positive", field="max_rundown_time_s")
        if not self.drive.stages:
            raise InvalidInput("the drive needs at least one stage", field="drive.stages")
        if self.balancing.mode not in BALANCING_MODES:
            raise InvalidInput(f"balancing mode must be one of {BALANCING_MODES}", field="balancing.mode")
