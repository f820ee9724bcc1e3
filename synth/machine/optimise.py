"""The machine optimised as a whole: the linkage's family member, counterweights, flywheel, motor and ratio together.

The design chain takes each stage's answer as given. Here the free dimension of the linkage (the family parameter
u of the dimensional synthesis: the crank pivot's place on its circle) is chosen together with everything the
chain chooses for that member, for a stated objective: the motor's rated power, the mass added to the machine
(counterweights, balancer masses and the flywheel body), the RMS shaking force, or a weighted sum of these, each
normalised by its value on the chain's own machine (the synthesis endpoint's default member designed by
:func:`design_machine`).

How the family is covered, in plain functions of plain data so that the candidates' chains run on worker
processes (:func:`optimise_machine` runs them one after another):

1. :func:`scan_family`: the kinematic constraints of many members at once (vectorised), the feasible runs of the
   parameter, the chain's member, and evenly spread candidates over the feasible runs;
2. :func:`design_members`: the chain to its steady machine on the candidates (see :mod:`.optimise_light`), each
   scored on the simulated steady machine (its checks: delta, speed, motor heating and breakdown) and the
   optional shaking limits;
3. :func:`cells`, :func:`cell_plateaus` and :func:`search_plateau`: the members sharing the chain's discrete
   choices (catalogue motor, tooth numbers) form plateaus of the parameter on which the objective is continuous.
   Each cell between two scanned members is bounded from below by the parts of the objective the choices and the
   balancing fix, and pruned when that bound cannot beat the best scanned; the best cells are cut into plateaus,
   each plateau's end located by bisection on the discrete choice, and bounded Brent run between each plateau's
   ends (the plateaus of all cells side by side);
4. :func:`conclude_search`: the best member designed again as a whole machine (start and run-down simulations
   included; the next best when that fails a check), the gain over the chain in every
   objective, the Pareto set of two objectives over every member designed, the binding constraints and the
   certificate of how the family was covered.

The objective steps where the motor or the teeth change, so no Lipschitz constant bounds it and no gap bound is
claimed; the certificate states the plateaus found, searched, pruned (and why) and left.
"""

from __future__ import annotations

import math
import uuid
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any, Literal, TypeVar

import numpy as np
from scipy.optimize import minimize_scalar

from ..errors import Infeasible, InvalidInput, SolverFailed, SolverTimeout
from ..friction import PairFriction
from ..model import FloatArray, Linkage
from ..synthesis import CrankRockerSpec, SliderCrankSpec, synthesise_crank_rocker, synthesise_slider_crank
from ..synthesis import crank_rocker as _cr
from ..synthesis import slider_crank as _sc
from ..synthesis.family import MARGIN
from .chain import MachineDesign, design_machine
from .optimise_light import (SEARCH_WIDTH_STEPS, Choice, balancing_mass, discrete_choice, forget, kept,
                             steady_member)
from .optimise_parts import MachineParts, Prices, machine_parts
from .spec import BalancingChoice, DriveSpec, FlywheelChoice, MachineSpec

T = TypeVar("T")
ObjectiveName = Literal["motor_power", "added_mass", "rms_shaking_force", "machine_mass", "cost"]
#: The objectives, in the order every tuple of objective values holds them.
OBJECTIVES: tuple[ObjectiveName, ...] = ("motor_power", "added_mass", "rms_shaking_force", "machine_mass", "cost")
#: Units of the objectives, in the same order (cost in the currency of the request's prices).
OBJECTIVE_UNITS = ("W", "kg", "N", "kg", "currency")
#: The objectives that need the gear wheels sized in the search (the rest leave the sizing to the answer).
WEIGHED_PARTS = ("machine_mass", "cost")
#: Members whose kinematic constraints are evaluated at once to find the feasible runs of the parameter.
KINEMATIC_GRID = 4001
#: Largest and least number of members the chain designs in the scan.
MAX_SCAN, MIN_SCAN = 64, 4
#: Members the chain designs in the scan unless the request says otherwise.
DEFAULT_SCAN = 64
#: Cells searched at a time (and at most, unless the request asks for more), and steady-machine runs each plateau
#: may spend on bounded Brent after its two ends.
MAX_SEARCHED = 2
REFINE_EVALUATIONS = 2
#: Members designed in full at a time after the scan's bounds, least bound first (each round's best prunes the next).
BOUND_ROUND = 4
#: The stage of a scanned member the search bounded and did not design further.
BOUNDED = "bounded"
#: Best members of the search designed through the whole chain, in turn, until one passes its start checks.
FINAL_TRIES = 3
#: Plateaus walked at most in one cell.
MAX_WALK = 6
#: Bisection steps on the discrete choice locating each end of a plateau between two scanned members.
BISECT_STEPS = 5
#: A check within this fraction of its limit, or a kinematic bound within this many grid steps, binds.
BINDING_FRACTION = 0.02
BINDING_STEPS = 2
#: Fraction of the unbalanced RMS shaking force below which a balanced one is rounding [-].
SHAKING_FLOOR = 1e-6


def check_weights(weights: Mapping[str, float]) -> None:
    """The objectives' weights of a request: known objectives, finite and not negative, one of them positive."""
    for name, w in weights.items():
        if name not in OBJECTIVES:
            raise InvalidInput(f"unknown objective {name!r}; the objectives are {list(OBJECTIVES)}",
                               field=f"weights.{name}")
        if not (math.isfinite(w) and w >= 0):
            raise InvalidInput("an objective's weight must be finite and not negative", field=f"weights.{name}")
    if not any(w > 0 for w in weights.values()):
        raise InvalidInput("give at least one objective a positive weight", field="weights")


