"""Schemas of POST /v1/machines/optimise: the machine's function and choices in, the machine optimised as a whole
over its linkage family out, with its gains over the chain, its certificate and a Pareto set."""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal, Union

from pydantic import BaseModel, ConfigDict, Field
from pydantic.config import JsonDict

from ._engine import synth

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
    pair_frictions,
)
from .machine import MachineBalancingIn, MachineDesignOut, MachineDriveIn, MachineFlywheelIn, MachineIn
from .synthesis import (
    CrankRockerBoundsIn,
    CrankRockerDensityIn,
    SliderCrankBoundsIn,
    SliderCrankDensityIn,
    _within_limits,
)

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

    def to_spec(self, loads: tuple[synth.ProcessLoad, ...]) -> synth.CrankRockerSpec:
        """Engine synthesis spec (its dynamic objective unused); degrees become radians here."""
        bounds = _within_limits({n: r.pair() for n, r in self.bounds_m if r is not None},
                                ("crank", "coupler", "rocker", "ground"))
        return synth.CrankRockerSpec(
            swing=math.radians(self.swing_deg), time_ratio=self.time_ratio, scale_link=self.scale_link,
            scale_length=self.scale_length_m, bounds=bounds, max_length_ratio=self.max_length_ratio,
            min_transmission_angle=math.radians(self.min_transmission_angle_deg),
            slow_stroke={"ccw": 1, "cw": -1, None: 0}[self.slow_stroke],
            linear_density={k: v for k, v in dict(self.linear_density_kg_m).items() if v > 0}, loads=loads,
        )


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

    def to_spec(self, loads: tuple[synth.ProcessLoad, ...]) -> synth.SliderCrankSpec:
        """Engine synthesis spec (its dynamic objective unused); degrees become radians here."""
        given = {n: r.pair() for n, r in self.bounds_m if r is not None}
        bounds = {**_within_limits(given, ("crank", "rod")),
                  **(_within_limits(given, ("offset",), lowest=0.0) if "offset" in given else {})}
        return synth.SliderCrankSpec(
            stroke=self.stroke_m, time_ratio=self.time_ratio, bounds=bounds, max_length_ratio=self.max_length_ratio,
            min_transmission_angle=math.radians(self.min_transmission_angle_deg),
            slow_stroke={"positive": 1, "negative": -1, None: 0}[self.slow_stroke],
            linear_density={k: v for k, v in dict(self.linear_density_kg_m).items() if v > 0},
            slider_mass=self.slider_mass_kg, loads=loads,
        )


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

    def to_engine(self) -> synth.Prices:
        """Engine prices."""
        return synth.Prices(self.counterweight_per_kg, self.balancer_per_kg, self.flywheel_per_kg,
                            self.gears_per_kg, self.motor_per_kg, dict(self.motors))


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

    def to_engine(self, max_stages: int) -> synth.OptimiseSpec:
        """Engine optimisation (degrees and rpm become radians and rad/s here)."""
        if (self.delta is None) == (self.machine_type is None):
            raise synth.InvalidInput("give delta or machine_type (one of them)", field="delta")
        if (self.objective is None) == (self.weights is None):
            raise synth.InvalidInput("give objective or weights (one of them)", field="objective")
        delta = self.delta if self.delta is not None else synth.admissible_delta(str(self.machine_type))
        motion = "rotation" if isinstance(self.function, CrankRockerFunctionIn) else "translation"
        loads = tuple(load.to_engine(motion) for load in self.loads)
        weights = {self.objective: 1.0} if self.objective is not None else dict(self.weights or {})
        return synth.OptimiseSpec(
            function=self.function.to_spec(loads), speed=self.speed_rpm * math.pi / 30.0,
            drive=self.drive.to_engine(max_stages), delta=delta, balancing=self.balancing.to_engine(),
            flywheel=synth.FlywheelChoice(self.flywheel.placement, self.flywheel.geometry.to_engine()),
            samples=self.samples, speed_tolerance=self.speed_tolerance,
            weights={str(k): v for k, v in weights.items()}, max_rms_shaking_force=self.max_rms_shaking_force_N,
            max_rms_shaking_moment=self.max_rms_shaking_moment_Nm, pareto=(self.pareto[0], self.pareto[1]),
            scan=self.scan_members, search_cells=MAX_SCAN if self.search_cells == "all" else self.search_cells,
            friction=pair_frictions(self.friction), brake_torque=self.brake_torque_Nm,
            start_under_load=self.start_under_load, max_startup_time=self.max_startup_time_s,
            max_rundown_time=self.max_rundown_time_s, prices=self.prices.to_engine(),
        )


