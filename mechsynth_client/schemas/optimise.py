"""Schemas of POST /v1/machines/optimise: the machine's function and choices in, the machine optimised as a whole
over its linkage family out, with its gains over the chain, its certificate and a Pareto set."""

from __future__ import annotations

from typing import Annotated, Any, Literal, Union

from pydantic import BaseModel, ConfigDict, Field
from pydantic.config import JsonDict


from .common import (
    SIX_BAR_PRESS_EXAMPLE,
    FourBarIn,
    FrictionIn,
    Length,
    LoadIn,
    PlanarLinkageIn,
    SliderCrankIn,
    StrictModel,
    exactly_one,
)
from .machine import MachineBalancingIn, MachineDesignOut, MachineDriveIn, MachineFlywheelIn, MachineIn
from .synthesis import CrankRockerBoundsIn, CrankRockerDensityIn, SliderCrankBoundsIn, SliderCrankDensityIn

OptimiseObjective = Literal["motor_power", "added_mass", "rms_shaking_force", "machine_mass", "cost"]
DEFAULT_PARETO: tuple[OptimiseObjective, OptimiseObjective] = ("motor_power", "rms_shaking_force")
# The engine's scan bounds (synth.machine.optimise.MIN_SCAN, MAX_SCAN, DEFAULT_SCAN) and cells searched by default
# (MAX_SEARCHED), spelled here so that the schema loads without the engine; a test keeps them equal.
MIN_SCAN, MAX_SCAN, DEFAULT_SCAN = 4, 64, 64
DEFAULT_CELLS = 2

#: A crank-rocker machine: 40° of rocker swing at a time ratio of 1.15 from a 0.25 m rocker, 40 N·m against the
#: rocker over half the turn at 120 rpm, two helical stages, statically balanced, the least added mass.
CRANK_ROCKER_OPTIMISE_EXAMPLE: JsonDict = {
    "function": {"type": "crank_rocker", "swing_deg": 40, "time_ratio": 1.15, "scale_length_m": 0.25,
                 "linear_density_kg_m": {"crank": 4, "coupler": 3, "rocker": 5}, "min_transmission_angle_deg": 35},
    "loads": [{"type": "window", "torque_Nm": 40, "start_deg": 0, "end_deg": 180}],
    "speed_rpm": 120,
    "delta": 0.02,
    "drive": {"stages": ["helical", "helical"], "synchronous_rpm": 1500},
    "balancing": {"mode": "static"},
    "objective": "added_mass",
}

#: A slider-crank press: 0.12 m stroke at a time ratio of 1.2, 2 kN over the pressing half turn at 240 rpm,
#: motor power and RMS shaking force weighed alike, no balancing.
SLIDER_CRANK_OPTIMISE_EXAMPLE: JsonDict = {
    "function": {"type": "slider_crank", "stroke_m": 0.12, "time_ratio": 1.2,
                 "linear_density_kg_m": {"crank": 6, "rod": 4}, "slider_mass_kg": 8,
                 "min_transmission_angle_deg": 40},
    "loads": [{"type": "window", "force_N": 2000, "start_deg": 0, "end_deg": 180}],
    "speed_rpm": 240,
    "delta": 0.03,
    "drive": {"stages": ["helical", "helical"], "synchronous_rpm": 1500},
    "weights": {"motor_power": 1, "rms_shaking_force": 1},
}


#: The manual's examples scan the fewest members on a coarser cycle, so that trying them answers within seconds.
QUICK_SCAN: JsonDict = {"scan_members": MIN_SCAN, "samples": 48}


