"""Schemas of POST /v1/flywheel and GET /v1/machine-types."""

from __future__ import annotations

from typing import Annotated, Literal, get_args

from pydantic import BaseModel, ConfigDict, Field
from pydantic.config import JsonDict

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


class MachineTypeOut(BaseModel):
    """Admissible coefficient of speed fluctuation of one machine type (seed 003:443-453)."""

    machine_type: MachineType = Field(description="Identifier to give as a request's `machine_type`.")
    label: str = Field(description="The machine type in words, as the seeds' table names it.")
    delta_min: float = Field(description="Smallest admissible coefficient of speed fluctuation (w_max - w_min)/w_mean "
                             "of the range [-].")
    delta_max: float = Field(description="Largest admissible coefficient of speed fluctuation of the range [-].")
    default_delta: float = Field(description="The tightest value, used when a request names this machine type.")


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