@dataclass(frozen=True, slots=True)
class OptimiseSpec:
    """A machine to optimise: its function, and everything the chain needs besides the linkage.

    ``function`` the crank-rocker's swing and time ratio with its scale, or the slider-crank's stroke and time
    ratio, with link densities, loads, the transmission-angle limit and length bounds (the synthesis spec; its
    ``objective``, ``speed`` and ``samples`` are not used here); ``speed`` [rad/s], ``drive``, ``delta`` [-],
    ``balancing``, ``flywheel``, ``samples``, ``speed_tolerance`` [-] as in :class:`MachineSpec`; ``weights``
    objective name -> weight [-] of its normalised value; ``max_rms_shaking_force`` [N] and
    ``max_rms_shaking_moment`` [N·m] optional limits after balancing; ``pareto`` the two objectives of the
    Pareto set; ``scan`` members the chain designs in the scan; ``search_cells`` cells searched at most (those
    that could still beat the best found, best first, :data:`MAX_SEARCHED` at a time); ``friction``, ``brake_torque`` [N·m],
    ``start_under_load``, ``max_startup_time`` and ``max_rundown_time`` [s] as in :class:`MachineSpec` (the start
    and run-down checks are constraints like the others).
    """

    function: CrankRockerSpec | SliderCrankSpec
    speed: float
    drive: DriveSpec
    delta: float
    balancing: BalancingChoice = field(default_factory=BalancingChoice)
    flywheel: FlywheelChoice = field(default_factory=FlywheelChoice)
    samples: int = 120
    speed_tolerance: float = 0.05
    weights: Mapping[str, float] = field(default_factory=lambda: {"motor_power": 1.0})
    max_rms_shaking_force: float | None = None
    max_rms_shaking_moment: float | None = None
    pareto: tuple[str, str] = ("motor_power", "rms_shaking_force")
    scan: int = DEFAULT_SCAN
    search_cells: int = MAX_SEARCHED
    friction: tuple[PairFriction, ...] = ()
    brake_torque: float = 0.0
    start_under_load: bool = False
    max_startup_time: float = 60.0
    max_rundown_time: float | None = None
    prices: Prices = field(default_factory=Prices)

    @property
    def pareto_weighs_parts(self) -> bool:
        """The Pareto set holds the machine's mass or cost: every member's wheels are sized in the search."""
        return any(n in self.pareto for n in WEIGHED_PARTS)

    @property
    def weighs_parts(self) -> bool:
        """The objective or the Pareto set holds the machine's mass or cost: every member's wheels are sized."""
        return any(self.weights.get(n, 0.0) > 0 or n in self.pareto for n in WEIGHED_PARTS)

    def validate(self) -> None:
        """InvalidInput naming the field for an unknown objective, no weight, a bad limit or scan size, a price,
        or a motor catalogue without masses when the machine is weighed or priced."""
        self.function.validate()
        self.prices.validate()
        if self.weighs_parts and self.drive.catalogue is not None:
            for k, m in enumerate(self.drive.catalogue):
                if m.mass is None:
                    raise InvalidInput(f"catalogue motor {m.name!r} has no mass: machine_mass and cost need the "
                                       "mass of every motor", field=f"drive.motor_catalogue.{k}.mass_kg")
        check_weights(self.weights)
        for k, name in enumerate(self.pareto):
            if name not in OBJECTIVES:
                raise InvalidInput(f"unknown objective {name!r}; the objectives are {list(OBJECTIVES)}",
                                   field=f"pareto.{k}")
        if self.pareto[0] == self.pareto[1]:
            raise InvalidInput("the Pareto set needs two different objectives", field="pareto")
        for limit, where in ((self.max_rms_shaking_force, "max_rms_shaking_force_N"),
                             (self.max_rms_shaking_moment, "max_rms_shaking_moment_Nm")):
            if limit is not None and not (math.isfinite(limit) and limit > 0):
                raise InvalidInput("a shaking limit must be positive", field=where)
        if not MIN_SCAN <= self.scan <= MAX_SCAN:
            raise InvalidInput(f"scan must lie in [{MIN_SCAN}, {MAX_SCAN}] members", field="scan_members")
        if not 0 <= self.search_cells <= MAX_SCAN:
            raise InvalidInput(f"cells searched must lie in [0, {MAX_SCAN}]", field="search_cells")

    def machine(self, linkage: Linkage) -> MachineSpec:
        """The chain's machine with ``linkage`` as its linkage."""
        return MachineSpec(linkage=linkage, speed=self.speed, drive=self.drive, delta=self.delta,
                           balancing=self.balancing, flywheel=self.flywheel, samples=self.samples,
                           speed_tolerance=self.speed_tolerance, friction=self.friction,
                           brake_torque=self.brake_torque, start_under_load=self.start_under_load,
                           max_startup_time=self.max_startup_time, max_rundown_time=self.max_rundown_time)


@dataclass(frozen=True, slots=True)
class FamilyScan:
    """The kinematic scan: ``grid_points`` members, ``runs`` the feasible intervals of u, ``step`` the grid
    spacing [-], ``chain_parameter`` the synthesis endpoint's default member, ``candidates`` the members the
    chain designs (the chain's member first)."""

    parameter_range: tuple[float, float]
    grid_points: int
    feasible_points: int
    step: float
    runs: tuple[tuple[float, float], ...]
    chain_parameter: float
    candidates: tuple[float, ...]
    # the kinematic constraint each run's ends meet (None at the parameter range's own end)
    run_limits: tuple[tuple[str | None, str | None], ...]


@dataclass(frozen=True, slots=True)
class MemberScore:
    """One member designed by the chain: ``values`` its objectives in :data:`OBJECTIVES` order [W, kg, N, kg,
    currency] (machine mass and cost NaN when its wheels were not sized) and ``rms_shaking_moment`` [N·m] (None
    when the chain refused it), ``feasible`` every check and limit met, ``reason`` why not; ``stage`` scan or
    refine; ``parts`` the masses of its parts."""

    parameter: float
    values: tuple[float, ...] | None
    rms_shaking_moment: float | None
    feasible: bool
    reason: str | None
    stage: str
    rms_shaking_force_before: float | None = None
    choice: Choice | None = None
    # the objectives without the flywheel body and the wheels: what the member's discrete choice and balancing fix
    floor_values: tuple[float, ...] | None = None
    parts: MachineParts | None = None
    # the objectives with the wheels left out (never negative): a lower bound where they were not sized
    lower_values: tuple[float, ...] | None = None


@dataclass(frozen=True, slots=True)
class Refinement:
    """One plateau of the family (the members sharing the chain's motor and tooth numbers ``choice``): its scanned
    members' span [lo, hi] (after the search: its ends located by bisection), the scanned member ``start`` with
    the best score in it, ``bound`` the least score its members' discrete choice and balancing allow (the flywheel
    body left out), ``status`` searched, pruned (bound no better than the best found) or unsearched (beyond the
    budget of plateaus searched), steady-machine runs spent and the best member found."""

    lo: float
    hi: float
    start: float
    evaluations: int
    best_parameter: float
    choice: Choice | None = None
    bound: float = math.inf
    status: str = "searched"
    plateaus: int = 0


