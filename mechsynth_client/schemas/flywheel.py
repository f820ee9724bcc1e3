"""Schemas of POST /v1/flywheel and GET /v1/machine-types."""

from __future__ import annotations

import importlib
import math
from typing import Annotated, Any, Literal, get_args

from pydantic import BaseModel, ConfigDict, Field
from pydantic.config import JsonDict

from ._engine import np, synth
from .foundation import ElasticDriveOut, ElasticElementIn
from .motor import MotorIn
from .common import (
    at_most_one,
    exactly_one,
    given,
    service_limit,
    FOURBAR_EXAMPLE,
    MAX_INERTIA_KGM2,
    FrictionIn,
    LinkageFields,
    MechanismIn,
    StrictModel,
    WarningOut,
    degree_list,
    ensure_finite,
    one_of,
    pair_frictions,
    warnings_out,
)

# Torques far beyond any machine's, so that the cycle's work cannot overflow.
Torque = Annotated[float, Field(ge=-1e9, le=1e9)]

# The coursework's reduced resisting torque of a gear-shaper over one revolution (seed 002:104-123), closed at 360.
SHAPER_TABLES_EXAMPLE: JsonDict = {
    "crank_angle_deg": [0, 60, 120, 180, 240, 300, 360],
    "resisting_torque_Nm": [-1.7, -1500.6, -1496.7, -385.74, -145.33, -250.0, -1.7],
    "driving_torque_Nm": [0, 0, 0, 0, 0, 0, 0],
}


class FlywheelTablesIn(StrictModel):
    """The machine reduced to its crank, tabulated over one cycle (linear between rows)."""

    crank_angle_deg: list[Annotated[float, Field(ge=-1e5, le=1e5)]] = Field(
        min_length=3, json_schema_extra=service_limit("max_samples"), examples=[[0, 60, 120, 180, 240, 300, 360]],
        description="Strictly increasing crank angles [deg]; a last row at first + cycle_deg closes it.",
    )
    reduced_inertia_kgm2: list[Annotated[float, Field(ge=0, le=MAX_INERTIA_KGM2)]] | None = Field(
        None, description="Reduced inertia J_red of the mechanism at each angle [kg·m²]; left out: zero."
    )
    reduced_torque_Nm: list[Torque] | None = Field(
        None, description="Sum of driving and resisting reduced torques [N·m], positive drives the crank."
    )
    driving_torque_Nm: list[Torque] | None = Field(None, description="Reduced driving torque [N·m].")
    resisting_torque_Nm: list[Torque] | None = Field(
        None, description="Reduced resisting torque [N·m], negative where it resists."
    )
    constant_torque_role: Literal["driving", "resisting"] | None = Field(
        None, description="Which side the constant torque that balances the cycle's work takes: `driving` (the "
        "tables are the loads) or `resisting` (the tables are the drive, e.g. an engine's gas torque over 720°, "
        "and the constant torque is the consumer's load). Left out: `resisting` when only `driving_torque_Nm` is "
        "given, `driving` otherwise.",
    )

    def to_cycle(self, cycle_deg: float, max_samples: int) -> synth.ReducedCycle:
        """Engine cycle; degrees become radians here."""
        return synth.cycle_from_tables(
            [math.radians(a) for a in self.crank_angle_deg],
            reduced_inertia=self.reduced_inertia_kgm2,
            reduced_torque=self.reduced_torque_Nm,
            driving_torque=self.driving_torque_Nm,
            resisting_torque=self.resisting_torque_Nm,
            period=math.radians(cycle_deg),
            max_samples=max_samples,
            balance=self.constant_torque_role,
        )