class CrankRockerFunctionIn(StrictModel):
    """What a crank-rocker must do: the rocker's swing and time ratio, with one length that sets the scale."""

    type: Literal["crank_rocker"] = Field("crank_rocker", description="A crank-rocker four-bar.")
    swing_deg: float = Field(gt=0.0, lt=180.0, description="Rocker swing psi [deg].", examples=[40.0])
    time_ratio: float = Field(1.0, ge=1.0, le=100.0, description="Slow stroke time over fast stroke time (Q).")
    scale_link: Literal["rocker", "ground", "crank"] = Field("rocker", description="The link whose length is given.")
    scale_length_m: Length = Field(description="Its length [m].", examples=[0.25])
    bounds_m: CrankRockerBoundsIn = Field(default_factory=CrankRockerBoundsIn,
                                          description="Length ranges of the links [m].")
    slow_stroke: Literal["ccw", "cw"] | None = Field(
        None, description="Rocker turning counter-clockwise or clockwise in the slow stroke (crank counter-clockwise).")
    linear_density_kg_m: CrankRockerDensityIn = Field(description="Mass per metre of each link (uniform bars) "
                                                      "[kg/m].")
    min_transmission_angle_deg: float = Field(0.0, ge=0.0, le=89.0, description="Lowest admissible transmission "
                                              "angle [deg].")
    max_length_ratio: float = Field(4.0, gt=1.0, le=100.0, description="No link longer than this many rocker "
                                    "lengths.")


class SliderCrankFunctionIn(StrictModel):
    """What an offset slider-crank must do: the stroke and time ratio."""

    type: Literal["slider_crank"] = Field("slider_crank", description="An offset slider-crank.")
    stroke_m: Length = Field(description="Slider stroke H [m].", examples=[0.12])
    time_ratio: float = Field(1.0, ge=1.0, le=100.0, description="Slow stroke time over fast stroke time (Q).")
    bounds_m: SliderCrankBoundsIn = Field(default_factory=SliderCrankBoundsIn,
                                          description="Ranges of the crank, rod and offset [m].")
    slow_stroke: Literal["positive", "negative"] | None = Field(
        None, description="Slider moving along +x or -x in the slow stroke (crank counter-clockwise).")
    linear_density_kg_m: SliderCrankDensityIn = Field(description="Mass per metre of crank and rod [kg/m].")
    slider_mass_kg: float = Field(0.0, ge=0, le=1e7, description="Slider mass [kg].")
    min_transmission_angle_deg: float = Field(0.0, ge=0.0, le=89.0, description="Lowest admissible transmission "
                                              "angle [deg].")
    max_length_ratio: float = Field(4.0, gt=1.0, le=100.0, description="The rod at most this many strokes.")


FunctionIn = Annotated[Union[CrankRockerFunctionIn, SliderCrankFunctionIn], Field(discriminator="type")]
Weight = Annotated[float, Field(ge=0, le=1e6)]
Price = Annotated[float, Field(ge=0, le=1e9)]


class PricesIn(StrictModel):
    """Prices of the machine's parts in one currency, for the `cost` objective. The defaults are rough euro
    figures for a small machine: steel counterweights cut and drilled, balancer masses with their machining,
    a grey cast-iron flywheel cast and turned, hardened alloy-steel wheels cut and ground, and an IEC
    four-pole motor by its mass when it has no price of its own."""

    counterweight_per_kg: Price = Field(3.0, description="Counterweights [currency/kg].")
    balancer_per_kg: Price = Field(4.0, description="Lanchester balancer masses [currency/kg].")
    flywheel_per_kg: Price = Field(2.5, description="The flywheel body [currency/kg].")
    gears_per_kg: Price = Field(12.0, description="Gear wheels as sized for strength [currency/kg].")
    motor_per_kg: Price = Field(6.0, description="A catalogue motor without its own price in `motors`, by its "
                                "catalogue mass [currency/kg].")
    motors: dict[Annotated[str, Field(min_length=1, max_length=80)], Price] = Field(
        default_factory=dict, max_length=500, description="Catalogue name -> price of that motor [currency].",
        examples=[{"4A71A4": 140.0}])