@dataclass(frozen=True, slots=True)
class Certificate:
    """How the family was covered and what binds at the answer."""

    scan: FamilyScan
    members_designed: int
    feasible_designed: int
    refinements: tuple[Refinement, ...]
    gap_bound: float | None
    binding: tuple[str, ...]
    statement: str


@dataclass(frozen=True, slots=True)
class Gain:
    """One objective on the chain's machine and on the optimum; ``gain`` chain less optimum (positive: better);
    ``relative`` the gain over the objective's scale (its value on the chain's machine, see :func:`normalisers`)."""

    objective: str
    unit: str
    chain: float
    optimum: float
    gain: float
    relative: float


@dataclass(frozen=True, slots=True)
class MachineOptimum:
    """The optimised machine: its whole ``design`` (as :func:`design_machine` answers), the family ``parameter``,
    its ``values`` and weighted normalised ``score``; the ``chain``'s machine (as the scan designed it), its
    member ``chain_linkage`` and its score; ``gains`` per objective; ``pareto`` the non-dominated members of
    the two ``pareto_objectives``; every member designed; the certificate."""

    spec: OptimiseSpec
    design: MachineDesign
    parameter: float
    values: tuple[float, ...]
    score: float
    chain: MemberScore
    chain_linkage: Linkage
    chain_score: float | None
    chain_reason: str | None
    normalisers: tuple[float, ...]
    gains: tuple[Gain, ...]
    pareto_objectives: tuple[str, str]
    pareto: tuple[MemberScore, ...]
    members: tuple[MemberScore, ...]
    certificate: Certificate
    parts: MachineParts | None = None


_FIELDS = {
    "swing_deg": "function.swing_deg", "time_ratio": "function.time_ratio", "scale_length_m": "function.scale_length_m",
    "stroke_m": "function.stroke_m", "max_length_ratio": "function.max_length_ratio",
    "slow_stroke": "function.slow_stroke", "linear_density_kg_m": "function.linear_density_kg_m",
    "min_transmission_angle": "function.min_transmission_angle_deg",
}


def _field_of_constraint(name: str | None) -> str | None:
    """The request field behind a family constraint or a synthesis field."""
    if name is None:
        return None
    if name in _FIELDS:
        return _FIELDS[name]
    for end in ("_length_min", "_length_max"):
        if name.endswith(end):
            return f"function.bounds_m.{name[: -len(end)]}"
    if name.startswith("pivot_"):
        return "function.crank_pivot_region_m"
    return f"function.{name}"


def member_linkage(spec: OptimiseSpec, u: float) -> Linkage:
    """The family member at ``u`` with its link masses and loads."""
    return _member(spec, u)


def _member(spec: OptimiseSpec, u: float) -> Linkage:
    f = spec.function
    return _cr.member(f, u) if isinstance(f, CrankRockerSpec) else _sc.member(f, u)