class FlywheelElasticDriveIn(StrictModel):
    """The motor's rotor joined to the machine by an elastic link, with the flywheel this request sizes on one side
    of it: the two-mass drive of POST /v1/machines/elastic-drive, reduced to the crank."""

    stiffness_Nm_rad: float | None = Field(None, gt=0, le=1e12, description="The link's torsional stiffness "
                                           "reduced to the crank [N·m/rad]; or give `elements`.")
    elements: list[ElasticElementIn] = Field(default_factory=list, max_length=16, description="Shafts and "
                                             "couplings of the link, in series, each reduced by its speed ratio "
                                             "squared.")
    flywheel_on: Literal["crank", "motor_shaft"] = Field(
        "crank", description="Where the flywheel sits: `crank`: with the machine (the link's second mass); "
        "`motor_shaft`: with the rotor (the first mass), its inertia on that shaft the crank's over the gear ratio "
        "squared.")
    motor_side_inertia_kgm2: float = Field(0.0, ge=0, le=MAX_INERTIA_KGM2, description="Inertia on the motor "
                                           "shaft besides the rotor and the flywheel (coupling half) [kg·m²].")
    damping_ratio: float = Field(0.05, ge=0, le=2, description="The link's damping as a ratio of the two-mass "
                                 "mode's critical damping [-].")
    start: bool = Field(False, description="Also simulate the run-up from rest with the elastic link.")

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"stiffness_Nm_rad": 2000, "flywheel_on": "crank"},
        {"elements": [{"type": "shaft", "speed_ratio": 3.0, "diameter_m": 0.03, "length_m": 0.4},
                      {"type": "coupling", "speed_ratio": 3.0, "stiffness_Nm_rad": 2e3}],
         "flywheel_on": "motor_shaft", "start": True}]})

    def link_stiffness(self) -> float:
        """The link's stiffness at the crank, given or from its elements; InvalidInput naming the field."""
        if (self.stiffness_Nm_rad is None) == (not self.elements):
            raise synth.InvalidInput("give the link's stiffness_Nm_rad or its elements, one of the two",
                                     field="elastic_drive.stiffness_Nm_rad")
        if self.stiffness_Nm_rad is not None:
            return self.stiffness_Nm_rad
        try:
            elements = tuple(e.to_engine(k) for k, e in enumerate(self.elements))
            return float(importlib.import_module("synth.machine.elastic_drive").link_stiffness(elements))
        except synth.InvalidInput as error:
            raise synth.InvalidInput(str(error), field=f"elastic_drive.{error.field}") from error


class ShaftIn(StrictModel):
    """A shaft of the drive that may carry the flywheel."""

    name: str = Field(min_length=1, max_length=40, description="Name of the shaft in the answer.",
                      examples=["motor"])
    speed_ratio: float = Field(ge=1e-4, le=1e5, description="Shaft speed over crank speed [-].", examples=[19.45])


Ratio = Annotated[list[Annotated[float, Field(gt=0, le=10)]], Field(min_length=2, max_length=2)]
MachineType = Literal[
    "ac_generators", "dc_generators", "internal_combustion_engines", "piston_compressors", "metal_cutting_machine_tools"
]
SizingMethod = Literal["exact", "mertsalov", "energy", "motor_nlp", "simulated"]
MACHINE_TYPES: tuple[MachineType, ...] = get_args(MachineType)
SIZING_METHODS: tuple[SizingMethod, ...] = get_args(SizingMethod)
FLYWHEEL_SHAPES: tuple[Literal["rim", "disc"], ...] = ("rim", "disc")


class GeometryIn(StrictModel):
    """Shape, material and limits of the flywheel, and the shafts it may sit on (the crank shaft always)."""

    shape: Literal["rim", "disc"] = Field("rim", description="rim: a heavy rim on spokes; disc: a solid disc.")
    density_kg_m3: float = Field(7200.0, ge=1, le=1e5, description="Cast iron 7200, steel 7850 [kg/m³].")
    max_rim_speed_m_s: float | None = Field(30.0, gt=0, le=1e4, description="At the outer radius; cast iron 25-30 [m/s].")
    allowable_stress_Pa: float | None = Field(None, ge=1, le=1e12, description="Allowable hoop (rim) or centre (disc) stress.")
    max_diameter_m: float | None = Field(None, ge=1e-4, le=1e3, description="Largest outer diameter [m].")
    thickness_ratio: Ratio = Field([0.1, 0.2], description="Rim radial thickness a over mean diameter D: [min, max].")
    width_ratio: Ratio = Field([0.1, 0.2], description="Width b over diameter D: [min, max].")
    shafts: list[ShaftIn] = Field(default_factory=list, max_length=20,
                                  description="Faster shafts that may carry it instead of the crank shaft.")

    def to_engine(self) -> synth.GeometrySpec:
        """Engine geometry specification."""
        return synth.GeometrySpec(
            shape=self.shape,
            density=self.density_kg_m3,
            max_rim_speed=self.max_rim_speed_m_s,
            allowable_stress=self.allowable_stress_Pa,
            max_diameter=self.max_diameter_m,
            thickness_ratio=(self.thickness_ratio[0], self.thickness_ratio[1]),
            width_ratio=(self.width_ratio[0], self.width_ratio[1]),
            shafts=tuple(synth.Shaft(s.name, s.speed_ratio) for s in self.shafts),
        )