class MachineOptimiseIn(StrictModel):
    """A machine optimised as a whole: its linkage's function, the process load, the working speed, the target
    delta (or a machine type), the drive and the balancing and flywheel choices, and what to minimise."""

    function: FunctionIn = Field(description="What the linkage must do, chosen by `type`: crank_rocker (swing, time "
                                 "ratio, one length) or slider_crank (stroke, time ratio).")
    loads: list[LoadIn] = Field(default_factory=list, max_length=8, description="Process loads on the output: "
                                "torque_Nm on a rocker, force_N on a slider.")
    speed_rpm: float = Field(ge=1e-3, le=1e5, description="Working crank speed [rev/min].", examples=[120])
    samples: int = Field(120, ge=12, le=720, description="Crank angles per revolution for every member's chain.")
    delta: float | None = Field(None, ge=1e-4, lt=1, description="Target (w_max - w_min)/w_mean [-].")
    machine_type: str | None = Field(None, max_length=80, description="A machine type of GET /v1/machine-types.")
    drive: MachineDriveIn = Field(default_factory=MachineDriveIn, description="Gear stages and the motor "
                                  "catalogue or speed class.")
    balancing: MachineBalancingIn = Field(default_factory=MachineBalancingIn, description="Counterweights (or "
                                          "none), as /v1/machines/design takes them.")
    flywheel: MachineFlywheelIn = Field(default_factory=MachineFlywheelIn, description="Where the flywheel may sit "
                                        "and what it is made of.")
    speed_tolerance: float = Field(0.05, gt=0, lt=1, description="How far the simulated mean crank speed may lie "
                                   "from speed_rpm [-].")
    objective: OptimiseObjective | None = Field(
        None, description="One objective to minimise: motor_power (rated power of the catalogue motor), added_mass "
        "(counterweights, balancer masses and the flywheel body), rms_shaking_force (after balancing), "
        "machine_mass (those with the gear wheels as sized for strength and the motor's catalogue mass) or cost "
        "(the same parts at `prices`); or give weights.")
    weights: dict[OptimiseObjective, Weight] | None = Field(
        None, max_length=5, description="Weights of the objectives, each normalised by its value on the chain's "
        "machine (/v1/machines/design on the synthesis endpoint's default member); instead of objective.")
    max_rms_shaking_force_N: float | None = Field(None, gt=0, le=1e9, description="Largest RMS shaking force "
                                                  "after balancing [N].")
    max_rms_shaking_moment_Nm: float | None = Field(None, gt=0, le=1e9, description="Largest RMS shaking moment "
                                                    "about the crank pivot after balancing [N·m].")
    pareto: list[OptimiseObjective] = Field(
        default_factory=lambda: list(DEFAULT_PARETO), min_length=2, max_length=2,
        description="The two objectives of the Pareto set over every member designed.")
    friction: FrictionIn | None = Field(None, description="Friction per pair of the linkage, as "
                                        "/v1/machines/design takes it.")
    brake_torque_Nm: float = Field(0.0, ge=0, le=1e9, description="Brake torque at the crank during the run-down "
                                   "[N·m].")
    start_under_load: bool = Field(False, description="The start check holds the process load too, as "
                                   "/v1/machines/design takes it.")
    max_startup_time_s: float = Field(60.0, gt=0, le=1e4, description="Longest acceptable run-up from rest to the "
                                      "steady cycle [s]: a constraint on every member.")
    max_rundown_time_s: float | None = Field(None, gt=0, le=1e4, description="Longest acceptable run-down to rest "
                                             "with the motor off [s]; null: not checked.")
    scan_members: int = Field(DEFAULT_SCAN, ge=MIN_SCAN, le=MAX_SCAN, description="Members spread evenly over the "
                              "feasible family that the chain designs (to its steady machine) before the cells "
                              "between them are searched.")
    search_cells: Annotated[int, Field(ge=0, le=MAX_SCAN)] | Literal["all"] = Field(
        DEFAULT_CELLS, description="Cells between scanned members searched at most, those that could still beat the "
        "best member found first, two at a time; \"all\": every cell until each is searched or pruned by the best "
        "found (the family's optimum as far as the bounds hold, at the cost of more chain runs).")
    prices: PricesIn = Field(default_factory=PricesIn, description="Prices of the parts for the cost objective "
                             "(and the cost every answer reports).")

    model_config = ConfigDict(json_schema_extra={"allOf": [exactly_one("delta", "machine_type"),
                                                           exactly_one("objective", "weights")],
                                                 "examples": [{**CRANK_ROCKER_OPTIMISE_EXAMPLE, **QUICK_SCAN},
                                                              {**SLIDER_CRANK_OPTIMISE_EXAMPLE, **QUICK_SCAN}]})


MemberMechanism = Annotated[Union[FourBarIn, SliderCrankIn], Field(discriminator="type")]