def _slack(spec: OptimiseSpec, u: FloatArray) -> Mapping[str, FloatArray]:
    f = spec.function
    return _cr.family_slack(f, u) if isinstance(f, CrankRockerSpec) else _sc.family_slack(f, u)


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Index ranges [i, j] of the consecutive True entries of ``mask``."""
    edges = np.flatnonzero(np.diff(np.r_[0, mask.astype(int), 0]))
    return [(int(a), int(b) - 1) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def scan_family(spec: OptimiseSpec) -> FamilyScan:
    """The kinematic scan of the family and the members the chain will design.

    Raises InvalidInput for a function no linkage of the family meets and Infeasible naming the request field
    when the bounds or the transmission-angle limit exclude the whole family.
    """
    spec.validate()
    f = spec.function
    try:
        chain_u = (synthesise_crank_rocker(replace(f, objective="transmission_angle"))
                   if isinstance(f, CrankRockerSpec)
                   else synthesise_slider_crank(replace(f, objective="transmission_angle"))).parameter
    except Infeasible as exc:
        raise Infeasible(exc.reason, exc.constraint, field=_field_of_constraint(exc.constraint),
                         **exc.details) from exc
    except InvalidInput as exc:
        raise InvalidInput(str(exc), field=_field_of_constraint(exc.field)) from exc
    lo, hi = _cr.parameter_range(f) if isinstance(f, CrankRockerSpec) else (0.0, 1.0)
    u = np.linspace(lo, hi, KINEMATIC_GRID)
    slack = _slack(spec, u)
    names = list(slack)
    stacked = np.stack([slack[n] for n in names])
    ok = np.all(stacked > MARGIN, axis=0)
    runs = _runs(ok)
    feasible_u = u[ok]
    # candidates spread evenly over the feasible members, the chain's own member first
    picks = feasible_u[np.unique(np.linspace(0, feasible_u.size - 1, spec.scan).round().astype(int))]
    candidates = (chain_u, *(float(p) for p in picks if abs(p - chain_u) > 1e-12))

    def limit(i: int) -> str | None:
        if i < 0 or i >= u.size:
            return None
        return names[int(np.argmin(stacked[:, i]))]

    return FamilyScan(
        parameter_range=(lo, hi), grid_points=u.size, feasible_points=int(ok.sum()), step=float(u[1] - u[0]),
        runs=tuple((float(u[a]), float(u[b])) for a, b in runs), chain_parameter=float(chain_u),
        candidates=candidates, run_limits=tuple((limit(a - 1), limit(b + 1)) for a, b in runs),
    )


def _limits_missed(spec: OptimiseSpec, force: float, moment: float) -> list[str]:
    out = []
    if spec.max_rms_shaking_force is not None and force > spec.max_rms_shaking_force:
        out.append("exceeds max_rms_shaking_force_N")
    if spec.max_rms_shaking_moment is not None and moment > spec.max_rms_shaking_moment:
        out.append("exceeds max_rms_shaking_moment_Nm")
    return out


def _steady_score(spec: OptimiseSpec, u: float, stage: str, time_limit_s: float, size_gears: bool,
                  exact: bool = False) -> MemberScore:
    """The member's steady machine (no start or run-down simulation: the optimum's own design runs them); the
    gears' strength sizing, which comes last and feeds nothing back, only when ``size_gears`` (the machine's
    mass and cost need the wheels)."""
    machine = spec.machine(_member(spec, u))
    if not size_gears:
        machine = replace(machine, drive=replace(machine.drive, strength=None))
    try:
        m = steady_member(machine, time_limit_s=time_limit_s, size_gears=size_gears,
                          width_steps=None if exact else SEARCH_WIDTH_STEPS)
    except (Infeasible, InvalidInput, SolverFailed, SolverTimeout) as exc:
        return MemberScore(u, None, None, False, f"the chain refuses it: {exc}", stage)
    reasons = [f"fails its {name} check" for name in m.failed]
    reasons += _limits_missed(spec, m.values[2], m.rms_shaking_moment)
    p = m.parts
    return MemberScore(u, (*m.values, p.mass, p.cost(spec.prices)), m.rms_shaking_moment, not reasons,
                       "; ".join(reasons) or None, stage, m.rms_shaking_force_before, m.choice,
                       (m.values[0], m.balancing_mass, m.values[2], p.fixed_mass, p.fixed_cost(spec.prices)), p,
                       (*m.values, p.fixed_mass + p.flywheel,
                        p.fixed_cost(spec.prices) + spec.prices.flywheel * p.flywheel))


def _score_member(spec: OptimiseSpec, u: float, stage: str, time_limit_s: float,
                  size_gears: bool = False) -> tuple[MemberScore, MachineDesign | None]:
    if stage in ("scan", "refine"):
        # the members asked for by name (the chain's own) get the chain's precision: the gains compare them
        return _steady_score(spec, u, stage, time_limit_s, size_gears or spec.weighs_parts, size_gears), None
    machine = spec.machine(_member(spec, u))
    try:
        d = design_machine(machine, time_limit_s=time_limit_s)
    except (Infeasible, InvalidInput, SolverFailed, SolverTimeout) as exc:
        return MemberScore(u, None, None, False, f"the chain refuses it: {exc}", stage), None
    values = objective_values(d, spec.prices)
    reasons = [f"fails its {c.name} check" for c in d.checks if not c.passed]
    after = d.balancing.after
    reasons += _limits_missed(spec, after.rms_shaking_force, after.rms_shaking_moment)
    choice = (d.drive.motor.name, () if d.teeth is None else tuple((s.pinion_teeth, s.gear_teeth)
                                                                   for s in d.teeth.stages))
    return (MemberScore(u, values, after.rms_shaking_moment, not reasons, "; ".join(reasons) or None, stage,
                        d.before.summary().rms_shaking_force, choice, parts=design_parts(d)), d)


def design_parts(d: MachineDesign) -> MachineParts:
    """The parts of a whole machine design: counterweights, balancers, flywheel body, the wheels as the chain
    sized them (none when the drive asks for no sizing) and the catalogue motor."""
    return machine_parts(d.balancing, d.placement, d.gears, True, d.drive.motor)


def objective_values(d: MachineDesign, prices: Prices | None = None) -> tuple[float, ...]:
    """Motor rated power [W], added mass [kg] (counterweights, Lanchester balancer masses, flywheel body), RMS
    shaking force after balancing [N], the machine's mass [kg] (those with the wheels and the motor) and its
    cost at ``prices`` of a machine design."""
    bal = d.balancing
    mass = balancing_mass(bal)
    if d.placement is not None:
        mass += d.placement.mass
    p = design_parts(d)
    return (float(d.drive.motor.rated_power), float(mass), float(bal.after.rms_shaking_force), p.mass,
            p.cost(prices or Prices()))


def design_members(spec: OptimiseSpec, parameters: Sequence[float], *, time_limit_s: float = 20.0,
                   stage: str = "scan", size_gears_at: Sequence[float] = ()) -> tuple[MemberScore, ...]:
    """The chain on each member at ``parameters``, scored on its simulated machine; the wheels sized on the
    members at ``size_gears_at`` (the chain's own, whose mass and cost the gains report) or on every member when
    the objective weighs the machine."""
    sized = {float(u) for u in size_gears_at}
    return tuple(_score_member(spec, float(u), stage, time_limit_s, float(u) in sized)[0] for u in parameters)


def bounds_apply(spec: OptimiseSpec) -> bool:
    """The scan may bound members instead of designing them: the objective holds only parts the discrete choice
    and the balancing fix from below (motor power, balancing masses, shaking force); the machine's mass and cost
    need every member's wheels and motor as the chain sizes them."""
    return not spec.weighs_parts


def bound_members(spec: OptimiseSpec, parameters: Sequence[float], *,
                  time_limit_s: float = 20.0) -> tuple[MemberScore, ...]:
    """Each member bounded (stage :data:`BOUNDED`), not designed: the chain up to its discrete choice (analysis,
    balancing, the drive's split and teeth), with the parts of the objectives that fixes as ``floor_values``:
    the motor before any upgrade the steady checks ask for (which only takes a larger one), the balancing masses
    (the flywheel body, never negative, left out) and the shaking force after balancing. A member the chain
    refuses in these stages is refused as the scan refuses it."""
    out: list[MemberScore] = []
    for u in parameters:
        machine = spec.machine(_member(spec, float(u)))
        machine = replace(machine, drive=replace(machine.drive, strength=None))
        try:
            c = discrete_choice(machine, time_limit_s=time_limit_s)
        except (Infeasible, InvalidInput, SolverFailed, SolverTimeout) as exc:
            out.append(MemberScore(float(u), None, None, False, f"the chain refuses it: {exc}", "scan"))
            continue
        floor = (c.motor_power, c.balancing_mass, c.rms_shaking_force, math.nan, math.nan)
        out.append(MemberScore(float(u), None, None, False, None, BOUNDED, choice=c.choice, floor_values=floor))
    return tuple(out)


def scan_members(spec: OptimiseSpec, parameters: Sequence[float], chain_parameter: float, *,
                 time_limit_s: float = 20.0) -> tuple[MemberScore, ...]:
    """The scan's first pass over ``parameters``: the chain's own member designed in full (its wheels sized: the
    gains report its mass and cost), the others bounded when :func:`bounds_apply`, else designed in full."""
    out: list[MemberScore] = []
    for u in parameters:
        if u == chain_parameter or not bounds_apply(spec):
            out += design_members(spec, [u], time_limit_s=time_limit_s, size_gears_at=(chain_parameter,))
        else:
            out += bound_members(spec, [u], time_limit_s=time_limit_s)
    return tuple(out)


def _scales_from_chain(members: Sequence[MemberScore], chain_parameter: float) -> bool:
    """Every objective's scale is its value on the chain's machine, whatever the other members give."""
    chain = next((m for m in members if m.parameter == chain_parameter and m.values is not None), None)
    if chain is None or chain.values is None:
        return False
    return all(v > 0 or (OBJECTIVES[k] == "rms_shaking_force" and bool(chain.rms_shaking_force_before))
               for k, v in enumerate(chain.values))


def members_to_design(spec: OptimiseSpec, scan: FamilyScan, members: Sequence[MemberScore]) -> tuple[float, ...]:
    """The bounded members to design in full next, :data:`BOUND_ROUND` at most, least bound first: those whose
    bound is better than the best member designed, and their neighbours in the scan (so that every cell that
    could still be searched has both ends designed, as it would had every member been designed). Every bounded
    member when the objectives' scales do not all come from the chain's machine (they would then depend on
    which members were designed). None when no bounded member could still win."""
    bounded = [m for m in members if m.stage == BOUNDED]
    if not bounded:
        return ()
    if not _scales_from_chain(members, scan.chain_parameter):
        return tuple(m.parameter for m in bounded)
    norm = normalisers(members, scan.chain_parameter)
    every = _scores(spec, members, norm)
    best = float(np.min(every)) if every.size else math.inf
    scanned = sorted((m for m in members if m.stage in ("scan", BOUNDED)), key=lambda m: m.parameter)

    def floor(m: MemberScore) -> float:
        return -math.inf if m.floor_values is None else score(spec, m.floor_values, norm)

    open_ = set()
    for i, m in enumerate(scanned):
        if floor(m) < best * (1 - 1e-12):
            open_.add(m.parameter)
            for j in (i - 1, i + 1):
                if 0 <= j < len(scanned) and _run_of(scan, scanned[j].parameter) == _run_of(scan, m.parameter):
                    open_.add(scanned[j].parameter)
    todo = sorted((m for m in bounded if m.parameter in open_), key=lambda m: (floor(m), m.parameter))
    return tuple(m.parameter for m in todo[:BOUND_ROUND])


def with_designed(members: Sequence[MemberScore], designed: Iterable[MemberScore]) -> tuple[MemberScore, ...]:
    """``members`` with the bounded ones that were since ``designed`` in their place."""
    by = {m.parameter: m for m in designed}
    return tuple(by.get(m.parameter, m) for m in members)


def normalisers(members: Iterable[MemberScore], chain_parameter: float) -> tuple[float, ...]:
    """Each objective's scale: its value on the chain's machine, else the largest over the members designed,
    else 1 (an objective that is zero everywhere weighs nothing). A balanced machine's RMS shaking force is
    rounding; its scale is at least a millionth of the chain's linkage before balancing."""
    members = list(members)
    chain = next((m for m in members if m.parameter == chain_parameter and m.values is not None), None)
    out = []
    for k in range(len(OBJECTIVES)):
        v = chain.values[k] if chain is not None and chain.values is not None else 0.0
        if OBJECTIVES[k] == "rms_shaking_force" and chain is not None and chain.rms_shaking_force_before:
            v = max(v, SHAKING_FLOOR * chain.rms_shaking_force_before)
        if not v > 0:
            v = max((m.values[k] for m in members if m.values is not None and math.isfinite(m.values[k])),
                    default=0.0)
        out.append(v if v > 0 else 1.0)
    return tuple(out)


def score(spec: OptimiseSpec, values: Sequence[float], norm: Sequence[float]) -> float:
    """The weighted sum of the normalised objectives [-] (an objective of no weight, sized or not, adds nothing)."""
    return float(sum(spec.weights[name] * values[k] / norm[k] for k, name in enumerate(OBJECTIVES)
                     if spec.weights.get(name, 0.0) > 0))


def _search_values(m: MemberScore) -> tuple[float, ...] | None:
    """A member's objectives, their lower bound where its wheels were not sized."""
    if m.values is not None and m.lower_values is not None and not all(math.isfinite(v) for v in m.values):
        return m.lower_values
    return m.values


def _scores(spec: OptimiseSpec, members: Sequence[MemberScore], norm: Sequence[float]) -> np.ndarray:
    out = []
    for m in members:
        v = _search_values(m)
        out.append(score(spec, v, norm) if m.feasible and v is not None else np.inf)
    return np.array(out)


def settle(spec: OptimiseSpec, members: Sequence[MemberScore], chain_parameter: float, *,
           time_limit_s: float = 20.0) -> tuple[tuple[MemberScore, ...], int]:
    """Size the wheels of the members, best bound first, until no member left unsized could beat the best sized
    one: its score without the wheels (their mass and cost never negative) is no better. Returns the members
    (the sized ones in place of their bounds) and how many were sized here. Nothing to do unless the objective
    weighs the machine's mass or cost."""
    out = list(members)
    if not spec.weighs_parts:
        return tuple(out), 0
    norm = normalisers(out, chain_parameter)
    sized_here = 0
    while True:
        s = _scores(spec, out, norm)
        exact = np.array([m.values is not None and all(math.isfinite(v) for v in m.values) for m in out])
        best = float(np.min(np.where(exact, s, np.inf)))
        open_ = [i for i in np.argsort(s, kind="stable") if not exact[i] and np.isfinite(s[i])]
        if not open_ or s[open_[0]] >= best * (1 - 1e-12):
            return tuple(out), sized_here
        i = int(open_[0])
        again = _score_member(spec, out[i].parameter, out[i].stage, time_limit_s, True)[0]
        out[i] = again
        sized_here += 1


def _run_of(scan: FamilyScan, u: float) -> int:
    return next(k for k, r in enumerate(scan.runs) if r[0] - 1e-12 <= u <= r[1] + 1e-12)


def cells(spec: OptimiseSpec, scan: FamilyScan, members: Sequence[MemberScore],
          done: Iterable[tuple[float, float]] = ()) -> list[Refinement]:
    """The cells of the scan: the spans between neighbouring scanned members of one feasible run, each with its
    bound and status, in the order they are searched (best scanned end first).

    Within a cell the chain's discrete choices (catalogue motor, tooth numbers) may change: the members sharing
    one form a plateau on which the objective is continuous. A cell's bound is the least score of the
    objectives' parts the discrete choice and the balancing fix (motor power, balancing masses, shaking force;
    the flywheel body, never negative, left out) at its two ends: a bound as far as those parts are monotone
    across the cell. The cells whose (lo, hi) are in ``done`` are searched; of the others, a cell whose bound is
    no better than the best score of every member designed is pruned, and the rest are open."""
    norm = normalisers(members, scan.chain_parameter)
    scanned = sorted((m for m in members if m.stage in ("scan", BOUNDED)), key=lambda m: m.parameter)
    s = _scores(spec, scanned, norm)
    every = _scores(spec, members, norm)
    best = float(np.min(every)) if every.size else math.inf
    searched = set(done)
    found = []
    for i in range(len(scanned) - 1):
        a, b = scanned[i], scanned[i + 1]
        if _run_of(scan, a.parameter) != _run_of(scan, b.parameter):
            continue
        floors = [score(spec, m.floor_values, norm) for m in (a, b) if m.floor_values is not None]
        bound = min(floors) if len(floors) == 2 else -math.inf
        ends = (float(s[i]), float(s[i + 1]))
        start = a if ends[0] <= ends[1] else b
        if (a.parameter, b.parameter) in searched:
            status = "searched"
        elif math.isfinite(best) and bound >= best * (1 - 1e-12):
            status = "pruned"
        else:
            status = "open"
        found.append(((min(ends), max(ends)), Refinement(a.parameter, b.parameter, start.parameter, 0,
                                                         start.parameter, start.choice, float(bound), status)))
    # best scanned end first; of two cells sharing that end, the one whose other end is better
    return [r for _, r in sorted(found, key=lambda x: (x[0], x[1].bound))]


def next_cells(spec: OptimiseSpec, scan: FamilyScan, members: Sequence[MemberScore],
               done: Iterable[tuple[float, float]]) -> tuple[Refinement, ...]:
    """The cells to search next: the first :data:`MAX_SEARCHED` open ones of :func:`cells` (every member designed
    so far sets the best they must beat), within the request's budget of ``search_cells``."""
    done = tuple(done)
    room = min(MAX_SEARCHED, spec.search_cells - len(done))
    if room <= 0:
        return ()
    return tuple(replace(r, status="searched") for r in cells(spec, scan, members, done)
                 if r.status == "open")[:room]


def _choice_at(spec: OptimiseSpec, u: float, time_limit_s: float) -> Choice | None:
    machine = spec.machine(_member(spec, u))
    try:
        return discrete_choice(replace(machine, drive=replace(machine.drive, strength=None)),
                               time_limit_s=time_limit_s).choice
    except (Infeasible, InvalidInput, SolverFailed, SolverTimeout):
        return None


def _plateau_end(spec: OptimiseSpec, inside: float, outside: float, choice: Choice | None,
                 choices: dict[float, Choice | None], time_limit_s: float) -> tuple[float, float, Choice | None]:
    """The plateau of ``choice`` ends between ``inside`` and ``outside``: the last member found on it and the
    first beyond it with its choice, by :data:`BISECT_STEPS` bisections on the chain's discrete choice.
    ``choices`` holds the members' choices known so far and gains those found here."""

    def at(u: float) -> Choice | None:
        if u not in choices:
            choices[u] = _choice_at(spec, u, time_limit_s)
        return choices[u]

    beyond = at(outside)
    if beyond == choice:
        return outside, outside, beyond
    for _ in range(BISECT_STEPS):
        mid = 0.5 * (inside + outside)
        found = at(mid)
        if found == choice:
            inside = mid
        else:
            outside, beyond = mid, found
    return inside, outside, beyond


@dataclass(frozen=True, slots=True)
class Plateau:
    """A stretch [lo, hi] of a searched cell on which every member has the discrete ``choice``; ``width`` is the
    cell's, which sets Brent's tolerance."""

    lo: float
    hi: float
    choice: Choice | None
    width: float


def cell_plateaus(spec: OptimiseSpec, members: Sequence[MemberScore], r: Refinement, *,
                  time_limit_s: float = 20.0) -> tuple[Refinement, tuple[Plateau, ...]]:
    """The cell ``r`` (of :func:`next_cells`) cut into its plateaus from its lower end, each one's end located by
    bisection on the chain's discrete choice, :data:`MAX_WALK` at most."""
    known = {m.parameter: m for m in members}
    # the choices the scan's bounds found (a designed member's choice is its steady machine's, which a motor
    # upgrade may have changed); the cell's upper end is asked for by every plateau of the walk
    choices = {m.parameter: m.choice for m in members if m.stage == BOUNDED and r.lo <= m.parameter <= r.hi}
    x, choice = r.lo, known[r.lo].choice
    out: list[Plateau] = []
    while x < r.hi and len(out) < MAX_WALK:
        inside, outside, beyond = _plateau_end(spec, x, r.hi, choice, choices, time_limit_s)
        out.append(Plateau(x, inside, choice, r.hi - r.lo))
        if outside <= inside:
            break
        x, choice = outside, beyond
    return r, tuple(out)


def search_plateau(spec: OptimiseSpec, scan: FamilyScan, members: Sequence[MemberScore], plateau: Plateau, *,
                   time_limit_s: float = 20.0) -> tuple[MemberScore, ...]:
    """The steady machine at both ends of ``plateau``, then bounded Brent between them; every member it designed
    (the scanned ones are not designed again)."""
    norm = normalisers(members, scan.chain_parameter)
    s = _scores(spec, members, norm)
    # an infeasible member is worse than any feasible one: the penalty keeps Brent's steps finite
    penalty = 10.0 * (1.0 + float(np.max(np.where(np.isfinite(s), s, 0.0))))
    known = {m.parameter: m for m in members}
    seen: list[MemberScore] = []

    def f(x: float) -> float:
        m = known.get(x) or _score_member(spec, float(x), "refine", time_limit_s)[0]
        if x not in known:
            known[x] = m
            seen.append(m)
        return score(spec, m.values, norm) if m.feasible and m.values is not None else penalty

    f(plateau.lo)
    f(plateau.hi)
    if plateau.hi > plateau.lo:
        minimize_scalar(f, bounds=(plateau.lo, plateau.hi), method="bounded",
                        options={"maxiter": REFINE_EVALUATIONS, "xatol": 1e-5 * plateau.width})
    return tuple(seen)


def cell_refinement(spec: OptimiseSpec, scan: FamilyScan, members: Sequence[MemberScore], r: Refinement,
                    plateaus: int, seen: Sequence[MemberScore]) -> Refinement:
    """The searched cell's record: runs spent, plateaus walked and its best member among the scanned ones and
    ``seen``, those its plateaus' searches designed."""
    norm = normalisers(members, scan.chain_parameter)
    mine = [m for m in (*members, *seen) if r.lo <= m.parameter <= r.hi]
    i = int(np.argmin(_scores(spec, mine, norm)))
    return replace(r, evaluations=len(seen), best_parameter=float(mine[i].parameter), choice=mine[i].choice,
                   plateaus=plateaus)


def _pareto(members: Sequence[MemberScore], a: int, b: int) -> tuple[MemberScore, ...]:
    ok = [m for m in members if m.feasible and m.values is not None]
    out: list[MemberScore] = []
    for m in ok:
        assert m.values is not None
        va, vb = m.values[a], m.values[b]
        dominated = any(o.values is not None and o.values[a] <= va and o.values[b] <= vb
                        and (o.values[a] < va or o.values[b] < vb) for o in ok)
        if not dominated and not any(o.values is not None and o.values[a] == va and o.values[b] == vb
                                     for o in out):
            out.append(m)
    return tuple(sorted(out, key=lambda m: (m.values[a] if m.values else 0.0, m.parameter)))


def _binding(spec: OptimiseSpec, scan: FamilyScan, d: MachineDesign, u: float) -> tuple[str, ...]:
    out = []
    for (lo, hi), (at_lo, at_hi) in zip(scan.runs, scan.run_limits, strict=True):
        if lo - 1e-12 <= u <= hi + 1e-12:
            if u - lo <= BINDING_STEPS * scan.step:
                out.append(at_lo or "parameter range")
            if hi - u <= BINDING_STEPS * scan.step:
                out.append(at_hi or "parameter range")
    for c in d.checks:
        if c.name != "mean_speed" and c.limit > 0 and c.value >= (1 - BINDING_FRACTION) * c.limit:
            out.append(c.name)
    after = d.balancing.after
    for value, limit, name in ((after.rms_shaking_force, spec.max_rms_shaking_force, "max_rms_shaking_force_N"),
                               (after.rms_shaking_moment, spec.max_rms_shaking_moment, "max_rms_shaking_moment_Nm")):
        if limit is not None and value >= (1 - BINDING_FRACTION) * limit:
            out.append(name)
    return tuple(dict.fromkeys(out))


def conclude(spec: OptimiseSpec, scan: FamilyScan, members: Sequence[MemberScore], refinements:
             Sequence[Refinement], *, time_limit_s: float = 20.0) -> MachineOptimum:
    """The best member designed again as a whole machine, with the chain's design, the gains, the Pareto set and
    the certificate. Infeasible when no member designed meets every check and limit."""
    members, sized_here = settle(spec, members, scan.chain_parameter, time_limit_s=time_limit_s)
    norm = normalisers(members, scan.chain_parameter)
    s = _scores(spec, members, norm)
    if not np.isfinite(s).any():
        reasons = sorted({m.reason for m in members if m.reason})
        raise Infeasible("no member of the family gives a machine that meets every check and limit: "
                         + "; ".join(reasons[:3]), "machine checks", field=None, members_designed=len(members))
    again, design, best = None, None, members[int(np.argmin(s))]
    # the search ran the steady machine; the answer's whole chain adds the start and run-down checks
    for i in np.argsort(s, kind="stable")[:FINAL_TRIES]:
        if not np.isfinite(s[i]):
            break
        best = members[int(i)]
        again, design = _score_member(spec, best.parameter, "optimum", time_limit_s)
        if design is not None and again.feasible:
            break
    if again is not None and not again.feasible:
        raise Infeasible("no member of the family gives a machine that meets every check and limit: the best "
                         f"{FINAL_TRIES} of the search, designed through the whole chain: {again.reason}",
                         "machine checks", field=None, members_designed=len(members))
    if design is None or again is None or again.values is None:
        raise SolverFailed("not_reproduced", "the best member's chain did not run again")
    values = again.values
    # the chain's own member was designed in the scan, as /v1/machines/design designs it
    chain_member = next(m for m in members if m.parameter == scan.chain_parameter)
    chain_values = chain_member.values
    gains = []
    for k, (name, unit) in enumerate(zip(OBJECTIVES, OBJECTIVE_UNITS, strict=True)):
        c = chain_values[k] if chain_values is not None else math.nan
        gains.append(Gain(name, unit, c, values[k], c - values[k], (c - values[k]) / norm[k]))
    a, b = (OBJECTIVES.index(n) for n in spec.pareto)
    binding = _binding(spec, scan, design, best.parameter)
    bounded = [k for k, m in enumerate(members) if m.stage == BOUNDED]
    if bounded:
        # what the bound was measured against: the best member found, the search's included
        best_score = float(np.min(s))
        members = list(members)
        for k in bounded:
            m = members[k]
            floor = score(spec, m.floor_values, norm) if m.floor_values is not None else math.nan
            members[k] = replace(m, reason=f"not designed further: its bound {floor:.6g} (motor, balancing masses and "
                                 f"shaking force its discrete choice fixes, the flywheel body left out) is no "
                                 f"better than the best member found ({best_score:.6g})")
        members = tuple(members)
    designed = len(members) - len(bounded)
    feasible = int(np.isfinite(s).sum())
    searched = {(r.lo, r.hi): r for r in refinements}
    # what is still open once the search has stopped was left by the budget
    found = [searched[(r.lo, r.hi)] if r.status == "searched" else replace(r, status="unsearched")
             if r.status == "open" else r for r in cells(spec, scan, members, searched)]
    counts = {k: sum(r.status == k for r in found) for k in ("searched", "pruned", "unsearched")}
    statement = (
        f"{scan.grid_points} members of the family checked kinematically at once ({scan.feasible_points} within "
        f"the bounds and the transmission-angle limit, in {len(scan.runs)} run(s) of the parameter); "
        f"{len(scan.candidates)} spread evenly over the feasible runs (the chain's own member among them) "
        + (f"bounded first by the chain up to its discrete choice (the motor, the balancing masses and the shaking "
           f"force that choice fixes; the flywheel body, never negative, left out); the chain's own member and "
           f"the {len(scan.candidates) - len(bounded) - 1} whose bound (or a neighbour's) could still beat the "
           f"best member found run through the chain to their steady machine, least bound first, {BOUND_ROUND} "
           f"at a time; the {len(bounded)} others could not win and were not designed further. "
           if bounded else "run through the chain to their steady machine. ")
        + f"Members sharing the chain's motor and tooth numbers form "
        f"plateaus of the parameter on which the objective is continuous. Of the {len(found)} cells between "
        f"neighbouring scanned members, {counts['pruned']} were pruned: their least score from the motor, the "
        f"balancing masses and the shaking force at their ends (the flywheel body, never negative, left out) is "
        f"no better than the best member found; {counts['searched']} were searched, {MAX_SEARCHED} at a time, "
        f"those that could still beat the best found first, "
        f"{sum(r.plateaus for r in found if r.status == 'searched')} plateaus walked, each one's end located by "
        f"{BISECT_STEPS} bisection steps on the discrete choice, then bounded Brent between its ends "
        f"({sum(r.evaluations for r in refinements)} runs); "
        + (f"{counts['unsearched']} were left beyond the budget (search_cells {spec.search_cells}). "
           if counts["unsearched"] else "none was left: every cell that could beat the best found was searched. ")
        + f"{designed} members designed, {feasible} meeting every check and limit; the answer "
        "was designed again through the whole chain, start and run-down included. A plateau narrower than a "
        "bisection step is not seen, and the bound assumes the fixed parts monotone across a cell: no gap bound "
        "is claimed."
    )
    if spec.weighs_parts:
        sized = sum(1 for m in members if m.values is not None and all(math.isfinite(v) for v in m.values))
        statement += (f" The machine's mass and cost need the gear wheels sized for strength: {sized} members "
                      f"were sized ({sized_here} of them best bound first after the search); every other member's "
                      "score without its wheels (never negative) is no better than the best sized, so sizing it "
                      "could not change the answer.")
    certificate = Certificate(scan, designed, feasible, tuple(found), None, binding, statement)
    return MachineOptimum(
        spec=spec, design=design, parameter=best.parameter, values=values, score=score(spec, values, norm),
        chain=chain_member, chain_linkage=_member(spec, scan.chain_parameter),
        chain_score=score(spec, chain_values, norm) if chain_values is not None and chain_member.feasible else None,
        chain_reason=chain_member.reason, normalisers=norm, gains=tuple(gains),
        pareto_objectives=spec.pareto, pareto=_pareto(members, a, b), members=members, certificate=certificate,
        parts=design_parts(design),
    )


def conclude_search(spec: OptimiseSpec, scan: FamilyScan, members: Sequence[MemberScore],
                    walks: Sequence[tuple[Refinement, Sequence[Plateau]]],
                    seen: Sequence[Sequence[MemberScore]], *, time_limit_s: float = 20.0) -> MachineOptimum:
    """:func:`conclude` after the cells' search: ``walks`` each searched cell and its plateaus
    (:func:`cell_plateaus`) in the order they were searched, ``seen`` what each plateau's search designed
    (:func:`search_plateau`), the plateaus in the walks' order."""
    refinements: list[Refinement] = []
    extra = designed(seen)
    i = 0
    for r, plateaus in walks:
        mine = tuple(m for part in seen[i : i + len(plateaus)] for m in part)
        i += len(plateaus)
        refinements.append(cell_refinement(spec, scan, members, r, len(plateaus), mine))
    return conclude(spec, scan, tuple(members) + extra, refinements, time_limit_s=time_limit_s)


def designed(seen: Sequence[Sequence[MemberScore]]) -> tuple[MemberScore, ...]:
    """Every member the plateaus' searches designed, in their order."""
    return tuple(m for part in seen for m in part)


def in_run(run: str, fn: Callable[..., T], /, *args: Any, **kwargs: Any) -> T:
    """``fn(*args, **kwargs)`` as a stage of the optimisation ``run`` (a name of its own): a member's stages up to
    its drive that an earlier stage of the run computed in this process are taken as they were
    (:func:`.optimise_light.kept`)."""
    with kept(run):
        return fn(*args, **kwargs)


def optimise_machine(spec: OptimiseSpec, *, time_limit_s: float = 20.0) -> MachineOptimum:
    """Optimise the machine as a whole over its linkage family; every stage in this process, one after another.

    Parameters
    ----------
    spec
        The machine's function, load, speed [rad/s], drive, target delta [-], balancing and flywheel choices, the
        objective's weights and the optional shaking limits [N, N·m].
    time_limit_s
        Each solver's time limit [s].

    Raises InvalidInput or Infeasible naming the request field, or Infeasible when no member meets the checks.
    """
    run = uuid.uuid4().hex
    try:
        with kept(run):
            return _optimise_machine(spec, time_limit_s)
    finally:
        forget(run)


def _optimise_machine(spec: OptimiseSpec, time_limit_s: float) -> MachineOptimum:
    scan = scan_family(spec)
    members = scan_members(spec, scan.candidates, scan.chain_parameter, time_limit_s=time_limit_s)
    while bound_round := members_to_design(spec, scan, members):
        members = with_designed(members, design_members(spec, bound_round, time_limit_s=time_limit_s))
    walks: list[tuple[Refinement, tuple[Plateau, ...]]] = []
    seen: list[tuple[MemberScore, ...]] = []
    # rounds of cells, each round's cells chosen against the best of every member designed before it
    while todo := next_cells(spec, scan, members + designed(seen), ((r.lo, r.hi) for r, _ in walks)):
        for r in todo:
            walk = cell_plateaus(spec, members, r, time_limit_s=time_limit_s)
            walks.append(walk)
            seen.extend(search_plateau(spec, scan, members, p, time_limit_s=time_limit_s) for p in walk[1])
    return conclude_search(spec, scan, members, walks, seen, time_limit_s=time_limit_s)
