"""Schemas of the drive-design endpoints: POST /v1/gears/split, /v1/gears/teeth, /v1/gears/drive."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Annotated, Literal, get_args

from pydantic import BaseModel, ConfigDict, Field, model_validator

from .common import (
    MAX_INERTIA_KGM2,
    StrictModel,
    WarningOut,
    at_least_one,
    at_most_one,
    exactly_one,
    given,
    service_limit,
)
from .rating import SizedStageOut, StrengthIn

_SPEEDS = ("motor_speed_rpm", "motor_speed_rad_s", "output_speed_rpm", "output_speed_rad_s")
# The engine's bounds (synth.gearing.teeth): the schemas load without the engine.
MIN_PRESSURE_ANGLE_DEG = 10.0
MAX_PRESSURE_ANGLE_DEG = 30.0

RPM = math.pi / 30.0

STAGE_TYPES: tuple[StageType, ...] = ("spur", "helical", "open_spur", "bevel", "planetary", "worm", "belt", "chain")
if TYPE_CHECKING:
    StageType = Literal["spur", "helical", "open_spur", "bevel", "planetary", "worm", "belt", "chain"]
else:
    # A Literal for the type checker; at run time the engine checks the name against its table, so that the
    # answer names the stage (`stages[1].type`) and lists the types, where a Literal inside the count-or-list
    # union would answer "stages: Input should be a valid integer".
    StageType = Annotated[str, Field(json_schema_extra={"enum": list(STAGE_TYPES)})]
Objective = Literal["min_inertia", "min_volume", "handbook"]
OBJECTIVES: tuple[Objective, ...] = get_args(Objective)
TorqueBasis = Literal["load", "rated"]
TORQUE_BASES: tuple[TorqueBasis, ...] = get_args(TorqueBasis)


class StageIn(StrictModel):
    """A stage of the layout: a type from the table (GET /v1/gears/stage-types) with optional overrides."""

    type: StageType = Field(description="Stage type: spur, helical, open_spur, bevel, planetary, worm, belt, chain.",
                            examples=["helical"])
    ratio_min: float | None = Field(None, gt=0, le=1e4, description="Smallest admissible stage ratio [-].")
    ratio_max: float | None = Field(None, gt=0, le=1e4, description="Largest admissible stage ratio [-].")
    efficiency: float | None = Field(None, gt=0, le=1, description="Stage efficiency incl. its bearings [-].")
    ratio: float | None = Field(None, gt=0, le=1e4, description="Fixed stage ratio (a standard ratio, say) [-].")


# Bounded here, before anything is allocated per stage; the service setting max_stages may lower it.
MAX_STAGES = 12
StagesIn = (Annotated[int, Field(ge=1, le=MAX_STAGES, json_schema_extra=service_limit("max_stages"))]
            | Annotated[list[StageType | StageIn], Field(min_length=1, max_length=MAX_STAGES,
                                                         json_schema_extra=service_limit("max_stages"))])


class _InertiaFields(StrictModel):
    pinion_inertia_kgm2: float = Field(1e-3, gt=0, le=MAX_INERTIA_KGM2, description="Inertia of every pinion [kg·m²]; a gear of stage "
                                       "ratio u has u⁴ times it (same module and face width).")
    load_inertia_kgm2: float = Field(0.0, ge=0, le=MAX_INERTIA_KGM2, description="Inertia on the output shaft [kg·m²].")
    shaft_inertias_kgm2: list[Annotated[float, Field(ge=0, le=MAX_INERTIA_KGM2)]] | None = Field(
        None, max_length=MAX_STAGES + 1, description="Extra inertia on each shaft, motor shaft to output shaft (stages + 1 values) [kg·m²].")


class SplitIn(_InertiaFields):
    """A total ratio (or the motor and output speeds) to split between the stages."""

    total_ratio: float | None = Field(None, ge=1e-4, le=1e6, description="Motor speed over output speed [-].")
    motor_speed_rpm: float | None = Field(None, ge=1e-3, le=1e6, description="Motor speed [rev/min], with an output "
                                          "speed.")
    output_speed_rpm: float | None = Field(None, ge=1e-3, le=1e6, description="Output shaft speed [rev/min].")
    motor_speed_rad_s: float | None = Field(None, ge=1e-4, le=1e5, description="Motor speed [rad/s], with an output "
                                            "speed.")
    output_speed_rad_s: float | None = Field(None, ge=1e-4, le=1e5, description="Output shaft speed [rad/s].")
    stages: StagesIn = Field(2, description="A count of spur stages, or a list of stage types or stages, motor "
                             "side first.")
    objective: Objective = Field(
        "min_inertia", description="min_inertia: least train inertia on the motor shaft; min_volume: least gear "
        "volume; handbook: the two-stage rule of thumb.")
    motor_inertia_kgm2: float = Field(0.0, ge=0, le=MAX_INERTIA_KGM2, description="Rotor inertia, added on the motor "
                                      "shaft [kg·m²].")
    input_torque_Nm: float = Field(1.0, gt=0, le=1e9, description="Motor-shaft torque for the volume model [N·m]; "
                                   "scales the volume, not the split.")
    handbook_factor: float = Field(0.88, gt=0, le=10, description="Handbook rule: slow stage = factor * sqrt(U).")
    snap_r20: bool = Field(False, description="Snap the stage ratios to R20 preferred numbers.")
    snap_tolerance: float | None = Field(None, gt=0, lt=1, description="Admissible relative deviation of the "
                                         "snapped total; default 2.5 % up to U = 4.5, 4 % above.")

    model_config = ConfigDict(json_schema_extra={
        # _one_ratio's rule: total_ratio, or a motor speed and an output speed, each given once
        "allOf": [{"oneOf": [given("total_ratio"),
                             {"allOf": [at_least_one("motor_speed_rpm", "motor_speed_rad_s"),
                                        at_least_one("output_speed_rpm", "output_speed_rad_s")]}]},
                  {"not": {"allOf": [given("total_ratio"), at_least_one(*_SPEEDS)]}},
                  at_most_one("motor_speed_rpm", "motor_speed_rad_s"),
                  at_most_one("output_speed_rpm", "output_speed_rad_s")],
        "examples": [
        {"total_ratio": 12.5, "stages": 2, "objective": "min_inertia", "snap_r20": True},
        {"motor_speed_rpm": 1460, "output_speed_rpm": 30, "stages": ["helical", "helical", "spur"],
         "objective": "min_volume", "input_torque_Nm": 50},
        {"total_ratio": 17, "stages": [{"type": "bevel", "ratio": 3}, "open_spur"], "objective": "handbook"},
    ]})

    @model_validator(mode="after")
    def _one_ratio(self) -> SplitIn:
        given = [self.total_ratio is not None,
                 self.motor_speed_rpm is not None or self.motor_speed_rad_s is not None,
                 self.output_speed_rpm is not None or self.output_speed_rad_s is not None]
        if given[0] == (given[1] or given[2]) or (not given[0] and not all(given[1:])):
            raise ValueError("give total_ratio, or a motor speed and an output speed (rpm or rad/s)")
        if self.motor_speed_rpm is not None and self.motor_speed_rad_s is not None:
            raise ValueError("give the motor speed once, in rpm or in rad/s")
        if self.output_speed_rpm is not None and self.output_speed_rad_s is not None:
            raise ValueError("give the output speed once, in rpm or in rad/s")
        return self


class StageOut(BaseModel):
    """A stage as used: type, admissible range and efficiency."""

    type: StageType = Field(description="Stage type, from the stage-type table.")
    ratio_min: float = Field(description="Smallest admissible ratio of this stage, input over output speed [-].")
    ratio_max: float = Field(description="Largest admissible ratio of this stage [-].")
    efficiency: float = Field(description="Stage efficiency, output over input power [-].")
    fixed_ratio: float | None = Field(None, description="The ratio the layout fixes for this stage [-]; null when "
                                      "the split chooses it.")


class SplitChecksOut(BaseModel):
    """Independent checks of a split."""

    objective_model: float = Field(description="The objective re-evaluated with the plain model at the answer.")
    ratio_product_error: float = Field(description="|prod(stage_ratios)/total_ratio - 1|.")
    kkt_residual: float | None = Field(description="Largest violation of the first-order optimality conditions "
                                       "(finite differences of the plain model, relative); null for the handbook "
                                       "rule or snapped ratios.")


class SplitOut(BaseModel):
    """Stage ratios, motor side first, with the objective and both model figures."""

    total_ratio: float = Field(description="Total ratio to split, motor speed over output speed [-].")
    objective: Objective = Field(description="The objective the split minimised.")
    stage_ratios: list[float] = Field(description="Ratio of each stage, input over output speed, motor side first "
                                      "[-]; their product is the total ratio (within the snap tolerance when "
                                      "snapped).")
    continuous_ratios: list[float] = Field(description="The optimum before R20 snapping.")
    objective_value: float = Field(description="The objective at the answer, in objective_unit: the train's "
                                   "inertia reduced to the motor shaft (min_inertia, handbook) or the gear volume "
                                   "(min_volume).")
    objective_unit: Literal["m3", "kgm2"] = Field(description="Unit of objective_value: m3 for min_volume, kgm2 "
                                                  "otherwise.")
    reduced_inertia_kgm2: float = Field(description="Train inertia on the motor shaft at these ratios.")
    gear_volume_m3: float | None = Field(description="Pinion and gear volume sized for contact stress; null when "
                                         "a stage type has no sizing rule.")
    stages: list[StageOut] = Field(description="The stages as used, motor side first: type, admissible ratio "
                                   "range, efficiency and fixed ratio.")
    snapped: bool = Field(description="The stage ratios were moved to R20 preferred numbers.")
    snap_tolerance: float | None = Field(description="Admissible relative deviation of the snapped total ratio "
                                         "that was used [-]; null without snapping.")
    solver: str = Field(description="What found the split: clarabel (the geometric programs) or closed form "
                        "(the handbook rule).")
    solver_status: str = Field(description="The solver's final status (optimal for the closed form).")
    solve_time_s: float = Field(description="Solver time [s]; 0 for the closed form.")
    checks: SplitChecksOut = Field(description="Independent checks of the split.")
    warnings: list[WarningOut] = Field(description="Likely mistakes and weak points of the split (a ratio outside "
                                       "a stage type's usual range, say); the answer stands.")


class TeethIn(StrictModel):
    """A total ratio to realise with integer tooth numbers, exactly optimal over the whole train."""

    total_ratio: float = Field(ge=1e-4, le=1e6, description="Target ratio of the train [-].", examples=[17.3])
    stages: StagesIn = Field(2, description="A count of spur stages, or a list of toothed stage types or stages "
                             "with ratio ranges, motor side first.")
    min_teeth: int | None = Field(None, ge=1, le=100_000, description="Your bound on every wheel; replaces the undercut limit, "
                                  "which then only warns.")
    max_teeth: int = Field(100, ge=2, le=100_000, description="Most teeth on any wheel.")
    tolerance: float | None = Field(None, ge=0, lt=1, description="Relative ratio tolerance: given, the fewest "
                                    "teeth within it; else the closest ratio.")
    pressure_angle_deg: float = Field(20.0, ge=MIN_PRESSURE_ANGLE_DEG, le=MAX_PRESSURE_ANGLE_DEG,
                                      description="Pressure angle of the basic rack [deg]; 20 is the ISO 53 "
                                      "standard, 14.5 and 25 the older and the heavy-duty racks.")
    addendum_coefficient: float = Field(1.0, gt=0, le=2, description="Addendum over module, h_a* [-].")
    profile_shift: float = Field(0.0, ge=-1, le=1, description="Shift x on the smaller wheel of each pair, -x on the "
                                 "larger.")
    hunting_teeth: bool = Field(False, description="No common factor between the teeth of a pair.")
    reverted: bool = Field(False, description="Coaxial input and output: equal tooth sums in every stage.")
    planets: int = Field(3, ge=2, le=12, description="Planets of every planetary stage: z_r = z_s + 2 z_p, "
                         "(z_s + z_r)/planets an integer, and neighbouring planets' tips clear.")

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"total_ratio": 17.3, "stages": 2, "max_teeth": 100},
        {"total_ratio": 12, "stages": 2, "max_teeth": 80, "tolerance": 0.01, "reverted": True, "hunting_teeth": True},
        {"total_ratio": 6, "stages": ["spur"], "min_teeth": 14, "max_teeth": 120},
        {"total_ratio": 17.3, "stages": ["spur", "planetary"], "planets": 3, "max_teeth": 100},
    ]})


class MeshOut(BaseModel):
    """One stage's tooth numbers; ratio = gear_teeth / pinion_teeth. A planetary stage (sun in, ring held,
    carrier out) gives its sun as pinion_teeth, its ring as gear_teeth, ratio = 1 + ring/sun, and the planets."""

    pinion_teeth: int = Field(description="Teeth of the driving wheel (a planetary stage's sun).")
    gear_teeth: int = Field(description="Teeth of the driven wheel (a planetary stage's ring).")
    ratio: float = Field(description="Stage ratio, input over output speed: gear_teeth/pinion_teeth, or 1 + "
                         "ring/sun for a planetary stage [-].")
    sun_teeth: int | None = Field(None, description="Planetary stage: teeth of the sun; null for a simple pair.")
    planet_teeth: int | None = Field(None, description="Planetary stage: teeth of each planet; null for a simple "
                                     "pair.")
    ring_teeth: int | None = Field(None, description="Planetary stage: teeth of the ring; null for a simple pair.")
    planets: int | None = Field(None, description="Planetary stage: number of planets; null for a simple pair.")
    efficiency: float | None = Field(None, description="Planetary stage: efficiency with the sun driving the "
                                     "carrier, by the power through the carrier-held train (two closed spur meshes' "
                                     "basic efficiency) [-]; null for a simple pair.")
    back_efficiency: float | None = Field(None, description="Planetary stage: efficiency with the carrier driving "
                                          "the sun (power flowing back) [-]; null for a simple pair.")


class TeethChecksOut(BaseModel):
    """A plain enumeration of every combination, run when there are at most a million (else nulls)."""

    enumeration_combinations: int | None = Field(description="Combinations the plain enumeration examined; null when "
                                                 "it was not run (more than a million).")
    enumeration_ratio_error: float | None = Field(description="Its best relative ratio error |U/U_target - 1| [-]; "
                                                  "null when not run.")
    enumeration_total_teeth: int | None = Field(description="Total teeth of its best train; null when not run.")
    agrees: bool | None = Field(description="The enumeration found the same ratio error and total teeth as the "
                                "search; null when not run.")


class TeethOut(BaseModel):
    """Tooth numbers, motor side first, with the achieved ratio and how they were found."""

    stages: list[MeshOut] = Field(description="Tooth numbers of each stage, motor side first.")
    total_ratio: float = Field(description="Achieved ratio.")
    target_ratio: float = Field(description="The requested total ratio [-].")
    ratio_error: float = Field(description="|total_ratio/target_ratio - 1|.")
    total_teeth: int = Field(description="Teeth of every wheel of the train added up (a planetary stage: sun, one "
                             "planet and ring).")
    tolerance: float | None = Field(description="The relative ratio tolerance asked for [-]; null: the closest "
                                    "ratio was sought.")
    method: str = Field(description="How the tooth numbers were found, in words.")
    search_time_s: float = Field(description="Time the search took [s].")
    products_examined: int = Field(description="Partial ratio products the search enumerated.")
    undercut_limit: float = Field(description="2 (h_a - x)/sin² alpha.")
    min_pinion_teeth: int = Field(description="Fewest teeth allowed on the smaller wheel of a pair: the undercut "
                                  "limit rounded up, or the request's min_teeth.")
    min_gear_teeth: int = Field(description="Fewest teeth allowed on the larger wheel of a pair (its profile shift "
                                "is -x), or the request's min_teeth.")
    checks: TeethChecksOut = Field(description="A plain enumeration of every combination, when small enough.")
    warnings: list[WarningOut] = Field(description="Likely mistakes and weak points (a wheel below the undercut "
                                       "limit, say); the answer stands.")


class CatalogueMotorIn(StrictModel):
    """A motor of your own catalogue."""

    name: str = Field(min_length=1, max_length=80, description="Catalogue designation.", examples=["4A100L4"])
    rated_power_W: float = Field(gt=0, le=1e9, description="Rated output power [W].", examples=[4000.0])
    synchronous_rpm: float = Field(gt=0, le=1e5, description="Synchronous speed [rev/min].", examples=[1500.0])
    rated_rpm: float = Field(gt=0, le=1e5, description="Speed at rated power [rev/min].", examples=[1430.0])
    rotor_inertia_kgm2: float | None = Field(None, ge=0, le=MAX_INERTIA_KGM2,
                                             description="Rotor inertia [kg·m²]; unknown: null.")
    mass_kg: float | None = Field(None, gt=0, le=1e6, description="Mass of the motor [kg]; unknown: null (the "
                                  "machine optimisation's machine_mass and cost need it).")

    @model_validator(mode="after")
    def _slip(self) -> CatalogueMotorIn:
        if self.rated_rpm > self.synchronous_rpm:
            raise ValueError("rated_rpm cannot exceed synchronous_rpm")
        return self


class DriveIn(_InertiaFields):
    """Output power and speed and a layout: the motor, the split and every shaft's speed, power and torque."""

    output_power_W: float = Field(gt=0, le=1e9, description="Power the output shaft delivers [W].",
                                  examples=[3000.0])
    output_speed_rpm: float | None = Field(None, ge=1e-3, le=1e6, description="Output shaft speed [rev/min].")
    output_speed_rad_s: float | None = Field(None, ge=1e-4, le=1e5, description="Output shaft speed [rad/s].")
    stages: StagesIn = Field(2, description="A count of spur stages, or a list of stage types or stages, motor "
                             "side first.")
    reserve_factor: float = Field(1.1, gt=0, le=10, description="xi in P_req = P_out xi / eta.")
    drive_efficiency: float | None = Field(None, gt=0, le=1, description="eta assumed for the motor choice; "
                                           "default the product of the stage efficiencies.")
    synchronous_rpm: float | None = Field(None, gt=0, le=1e5, description="Restrict the motor to one speed class.")
    motor: str | None = Field(None, description="A catalogue motor by name instead of the automatic choice.")
    motor_catalogue: list[CatalogueMotorIn] | None = Field(
        None, min_length=1, max_length=500,
        description="Your motors to choose from (a vendor's data); default the shipped representative catalogue "
        "listed at GET /v1/gears/motors.")
    objective: Objective = Field(
        "min_inertia", description="How the ratio is split: as in POST /v1/gears/split.")
    torque_basis: TorqueBasis = Field(
        "load", description="Shaft powers from the output power (load) or the motor's rated power (rated).")
    snap_r20: bool = Field(False, description="Snap the stage ratios to R20 preferred numbers.")
    snap_tolerance: float | None = Field(None, gt=0, lt=1, description="Admissible relative deviation of the "
                                         "snapped total; default 2.5 % up to U = 4.5, 4 % above.")
    strength: StrengthIn | None = Field(None, description="Size every cylindrical stage for strength (ISO 6336) "
                                        "from its shaft torque: module, face width, centre distance, safety "
                                        "factors. With objective min_volume and only spur or helical stages, "
                                        "the split's volume model is the sizing's.")

    model_config = ConfigDict(json_schema_extra={**exactly_one("output_speed_rpm", "output_speed_rad_s"), "examples": [
        {"output_power_W": 3000, "output_speed_rpm": 60, "stages": ["helical", "spur"], "objective": "min_volume",
         "strength": {"pinion_material": "case_hardened_MQ", "gear_material": "case_hardened_MQ",
                      "application_factor": 1.25, "life_h": 20000, "min_safety_contact": 1.1,
                      "min_safety_root": 1.5}},
        {"output_power_W": 20000, "output_speed_rad_s": 9.0, "drive_efficiency": 0.8, "torque_basis": "rated",
         "stages": [{"type": "bevel", "ratio": 3, "efficiency": 0.931}, {"type": "open_spur", "efficiency": 0.891}]},
        {"output_power_W": 3000, "output_speed_rpm": 60, "stages": ["helical", "helical"], "load_inertia_kgm2": 2.0},
    ]})

    @model_validator(mode="after")
    def _one_speed(self) -> DriveIn:
        if (self.output_speed_rpm is None) == (self.output_speed_rad_s is None):
            raise ValueError("give the output speed once, as output_speed_rpm or output_speed_rad_s")
        return self

    def output_speed(self) -> float:
        """Output speed [rad/s]."""
        if self.output_speed_rad_s is not None:
            return self.output_speed_rad_s
        assert self.output_speed_rpm is not None
        return self.output_speed_rpm * RPM

    def synchronous_speed(self) -> float | None:
        """Synchronous speed class [rad/s], if given."""
        return None if self.synchronous_rpm is None else self.synchronous_rpm * RPM