class FamilyMemberOut(BaseModel):
    """One member of the family the whole chain designed, and what its machine gives."""

    parameter: float = Field(description="Family parameter u of the member (the crank pivot's place on its "
                             "circle; its sign the side of the chord for a crank-rocker) [-].")
    stage: str = Field(description="scan (the steady machine), bounded (a scanned member bounded by its discrete "
                       "choice and not designed further: that bound could not beat the best member found; its "
                       "reason gives the bound), refine (a cell walked plateau by plateau), optimum or chain.")
    feasible: bool = Field(description="Its machine passes every check and meets the shaking limits.")
    reason: str | None = Field(description="Why not, when not feasible; null otherwise.")
    motor_power_W: float | None = Field(description="Rated power of its catalogue motor [W]; null when the chain "
                                        "refused the member.")
    added_mass_kg: float | None = Field(description="Counterweights, balancer masses and flywheel body [kg].")
    rms_shaking_force_N: float | None = Field(description="RMS shaking force after balancing [N].")
    rms_shaking_moment_Nm: float | None = Field(description="RMS shaking moment about the crank pivot after "
                                                "balancing [N·m].")
    machine_mass_kg: float | None = Field(None, description="Counterweights, balancer masses, flywheel body, gear "
                                          "wheels and motor [kg]; null when its wheels were not sized (the search "
                                          "sizes them only when the objective or the Pareto set weighs the "
                                          "machine).")
    cost: float | None = Field(None, description="The same parts at the request's prices [currency]; null as "
                               "machine_mass_kg.")
    machine_mass_bound_kg: float | None = Field(None, description="Its machine mass without the gear wheels "
                                                "(counterweights, balancers, flywheel body, motor): a lower bound "
                                                "where the wheels were not sized [kg].")
    motor: str | None = Field(None, description="Its catalogue motor; null when the chain refused the member.")
    mechanism: MemberMechanism | None = Field(None, description="The member as the `mechanism` of a "
                                              "/v1/machines/design request (that request with the optimisation's "
                                              "machine around it designs this member).")


class MachinePartsOut(BaseModel):
    """What the optimised machine weighs, part by part, and what it costs."""

    counterweights_kg: float = Field(description="Counterweights (a slider-crank's crank counterweight among "
                                     "them) [kg].")
    balancers_kg: float = Field(description="Lanchester balancer masses, two per pair [kg].")
    flywheel_kg: float = Field(description="The flywheel body (rim or disc: density × volume) [kg].")
    gears_kg: float = Field(description="Every wheel as sized for strength, solid discs of the reference "
                            "diameters and the face width [kg]; 0 when drive.size_gears is false.")
    motor_kg: float = Field(description="The catalogue motor's mass [kg].")
    motor: str = Field(description="The catalogue motor.")
    machine_mass_kg: float = Field(description="Their sum [kg].")
    motor_price: float = Field(description="The motor's price: its own in prices.motors, else its mass at "
                               "prices.motor_per_kg [currency].")
    cost: float = Field(description="Every part at its price [currency].")


class GainOut(BaseModel):
    """One objective on the chain's machine and on the optimum."""

    objective: str = Field(description="motor_power, added_mass, rms_shaking_force, machine_mass or cost.")
    unit: str = Field(description="W, kg, N, kg or currency (the prices' own).")
    chain: float | None = Field(description="Its value on the chain's machine; null when the chain refused its "
                                "member.")
    optimum: float = Field(description="Its value on the optimised machine.")
    gain: float | None = Field(description="Chain less optimum, in `unit`: positive is better.")
    relative_gain: float | None = Field(description="The gain over the objective's scale (its value on the "
                                        "chain's machine) [-].")


class RefinementOut(BaseModel):
    """One cell of the family between two neighbouring scanned members: its bound and how it was covered."""

    lo: float = Field(description="Lower end of the cell in u (a scanned member) [-].")
    hi: float = Field(description="Upper end [-].")
    start: float = Field(description="The cell's end with the better score [-].")
    status: str = Field(description="searched (walked plateau by plateau), pruned (its bound is no better than "
                        "the best scanned) or unsearched (beyond the budget of cells searched).")
    bound: float | None = Field(description="Least score the motor, balancing masses and shaking force at its "
                                "ends allow, the flywheel body left out [-]; null when an end was refused.")
    plateaus: int = Field(description="Plateaus (members sharing one catalogue motor and tooth numbers) walked.")
    evaluations: int = Field(description="Chain runs (to the steady machine) it spent.")
    best_parameter: float = Field(description="Best member found in it [-].")
    motor: str | None = Field(description="Catalogue motor of that member; null when none was designed.")
    teeth: list[list[int]] | None = Field(description="Its (pinion, gear) teeth per toothed stage.")


