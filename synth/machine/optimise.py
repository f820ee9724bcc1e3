"""The machine optimised as a whole: the linkage's family member, counterweights, flywheel, motor and ratio together.

The design chain takes each stage's answer as given. Here the free dimension of the linkage (the family parameter
u of the dimensional synthesis: the crank pivot's place on its circle) is chosen together with everything the
chain chooses for that member, for a stated objective: the motor's rated power, the mass added to the machine
(counterweights, balancer masses and the flywheel body), the RMS shaking force, or a weighted sum of these, each
normalised by its value on the chain's own machine (the synthesis endpoint's default member designed by
:func:`design_machine`).

How the family is covered, in four plain functions of plain data so that the candidates' chains run on worker
processes (:func:`optimise_machine` runs them one after another):

1. :func:`scan_family`: the kinematic constraints of many members at once (vectorised), the feasible runs of the
   parameter, the chain's member, and evenly spread candidates over the feasible runs;
2. :func:`design_members`: the whole chain on candidates, each scored on the simulated machine (its checks:
   delta, speed, motor heating and breakdown) and the optional shaking limits;
3. :func:`refine_bracket`: bounded Brent on the chain itself within the bracket around one of the best local
   minima of the scan (a multistart over the brackets);
4. :func:`conclude`: the best member designed again as a whole machine, the gain over the chain in every
   objective, the Pareto set of two objectives over every member designed, the binding constraints and the
   certificate of how the family was covered.

The motor comes from a catalogue, so the objective steps where the motor changes: no Lipschitz constant bounds it
and no gap bound is claimed; the certificate states the scan density and the refinements instead.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Literal

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
from .spec import BalancingChoice, DriveSpec, FlywheelChoice, MachineSpec

ObjectiveName = Literal["motor_power", "added_mass", "rms_shaking_force"]
#: The objectives, in the order every tuple of objective values holds them.
OBJECTIVES: tuple[ObjectiveName, ...] = ("motor_power", "added_mass", "rms_shaking_force")
#: Units of the objectives, in the same order.
OBJECTIVE_UNITS = ("W", "kg", "N")
#: Members whose kinematic constraints are evaluated at once to find the feasible runs of the parameter.
KINEMATIC_GRID = 4001
#: Largest and least number of members the chain designs in the scan.
MAX_SCAN, MIN_SCAN = 64, 4
#: Members the chain designs in the scan unless the request says otherwise.
DEFAULT_SCAN = 20
#: Brackets refined around the scan's best local minima, and chain runs each refinement may spend.
BRACKETS = 2
REFINE_EVALUATIONS = 6
#: A check within this fraction of its limit, or a kinematic bound within this many grid steps, binds.
BINDING_FRACTION = 0.02
BINDING_STEPS = 2
#: Fraction of the unbalanced RMS shaking force below which a balanced one is rounding [-].
SHAKING_FLOOR = 1e-6


@dataclass(frozen=True, slots=True)
class OptimiseSpec:
    """A machine to optimise: its function, and everything the chain needs besides the linkage.

    ``function`` the crank-rocker's swing and time ratio with its scale, or the slider-crank's stroke and time
    ratio, with link densities, loads, the transmission-angle limit and length bounds (the synthesis spec; its
    ``objective``, ``speed`` and ``samples`` are not used here); ``speed`` [rad/s], ``drive``, ``delta`` [-],
    ``balancing``, ``flywheel``, ``samples``, ``speed_tolerance`` [-] as in :class:`MachineSpec`; ``weights``
    objective name -> weight [-] of its normalised value; ``max_rms_shaking_force`` [N] and
    ``max_rms_shaking_moment`` [N·m] optional limits after balancing; ``pareto`` the two objectives of the
    Pareto set; ``scan`` members the chain designs in the scan; ``friction``, ``brake_torque`` [N·m],
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
    friction: tuple[PairFriction, ...] = ()
    brake_torque: float = 0.0
    start_under_load: bool = False
    max_startup_time: float = 60.0
    max_rundown_time: float | None = None

    def validate(self) -> None:
        """InvalidInput naming the field for an unknown objective, no weight, a bad limit or scan size."""
        self.function.validate()
        for name, w in self.weights.items():
            if name not in OBJECTIVES:
                raise InvalidInput(f"unknown objective {name!r}; the objectives are {list(OBJECTIVES)}",
                                   field=f"weights.{name}")
            if not (math.isfinite(w) and w >= 0):
                raise InvalidInput("an objective's weight must be finite and not negative", field=f"weights.{name}")
        if not any(w > 0 for w in self.weights.values()):
            raise InvalidInput("give at least one objective a positive weight", field="weights")
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
    """One member designed by the chain: ``values`` its objectives in :data:`OBJECTIVES` order [W, kg, N] and
    ``rms_shaking_moment`` [N·m] (None when the chain refused it), ``feasible`` every check and limit met,
    ``reason`` why not; ``stage`` scan or refine."""

    parameter: float
    values: tuple[float, float, float] | None
    rms_shaking_moment: float | None
    feasible: bool
    reason: str | None
    stage: str
    rms_shaking_force_before: float | None = None


