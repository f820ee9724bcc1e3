"""Any linkage's free dimensions chosen with its machine: a Sobol sample of the box, then local refinement.

A general linkage (the dyad description of :class:`PlanarLinkage`) has numbers marked free, each within bounds: a
frame point's coordinate, a link's length, a point of a link. The function it must do is a set of constraints on
the analysed linkage: the output's travel (a slider's stroke [m] or a turning output's swing [rad]) within a band,
the time ratio within a band, the least transmission angle of every RRR and RRP dyad, and assembly over the whole
turn. The machine around it (loads, speed, drive, balancing, flywheel) is the chain's.

1. :func:`sample_box`: a scrambled Sobol sample of the box (``scipy.stats.qmc``), the request's own numbers first;
2. :func:`check_member`: each member's kinematics over the whole turn in one vectorised pass over the crank
   angles (positions and their first analogues), which gives the travel, the time ratio from the extremes (the
   zero crossings of the output's velocity analogue) and the transmission angles;
3. the kinematically feasible members through the chain to their steady machine (as the family optimisation
   scores them, :mod:`.optimise_light`), scored by the same objectives;
4. the best feasible members refined by COBYLA on the score, the function's constraints (as slacks) and the box
   its constraints (a member off the function is run through the chain too, so that the score stays continuous
   across a constraint's boundary; only members meeting everything count), then the best member designed through
   the whole chain.

The stages are plain functions of plain data, so that the service can run them as separate tasks side by side:
:func:`scan_box` (the sample and its kinematic check), :func:`design_sample` (the chain on some of the sample's
feasible members), :func:`refine_start` (one refinement from the k-th best member) and :func:`conclude_linkage`
(the answer and its certificate). :func:`optimise_linkage` runs them one after another in one process and gives
the same answer.

The objective steps where the catalogue motor or the teeth change and the feasible set need not be convex: the
certificate states the coverage (members sampled, feasible, designed, refined, runs) and claims no gap.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np
from scipy.optimize import minimize
from scipy.stats import qmc

from ..errors import Infeasible, InvalidInput, NotAssemblable, SolverFailed, SolverTimeout
from ..kinematics import PlanarLinkage
from ..kinematics.linkage import LinkSpec
from .chain import MachineDesign, design_machine
from .optimise import OBJECTIVE_UNITS, OBJECTIVES, WEIGHED_PARTS, check_weights, design_parts, objective_values
from .optimise_light import steady_member
from .optimise_parts import MachineParts, Prices
from .spec import MachineSpec

#: Crank angles of the kinematic check of each member.
CHECK_ANGLES = 720
#: Bounds on the sample and the refinement.
MIN_SAMPLES, MAX_SAMPLES, DEFAULT_SAMPLES = 8, 512, 64
MAX_FREE = 6
MAX_REFINED, DEFAULT_REFINED = 8, 4
MAX_REFINE_RUNS, DEFAULT_REFINE_RUNS = 200, 60
#: Extremes of the output within this fraction of its travel of the highest (lowest) count as its end too.
LEVEL = 0.01
#: The Sobol sequence's seed: the same request gives the same members.
SOBOL_SEED = 20240611


@dataclass(frozen=True, slots=True)
class FreeDimension:
    """A number of the linkage left free within [lo, hi]: ``path`` ``frame_points_m.<point>.x`` (or ``.y``),
    ``links.<link>.length_m`` or ``links.<link>.points_m.<point>.x`` (or ``.y``) [m]."""

    path: str
    lo: float
    hi: float


@dataclass(frozen=True, slots=True)
class LinkageFunction:
    """What the linkage must do: ``travel`` the output's stroke [m] (a slider) or swing [rad] (a turning output)
    within [lo, hi]; ``time_ratio`` [-] within [lo, hi] (None: not constrained); ``min_transmission_angle``
    [rad] of every RRR and RRP dyad over the turn."""

    travel: tuple[float, float] | None = None
    time_ratio: tuple[float, float] | None = None
    min_transmission_angle: float = 0.0


@dataclass(frozen=True, slots=True)
class LinkageOptimiseSpec:
    """The machine around the linkage (``machine``, its linkage the one with the request's own numbers), the
    free dimensions, the function, the objectives' ``weights``, the sample's size, how many of the best members
    are refined and with how many chain runs each, and the prices of the parts."""

    machine: MachineSpec
    free: tuple[FreeDimension, ...]
    function: LinkageFunction
    weights: Mapping[str, float] = field(default_factory=lambda: {"machine_mass": 1.0})
    samples: int = DEFAULT_SAMPLES
    refined: int = DEFAULT_REFINED
    refine_runs: int = DEFAULT_REFINE_RUNS
    prices: Prices = field(default_factory=Prices)

    @property
    def weighs_parts(self) -> bool:
        """The objective weighs the machine's mass or cost: every member's wheels are sized."""
        return any(self.weights.get(n, 0.0) > 0 for n in WEIGHED_PARTS)

    def validate(self) -> None:
        """InvalidInput naming the field: a free number the linkage does not have, bad bounds, an unknown
        objective, counts out of range."""
        if not isinstance(self.machine.linkage.mechanism, PlanarLinkage):
            raise InvalidInput("free dimensions need a general linkage (type linkage)", field="machine.mechanism")
        if not 1 <= len(self.free) <= MAX_FREE:
            raise InvalidInput(f"give 1 to {MAX_FREE} free dimensions", field="free")
        seen = set()
        for k, d in enumerate(self.free):
            if d.path in seen:
                raise InvalidInput(f"{d.path} is free twice", field=f"free.{k}.path")
            seen.add(d.path)
            if not (math.isfinite(d.lo) and math.isfinite(d.hi) and d.lo < d.hi):
                raise InvalidInput("a free dimension needs finite bounds min < max", field=f"free.{k}.min")
            current(self.machine.linkage.mechanism, d.path, f"free.{k}.path")
            if d.path.endswith("length_m") and d.lo <= 0:
                raise InvalidInput("a link's length must stay positive", field=f"free.{k}.min")
        check_weights(self.weights)
        if not MIN_SAMPLES <= self.samples <= MAX_SAMPLES:
            raise InvalidInput(f"samples must lie in [{MIN_SAMPLES}, {MAX_SAMPLES}]", field="samples")
        if not 0 <= self.refined <= MAX_REFINED:
            raise InvalidInput(f"refined must lie in [0, {MAX_REFINED}]", field="refined")
        if not 1 <= self.refine_runs <= MAX_REFINE_RUNS:
            raise InvalidInput(f"refine_runs must lie in [1, {MAX_REFINE_RUNS}]", field="refine_runs")
        self.prices.validate()


def _split(path: str, where: str) -> list[str]:
    parts = path.split(".")
    ok = ((len(parts) == 3 and parts[0] == "frame_points_m" and parts[2] in ("x", "y"))
          or (len(parts) == 3 and parts[0] == "links" and parts[2] == "length_m")
          or (len(parts) == 5 and parts[0] == "links" and parts[2] == "points_m" and parts[4] in ("x", "y")))
    if not ok:
        raise InvalidInput(f"{path!r} is not a free number: frame_points_m.<point>.x|y, links.<link>.length_m or "
                           "links.<link>.points_m.<point>.x|y", field=where)
    return parts


def current(mech: PlanarLinkage, path: str, where: str = "free") -> float:
    """The linkage's number at ``path``; InvalidInput naming ``where`` when it has none."""
    p = _split(path, where)
    if p[0] == "frame_points_m":
        pts = dict(mech.frame_points)
        if p[1] not in pts:
            raise InvalidInput(f"no frame point {p[1]!r}; the frame has {list(pts)}", field=where)
        return float(pts[p[1]][0 if p[2] == "x" else 1])
    names = [link.name for link in mech.links]
    if p[1] not in names:
        raise InvalidInput(f"no link {p[1]!r}; the linkage has {names}", field=where)
    link = mech.link(p[1])
    if p[2] == "length_m":
        if len(link.joints) < 2:
            raise InvalidInput(f"link {p[1]!r} has one point and no length", field=where)
        return float(link.length)
    pts = dict(link.points)
    if p[3] not in pts:
        raise InvalidInput(f"link {p[1]!r} has no further point {p[3]!r}; it has {list(pts)}", field=where)
    return float(pts[p[3]][0 if p[4] == "x" else 1])


def _set_xy(items: tuple[tuple[str, tuple[float, float]], ...], name: str, axis: str,
            value: float) -> tuple[tuple[str, tuple[float, float]], ...]:
    return tuple((k, ((value, xy[1]) if axis == "x" else (xy[0], value)) if k == name else xy) for k, xy in items)


def apply(mech: PlanarLinkage, free: Sequence[FreeDimension], x: Sequence[float]) -> PlanarLinkage:
    """The linkage with the free numbers set to ``x``."""
    frame = mech.frame_points
    links = {link.name: link for link in mech.links}
    for d, v in zip(free, x, strict=True):
        p = d.path.split(".")
        if p[0] == "frame_points_m":
            frame = _set_xy(frame, p[1], p[2], float(v))
        elif p[2] == "length_m":
            links[p[1]] = replace(links[p[1]], length=float(v))
        else:
            links[p[1]] = replace(links[p[1]], points=_set_xy(links[p[1]].points, p[3], p[4], float(v)))
    out: list[LinkSpec] = [links[link.name] for link in mech.links]
    return PlanarLinkage(frame, tuple(out), mech.joints, mech.crank_link, mech.output, mech.branches)


@dataclass(frozen=True, slots=True)
class Kinematics:
    """A member's kinematic figures: ``travel`` [m or rad], ``time_ratio`` [-], ``min_transmission_angle``
    [rad] (pi/2 without an RRR or RRP dyad), ``reason`` the constraint missed (None: feasible)."""

    travel: float
    time_ratio: float
    min_transmission_angle: float
    reason: str | None
    # the time ratios of every pair of extremes within LEVEL of the highest and the lowest (an output with two
    # nearly level ends has an ill-defined time ratio: both must lie in the band)
    time_ratio_span: tuple[float, float] = (math.nan, math.nan)

    @property
    def feasible(self) -> bool:
        return self.reason is None


def _fold(a: np.ndarray) -> np.ndarray:
    """An angle between two lines folded into [0, pi/2]."""
    t = np.mod(a, math.pi)
    return np.asarray(np.minimum(t, math.pi - t), dtype=float)


def linkage_kinematics(mech: PlanarLinkage, n: int = CHECK_ANGLES) -> Kinematics:
    """Travel, time ratio and least transmission angle of a linkage over the whole turn, in one vectorised pass
    over ``n`` crank angles; NotAssemblable when a dyad cannot close somewhere in the turn."""
    phi = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    points, angles = mech.solve(phi)
    out = mech.output or mech.links[-1].name
    link = mech.link(out)
    if len(link.joints) == 1:
        # a block: its x-axis runs along its slide; the travel is its origin's displacement along that axis
        a = angles[out].angle
        unit = np.stack([np.cos(a), np.sin(a)], axis=1)
        p = points[link.joints[0]]
        s, ds = np.sum(p.pos * unit, axis=1), np.sum(p.d1 * unit, axis=1)
    else:
        s, ds = np.unwrap(angles[out].angle), angles[out].d1
    # the extremes where the velocity analogue changes sign, located between samples by linear interpolation
    crossing = np.flatnonzero(np.sign(ds) != np.sign(np.roll(ds, -1)))
    travel = float(np.max(s) - np.min(s))
    if crossing.size < 2 or travel <= 0:
        ratio = math.inf
    else:
        step = phi[1] - phi[0]
        at = phi[crossing] + step * ds[crossing] / (ds[crossing] - np.roll(ds, -1)[crossing])
        sc = s[crossing]

        def ratio_of(hi: float, lo: float) -> float:
            forward = float(np.mod(hi - lo, 2 * math.pi))
            return max(forward, 2 * math.pi - forward) / max(min(forward, 2 * math.pi - forward), 1e-12)

        ratio = ratio_of(at[np.argmax(sc)], at[np.argmin(sc)])
        tops = at[sc >= sc.max() - LEVEL * travel]
        bottoms = at[sc <= sc.min() + LEVEL * travel]
        every = [ratio_of(h, b) for h in tops for b in bottoms]
        span = (min(every), max(every))
    mu = math.pi / 2
    for dyad in mech.dyads:
        first, second = dyad.links
        if dyad.kind == "RRR":
            mu = min(mu, float(np.min(_fold(angles[first].angle - angles[second].angle))))
        elif dyad.kind == "RRP":
            # the rod against the slide: pi/2 less the angle between them
            mu = min(mu, float(np.min(math.pi / 2 - _fold(angles[first].angle - angles[second].angle))))
    return Kinematics(travel, ratio, mu, None, span if crossing.size >= 2 and travel > 0 else (ratio, ratio))


def check_member(mech: PlanarLinkage, function: LinkageFunction) -> Kinematics:
    """The member's kinematics and the first constraint of ``function`` it misses (none: feasible)."""
    try:
        k = linkage_kinematics(mech)
    except NotAssemblable as exc:
        return Kinematics(math.nan, math.nan, math.nan, f"not assemblable over the whole turn: {exc}")
    reason = None
    if function.travel is not None and not function.travel[0] <= k.travel <= function.travel[1]:
        reason = "travel outside its band"
    elif function.time_ratio is not None and not function.time_ratio[0] <= k.time_ratio <= function.time_ratio[1]:
        reason = "time ratio outside its band"
    elif function.time_ratio is not None and not (function.time_ratio[0] <= k.time_ratio_span[0]
                                                  and k.time_ratio_span[1] <= function.time_ratio[1]):
        reason = f"time ratio ill-defined: the output's ends are within {LEVEL:.0%} of its travel of another extreme"
    elif k.min_transmission_angle < function.min_transmission_angle:
        reason = "transmission angle under its limit"
    return replace(k, reason=reason)


@dataclass(frozen=True, slots=True)
class LinkageMember:
    """One member: its free numbers ``x``, its kinematics, its objectives in :data:`OBJECTIVES` order (None when
    the chain did not run or refused it), ``feasible`` every constraint and check met, ``reason`` why not,
    ``stage`` sample, refine or optimum."""

    x: tuple[float, ...]
    kinematics: Kinematics
    values: tuple[float, ...] | None
    feasible: bool
    reason: str | None
    stage: str
    parts: MachineParts | None = None


def sample_box(spec: LinkageOptimiseSpec) -> np.ndarray:
    """The request's own numbers (when inside the box) and a scrambled Sobol sample of the box, (members, free)."""
    lo = np.array([d.lo for d in spec.free])
    hi = np.array([d.hi for d in spec.free])
    sobol = qmc.Sobol(len(spec.free), scramble=True, seed=SOBOL_SEED)
    # a power of two keeps the sequence balanced; the request's count is taken from its first members
    m = int(math.ceil(math.log2(spec.samples)))
    pts = qmc.scale(sobol.random_base2(m)[: spec.samples], lo, hi)
    mech = spec.machine.linkage.mechanism
    assert isinstance(mech, PlanarLinkage)
    own = np.array([current(mech, d.path) for d in spec.free])
    if np.all((own >= lo) & (own <= hi)):
        pts = np.vstack([own, pts])
    return np.asarray(pts, dtype=float)


def _checked(spec: LinkageOptimiseSpec, xs: tuple[float, ...]) -> tuple[PlanarLinkage | None, Kinematics]:
    """The member's linkage (None when its numbers make none) and its kinematic check."""
    mech = spec.machine.linkage.mechanism
    assert isinstance(mech, PlanarLinkage)
    try:
        member = apply(mech, spec.free, xs)
    except InvalidInput as exc:
        return None, Kinematics(math.nan, math.nan, math.nan, str(exc))
    return member, check_member(member, spec.function)


def design_member(spec: LinkageOptimiseSpec, x: Sequence[float], stage: str,
                  time_limit_s: float = 20.0, always: bool = False) -> LinkageMember:
    """One member: its kinematic check, then (when feasible, or ``always`` when it assembles) the chain to its
    steady machine."""
    xs = tuple(float(v) for v in x)
    member, kin = _checked(spec, xs)
    return _through_chain(spec, xs, member, kin, stage, time_limit_s, always)


def _through_chain(spec: LinkageOptimiseSpec, xs: tuple[float, ...], member: PlanarLinkage | None,
                   kin: Kinematics, stage: str, time_limit_s: float, always: bool) -> LinkageMember:
    if member is None or (not kin.feasible and not (always and math.isfinite(kin.travel))):
        return LinkageMember(xs, kin, None, False, kin.reason, stage)
    machine = replace(spec.machine, linkage=replace(spec.machine.linkage, mechanism=member))
    if not spec.weighs_parts:
        machine = replace(machine, drive=replace(machine.drive, strength=None))
    try:
        m = steady_member(machine, time_limit_s=time_limit_s, size_gears=spec.weighs_parts)
    except (Infeasible, InvalidInput, SolverFailed, SolverTimeout, NotAssemblable) as exc:
        return LinkageMember(xs, kin, None, False, f"the chain refuses it: {exc}", stage)
    p = m.parts
    values = (*m.values, p.mass, p.cost(spec.prices))
    reason = kin.reason or "; ".join(f"fails its {n} check" for n in m.failed) or None
    return LinkageMember(xs, kin, values, reason is None, reason, stage, p)


def slack(function: LinkageFunction, kin: Kinematics) -> np.ndarray:
    """Each constraint of the function as a slack, positive when met, relative to its band (travel, time ratio)
    or in radians (transmission angle); -1 everywhere when the member does not assemble."""
    if not math.isfinite(kin.travel):
        return -np.ones(5)
    out = []
    for band, (a, b) in ((function.travel, (kin.travel, kin.travel)), (function.time_ratio, kin.time_ratio_span)):
        if band is None:
            out += [1.0, 1.0]
        else:
            scale = max(band[1], 1e-9)
            out += [(a - band[0]) / scale, (band[1] - b) / scale if math.isfinite(b) else -1.0]
    out.append(kin.min_transmission_angle - function.min_transmission_angle)
    return np.array(out)


def _score(spec: LinkageOptimiseSpec, values: Sequence[float], norm: Sequence[float]) -> float:
    return float(sum(spec.weights[n] * values[k] / norm[k] for k, n in enumerate(OBJECTIVES)
                     if spec.weights.get(n, 0.0) > 0))


def _normalisers(members: Sequence[LinkageMember]) -> tuple[float, ...]:
    """Each objective's scale: its value on the first member designed (the request's own linkage when it is
    feasible), else the largest over the members, else 1."""
    designed = [m for m in members if m.values is not None]
    out = []
    for k in range(len(OBJECTIVES)):
        v = designed[0].values[k] if designed and designed[0].values is not None else 0.0
        if not (math.isfinite(v) and v > 0):
            v = max((m.values[k] for m in designed if m.values is not None and math.isfinite(m.values[k])),
                    default=0.0)
        out.append(v if v > 0 else 1.0)
    return tuple(out)


@dataclass(frozen=True, slots=True)
class LinkageCertificate:
    """How the box was covered: members ``sampled`` (the request's own among them when inside the box),
    kinematically feasible, designed by the chain, feasible after it, members ``refined`` and the chain runs the
    refinement spent; ``gap_bound`` None (none is claimed); the statement in words."""

    sampled: int
    kinematic_feasible: int
    designed: int
    feasible: int
    refined: int
    refine_runs: int
    gap_bound: float | None
    statement: str


@dataclass(frozen=True, slots=True)
class LinkageOptimum:
    """The optimised linkage's machine: its whole ``design``, its free numbers ``x``, ``values`` and ``score``
    [-], the ``normalisers``, the members (sample and refinement), its parts and the certificate."""

    spec: LinkageOptimiseSpec
    design: MachineDesign
    x: tuple[float, ...]
    kinematics: Kinematics
    values: tuple[float, ...]
    score: float
    normalisers: tuple[float, ...]
    members: tuple[LinkageMember, ...]
    parts: MachineParts
    certificate: LinkageCertificate
    units: tuple[str, ...] = OBJECTIVE_UNITS


@dataclass(frozen=True, slots=True)
class BoxScan:
    """The sample of the box, the request's own numbers first when inside it, with each member's kinematic
    check: ``points`` the free numbers of each member [m], ``kinematics`` its figures."""

    points: tuple[tuple[float, ...], ...]
    kinematics: tuple[Kinematics, ...]

    @property
    def feasible(self) -> tuple[int, ...]:
        """The members meeting the function kinematically, by their place in the sample."""
        return tuple(i for i, k in enumerate(self.kinematics) if k.feasible)

    def members(self, designed: Sequence[tuple[int, LinkageMember]]) -> tuple[LinkageMember, ...]:
        """The sample's members in its order: those ``designed`` (by their place) by the chain, the others as
        the kinematic check left them."""
        by_place = dict(designed)
        return tuple(by_place.get(i) or LinkageMember(x, k, None, False, k.reason, "sample")
                     for i, (x, k) in enumerate(zip(self.points, self.kinematics, strict=True)))


def scan_box(spec: LinkageOptimiseSpec) -> BoxScan:
    """First stage: the request checked, the box sampled and every member checked kinematically over the turn.

    Raises InvalidInput naming the field."""
    spec.validate()
    points = tuple(tuple(float(v) for v in x) for x in sample_box(spec))
    return BoxScan(points, tuple(_checked(spec, x)[1] for x in points))


def design_sample(spec: LinkageOptimiseSpec, scan: BoxScan, places: Sequence[int], *,
                  time_limit_s: float = 20.0) -> tuple[tuple[int, LinkageMember], ...]:
    """Second stage: the members at ``places`` of the sample through the chain to their steady machine, each
    with its place."""
    mech = spec.machine.linkage.mechanism
    assert isinstance(mech, PlanarLinkage)
    out = []
    for i in places:
        x, kin = scan.points[i], scan.kinematics[i]
        # a kinematically feasible member's numbers made a linkage in the scan already
        member = apply(mech, spec.free, x) if kin.feasible else None
        out.append((i, _through_chain(spec, x, member, kin, "sample", time_limit_s, False)))
    return tuple(out)


@dataclass(frozen=True, slots=True)
class _Ranking:
    """The sample's members scored: the objectives' ``norm``, each member's score (inf: infeasible), the score
    given to a member the chain refuses during refinement and the places of the refinements' starts."""

    norm: tuple[float, ...]
    scores: np.ndarray
    penalty: float
    starts: tuple[int, ...]


def _rank(spec: LinkageOptimiseSpec, members: Sequence[LinkageMember]) -> _Ranking:
    norm = _normalisers(members)
    scores = np.array([_score(spec, m.values, norm) if m.feasible and m.values is not None else np.inf
                       for m in members])
    finite = scores[np.isfinite(scores)]
    penalty = 10.0 * (1.0 + float(np.max(finite))) if finite.size else math.inf
    starts = tuple(int(i) for i in np.argsort(scores, kind="stable")[: spec.refined] if np.isfinite(scores[i]))
    return _Ranking(norm, scores, penalty, starts)


def refine_start(spec: LinkageOptimiseSpec, scan: BoxScan, members: Sequence[LinkageMember], k: int, *,
                 time_limit_s: float = 20.0) -> tuple[LinkageMember, ...]:
    """Third stage, one task per start: COBYLA from the ``k``-th best member of the sample (``members``, in the
    sample's order) on the score, the function's slacks and the box its constraints; every member it looked
    at, in the order it did; none when the sample has no ``k``-th feasible member."""
    rank = _rank(spec, members)
    if k >= len(rank.starts):
        return ()
    lo = np.array([d.lo for d in spec.free])
    hi = np.array([d.hi for d in spec.free])
    width = hi - lo
    seen: dict[tuple[float, ...], LinkageMember] = {}
    looked: list[LinkageMember] = []

    def at(z: np.ndarray) -> LinkageMember:
        # the search works in the unit box; a member off the function is still run through the chain (when it
        # assembles) so that the objective stays continuous across the constraints' boundaries
        x = tuple(float(v) for v in lo + np.clip(z, 0.0, 1.0) * width)
        if x not in seen:
            seen[x] = design_member(spec, x, "refine", time_limit_s, always=True)
            looked.append(seen[x])
        return seen[x]

    def f(z: np.ndarray) -> float:
        m = at(z)
        return _score(spec, m.values, rank.norm) if m.values is not None else rank.penalty

    def g(z: np.ndarray) -> np.ndarray:
        return np.concatenate([slack(spec.function, at(z).kinematics), z, 1.0 - z])

    # COBYLA follows an active constraint (the least stroke, say) where a penalty would stall
    minimize(f, (np.array(scan.points[rank.starts[k]]) - lo) / width, method="COBYLA",
             constraints=[{"type": "ineq", "fun": g}],
             options={"maxiter": spec.refine_runs, "rhobeg": 0.1, "tol": 1e-5})
    return tuple(looked)


def conclude_linkage(spec: LinkageOptimiseSpec, scan: BoxScan, members: Sequence[LinkageMember],
                     refinements: Sequence[Sequence[LinkageMember]], *, time_limit_s: float = 20.0
                     ) -> LinkageOptimum:
    """Last stage: the best member of the sample (``members``, in its order) and of the refinements (in the
    order of their starts) designed through the whole chain, with the certificate.

    Raises Infeasible when no member meets the function and every check, or the best three fail the whole
    chain."""
    rank = _rank(spec, members)
    if not np.isfinite(rank.scores).any():
        reasons = sorted({m.reason for m in members if m.reason})
        raise Infeasible("no member of the box meets the function and every check: " + "; ".join(reasons[:3]),
                         "function", field="function", members_sampled=len(members))
    refined_members = [m for r in refinements for m in r]
    everything = list(members) + refined_members
    norm = rank.norm
    s = np.array([_score(spec, m.values, norm) if m.feasible and m.values is not None else np.inf
                  for m in everything])
    design: MachineDesign | None = None
    best = everything[int(np.argmin(s))]
    reason = None
    mech = spec.machine.linkage.mechanism
    assert isinstance(mech, PlanarLinkage)
    for i in np.argsort(s, kind="stable")[:3]:
        if not np.isfinite(s[i]):
            break
        best = everything[int(i)]
        machine = replace(spec.machine, linkage=replace(spec.machine.linkage,
                                                        mechanism=apply(mech, spec.free, best.x)))
        try:
            d = design_machine(machine, time_limit_s=time_limit_s)
        except (Infeasible, InvalidInput, SolverFailed, SolverTimeout) as exc:
            reason = str(exc)
            continue
        if d.passed:
            design = d
            break
        reason = "; ".join(c.name for c in d.checks if not c.passed)
    if design is None:
        raise Infeasible(f"the best members fail the whole chain: {reason}", "machine checks", field=None)
    values = objective_values(design, spec.prices)
    parts = design_parts(design)
    kin_ok = len(scan.feasible)
    feasible = int(np.isfinite(s).sum())
    runs = len(refined_members)
    starts = len(rank.starts)
    statement = (
        f"{len(members)} members of the box of {len(spec.free)} free dimension(s) (the request's own numbers and "
        f"a scrambled Sobol sample) checked kinematically over the whole turn, each in one vectorised pass over "
        f"{CHECK_ANGLES} crank angles (assembly, travel, time ratio, least transmission angle): {kin_ok} met the "
        f"function and ran through the chain to their steady machine. The best {starts} were refined by "
        f"COBYLA on the score with the function as its constraints ({runs} members looked at). {feasible} of "
        f"the {len(everything)} members (sample and refinement) meet every constraint and check; the answer was "
        "designed again through the whole chain, start and run-down included. The objective steps where the "
        "catalogue motor or the teeth change and the feasible set need not be convex or connected: no gap bound "
        "is claimed."
    )
    cert = LinkageCertificate(len(members), kin_ok, sum(m.values is not None for m in everything), feasible,
                              starts, runs, None, statement)
    return LinkageOptimum(spec, design, best.x, best.kinematics, values, _score(spec, values, norm), norm,
                          tuple(everything), parts, cert)


def optimise_linkage(spec: LinkageOptimiseSpec, *, time_limit_s: float = 20.0) -> LinkageOptimum:
    """Choose the free dimensions and the machine together; every stage in this process, one after another.

    Raises InvalidInput naming the field, Infeasible when no member meets the function and every check."""
    scan = scan_box(spec)
    members = scan.members(design_sample(spec, scan, scan.feasible, time_limit_s=time_limit_s))
    refinements = [refine_start(spec, scan, members, k, time_limit_s=time_limit_s) for k in range(spec.refined)]
    return conclude_linkage(spec, scan, members, refinements, time_limit_s=time_limit_s)