class OptimiseCertificateOut(BaseModel):
    """How the family was covered and what binds at the answer."""

    statement: str = Field(description="The certificate in words.")
    parameter_range: list[float] = Field(description="The family parameter's whole range [lo, hi].")
    kinematic_members: int = Field(description="Members whose kinematic constraints (bounds, Grashof, the "
                                   "transmission-angle limit) were checked at once on a uniform grid.")
    kinematic_feasible: int = Field(description="Of these, the members within every kinematic constraint.")
    feasible_runs: list[list[float]] = Field(description="Intervals [lo, hi] of u the kinematic constraints "
                                             "admit.")
    members_designed: int = Field(description="Members the chain designed to their steady machine: scan and "
                                  "refinements (the bounded ones not counted).")
    feasible_designed: int = Field(description="Of these, the machines that pass every check and limit.")
    scan_members: int = Field(description="Members of the evenly spread scan (the chain's member among them).")
    refinements: list[RefinementOut] = Field(description="Every cell between neighbouring scanned members, in "
                                             "the order searched, with its bound and status.")
    cells_found: int = Field(description="Cells between neighbouring scanned members of one feasible run.")
    cells_searched: int = Field(description="Cells walked plateau by plateau.")
    cells_pruned: int = Field(description="Cells whose bound is no better than the best scanned score.")
    cells_unsearched: int = Field(description="Cells left beyond the budget.")
    gap_bound: float | None = Field(description="A bound on how much any member could beat the answer, in the "
                                    "score's unit; null: the motor catalogue makes the objective step, so no "
                                    "Lipschitz bound holds.")
    binding_constraints: list[str] = Field(description="Constraints active at the answer: a kinematic limit at "
                                           "the end of its feasible run, checks within 2 % of their limit "
                                           "(delta, motor_rms_torque, motor_peak_torque), the shaking limits.")


class MachineOptimiseOut(BaseModel):
    """The machine optimised as a whole: its design as /v1/machines/design answers it, the family member, the
    gains over the chain, the certificate and the Pareto set."""

    design: MachineDesignOut = Field(description="The optimised machine, designed and simulated as "
                                     "/v1/machines/design answers it.")
    mechanism: MemberMechanism = Field(description="The chosen member as the `mechanism` of a "
                                       "/v1/machines/design request.")
    parameter: float = Field(description="Its family parameter u [-].")
    weights: dict[str, float] = Field(description="The objectives' weights.")
    score: float = Field(description="Weighted sum of the normalised objectives of the optimum [-].")
    chain_score: float | None = Field(description="The same for the chain's machine [-]; null when it fails a "
                                      "check or limit.")
    chain_parameter: float = Field(description="Family parameter of the chain's member (the synthesis endpoint's "
                                   "default: the largest least transmission angle) [-].")
    chain_mechanism: MemberMechanism = Field(description="The chain's member as a `mechanism`.")
    chain_reason: str | None = Field(description="Why the chain's machine is not feasible; null when it is.")
    gains: list[GainOut] = Field(description="Every objective on the chain's machine and on the optimum.")
    certificate: OptimiseCertificateOut = Field(description="How the family was covered and what binds.")
    pareto_objectives: list[str] = Field(description="The two objectives of the Pareto set.")
    pareto: list[FamilyMemberOut] = Field(description="Members designed that no other designed member beats in "
                                          "both Pareto objectives, by the first objective.")
    members: list[FamilyMemberOut] = Field(description="Every member the chain designed, by parameter.")
    parts: MachinePartsOut | None = Field(None, description="The optimised machine's parts: their masses, the "
                                          "machine's mass and its cost.")


# Bounds of POST /v1/machines/optimise-linkage (synth.machine.optimise_linkage's), spelled here so that the schema
# loads without the engine; a test keeps them equal.
LINKAGE_MIN_SAMPLES, LINKAGE_MAX_SAMPLES, LINKAGE_DEFAULT_SAMPLES = 8, 512, 64
LINKAGE_MAX_FREE, LINKAGE_MAX_REFINED, LINKAGE_MAX_REFINE_RUNS = 6, 8, 200