@dataclass(frozen=True, slots=True)
class Refinement:
    """One bracket refined by bounded Brent on the chain: [lo, hi], its start, runs spent, best found."""

    lo: float
    hi: float
    start: float
    evaluations: int
    best_parameter: float


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
    values: tuple[float, float, float]
    score: float
    chain: MemberScore
    chain_linkage: Linkage
    chain_score: float | None
    chain_reason: str | None
    normalisers: tuple[float, float, float]
    gains: tuple[Gain, ...]
    pareto_objectives: tuple[str, str]
    pareto: tuple[MemberScore, ...]
    members: tuple[MemberScore, ...]
    certificate: Certificate


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


def _score_member(spec: OptimiseSpec, u: float, stage: str, time_limit_s: float) -> tuple[MemberScore,
                                                                                          MachineDesign | None]:
    machine = spec.machine(_member(spec, u))
    if stage in ("scan", "refine"):
        # the gears are sized last, for the torques of the simulated machine, and feed nothing back: no
        # objective, check or limit here depends on them, so the search leaves them out and the optimum's own
        # design sizes them as the request asks
        machine = replace(machine, drive=replace(machine.drive, strength=None))
    try:
        d = design_machine(machine, time_limit_s=time_limit_s)
    except (Infeasible, InvalidInput, SolverFailed, SolverTimeout) as exc:
        return MemberScore(u, None, None, False, f"the chain refuses it: {exc}", stage), None
    values = objective_values(d)
    reasons = [f"fails its {c.name} check" for c in d.checks if not c.passed]
    after = d.balancing.after
    if spec.max_rms_shaking_force is not None and after.rms_shaking_force > spec.max_rms_shaking_force:
        reasons.append("exceeds max_rms_shaking_force_N")
    if spec.max_rms_shaking_moment is not None and after.rms_shaking_moment > spec.max_rms_shaking_moment:
        reasons.append("exceeds max_rms_shaking_moment_Nm")
    return (MemberScore(u, values, after.rms_shaking_moment, not reasons, "; ".join(reasons) or None, stage,
                        d.before.summary().rms_shaking_force), d)


def objective_values(d: MachineDesign) -> tuple[float, float, float]:
    """Motor rated power [W], added mass [kg] (counterweights, Lanchester balancer masses, flywheel body) and
    RMS shaking force after balancing [N] of a machine design."""
    bal = d.balancing
    mass = 0.0
    if bal.result is not None:
        mass += sum(c.mass for c in bal.result.counterweights)
    if bal.slider_crank is not None:
        mass += bal.slider_crank.crank_counterweight.mass
        if bal.mode == "full":
            mass += sum(2 * p.mass for p in bal.slider_crank.pairs)  # each pair: two shafts, each with its mass
    if d.placement is not None:
        mass += d.placement.mass
    return (float(d.drive.motor.rated_power), float(mass), float(bal.after.rms_shaking_force))


def design_members(spec: OptimiseSpec, parameters: Sequence[float], *, time_limit_s: float = 20.0,
                   stage: str = "scan") -> tuple[MemberScore, ...]:
    """The chain on each member at ``parameters``, scored on its simulated machine."""
    return tuple(_score_member(spec, float(u), stage, time_limit_s)[0] for u in parameters)


def normalisers(members: Iterable[MemberScore], chain_parameter: float) -> tuple[float, float, float]:
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
            v = max((m.values[k] for m in members if m.values is not None), default=0.0)
        out.append(v if v > 0 else 1.0)
    return (out[0], out[1], out[2])


def score(spec: OptimiseSpec, values: Sequence[float], norm: Sequence[float]) -> float:
    """The weighted sum of the normalised objectives [-]."""
    return float(sum(spec.weights.get(name, 0.0) * values[k] / norm[k] for k, name in enumerate(OBJECTIVES)))


def _scores(spec: OptimiseSpec, members: Sequence[MemberScore], norm: Sequence[float]) -> np.ndarray:
    return np.array([score(spec, m.values, norm) if m.feasible and m.values is not None else np.inf
                     for m in members])