def mechanism_json(linkage: synth.Linkage) -> dict[str, Any]:
    """A family member as the `mechanism` of a /v1/machines/design request (lengths [m], link masses)."""
    mech = linkage.mechanism
    links = {name: {"mass_kg": p.mass, "com_m": [p.com[0], p.com[1]], "inertia_kgm2": p.inertia}
             for name, p in linkage.links.items()}
    if isinstance(mech, synth.FourBar):
        return {"type": "fourbar", "ground_length_m": mech.ground, "crank_length_m": mech.crank,
                "coupler_length_m": mech.coupler, "rocker_length_m": mech.rocker, "branch": mech.branch,
                "links": links}
    assert isinstance(mech, synth.SliderCrank)
    return {"type": "slider_crank", "crank_length_m": mech.crank, "rod_length_m": mech.rod,
            "offset_m": mech.offset, "branch": mech.branch, "links": links}


MemberMechanism = Annotated[Union[FourBarIn, SliderCrankIn], Field(discriminator="type")]


def mechanism_out(linkage: synth.Linkage) -> FourBarIn | SliderCrankIn:
    """A family member as the `mechanism` model of a /v1/machines/design request."""
    body = mechanism_json(linkage)
    return FourBarIn.model_validate(body) if body["type"] == "fourbar" else SliderCrankIn.model_validate(body)


def member_linkage(spec: Any, u: float) -> Any:
    """The family member at ``u`` of an optimisation spec (engine objects)."""
    from synth.machine.optimise import member_linkage as engine_member

    return engine_member(spec, u)


class FamilyMemberOut(BaseModel):
    """One member of the family the whole chain designed, and what its machine gives."""

    parameter: float = Field(description="Family parameter u of the member (the crank pivot's place on its "
                             "circle; its sign the side of the chord for a crank-rocker) [-].")
    stage: str = Field(description="scan (the steady machine), refine (a cell walked plateau by plateau), optimum or chain.")
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

    @classmethod
    def from_engine(cls, m: Any, linkage: synth.Linkage | None = None) -> FamilyMemberOut:
        """Schema from an engine member score and its linkage."""
        v = m.values
        return cls(parameter=m.parameter, stage=m.stage, feasible=m.feasible, reason=m.reason,
                   motor_power_W=None if v is None else v[0], added_mass_kg=None if v is None else v[1],
                   rms_shaking_force_N=None if v is None else v[2], rms_shaking_moment_Nm=m.rms_shaking_moment,
                   machine_mass_kg=None if v is None else _finite(v[3]),
                   cost=None if v is None else _finite(v[4]),
                   machine_mass_bound_kg=None if m.lower_values is None else _finite(m.lower_values[3]),
                   motor=None if m.choice is None else m.choice[0],
                   mechanism=None if linkage is None else mechanism_out(linkage))


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

    @classmethod
    def from_engine(cls, p: Any, prices: Any) -> MachinePartsOut:
        """Schema from the engine's parts and prices."""
        return cls(counterweights_kg=p.counterweights, balancers_kg=p.balancers, flywheel_kg=p.flywheel,
                   gears_kg=p.gears or 0.0, motor_kg=p.motor, motor=p.motor_name, machine_mass_kg=p.mass,
                   motor_price=p.motor_price(prices), cost=p.cost(prices))


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
    members_designed: int = Field(description="Members the whole chain designed: scan and refinements.")
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

    @classmethod
    def from_engine(cls, c: Any) -> OptimiseCertificateOut:
        """Schema from the engine's certificate."""
        s = c.scan
        return cls(statement=c.statement, parameter_range=list(s.parameter_range), kinematic_members=s.grid_points,
                   kinematic_feasible=s.feasible_points, feasible_runs=[list(r) for r in s.runs],
                   members_designed=c.members_designed, feasible_designed=c.feasible_designed,
                   scan_members=len(s.candidates),
                   refinements=[RefinementOut(
                       lo=r.lo, hi=r.hi, start=r.start, status=r.status, bound=_finite(r.bound), plateaus=r.plateaus,
                       evaluations=r.evaluations, best_parameter=r.best_parameter,
                       motor=None if r.choice is None else r.choice[0],
                       teeth=None if r.choice is None else [list(p) for p in r.choice[1]]) for r in c.refinements],
                   cells_found=len(c.refinements),
                   cells_searched=sum(r.status == "searched" for r in c.refinements),
                   cells_pruned=sum(r.status == "pruned" for r in c.refinements),
                   cells_unsearched=sum(r.status == "unsearched" for r in c.refinements),
                   gap_bound=c.gap_bound, binding_constraints=list(c.binding))