class FlywheelIn(LinkageFields):
    """Flywheel sizing: the machine as tables or as a linkage with loads, the mean speed and the target delta."""

    mechanism: MechanismIn | None = Field(None, description="A linkage instead of tables (with its loads).")
    speed_rpm: float | None = Field(None, ge=1e-3, le=1e6, description="A linkage's crank speed: same as mean_speed_rpm.")
    tables: FlywheelTablesIn | None = Field(None, description="The reduced machine as tables over one cycle.")
    cycle_deg: Literal[360, 720] = Field(360, description="Cycle length: 720 for a four-stroke engine (tables only).")
    mean_speed_rpm: float | None = Field(None, ge=1e-3, le=1e6, description="(w_max + w_min)/2 [rev/min].")
    mean_speed_rad_s: float | None = Field(None, ge=1e-4, le=1e5, description="(w_max + w_min)/2 [rad/s].")
    delta: float | None = Field(None, gt=0, lt=1, description="Target (w_max - w_min)/w_mean [-].")
    machine_type: MachineType | None = Field(None, description="Machine type of GET /v1/machine-types: its tightest delta.")
    constant_inertia_kgm2: float = Field(0.0, ge=0, le=MAX_INERTIA_KGM2, description="Constant inertia already on the crank [kg·m²].")
    motor: MotorIn | None = Field(None, description="Motor characteristic; left out: constant driving torque.")
    geometry: GeometryIn | None = Field(None, description="Shape and place the flywheel; left out: size it only.")
    friction: FrictionIn | None = Field(None, description="A linkage's friction per pair: its losses at the mean "
                                        "speed are taken off the reduced load torque, so the flywheel and the motor "
                                        "are sized for the machine with its losses.")
    elastic_drive: FlywheelElasticDriveIn | None = Field(
        None, description="A linkage's drive with an elastic link between the `motor` (needed) and the machine, "
        "the sized flywheel on the crank or the motor shaft: natural frequencies, the torque in the link over the "
        "steady cycle against the rigid model's, the load harmonics near resonance and, when asked, the run-up.")

    def frictions(self) -> tuple[synth.PairFriction, ...]:
        """Engine pair frictions of the ``friction`` block."""
        return pair_frictions(self.friction)

    model_config = ConfigDict(
        json_schema_extra={
            # the rules mean_speed() and target_delta() apply, as JSON Schema states them
            "allOf": [exactly_one("tables", "mechanism"), exactly_one("delta", "machine_type"),
                      at_most_one("mean_speed_rpm", "mean_speed_rad_s"),
                      {"anyOf": [given("mean_speed_rpm"), given("mean_speed_rad_s"), given("mechanism", "speed_rpm")]},
                      {"anyOf": [{"not": given("elastic_drive")}, given("elastic_drive", "motor", "mechanism")]}],
            "examples": [
                {"tables": SHAPER_TABLES_EXAMPLE, "mean_speed_rad_s": 9.8, "delta": 0.1,
                 "geometry": {"density_kg_m3": 7850, "max_rim_speed_m_s": 45, "max_diameter_m": 0.75,
                              "shafts": [{"name": "motor", "speed_ratio": 19.45}]}},
                {"mechanism": FOURBAR_EXAMPLE, "mean_speed_rpm": 300, "machine_type": "piston_compressors",
                 "loads": [{"type": "window", "torque_Nm": 40, "start_deg": 0, "end_deg": 180}],
                 "constant_inertia_kgm2": 0.002},
                {"mechanism": FOURBAR_EXAMPLE, "mean_speed_rpm": 298, "delta": 0.01,
                 "loads": [{"type": "window", "torque_Nm": 40, "start_deg": 0, "end_deg": 180}],
                 "motor": {"synchronous_speed_rpm": 1500, "rated_speed_rpm": 1420, "rated_torque_Nm": 10,
                           "gear_ratio": 5, "rotor_inertia_kgm2": 0.005},
                 "elastic_drive": {"stiffness_Nm_rad": 2000, "flywheel_on": "crank"}},
            ]
        }
    )

    def mean_speed(self) -> float:
        """w_m [rad/s] from whichever mean speed is given (``speed_rpm`` for a linkage when it is the only one)."""
        given = [v for v in (self.mean_speed_rpm, self.mean_speed_rad_s) if v is not None]
        if len(given) > 1:
            raise synth.InvalidInput("give mean_speed_rpm or mean_speed_rad_s, not both", field="mean_speed_rad_s")
        if self.mean_speed_rad_s is not None:
            speed = self.mean_speed_rad_s
        elif self.mean_speed_rpm is not None:
            speed = self.mean_speed_rpm * math.pi / 30
        elif self.mechanism is not None and self.speed_rpm is not None:
            speed = self.speed_rpm * math.pi / 30
        else:
            raise synth.InvalidInput("give mean_speed_rpm or mean_speed_rad_s", field="mean_speed_rpm")
        if self.speed_rpm is not None and not math.isclose(speed, self.speed_rpm * math.pi / 30, rel_tol=1e-12):
            raise synth.InvalidInput("speed_rpm differs from the mean speed; give one of them", field="speed_rpm")
        return speed

    def target_delta(self) -> float:
        """The target delta, or the tightest admissible value of the machine type."""
        if (self.delta is None) == (self.machine_type is None):
            raise synth.InvalidInput("give delta or machine_type (one of them)", field="delta")
        return self.delta if self.delta is not None else synth.admissible_delta(str(self.machine_type))

    def uses_tables(self) -> bool:
        """True for tables, False for a linkage; InvalidInput unless exactly one is given."""
        if (self.tables is None) == (self.mechanism is None):
            raise synth.InvalidInput("give tables or a mechanism (one of them)", field="tables")
        if self.tables is not None:
            for name in ("loads", "torques", "counterweights", "gravity", "speed_rpm", "crank_angle_deg", "friction"):
                if getattr(self, name):
                    raise synth.InvalidInput(f"{name} belongs to a linkage; tables already hold the torques", field=name)
        if self.mechanism is not None:
            if self.cycle_deg != 360:
                raise synth.InvalidInput("a linkage's cycle is one crank revolution", field="cycle_deg")
            if self.crank_angle_deg is not None:
                raise synth.InvalidInput("a flywheel needs the whole cycle: use samples", field="crank_angle_deg")
            if self.crank_acceleration_rad_s2 != 0:
                raise synth.InvalidInput("steady motion has no mean crank acceleration", field="crank_acceleration_rad_s2")
        return self.tables is not None


