"""Schemas of POST /v1/machines/design: one machine described once, every stage's answer, the simulated check."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field
from pydantic.config import JsonDict

from .analysis import AnalysisOut
from .balancing import BalanceOut, SliderCrankBalanceOut, WeightsIn
from .common import (
    exactly_one,
    service_limit,
    FOURBAR_EXAMPLE,
    MAX_INERTIA_KGM2,
    MAX_MASS_KG,
    FrictionIn,
    Length,
    LinkageRequest,
    StrictModel,
    SummaryOut,
    WarningOut,
)
from .flywheel import FlywheelOut, Ratio
from .gearing import CatalogueMotorIn, DriveOut, MotorOut, Objective, StageIn, StageType, TeethOut
from .rating import SizedStageOut, StrengthIn
from .machine_strength import MachineStrengthIn, MachineStrengthOut
from .foundation import (
    IsolationOut,
    MachineElasticDriveIn,
    MachineElasticDriveOut,
    MachineFoundationIn,
    MachineRegulationIn,
    MachineRegulationOut,
)

#: The README's slider-crank press: a 2.5 kN pressing stroke over half the turn at 480 rpm, one helical stage.
PRESS_EXAMPLE: JsonDict = {
    "mechanism": {"type": "slider_crank", "crank_length_m": 0.06, "rod_length_m": 0.24,
                  "links": {"crank": {"mass_kg": 3, "com_m": [0.02, 0], "inertia_kgm2": 0.004},
                            "rod": {"mass_kg": 4, "com_m": [0.08, 0], "inertia_kgm2": 0.03},
                            "slider": {"mass_kg": 9}}},
    "loads": [{"type": "window", "force_N": 2500, "start_deg": 0, "end_deg": 180}],
    "speed_rpm": 480,
    "delta": 0.02,
    "drive": {"stages": ["helical"], "synchronous_rpm": 1500},
    "balancing": {"mode": "static"},
    "flywheel": {"placement": "lightest", "geometry": {"density_kg_m3": 7850, "max_rim_speed_m_s": 30}},
}


#: The lecture-10 shaper driven as the seeds' drive example: motor A2-72-4, a bevel stage fixed at 3, an open spur
#: stage, 9 rad/s at the crank; a cutting force of 1.2 kN over the working stroke.
SHAPER_EXAMPLE: JsonDict = {
    "mechanism": {"type": "slotted_lever", "crank_length_m": 0.1, "ground_length_m": 0.3, "rocker_length_m": 0.6,
                  "ram_height_m": 0.7,
                  "links": {"crank": {"mass_kg": 5.0},
                            "rocker": {"mass_kg": 10.0, "com_m": [0.25, 0.0], "inertia_kgm2": 0.3},
                            "ram": {"mass_kg": 12.0}}},
    "gravity": {"g_m_s2": 9.81},
    "loads": [{"type": "window", "force_N": 1200, "start_deg": -60, "end_deg": 60, "point_m": [0, -0.1]}],
    "speed_rpm": 85.944,
    "delta": 0.002,
    "drive": {"stages": [{"type": "bevel", "ratio": 3, "efficiency": 0.931},
                         {"type": "open_spur", "efficiency": 0.891}],
              "motor": "A2-72-4", "max_teeth": 120},
    "flywheel": {"placement": "lightest", "geometry": {"density_kg_m3": 7850, "max_rim_speed_m_s": 45,
                                                       "max_diameter_m": 0.75}},
}

#: A four-bar fully balanced, with what the other balancing modes would cost.
FOURBAR_MACHINE_EXAMPLE: JsonDict = {
    "mechanism": FOURBAR_EXAMPLE,
    "loads": [{"type": "window", "torque_Nm": 60, "start_deg": 0, "end_deg": 180}],
    "speed_rpm": 300,
    "delta": 0.01,
    "drive": {"stages": ["helical"], "synchronous_rpm": 1500},
    "balancing": {"mode": "full"},
    "alternatives": True,
}


StageCount = Annotated[int, Field(ge=1, le=20, json_schema_extra=service_limit("max_stages"))]
StageList = Annotated[list[StageType | StageIn], Field(min_length=1, max_length=20,
                                                       json_schema_extra=service_limit("max_stages"))]


class MachineDriveIn(StrictModel):
    """The drive from motor to crank, motor side first, and how its motor and teeth are chosen."""

    stages: StageCount | StageList = Field(
        2, description="A count of spur stages, or a list of stage types or stages, motor side first.")
    motor: str | None = Field(None, min_length=1, max_length=80,
                              description="A catalogue motor by name; left out, the smallest that covers the power.")
    motor_catalogue: list[CatalogueMotorIn] | None = Field(
        None, min_length=1, max_length=500, description="Your motors to choose from; default GET /v1/gears/motors.")
    synchronous_rpm: float | None = Field(None, gt=0, le=1e5, description="Restrict the motor to one speed class.")
    reserve_factor: float = Field(1.1, gt=0, le=100, description="xi in P_req = P_mean xi / eta.")
    objective: Objective = Field("min_inertia", description="How the ratio is split: as in POST /v1/gears/split.")
    pinion_inertia_kgm2: float = Field(1e-3, gt=0, le=MAX_INERTIA_KGM2,
                                       description="Every pinion; a gear of ratio u has u⁴ times it.")
    load_inertia_kgm2: float = Field(0.0, ge=0, le=MAX_INERTIA_KGM2, description="Extra inertia on the crank shaft.")
    shaft_inertias_kgm2: list[Annotated[float, Field(ge=0, le=MAX_INERTIA_KGM2)]] | None = Field(
        None, max_length=21, description="Extra inertia on each shaft, motor shaft to crank shaft (stages + 1).")
    max_teeth: int = Field(100, ge=2, le=400, description="Largest wheel of the tooth search.")
    min_teeth: int | None = Field(None, ge=1, le=400, description="Your bound on every wheel (else undercut).")
    tooth_tolerance: float | None = Field(None, ge=0, lt=1, description="Relative ratio tolerance of the teeth.")
    size_gears: bool = Field(True, description="Size every spur or helical stage for strength (ISO 6336) from "
                             "the torque its pinion shaft passes on over the simulated cycle.")
    strength: StrengthIn = Field(
        default_factory=StrengthIn, description="How the stages are sized: materials, life, minimum safety "
        "factors, module series (Miner's rule on the real cyclic load, so the application factor stays 1).")


class MachineBalancingIn(StrictModel):
    """How to balance the linkage: none, static, full or optimal for a four-bar; a slider-crank takes static (crank
    counterweight), full (and Lanchester balancers) or optimal; a shaper none or optimal."""

    mode: Literal["none", "static", "full", "optimal"] = Field("none", description="Balancing mode as in "
                                                               "POST /v1/balancing/*; none: as it is.")
    counterweight_links: list[str] | None = Field(
        None, min_length=1, max_length=5, description="Links that may carry a counterweight (counterweight modes): "
        "default a four-bar's or a shaper's crank and rocker, a slider-crank's crank.")
    max_radius_m: dict[str, Length] = Field(default_factory=dict, max_length=5,
                                            description="Largest counterweight radius per link [m].")
    weights: WeightsIn | None = Field(None, description="Optimal mode: dimensionless weights (each term over its "
                                      "value before balancing).")
    mass_budget_kg: float | None = Field(None, ge=0, le=MAX_MASS_KG, description="Largest total added mass [kg].")
    rotor_ratios: dict[str, Annotated[float, Field(gt=0, le=1e3)]] = Field(
        default_factory=dict, max_length=2, description="Full mode: counter-rotor speed over its link's.")


class MachineGeometryIn(StrictModel):
    """Shape, material and limits of the flywheel (the candidate shafts are the drive's)."""

    shape: Literal["rim", "disc"] = Field("rim", description="rim: a heavy rim on spokes; disc: a solid disc.")
    density_kg_m3: float = Field(7200.0, gt=0, le=1e5, description="Cast iron 7200, steel 7850 [kg/m³].")
    max_rim_speed_m_s: float | None = Field(30.0, gt=0, le=1e4, description="At the outer radius [m/s].")
    allowable_stress_Pa: float | None = Field(None, gt=0, le=1e12, description="Allowable hoop (rim) or centre "
                                              "(disc) stress [Pa].")
    max_diameter_m: float | None = Field(None, gt=0, le=1e3, description="Largest outer diameter [m].")
    thickness_ratio: Ratio = Field([0.1, 0.2], description="Rim radial thickness over mean diameter: [min, max].")
    width_ratio: Ratio = Field([0.1, 0.2], description="Width over diameter: [min, max].")


class MachineFlywheelIn(StrictModel):
    """Where the flywheel goes and what it may look like."""

    placement: Literal["crank", "motor", "lightest"] = Field(
        "lightest", description="On the crank shaft, the motor shaft, or the lightest shaft that holds it.")
    geometry: MachineGeometryIn = Field(default_factory=MachineGeometryIn, description="Shape, material and limits "
                                        "of the flywheel.")


class TitleBlockIn(StrictModel):
    """Who answers for the design record: printed in the PDF's title block, kept out of the request's hash."""

    project: str = Field("", max_length=200, description="The project the machine belongs to.")
    number: str = Field("", max_length=100, description="The record's number in the office's register.")
    revision: str = Field("", max_length=20, description="The record's revision (A, B, … or 1, 2, …).")
    title: str = Field("", max_length=200, description="The record's title; default the request's `name`.")
    designed_by: str = Field("", max_length=100, description="Who designed it.")
    designed_on: str = Field("", max_length=40, description="When (ISO 8601 date).")
    checked_by: str = Field("", max_length=100, description="Who checked it.")
    checked_on: str = Field("", max_length=40, description="When (ISO 8601 date).")
    approved_by: str = Field("", max_length=100, description="Who approved it.")
    approved_on: str = Field("", max_length=40, description="When (ISO 8601 date).")
    state: Literal["draft", "checked", "approved", "superseded"] = Field("draft", description="Where the record "
                                                                         "stands.")


class MachineIn(LinkageRequest):
    """One machine: the linkage with its loads at its working speed (`speed_rpm`), the drive, the target delta
    (or a machine type), the balancing and flywheel choices."""

    samples: int = Field(360, ge=3, le=3600, description="Uniformly spaced crank angles over one revolution, for "
                         "every stage of the chain.")
    delta: float | None = Field(None, ge=1e-4, lt=1, description="Target (w_max - w_min)/w_mean [-].")
    machine_type: str | None = Field(None, max_length=80, description="A machine type of GET /v1/machine-types.")
    drive: MachineDriveIn = Field(default_factory=MachineDriveIn, description="Gear stages and the motor.")
    balancing: MachineBalancingIn = Field(default_factory=MachineBalancingIn,
                                          description="Counterweights (or none) before the flywheel is sized.")
    flywheel: MachineFlywheelIn = Field(default_factory=MachineFlywheelIn,
                                        description="Where the flywheel may sit and what it is made of.")
    speed_tolerance: float = Field(0.05, gt=0, lt=1, description="How far the simulated mean crank speed may lie "
                                   "from speed_rpm [-].")
    alternatives: bool = Field(False, description="Also design the machine with the other balancing modes.")
    friction: FrictionIn | None = Field(None, description="Friction per pair of the linkage: its losses are in the "
                                        "power the motor is chosen for, in the flywheel sizing and the simulation; "
                                        "the static coefficients in the start check.")
    brake_torque_Nm: float = Field(0.0, ge=0, le=1e9, description="Brake torque at the crank during the run-down "
                                   "[N·m].")
    start_under_load: bool = Field(False, description="The machine starts and runs up with its process load on (a "
                                   "press stopped in the stroke); default: it starts and runs up idling, against "
                                   "gravity, link torques and the friction these cause, to its idle steady state "
                                   "(the process engaged once it runs, as a press's clutch does).")
    max_startup_time_s: float = Field(60.0, gt=0, le=1e4, description="Longest acceptable run-up from rest to the "
                                      "steady cycle [s] (check startup_time); a minute by default, the overload "
                                      "a motor takes at its start.")
    max_rundown_time_s: float | None = Field(None, gt=0, le=1e4, description="Longest acceptable run-down to rest "
                                             "with the motor off [s] (check rundown_time); null: not checked.")
    name: str | None = Field(None, max_length=200, description="A label for people: the design record's title "
                             "(?format=pdf); default \"machine design\".")
    title_block: TitleBlockIn | None = Field(None, description="The design record's title block (project, number, "
                                             "revision, designed/checked/approved with names and dates, state); "
                                             "default a draft with blank names. Not part of the request's hash.")
    foundation: MachineFoundationIn | None = Field(None, description="The machine's frame on isolators, driven "
                                                   "by its shaking force and moment after balancing at the "
                                                   "working speed; null: not asked.")
    elastic_drive: MachineElasticDriveIn | None = Field(None, description="An elastic link between the motor's "
                                                        "rotor and the train; null: the drive is rigid.")
    regulation: MachineRegulationIn | None = Field(None, description="A step in the process load and the speed's "
                                                   "answer (self-regulation or a PI controller); null: not asked.")

    model_config = ConfigDict(json_schema_extra={"examples": [PRESS_EXAMPLE, FOURBAR_MACHINE_EXAMPLE, SHAPER_EXAMPLE],
                                                 **exactly_one("delta", "machine_type")})

    strength: MachineStrengthIn | None = Field(
        None, description="Size the machine's parts for strength: every bar of the linkage (to the fixed point of "
        "its own masses, before balancing, so that balancing, the flywheel and the drive see the real links), "
        "every revolute joint's pin and bearing, the crank shaft with its bearings and keys; their checks join "
        "`checks`.")


class MachineMotorOut(BaseModel):
    """The chosen motor and its linear static characteristic through the real train."""

    motor: MotorOut = Field(description="The catalogue motor.")
    rated_torque_Nm: float = Field(description="Rated torque on the motor shaft, rated power over rated speed "
                                   "[N·m].")
    breakdown_torque_Nm: float | None = Field(description="Largest torque of the characteristic's linear branch on "
                                              "the motor shaft [N·m]; null when unbounded.")
    train_ratio: float = Field(description="Real ratio from the tooth numbers, motor over crank speed [-].")
    train_efficiency: float = Field(description="Efficiency of the train, the product of the stage efficiencies "
                                    "[-].")
    required_power_W: float = Field(description="Mean crank power × reserve / efficiency.")
    operating_speed_rpm: float = Field(description="Motor speed under the machine's mean load on its linear "
                                       "characteristic (zero torque at synchronous speed, through the rated point), "
                                       "where k·(n_s - n)·n meets the mean crank power / efficiency [rev/min]: the "
                                       "speed the train ratio is taken from, between the rated and the synchronous "
                                       "speed.")
    simulated_mean_speed_rpm: float = Field(description="Mean motor speed of the simulated machine, train ratio × "
                                            "its mean crank speed [rev/min]: the check of the operating point.")


class ReducedOut(BaseModel):
    """The balanced linkage reduced to its crank (counterweights, pendulum coupler and counter-rotors included)
    and the constant inertia on top of it."""

    crank_angle_deg: list[float] = Field(description="Crank angle of each sample [deg].")
    reduced_inertia_kgm2: list[float] = Field(description="Reduced inertia J_red of the balanced linkage on the "
                                              "crank at each sample [kg·m²].")
    reduced_load_torque_Nm: list[float] = Field(description="Reduced torque of the process loads, link torques and "
                                                "gravity on the crank at each sample [N·m]; positive drives the "
                                                "crank, negative resists.")
    friction_torque_Nm: list[float] | None = Field(None, description="The pairs' friction losses reduced to the "
                                                   "crank at each sample [N·m] (resists); the flywheel, the motor "
                                                   "and the simulation take the load torque less this. Null "
                                                   "without friction.")
    driving_torque_Nm: list[float] = Field(description="At constant crank speed, after balancing (without "
                                           "friction; with it in `analysis.friction` for the linkage as given).")
    mean_power_W: float = Field(description="Mean power the crank delivers to the linkage, its friction losses "
                                "included.")
    train_inertia_kgm2: float = Field(description="Gears, shafts (and balancer shafts) on the crank, rotor excluded.")
    rotor_inertia_kgm2: float = Field(description="Motor rotor reduced to the crank.")


class SimulationOut(BaseModel):
    """The assembled machine run to its periodic steady state (the independent check)."""

    achieved_delta: float = Field(description="Coefficient of speed fluctuation (w_max - w_min)/w_mean of the "
                                  "simulated steady motion, w_mean = (w_max + w_min)/2 [-].")
    target_delta: float = Field(description="The request's target delta (or its machine type's tightest) [-].")
    mean_crank_speed_rad_s: float = Field(description="2·pi over the simulated period.")
    mean_crank_speed_rpm: float = Field(description="The same mean crank speed [rev/min].")
    period_s: float = Field(description="Time of one crank revolution in the steady motion [s].")
    motor_peak_torque_Nm: float = Field(description="Largest absolute motor torque on the motor shaft over the "
                                        "cycle [N·m].")
    motor_rms_torque_Nm: float = Field(description="RMS over time.")
    breakdown_margin: float | None = Field(description="1 - peak / breakdown torque (current-limit margin).")
    crank_angle_deg: list[float] = Field(description="Crank angles over one revolution [deg]: at most 721 points "
                                         "of the simulation's steps, evenly picked, both ends kept.")
    omega_rad_s: list[float] = Field(description="Crank speed at each of those angles [rad/s].")
    motor_torque_Nm: list[float] = Field(description="Motor torque on the motor shaft at each of those angles "
                                         "[N·m]; positive drives the machine.")


class MachineCheckOut(BaseModel):
    """One target against the simulated machine."""

    name: str = Field(description="The target checked: delta, mean_speed, motor_rms_torque, motor_peak_torque, "
                      "motor_starts, startup_time or rundown_time.")
    label: str = Field("", description="The check's name in words, as the design record prints it.")
    value: float = Field(description="What the simulated machine gives, in the check's unit: delta [-], the relative "
                         "distance of the mean crank speed from speed_rpm [-], the motor's RMS or peak torque "
                         "[N·m], the largest torque holding the crank at rest [N·m], or the start-up or run-down "
                         "time [s].")
    limit: float = Field(description="The limit it is held against, in the same unit: the target delta, "
                         "speed_tolerance, the rated torque, the breakdown torque, the motor's starting torque "
                         "through the train [N·m], max_startup_time_s or max_rundown_time_s.")
    passed: bool = Field(description="The value is within its limit (delta to 1e-3, relative).")
    detail: str = Field(description="What the check compares, in words.")
    unit: str = Field("", description="The unit of `value` and `limit` (N·m, s); empty for a ratio.")


#: Points of a start-up or run-down curve in the answer, evenly picked from the simulation's steps.
TRANSIENT_POINTS = 1001


class EfficiencyOut(BaseModel):
    """Efficiency of each stage over the steady cycle."""

    linkage: float | None = Field(description="The linkage with friction in its pairs: 1 - lost work / driving "
                                  "work over the cycle [-] (1 without friction); null when the drive does no net "
                                  "work on it.")
    gears: float = Field(description="The train: the product of the stage efficiencies [-].")
    overall: float | None = Field(description="Linkage times gears [-].")


class IntegratorOut(BaseModel):
    """How the run-up was integrated, and the same integrator against a run-up known in closed form."""

    method: str = Field(description="The integration method.")
    time_step_s: float = Field(description="The spacing of the states it reports (its own steps are set by its "
                               "error control) [s].")
    reference_inertia_kgm2: float = Field(description="The reference run-up's constant inertia at the crank: the "
                                          "cycle's mean plus rotor, train and flywheel [kg·m²].")
    reference_load_Nm: float = Field(description="Its constant load torque at the crank, the cycle's mean "
                                     "(positive drives; zero when the motor could not turn against it) [N·m].")
    reference_time_s: float = Field(description="How long the reference run-up was integrated [s].")
    closed_form_error: float = Field(description="Largest |w - w_exact| over that run-up, relative to its final "
                                     "speed, w_exact = w_inf·(1 - exp(-k·t/J)) for the motor's linear branch of "
                                     "slope k at the crank [-].")


class StartUpOut(BaseModel):
    """The run-up from rest at the worst crank angle to the periodic steady state."""

    starts: bool = Field(description="The motor's starting torque through the train exceeds the torque holding the "
                         "crank at rest at every crank angle.")
    starting_torque_Nm: float = Field(description="The motor's starting (locked-rotor) torque through the train, "
                                      "at the crank [N·m].")
    max_resisting_torque_Nm: float = Field(description="Largest torque holding the crank at rest: gravity, link "
                                           "torques, breakaway friction and, with start_under_load, the process "
                                           "load [N·m].")
    worst_crank_angle_deg: float = Field(description="Where it is largest [deg].")
    start_crank_angle_deg: float | None = Field(description="Where the run-up starts [deg] (the worst angle); null "
                                                "without a run-up.")
    steady_time_s: float | None = Field(description="Time from rest until the crank speed stays within 1 % of the "
                                        "periodic steady speed (idling unless start_under_load) [s]; null when it "
                                        "does not get there.")
    motor_peak_torque_Nm: float = Field(description="Largest motor torque on its shaft over the run-up [N·m].")
    motor_rms_torque_Nm: float = Field(description="RMS over time of the motor torque until steady (the heating "
                                       "of the start) [N·m].")
    energy_residual: float | None = Field(description="Motor work - kinetic energy gained - losses - process work "
                                          "over the run-up, relative to the largest term [-]: the integration's "
                                          "check; null without a run-up.")
    time_s: list[float] = Field(description="Times of the curve [s], at most 1001 points of the simulation.")
    omega_rad_s: list[float] = Field(description="Crank speed at those times [rad/s].")
    motor_torque_Nm: list[float] = Field(description="Motor torque on its shaft at those times [N·m].")
    integrator: IntegratorOut | None = Field(None, description="The integration's method and step, and its error "
                                             "against a closed-form run-up; null without a run-up.")


class RunDownOut(BaseModel):
    """The run-down to rest with the motor switched off in the steady state."""

    stop_time_s: float | None = Field(description="Time until the crank comes to rest [s]; null when it still "
                                      "turns after 600 s or 400 000 samples passed.")
    brake_torque_Nm: float = Field(description="Brake torque at the crank [N·m].")
    energy_residual: float = Field(description="Kinetic energy given up - losses - process work over the run-down, "
                                   "relative to the largest term [-] (zero to rounding: with the motor off the "
                                   "run-down is integrated over the crank angle by this balance).")
    time_error: float = Field(description="The run-down's time by a quadrature rule of lower order, relative: the "
                              "check of the one integral approximated, time = integral of dphi/w [-].")
    time_s: list[float] = Field(description="Times of the curve [s], at most 1001 points.")
    omega_rad_s: list[float] = Field(description="Crank speed at those times [rad/s].")


class RunningOut(BaseModel):
    """How the machine really runs: efficiencies, start-up and run-down."""

    efficiency: EfficiencyOut = Field(description="Efficiency of the linkage, the gears and overall.")
    startup: StartUpOut = Field(description="The run-up from rest.")
    rundown: RunDownOut = Field(description="The run-down to rest (its checks are among the answer's `checks`).")


class MachineShaftOut(BaseModel):
    """One shaft in the simulated steady motion, motor first, crank last: what it passes on."""

    name: str = Field(description='Shaft name: "motor", "shaft 1", ... between the stages, "crank".')
    speed_ratio: float = Field(description="Shaft speed over crank speed.")
    mean_speed_rpm: float = Field(description="Mean shaft speed in the steady motion [rev/min].")
    mean_power_W: float = Field(description="Mean power the shaft passes on toward the crank, over time [W].")
    mean_torque_Nm: float = Field(description="Mean torque the shaft passes on, over time [N·m]: the motor's "
                                  "through the stages before it, less what accelerates the shafts up to it.")
    peak_torque_Nm: float = Field(description="Largest absolute torque the shaft passes on over the cycle [N·m].")
    rms_torque_Nm: float = Field(description="RMS over time of the torque the shaft passes on [N·m].")
    inertia_kgm2: float = Field(description="What turns with it, the flywheel included when it sits there.")
    carries_flywheel: bool = Field(description="The flywheel sits on this shaft.")


class MachineFlywheelBodyOut(BaseModel):
    """The flywheel where it sits: its inertia on its own shaft, its crank-equivalent beside it, and the body's
    geometry on that shaft."""

    shaft: str = Field(description='Shaft that carries it: "motor", "shaft 1", ... or "crank".')
    speed_ratio: float = Field(description="That shaft's speed over the crank's [-].")
    inertia_on_shaft_kgm2: float = Field(description="The flywheel's inertia about its own shaft [kg·m²]: the "
                                         "body's.")
    crank_equivalent_inertia_kgm2: float = Field(description="The same flywheel reduced to the crank, inertia on "
                                                 "its shaft × speed_ratio² [kg·m²]; what `flywheel."
                                                 "flywheel_inertia_kgm2` reports.")
    shape: str = Field(description="rim: a rim on spokes; disc: a solid disc.")
    mean_diameter_m: float = Field(description="Mean rim diameter (a disc's outer diameter) [m].")
    outer_diameter_m: float = Field(description="Outer diameter [m].")
    rim_thickness_m: float | None = Field(description="Radial thickness of the rim [m]; null for a disc.")
    width_m: float = Field(description="Axial width of the rim or disc [m].")
    mass_kg: float = Field(description="Mass of the rim (spokes and hub not counted) or of the disc [kg].")
    rim_speed_m_s: float = Field(description="Speed of the outer rim at the shaft's largest simulated speed [m/s].")
    inertia_check_kgm2: float = Field(description="Inertia about its shaft recomputed from the dimensions and "
                                      "density [kg·m²].")


class AlternativeOut(BaseModel):
    """The same machine with another balancing mode: what it costs."""

    mode: str = Field(description="The balancing mode: none, static, full or optimal.")
    available: bool = Field(description="The machine could be designed with this mode; false: see `reason`.")
    reason: str | None = Field(None, description="Why the mode does not apply or its design failed; null when "
                               "available.")
    rms_shaking_force_N: float | None = Field(None, description="RMS shaking force over the cycle after balancing "
                                              "[N]; null when not available.")
    rms_shaking_moment_Nm: float | None = Field(None, description="RMS shaking moment about the crank pivot O after "
                                                "balancing [N·m]; null when not available.")
    flywheel_inertia_kgm2: float | None = Field(None, description="The flywheel reduced to the crank "
                                                "(crank-equivalent) [kg·m²]; null when not available.")
    flywheel_inertia_on_shaft_kgm2: float | None = Field(None, description="The flywheel's inertia on its own "
                                                         "shaft [kg·m²]; null when none is needed.")
    flywheel_mass_kg: float | None = Field(None, description="Mass of the flywheel on its shaft [kg]; null when "
                                           "none is needed.")
    flywheel_shaft: str | None = Field(None, description="Shaft the flywheel sits on; null when none is needed.")
    motor: str | None = Field(None, description="Name of the catalogue motor this design uses; null when not "
                              "available.")
    peak_shaft_torque_Nm: float | None = Field(None, description="Largest peak torque over every shaft of the drive "
                                               "[N·m]; null when not available.")
    achieved_delta: float | None = Field(None, description="Coefficient of speed fluctuation of the simulated "
                                         "machine [-]; null when not available.")
    passed: bool | None = Field(None, description="Every check of this design passed; null when not available.")


class MachineDesignOut(BaseModel):
    """Every stage of the design in the shape its own endpoint answers with, and the simulated check."""

    passed: bool = Field(description="Every entry of `checks` meets its target, and nothing else decides it.")
    checks: list[MachineCheckOut] = Field(description="Every target against the simulated machine, in one list: "
                                          "delta, mean_speed, motor_rms_torque, motor_peak_torque (when the motor "
                                          "has a breakdown torque), motor_starts, startup_time (when it starts) and "
                                          "rundown_time (when max_rundown_time_s is given).")
    analysis: AnalysisOut = Field(description="The linkage as given, as /v1/analysis answers.")
    balancing_mode: str = Field(description="The balancing mode used: none, static, full or optimal.")
    balancing: BalanceOut | None = Field(None, description="The counterweight balance (a four-bar's static or "
                                         "full, any family's optimal), as /v1/balancing/* answers; null otherwise.")
    slider_crank_balancing: SliderCrankBalanceOut | None = Field(None, description="A slider-crank's balance, as "
                                                                 "/v1/balancing/slider-crank answers; null "
                                                                 "otherwise.")
    summary_after_balancing: SummaryOut = Field(description="Shaking force, moment and driving torque of the "
                                                "balanced linkage (Lanchester balancers included in full mode).")
    reduced: ReducedOut = Field(description="The balanced linkage reduced to its crank.")
    motor: MachineMotorOut = Field(description="The chosen motor and its characteristic through the real train.")
    drive: DriveOut = Field(description="Motor choice and ratio split, as /v1/gears/drive answers.")
    teeth: TeethOut | None = Field(None, description="Tooth numbers, as /v1/gears/teeth answers.")
    stage_ratios: list[float] = Field(description="Real stage ratios from the teeth.")
    gears: list[SizedStageOut | None] | None = Field(
        None, description="Every stage sized for strength from the cyclic torque its pinion shaft passes on "
        "(module, face width, centre distance, diameters, S_H and S_F on the cycle by Miner's rule, the binding "
        "constraint), motor side first; null for a stage that is not a spur or helical pair or could not be "
        "sized (warnings say why), and null throughout when drive.size_gears is false.")
    flywheel: FlywheelOut = Field(description="The flywheel sizing for the chosen motor (motor_nlp), checked by the "
                                  "simulated machine; its inertias are reduced to the crank (crank-equivalent), "
                                  "`flywheel_body` holds the body on its own shaft.")
    flywheel_shaft: str | None = Field(None, description="Shaft the flywheel sits on; null when none is needed.")
    flywheel_body: MachineFlywheelBodyOut | None = Field(None, description="The flywheel where it sits: inertia on "
                                                         "its own shaft, its crank-equivalent, its geometry; null "
                                                         "when none is needed.")
    simulation: SimulationOut = Field(description="The assembled machine run to its periodic steady state.")
    shafts: list[MachineShaftOut] = Field(description="Every shaft in the steady motion, motor first, crank last.")
    running: RunningOut | None = Field(None, description="Efficiency of each stage, the start-up from rest and the "
                                       "run-down to rest of the assembled machine.")
    alternatives: list[AlternativeOut] = Field(default_factory=list, description="With `alternatives: true`: the "
                                               "same machine with each other balancing mode; else empty.")
    warnings: list[WarningOut] = Field(default_factory=list, description="Every stage's likely mistakes, weak "
                                       "points and catalogue notes, each with its `stage` (analysis, balancing, "
                                       "drive, teeth, flywheel, motor, simulation) and its field as this request "
                                       "spells it; a failed check is here too (code check_failed).")
    request_sha256: str | None = Field(None, description="SHA-256 of the request's canonical JSON (validated, "
                                       "defaults included, keys sorted): the design record's identity, printed "
                                       "in the report's title block.")
    foundation: IsolationOut | None = Field(None, description="With `foundation`: the frame on its isolators, as "
                                            "/v1/machines/isolation answers (its time-integration check "
                                            "included); null otherwise.")
    elastic_drive: MachineElasticDriveOut | None = Field(None, description="With `elastic_drive`: the drive "
                                                         "with its elastic link, as /v1/machines/elastic-drive "
                                                         "answers (its checks included), and whether the gears "
                                                         "were sized for its torque; null otherwise.")
    strength: MachineStrengthOut | None = Field(None, description="With `strength`: the links, pins, bearings, "
                                                "crank shaft and keys as built, each with its checks.")
    regulation: MachineRegulationOut | None = Field(None, description="With `regulation`: the speed after the "
                                                    "load step, as /v1/machines/regulation answers; null "
                                                    "otherwise.")