class MotorOut(BaseModel):
    """A catalogue motor."""

    name: str = Field(description="Catalogue designation.")
    rated_power_W: float = Field(description="Rated output power on the shaft [W].")
    synchronous_rpm: float = Field(description="Synchronous speed, where the torque is zero [rev/min].")
    rated_rpm: float = Field(description="Speed at rated power [rev/min].")
    rotor_inertia_kgm2: float | None = Field(description="Rotor inertia [kg·m²]; null when the catalogue does not "
                                             "give it.")
    mass_kg: float | None = Field(None, description="Catalogue mass of the foot-mounted motor [kg]; null when the "
                                  "catalogue does not give it.")


class ShaftOut(BaseModel):
    """One shaft, motor shaft first."""

    speed_rpm: float = Field(description="Shaft speed at the motor's rated speed [rev/min].")
    speed_rad_s: float = Field(description="The same speed [rad/s].")
    power_W: float = Field(description="Power the shaft carries, after the efficiencies of the stages before it "
                           "[W].")
    torque_Nm: float = Field(description="Torque the shaft carries, power over speed [N·m].")
    inertia_kgm2: float = Field(description="What the shaft carries (gears, pinion, extra, load, rotor).")
    reduced_inertia_kgm2: float = Field(description="That inertia reduced to the motor shaft.")