#: The six-bar press of /v1/analysis (a crank-rocker whose rocker drives a ram through a rod) with the guide's
#: place and the rocker's lever arm free: a ram stroke of 0.18 to 0.26 m at a time ratio of 1.2 to 2.0 (the ram
#: reaches its top twice a turn, so both readings of its time ratio must lie in the band), no transmission angle
#: under 30°, 2 kN against the ram over the whole turn at 60 rpm, least machine mass.
SIX_BAR_OPTIMISE_EXAMPLE: JsonDict = {
    "machine": {
        "mechanism": SIX_BAR_PRESS_EXAMPLE,
        "loads": [{"type": "window", "force_N": 2000, "start_deg": 0, "end_deg": 360}],
        "speed_rpm": 60, "samples": 72, "delta": 0.05,
        "drive": {"stages": ["helical", "helical"], "synchronous_rpm": 1500, "size_gears": False},
    },
    "free": [{"path": "frame_points_m.G.x", "min": 0.40, "max": 0.50},
             {"path": "links.rocker.points_m.C.x", "min": 0.30, "max": 0.45}],
    "stroke_m": {"min": 0.18, "max": 0.26},
    "time_ratio": {"min": 1.2, "max": 2.0},
    "min_transmission_angle_deg": 30,
    "objective": "machine_mass",
}


#: The manual's example samples fewer members and refines one, so that trying it answers within seconds.
LINKAGE_QUICK: JsonDict = {"samples": 16, "refined": 1, "refine_runs": 20}


class FreeDimensionIn(StrictModel):
    """One number of the linkage left free within bounds."""

    path: str = Field(min_length=3, max_length=200, description="frame_points_m.<point>.x (or .y), "
                      "links.<link>.length_m or links.<link>.points_m.<point>.x (or .y).",
                      examples=["frame_points_m.G.x"])
    min: float = Field(ge=-1e3, le=1e3, description="Least value [m].", examples=[0.4])
    max: float = Field(ge=-1e3, le=1e3, description="Largest value [m].", examples=[0.5])


class BandIn(StrictModel):
    """A band [min, max]."""

    min: float = Field(ge=0, le=1e4, description="Least value.", examples=[0.18])
    max: float = Field(ge=0, le=1e4, description="Largest value.", examples=[0.26])


class LinkageOptimiseIn(StrictModel):
    """Any linkage's free dimensions chosen with its machine: the machine as /v1/machines/design takes it (its
    mechanism a general `linkage`), the numbers left free with their bounds, what the linkage must do and what to
    minimise."""

    machine: MachineIn = Field(description="The machine as /v1/machines/design takes it; its mechanism a general "
                               "linkage (type linkage) with the request's own numbers.")
    free: list[FreeDimensionIn] = Field(min_length=1, max_length=LINKAGE_MAX_FREE, description="The free numbers "
                                        "and their bounds.")
    stroke_m: BandIn | None = Field(None, description="The output's stroke band, for a sliding output [m].")
    swing_deg: BandIn | None = Field(None, description="The output's swing band, for a turning output [deg].")
    time_ratio: BandIn | None = Field(None, description="The time-ratio band (slower stroke over faster) [-].")
    min_transmission_angle_deg: float = Field(0.0, ge=0, le=89, description="Least transmission angle of every RRR "
                                              "and RRP dyad over the turn [deg].")
    objective: OptimiseObjective | None = Field(None, description="One objective to minimise (as "
                                                "/v1/machines/optimise); or give weights.")
    weights: dict[OptimiseObjective, Weight] | None = Field(None, max_length=5, description="Weights of the "
                                                            "objectives, each normalised by its value on the first "
                                                            "member designed (the request's own numbers when they "
                                                            "meet the function).")
    samples: int = Field(LINKAGE_DEFAULT_SAMPLES, ge=LINKAGE_MIN_SAMPLES, le=LINKAGE_MAX_SAMPLES,
                         description="Members of the scrambled Sobol sample of the box (the request's own numbers "
                         "are added when inside it).")
    refined: int = Field(4, ge=0, le=LINKAGE_MAX_REFINED, description="Best members refined by COBYLA, the "
                         "function as its constraints.")
    refine_runs: int = Field(60, ge=1, le=LINKAGE_MAX_REFINE_RUNS, description="Chain runs each refinement may "
                             "spend.")
    prices: PricesIn = Field(default_factory=PricesIn, description="Prices of the parts, as /v1/machines/optimise.")

    model_config = ConfigDict(json_schema_extra={"allOf": [exactly_one("objective", "weights")],
                                                 "examples": [{**SIX_BAR_OPTIMISE_EXAMPLE, **LINKAGE_QUICK}]})

    def mechanism_with(self, x: Any) -> dict[str, Any]:
        """The request's linkage with the free numbers set to ``x``, as the `mechanism` of a request."""
        body = self.machine.model_dump(mode="json")["mechanism"]
        for d, v in zip(self.free, x, strict=True):
            p = d.path.split(".")
            if p[0] == "frame_points_m":
                body["frame_points_m"][p[1]][0 if p[2] == "x" else 1] = float(v)
                continue
            link = next(k for k in body["links"] if k["name"] == p[1])
            if p[2] == "length_m":
                link["length_m"] = float(v)
            else:
                link["points_m"][p[3]][0 if p[4] == "x" else 1] = float(v)
        return dict(body)