def brackets(spec: OptimiseSpec, scan: FamilyScan, members: Sequence[MemberScore]) -> list[tuple[float, float, float]]:
    """(lo, hi, start) around the scan's best local minima, each within its feasible run, best first."""
    norm = normalisers(members, scan.chain_parameter)
    order = sorted(range(len(members)), key=lambda i: members[i].parameter)
    u = np.array([members[i].parameter for i in order])
    s = _scores(spec, [members[i] for i in order], norm)
    out = []
    for i in np.argsort(s, kind="stable"):
        if not np.isfinite(s[i]):
            break
        if (i > 0 and s[i - 1] < s[i]) or (i + 1 < s.size and s[i + 1] < s[i]):
            continue  # not a local minimum of the scan
        run = next(r for r in scan.runs if r[0] - 1e-12 <= u[i] <= r[1] + 1e-12)
        lo = max(u[i - 1], run[0]) if i > 0 else run[0]
        hi = min(u[i + 1], run[1]) if i + 1 < u.size else run[1]
        if hi > lo:
            out.append((float(lo), float(hi), float(u[i])))
        if len(out) == BRACKETS:
            break
    return out


def refine_bracket(spec: OptimiseSpec, scan: FamilyScan, members: Sequence[MemberScore], k: int, *,
                   time_limit_s: float = 20.0) -> tuple[Refinement | None, tuple[MemberScore, ...]]:
    """Bounded Brent on the chain within the ``k``-th bracket of :func:`brackets` (None when there is none),
    and every member it designed."""
    found = brackets(spec, scan, members)
    if k >= len(found):
        return None, ()
    lo, hi, start = found[k]
    norm = normalisers(members, scan.chain_parameter)
    seen: list[MemberScore] = []
    # an infeasible member is worse than any feasible one; the penalty keeps Brent's steps finite
    penalty = 10.0 * (1.0 + float(np.max(np.where(np.isfinite(s := _scores(spec, members, norm)), s, 0.0))))

    def f(x: float) -> float:
        m = _score_member(spec, float(x), "refine", time_limit_s)[0]
        seen.append(m)
        return score(spec, m.values, norm) if m.feasible and m.values is not None else penalty

    minimize_scalar(f, bounds=(lo, hi), method="bounded",
                    options={"maxiter": REFINE_EVALUATIONS, "xatol": 1e-4 * (hi - lo)})
    s = _scores(spec, seen, norm)
    best = seen[int(np.argmin(s))].parameter if np.isfinite(s).any() else start
    return Refinement(lo, hi, start, len(seen), float(best)), tuple(seen)


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
    members = tuple(members)
    norm = normalisers(members, scan.chain_parameter)
    s = _scores(spec, members, norm)
    if not np.isfinite(s).any():
        reasons = sorted({m.reason for m in members if m.reason})
        raise Infeasible("no member of the family gives a machine that meets every check and limit: "
                         + "; ".join(reasons[:3]), "machine checks", field=None, members_designed=len(members))
    best = members[int(np.argmin(s))]
    again, design = _score_member(spec, best.parameter, "optimum", time_limit_s)
    if design is None or again.values is None:
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
    designed = len(members)
    feasible = int(np.isfinite(s).sum())
    statement = (
        f"{scan.grid_points} members of the family checked kinematically at once ({scan.feasible_points} within "
        f"the bounds and the transmission-angle limit, in {len(scan.runs)} run(s) of the parameter); the chain "
        f"designed {designed} of them ({feasible} meeting every check and limit): {len(scan.candidates)} spread "
        f"evenly over the feasible runs, the chain's own member among them, then bounded Brent on the chain "
        f"itself in {len(refinements)} bracket(s) around the best local minima of that scan "
        f"({sum(r.evaluations for r in refinements)} runs). The motor comes from a catalogue, so the objective "
        "steps where the motor changes: no Lipschitz bound holds and no gap bound is claimed."
    )
    certificate = Certificate(scan, designed, feasible, tuple(refinements), None, binding, statement)
    return MachineOptimum(
        spec=spec, design=design, parameter=best.parameter, values=values, score=score(spec, values, norm),
        chain=chain_member, chain_linkage=_member(spec, scan.chain_parameter),
        chain_score=score(spec, chain_values, norm) if chain_values is not None and chain_member.feasible else None,
        chain_reason=chain_member.reason, normalisers=norm, gains=tuple(gains),
        pareto_objectives=spec.pareto, pareto=_pareto(members, a, b), members=members, certificate=certificate,
    )


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
    scan = scan_family(spec)
    members = design_members(spec, scan.candidates, time_limit_s=time_limit_s)
    refinements = []
    extra: list[MemberScore] = []
    for k in range(BRACKETS):
        r, seen = refine_bracket(spec, scan, members, k, time_limit_s=time_limit_s)
        if r is not None:
            refinements.append(r)
            extra.extend(seen)
    return conclude(spec, scan, members + tuple(extra), refinements, time_limit_s=time_limit_s)