class DriveChecksOut(BaseModel):
    """Independent checks of a drive."""

    power_balance_error: float = Field(description="|T_out w_out - P_0 prod(eta)| / (T_out w_out).")
    kinetic_energy_J: float = Field(description="Sum of 1/2 J w² over the shafts at rated speed.")
    reduced_kinetic_energy_J: float = Field(description="1/2 J_red w_motor²; equals kinetic_energy_J.")


class DriveOut(BaseModel):
    """The motor, the split and every shaft."""

    motor: MotorOut = Field(description="The chosen (or named) catalogue motor.")
    required_power_W: float = Field(description="Power the motor must deliver, output power × reserve_factor / "
                                    "drive_efficiency [W].")
    drive_efficiency: float = Field(description="Efficiency assumed for the motor choice: the request's, or the "
                                    "product of the stage efficiencies [-].")
    chain_efficiency: float = Field(description="Product of the stage efficiencies [-].")
    total_ratio: float = Field(description="The motor's rated speed over the output speed [-].")
    stage_ratios: list[float] = Field(description="Ratio of each stage, input over output speed, motor side first "
                                      "[-].")
    stage_efficiencies: list[float] = Field(description="Efficiency of each stage, motor side first [-].")
    shafts: list[ShaftOut] = Field(description="Every shaft, motor shaft first, output shaft last.")
    reduced_inertia_kgm2: float = Field(description="Everything that turns (rotor, wheels, extra shaft inertias, "
                                        "load) reduced to the motor shaft [kg·m²].")
    output_speed_rpm: float = Field(description="Output shaft speed the chosen motor and ratios give [rev/min].")
    torque_basis: TorqueBasis = Field(description="Where the shaft powers start: load, the output power over the "
                                      "chain efficiency; rated, the motor's rated power.")
    split: SplitOut = Field(description="The ratio split, as /v1/gears/split answers.")
    gears: list[SizedStageOut | None] | None = Field(None, description="Every stage sized for strength, motor "
                                                     "side first (null for a stage that is not a cylindrical "
                                                     "pair); null when no strength block was sent.")
    gear_mass_kg: float | None = Field(None, description="Mass of all sized wheels [kg]; null without sizing.")
    volume_agreement: float | None = Field(None, description="|V_split/V_sized - 1| of a strength-based split: "
                                           "the split's predicted wheel volume against the sized one [-].")
    checks: DriveChecksOut = Field(description="Independent checks of the drive.")
    warnings: list[WarningOut] = Field(description="Likely mistakes and catalogue notes; the answer stands.")


class StageTypeOut(BaseModel):
    """A row of the shipped stage-type table."""

    name: StageType = Field(description="Stage type, as a request's stages name it.")
    description: str = Field(description="The stage type in words.")
    ratio_min: float = Field(description="Smallest admissible single-stage ratio, input over output speed [-].")
    ratio_max: float = Field(description="Largest admissible single-stage ratio [-].")
    efficiency: float = Field(description="Default efficiency of one stage, bearings included [-].")
    toothed: bool = Field(description="A pinion and gear whose tooth numbers /v1/gears/teeth can search.")
    volume_coefficient_m3_per_Nm: float | None = Field(description="c of the contact-stress sizing rule, pinion "
                                                       "plus gear volume = c·T_pinion·(u + 1)(u² + 1)/u "
                                                       "[m³/(N·m)]; null where no rule is stated.")