class LinkageMemberOut(BaseModel):
    """One member of the box."""

    x: list[float] = Field(description="Its free numbers, in the order of `free` [m].")
    stage: str = Field(description="sample or refine.")
    feasible: bool = Field(description="It meets the function and its machine every check.")
    reason: str | None = Field(description="Why not; null when feasible.")
    stroke_or_swing: float | None = Field(description="The output's travel: stroke [m] or swing [deg]; null when it "
                                          "does not assemble.")
    time_ratio: float | None = Field(description="Its time ratio [-]; null when it does not assemble.")
    min_transmission_angle_deg: float | None = Field(description="Its least transmission angle [deg].")
    values: dict[str, float | None] | None = Field(description="Its objectives by name (null: not computed); "
                                                   "null when the chain did not run.")


class LinkageCertificateOut(BaseModel):
    """How the box was covered."""

    statement: str = Field(description="The certificate in words.")
    sampled: int = Field(description="Members of the Sobol sample (and the request's own).")
    kinematic_feasible: int = Field(description="Of these, the members meeting the function kinematically.")
    designed: int = Field(description="Members the chain designed (sample and refinement).")
    feasible: int = Field(description="Of these, those meeting every constraint and check.")
    refined: int = Field(description="Members refined by COBYLA.")
    refine_runs: int = Field(description="Members the refinement looked at.")
    gap_bound: float | None = Field(description="null: no gap bound is claimed.")


class FreeValueOut(BaseModel):
    """A free number as chosen."""

    path: str = Field(description="Its path, as the request's `free` names it.", examples=["frame_points_m.G.x"])
    value_m: float = Field(description="Its value [m].", examples=[0.4624])


class LinkageOptimiseOut(BaseModel):
    """The linkage's free numbers and its machine chosen together."""

    design: MachineDesignOut = Field(description="The optimised machine, as /v1/machines/design answers it.")
    mechanism: PlanarLinkageIn = Field(description="The chosen linkage as the `mechanism` of a /v1/machines/design "
                                       "request.")
    free: list[FreeValueOut] = Field(description="The free numbers chosen, in the order of the request's `free`.")
    stroke_or_swing: float = Field(description="Its output's travel: stroke [m] or swing [deg].")
    time_ratio: float = Field(description="Its time ratio [-], from its highest and lowest positions.")
    time_ratio_range: list[float] = Field(description="The least and largest time ratio over every pair of its "
                                          "ends (extremes within 1 % of the travel of the highest or lowest): an "
                                          "output that reaches its end twice a turn has two readings [-].")
    min_transmission_angle_deg: float = Field(description="Its least transmission angle [deg].")
    values: dict[str, float] = Field(description="Its objectives by name (units as /v1/machines/optimise's gains).")
    score: float = Field(description="Weighted sum of the normalised objectives [-].")
    parts: MachinePartsOut = Field(description="Its parts' masses, its machine mass and its cost.")
    certificate: LinkageCertificateOut = Field(description="The certificate: members sampled, feasible, designed "
                                               "and refined, and its statement.")
    members: list[LinkageMemberOut] = Field(description="Every member, sample then refinement.")