def _finite(v: float) -> float | None:
    return v if math.isfinite(v) else None


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

    @classmethod
    def from_engine(cls, r: synth.MachineOptimum) -> MachineOptimiseOut:
        """Schema from the engine's optimum."""
        return cls(
            design=MachineDesignOut.from_engine(r.design),
            mechanism=mechanism_out(r.design.spec.linkage), parameter=r.parameter, weights=dict(r.spec.weights),
            score=r.score, chain_score=r.chain_score, chain_parameter=r.certificate.scan.chain_parameter,
            chain_mechanism=mechanism_out(r.chain_linkage),
            chain_reason=r.chain_reason,
            gains=[GainOut(objective=g.objective, unit=g.unit, chain=_finite(g.chain), optimum=g.optimum,
                           gain=_finite(g.gain), relative_gain=_finite(g.relative)) for g in r.gains],
            certificate=OptimiseCertificateOut.from_engine(r.certificate),
            pareto_objectives=list(r.pareto_objectives),
            pareto=[FamilyMemberOut.from_engine(m) for m in r.pareto],
            members=[FamilyMemberOut.from_engine(m, member_linkage(r.spec, m.parameter))
                     for m in sorted(r.members, key=lambda m: m.parameter)],
            parts=None if r.parts is None else MachinePartsOut.from_engine(r.parts, r.spec.prices),
        )


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

    def pair(self, field: str, scale: float = 1.0) -> tuple[float, float]:
        """(min, max) times ``scale``; InvalidInput naming ``field`` when min > max."""
        if self.min > self.max:
            raise synth.InvalidInput("a band needs min <= max", field=f"{field}.min")
        return (self.min * scale, self.max * scale)


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

    def to_engine(self, max_stages: int) -> Any:
        """Engine spec (degrees become radians here)."""
        from synth.machine.optimise_linkage import FreeDimension, LinkageFunction, LinkageOptimiseSpec

        if (self.objective is None) == (self.weights is None):
            raise synth.InvalidInput("give objective or weights (one of them)", field="objective")
        if self.machine.mechanism.type != "linkage":
            raise synth.InvalidInput("free dimensions need a general linkage (type linkage)",
                                     field="machine.mechanism.type")
        if self.stroke_m is not None and self.swing_deg is not None:
            raise synth.InvalidInput("give stroke_m (a sliding output) or swing_deg (a turning one), not both",
                                     field="swing_deg")
        travel = (self.stroke_m.pair("stroke_m") if self.stroke_m is not None
                  else self.swing_deg.pair("swing_deg", math.pi / 180) if self.swing_deg is not None else None)
        weights = {self.objective: 1.0} if self.objective is not None else dict(self.weights or {})
        return LinkageOptimiseSpec(
            machine=self.machine.to_engine(max_stages),
            free=tuple(FreeDimension(d.path, d.min, d.max) for d in self.free),
            function=LinkageFunction(travel, None if self.time_ratio is None else self.time_ratio.pair("time_ratio"),
                                     math.radians(self.min_transmission_angle_deg)),
            weights={str(k): v for k, v in weights.items()}, samples=self.samples, refined=self.refined,
            refine_runs=self.refine_runs, prices=self.prices.to_engine())

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

    @classmethod
    def from_engine(cls, r: Any, body: dict[str, Any]) -> LinkageOptimiseOut:
        """Schema from the engine's optimum and the request (as JSON)."""
        req = LinkageOptimiseIn.model_validate(body)
        turning = req.swing_deg is not None or (req.stroke_m is None and _turns(req))
        k = 180 / math.pi if turning else 1.0
        names = ("motor_power", "added_mass", "rms_shaking_force", "machine_mass", "cost")

        def member(m: Any) -> LinkageMemberOut:
            kin = m.kinematics
            ok = math.isfinite(kin.travel)
            return LinkageMemberOut(
                x=list(m.x), stage=m.stage, feasible=m.feasible, reason=m.reason,
                stroke_or_swing=kin.travel * k if ok else None, time_ratio=_finite(kin.time_ratio) if ok else None,
                min_transmission_angle_deg=math.degrees(kin.min_transmission_angle) if ok else None,
                values=None if m.values is None else {n: _finite(v) for n, v in zip(names, m.values, strict=True)})

        c = r.certificate
        return cls(
            design=MachineDesignOut.from_engine(r.design),
            mechanism=PlanarLinkageIn.model_validate(req.mechanism_with(r.x)),
            free=[FreeValueOut(path=d.path, value_m=float(v)) for d, v in zip(req.free, r.x, strict=True)],
            stroke_or_swing=r.kinematics.travel * k, time_ratio=r.kinematics.time_ratio,
            time_ratio_range=list(r.kinematics.time_ratio_span),
            min_transmission_angle_deg=math.degrees(r.kinematics.min_transmission_angle),
            values=dict(zip(names, r.values, strict=True)), score=r.score,
            parts=MachinePartsOut.from_engine(r.parts, r.spec.prices),
            certificate=LinkageCertificateOut(statement=c.statement, sampled=c.sampled,
                                              kinematic_feasible=c.kinematic_feasible, designed=c.designed,
                                              feasible=c.feasible, refined=c.refined, refine_runs=c.refine_runs,
                                              gap_bound=c.gap_bound),
            members=[member(m) for m in r.members])


def _turns(req: LinkageOptimiseIn) -> bool:
    """The linkage's output turns (a link with two points) rather than slides (a block)."""
    mech = req.machine.mechanism
    assert mech.type == "linkage"
    out = mech.output or mech.links[-1].name
    return len(next(k for k in mech.links if k.name == out).joints) > 1