class MachineTypeOut(BaseModel):
    """Admissible coefficient of speed fluctuation of one machine type (seed 003:443-453)."""

    machine_type: MachineType = Field(description="Identifier to give as a request's `machine_type`.")
    label: str = Field(description="The machine type in words, as the seeds' table names it.")
    delta_min: float = Field(description="Smallest admissible coefficient of speed fluctuation (w_max - w_min)/w_mean "
                             "of the range [-].")
    delta_max: float = Field(description="Largest admissible coefficient of speed fluctuation of the range [-].")
    default_delta: float = Field(description="The tightest value, used when a request names this machine type.")

    @classmethod
    def from_engine(cls, row: synth.MachineType) -> MachineTypeOut:
        """Schema from an engine table row."""
        return cls(
            machine_type=one_of(MACHINE_TYPES, row.name), label=row.label, delta_min=row.delta_min,
            delta_max=row.delta_max,
            default_delta=row.default_delta,
        )


class MethodOut(BaseModel):
    """One sizing method and the steady motion its inertia gives, found by integrating the equation of motion."""

    method: SizingMethod = Field(
        description="simulated (whole-machine design only): the motor NLP's inertia raised until the simulated "
        "machine, looked at between the samples too, meets the target.")
    required_constant_inertia_kgm2: float = Field(description="Constant inertia needed on top of J_red(phi).")
    flywheel_inertia_kgm2: float = Field(description="Inertia to add to the constant inertia already there.")
    achieved_delta: float = Field(description="Delta of the simulated steady motion (2 when the machine stalls).")
    delta_error_rel: float = Field(description="achieved_delta / target delta - 1.")
    omega_min_rad_s: float = Field(description="Lowest crank speed of the simulated steady motion over the cycle "
                                   "[rad/s].")
    omega_max_rad_s: float = Field(description="Highest crank speed of the simulated steady motion [rad/s].")
    stalls: bool = Field(description="The simulated speed falls to zero within the cycle: no steady motion at this "
                         "mean speed (achieved_delta is then 2).")

    @classmethod
    def from_engine(cls, m: synth.MethodResult, target: float) -> MethodOut:
        """Schema from an engine method result."""
        return cls(
            method=one_of(SIZING_METHODS, m.method),
            required_constant_inertia_kgm2=m.required_constant_inertia,
            flywheel_inertia_kgm2=m.flywheel_inertia,
            achieved_delta=m.achieved_delta,
            delta_error_rel=m.achieved_delta / target - 1,
            omega_min_rad_s=m.speed.omega_min,
            omega_max_rad_s=m.speed.omega_max,
            stalls=m.speed.stalls,
        )


class EnergyMassOut(BaseModel):
    """The energy-mass (Wittenbauer) diagram: excess work over J_red at the samples, and its limit tangents."""

    crank_angle_deg: list[float] = Field(description="Crank angle of each sample of the cycle as sized [deg].")
    reduced_inertia_kgm2: list[float] = Field(description="Reduced inertia J_red of the variable-inertia part at "
                                              "each sample [kg·m²], constant inertia excluded.")
    excess_work_J: list[float] = Field(description="Excess work A(phi) at each sample: the work of the reduced "
                                       "torques, balanced over the cycle by a constant driving torque, from the "
                                       "first sample [J].")
    tangent_max_slope_J_per_kgm2: float = Field(description="w_max²/2.")
    tangent_max_intercept_J: float = Field(description="Work-axis intercept of the upper tangent, of slope "
                                           "w_max²/2: the largest A - (w_max²/2)·J_red over the cycle [J].")
    tangent_min_slope_J_per_kgm2: float = Field(description="w_min²/2.")
    tangent_min_intercept_J: float = Field(description="Work-axis intercept of the lower tangent, of slope "
                                           "w_min²/2: the smallest A - (w_min²/2)·J_red over the cycle [J].")


class SpeedOut(BaseModel):
    """Simulated steady crank speed over the cycle of the design method."""

    method: SizingMethod = Field(description="The method whose inertia was simulated (the design method).")
    crank_angle_deg: list[float] = Field(description="Crank angles over one cycle [deg]: at most 721 points of the "
                                         "dense simulation, evenly picked, both ends kept.")
    omega_rad_s: list[float] = Field(description="Simulated crank speed at each of those angles [rad/s].")


class FlywheelPlacementOut(BaseModel):
    """A flywheel on one shaft; ``inertia_check_kgm2`` is recomputed from the dimensions."""

    shaft: str = Field(description="Shaft that carries it: crank, or a name from `geometry.shafts`.")
    speed_ratio: float = Field(description="Shaft speed over crank speed [-].")
    shape: Literal["rim", "disc"] = Field(description="rim: a rim on spokes; disc: a solid disc.")
    inertia_kgm2: float = Field(description="Inertia on this shaft: crank-shaft inertia / speed_ratio².")
    diameter_m: float = Field(description="Mean rim diameter (disc: outer diameter).")
    outer_diameter_m: float = Field(description="Outer diameter, mean diameter plus rim thickness (disc: the "
                                    "diameter) [m].")
    rim_thickness_m: float | None = Field(description="Radial thickness of the rim [m]; null for a disc.")
    width_m: float = Field(description="Axial width of the rim or disc [m].")
    mass_kg: float = Field(description="Mass of the rim (spokes and hub not counted) or of the disc [kg].")
    rim_speed_m_s: float = Field(description="Speed of the outer rim at the shaft's largest simulated speed "
                                 "[m/s].")
    inertia_check_kgm2: float = Field(description="Inertia about the shaft recomputed from the dimensions and "
                                      "density [kg·m²]; equals inertia_kgm2 to the solver's tolerance.")

    @classmethod
    def from_engine(cls, b: synth.FlywheelBody) -> FlywheelPlacementOut:
        """Schema from an engine flywheel body."""
        return cls(
            shaft=b.shaft, speed_ratio=b.speed_ratio, shape=one_of(FLYWHEEL_SHAPES, b.shape), inertia_kgm2=b.inertia,
            diameter_m=b.diameter,
            outer_diameter_m=b.outer_diameter, rim_thickness_m=b.thickness, width_m=b.width, mass_kg=b.mass,
            rim_speed_m_s=b.rim_speed, inertia_check_kgm2=b.inertia_check,
        )


class PlacementMissOut(BaseModel):
    """A shaft that cannot carry the flywheel and the limit that binds there."""

    shaft: str = Field(description="Shaft that cannot carry it.")
    speed_ratio: float = Field(description="Shaft speed over crank speed [-].")
    constraint: str = Field(description="The geometry limit that binds there: max_rim_speed_m_s, "
                            "allowable_stress_Pa or max_diameter_m.")
    max_inertia_kgm2: float = Field(description="Largest inertia on this shaft within the limits.")


class GeometryOut(BaseModel):
    """The lightest flywheel and every shaft's outcome."""

    best: FlywheelPlacementOut = Field(description="The lightest flywheel over every shaft that can carry one.")
    placements: list[FlywheelPlacementOut] = Field(description="The least-mass flywheel on each shaft that can "
                                                   "carry it, the crank shaft first.")
    misses: list[PlacementMissOut] = Field(description="Shafts that cannot carry it within the limits.")


class FlywheelOut(BaseModel):
    """Flywheel sizing by every method, each checked by the simulated equation of motion.

    The top-level inertia, ``achieved_delta``, the geometry and ``speed`` all come from one method,
    ``design_method``: exact (Wittenbauer) for a constant driving torque, ``motor_nlp`` when a motor is given.
    """

    flywheel_inertia_kgm2: float = Field(description="Inertia to add on the crank, design method.")
    required_constant_inertia_kgm2: float = Field(description="Constant inertia needed on top of J_red, design method.")
    achieved_delta: float = Field(description="Simulated delta with the design method's inertia.")
    target_delta: float = Field(description="Target coefficient of speed fluctuation (w_max - w_min)/w_mean: the "
                                "request's delta or its machine type's tightest value [-].")
    mean_speed_rad_s: float = Field(description="Target mean crank speed w_m = (w_max + w_min)/2 [rad/s].")
    omega_min_rad_s: float = Field(description="Target w_m(1 - delta/2).")
    omega_max_rad_s: float = Field(description="Target w_m(1 + delta/2).")
    constant_inertia_kgm2: float = Field(description="Constant inertia already on the crank, motor rotor included.")
    constant_driving_torque_Nm: float = Field(description="Constant torque that balances the cycle's work, positive "
                                              "where it drives the crank (negative: a constant resistance).")
    constant_torque_role: Literal["driving", "resisting"] = Field(
        "driving", description="The side the constant torque takes: `driving` (the given torques are loads) or "
        "`resisting` (they are the drive, an engine's; the constant torque is then the consumer's load).")
    cycle_work_J: float = Field(description="Work of the given torques over the cycle, before that balance.")
    motor_mean_speed_rad_s: float | None = Field(None, description="Angle-average steady speed with the motor.")
    design_method: SizingMethod = Field(description="The method the top-level figures, the geometry and `speed` "
                                        "come from: exact for a constant driving torque, motor_nlp with a motor "
                                        "(simulated when a whole-machine design had to raise it).")
    methods: list[MethodOut] = Field(description="Every sizing method side by side, each with the steady motion "
                                     "its inertia gives.")
    energy_mass: EnergyMassOut = Field(description="The energy-mass (Wittenbauer) diagram with both limit "
                                       "tangents.")
    speed: SpeedOut = Field(description="The design method's simulated crank speed over the cycle.")
    geometry: GeometryOut | None = Field(None, description="The flywheel's shape on each candidate shaft; null "
                                         "without `geometry` in the request or when no flywheel is needed.")
    warnings: list[WarningOut] = Field(default_factory=list, description="Likely mistakes in the request.")
    elastic_drive: ElasticDriveOut | None = Field(
        None, description="The drive through the elastic link with the sized flywheel (as POST "
        "/v1/machines/elastic-drive answers it); null when the request has no `elastic_drive`. Its load "
        "harmonics near resonance are also among `warnings`, their field under `elastic_drive`.")

    @classmethod
    def from_engine(cls, r: synth.FlywheelResult, warnings: list[synth.DesignWarning] | None = None,
                    drive: Any = None) -> FlywheelOut:
        """Schema from the engine result (radians become degrees here), with the elastic drive's when given."""
        elastic = None if drive is None else ElasticDriveOut.from_engine(drive)
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
                best=FlywheelPlacementOut.from_engine(r.geometry.best),
                placements=[FlywheelPlacementOut.from_engine(b) for b in r.geometry.bodies],
                misses=[
                    PlacementMissOut(shaft=m.shaft, speed_ratio=m.speed_ratio, constraint=m.constraint,
                                     max_inertia_kgm2=m.max_inertia)
                    for m in r.geometry.misses
                ],
            )
        return cls(
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
            methods=[MethodOut.from_engine(m, r.target_delta) for m in r.methods],
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
