"""Any planar linkage built from a driving crank and class-II Assur groups (dyads), solved in closed form.

A linkage is given by its links and joints: every moving link carries named points in its own frame (origin at
its first point, x-axis toward its second, at ``length``), the frame carries fixed points, and each joint is a
revolute (a point shared by two links) or a prismatic pair (a slide axis fixed in one link along which a point of
the other runs, both links turning together). The structural analysis (:func:`synth.structure.analyse_structure`)
splits it into the crank and its dyads in the order they can be added; each dyad is then placed on the links known
before it in closed form, with its assembly branch, for all crank angles at once (seed 001:767-1190, the digest's
section 1).

The five dyads, named by their pairs outer-inner-outer (R revolute, P prismatic):

* RRR: two bars on two known points; the inner joint at a circle-circle intersection. Branch +1: the inner
  joint to the left of the line from the first link's outer joint to the second's (links in request order).
* RRP: a bar on a known point and a block on a known axis; the inner joint at a circle-line intersection.
  Branch +1: the inner joint ahead, along the slide axis, of the foot of the perpendicular from the bar's pivot.
* RPR: two links turning about known points, sliding in each other (a slotted lever). Branch +1: the pivot
  of the sliding link ahead of the pivot of the link that carries the slide axis, along that axis.
* PRP: two blocks on two known axes pinned together; the pin at the intersection of two lines. No branch.
* RPP: a link turning about a known point sliding in a link that slides on a known axis (a Scotch yoke). No branch.

Their closed-form positions are written with :mod:`synth.kinematics.jets`, which carries the first and second
derivatives in the crank angle with every value.
"""

from __future__ import annotations

import dataclasses
import functools
import itertools
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from ..errors import InvalidInput, NotAssemblable, angle_ranges_deg
from ..mechanism import AngleAnalogues, FloatArray, PointAnalogues
from ..structure import ROMAN, Pair, PassiveLink, Redundancy, Structure, analyse_structure
from ..topology import Joint, Topology
from . import jets as J
from .groups import (CLOSURE_TOLERANCE, RANK_TOLERANCE, NumericGroup, Side, constraint_jacobian, continuation_path,
                     place_group, rank_and_dependent)
from .jets import Jet
from .motion import cross_c, dot_c

FRAME = "frame"
BoolArray = NDArray[np.bool_]
DyadKind = Literal["RRR", "RRP", "RPR", "PRP", "RPP"]
# Below this the two lines of a PRP or RPP dyad are taken as parallel (sine of the angle between them).
PARALLEL = 1e-12
#: Crank angles over the cycle at which a linkage with W = 3n - 2p < 1 is tried for redundant constraints.
REDUNDANCY_SAMPLES = 24
#: Sets of passive links tried before a chain is declared a structure.
MAX_PASSIVE_TRIES = 64
#: Dyads whose branches a passive link chooses angle by angle (2**this placements).
MAX_BRANCH_FLIPS = 4
#: Below this ratio of the constraint Jacobian's last kept singular value to its largest an angle is a change
#: point, and the analogues there come from CHANGE_STEP [rad] either side.
CHANGE_RATIO = 1e-6
CHANGE_STEP = 1e-3


@dataclass(frozen=True, slots=True)
class LinkSpec:
    """A moving link: its points in its own frame [m].

    ``joints[0]`` is the frame origin (0, 0); ``joints[1]``, when given, lies on the x-axis at ``length``;
    ``points`` are further named points (name, (x, y)). A block has one point and its x-axis along its slide.
    """

    name: str
    joints: tuple[str, ...]
    length: float = 0.0
    points: tuple[tuple[str, tuple[float, float]], ...] = ()

    def local(self) -> dict[str, tuple[float, float]]:
        """Every named point of the link in its frame [m]."""
        out: dict[str, tuple[float, float]] = {self.joints[0]: (0.0, 0.0)}
        if len(self.joints) > 1:
            out[self.joints[1]] = (self.length, 0.0)
        out.update({name: (float(xy[0]), float(xy[1])) for name, xy in self.points})
        return out


@dataclass(frozen=True, slots=True)
class JointSpec:
    """A lower pair between two links (``"frame"`` for the fixed link).

    The reaction is reported as the force (and for a prismatic pair the couple) ``links[0]`` exerts on ``links[1]``.
    Revolute: ``point`` (default the joint's name) is a point of both links. Prismatic: the slide axis is fixed in
    ``axis_link`` (one of the two; default ``links[0]``) at ``axis_angle`` [rad] in its frame, through its point
    ``through`` (default its origin); the other link's point ``point`` (default its origin) runs along it, with the
    axis at ``slider_angle`` [rad] in that link's frame.
    """

    name: str
    kind: Literal["revolute", "prismatic"]
    links: tuple[str, str]
    point: str | None = None
    axis_link: str | None = None
    axis_angle: float = 0.0
    through: str | None = None
    slider_angle: float = 0.0


@dataclass(frozen=True, slots=True)
class Dyad:
    """One class-II group as it is solved: kind, its two links in solving order, inner and outer joints."""

    kind: DyadKind
    links: tuple[str, str]
    inner: str
    outer: tuple[str, str]
    branch: int


@dataclass(frozen=True)
class _Place:
    """A solved link: the fixed-frame jet of one of its points (``anchor``, at ``local`` in the link) and its
    angle jet."""

    anchor: Jet
    local: tuple[float, float]
    angle: Jet
    given_axis: Jet | None = None

    @functools.cached_property
    def axis(self) -> Jet:
        """The link frame's unit x-axis, computed once for all of the link's points (or given by the dyad that
        placed the link, from a vector along it)."""
        return J.unit(self.angle) if self.given_axis is None else self.given_axis

    @functools.cached_property
    def _points(self) -> dict[tuple[float, float], Jet]:
        return {self.local: self.anchor}

    def point(self, local: tuple[float, float]) -> Jet:
        """Fixed-frame jet of the link's point at ``local`` [m] (each resolved once: the dyads placed on this link
        and the final list of points ask for the same pins)."""
        if (found := self._points.get(local)) is not None:
            return found
        offset = (local[0] - self.local[0], local[1] - self.local[1])
        jet = self._points[local] = J.add(self.anchor, J.rotate(self.angle, offset, self.axis))
        return jet


@dataclass(frozen=True, slots=True)
class _Line:
    """A prismatic pair seen from its known side: the slide axis in the fixed frame (a point ``base`` on it and
    its direction ``psi``), the unknown link's angle, and the unknown link's point on the axis with the axis
    direction in that link's frame."""

    base: Jet
    psi: Jet
    angle: Jet
    on_axis: tuple[float, float]
    local_angle: float

    def offset(self, local: tuple[float, float]) -> float:
        """Signed distance [m] of the unknown link's point ``local`` from the axis (left of its direction +)."""
        c, s = math.cos(self.local_angle), math.sin(self.local_angle)
        dx, dy = local[0] - self.on_axis[0], local[1] - self.on_axis[1]
        return c * dy - s * dx


def _const_angle(value: float, n: int) -> Jet:
    return Jet(np.full(n, value), np.zeros(n), np.zeros(n))


@dataclass(frozen=True)
class PlanarLinkage:
    """A one-degree-of-freedom planar linkage of revolute and prismatic pairs, driven by a crank about the origin.

    Parameters
    ----------
    frame_points : fixed points (name, (x, y)) [m]; the crank's pivot is at (0, 0).
    links : the moving links (:class:`LinkSpec`), lengths [m].
    joints : the pairs (:class:`JointSpec`), angles [rad].
    crank_link : the driven link, turning about its first point, a frame point at the origin; the crank angle is
        the angle of its x-axis.
    output : the working member (default the last link), joined to the frame: by a revolute (it turns, its load
        is a torque) or by a prismatic pair (it slides, its load is a force along the slide).
    branches : assembly branch (+1 or -1) per dyad, keyed by the dyad's inner joint; default +1.
    assembly : points (name, (x, y)) [m] as drawn at crank angle 0: where a group of class III or above starts
        its numerical placement, and so the branch it keeps.
    """

    frame_points: tuple[tuple[str, tuple[float, float]], ...]
    links: tuple[LinkSpec, ...]
    joints: tuple[JointSpec, ...]
    crank_link: str
    output: str | None = None
    branches: tuple[tuple[str, int], ...] = ()
    assembly: tuple[tuple[str, tuple[float, float]], ...] = ()
    family: str = field(default="linkage", init=False)
    topology: Topology = field(init=False, compare=False)
    origins: dict[str, str] = field(init=False, compare=False)
    dyads: tuple[Dyad, ...] = field(init=False, compare=False)
    steps: tuple[Dyad | NumericGroup, ...] = field(init=False, compare=False)
    passive: tuple[PassiveLink, ...] = field(init=False, compare=False)
    redundancy: Redundancy | None = field(init=False, compare=False)

    def __post_init__(self) -> None:
        _validate(self)
        topo = _topology(self)
        object.__setattr__(self, "topology", topo)
        object.__setattr__(self, "origins", {link.name: link.joints[0] for link in self.links})
        object.__setattr__(self, "passive", ())
        object.__setattr__(self, "redundancy", None)
        if 3 * len(self.links) - 2 * len(self.joints) == 1:
            steps = _decompose(self, ())
        else:
            steps, passive, redundancy = _find_passive(self)
            object.__setattr__(self, "passive", passive)
            object.__setattr__(self, "redundancy", redundancy)
        object.__setattr__(self, "steps", steps)
        object.__setattr__(self, "dyads", tuple(s for s in steps if isinstance(s, Dyad)))

    def __hash__(self) -> int:
        return hash((self.frame_points, self.links, self.joints, self.crank_link, self.output, self.branches,
                     self.assembly))

    def assumptions(self) -> tuple[str, ...]:
        """What the answer for this linkage assumes beyond rigid links and ideal pairs, one sentence each."""
        out = []
        if self.redundancy is not None:
            r = self.redundancy
            out.append(f"statically indeterminate reactions: the pairs {list(r.redundant_pairs)} of the passive "
                       f"link(s) {[p.link for p in r.passive]} repeat constraints of the others, so equilibrium fixes "
                       "the reactions only up to self-balanced sets; those given are the least-norm split (the "
                       "pseudo-inverse: the least sum of squared reaction components), the driving torque does not "
                       "depend on it")
        for g in self.numeric_groups:
            out.append(f"the class-{ROMAN[g.group_class]} group of links {list(g.links)} is placed numerically: "
                       "Newton's method on its loop equations, continued from its assembly at crank angle 0 "
                       "(assembly_m, or the first start that closes) in steps of at most 2°, each loop closed to "
                       "1e-9 m")
        return tuple(out)

    @property
    def numeric_groups(self) -> tuple[NumericGroup, ...]:
        """The groups of class III and above, placed numerically."""
        return tuple(s for s in self.steps if isinstance(s, NumericGroup))

    @property
    def crank(self) -> float:
        """Crank length [m] (from its pivot to its second point)."""
        return self.link(self.crank_link).length

    def link(self, name: str) -> LinkSpec:
        """The link called ``name``."""
        return next(link for link in self.links if link.name == name)

    def link_lengths(self) -> dict[str, float]:
        """Length of every link with two or more joints [m]."""
        return {link.name: link.length for link in self.links if len(link.joints) > 1}

    def solve(self, phi: FloatArray) -> tuple[dict[str, PointAnalogues], dict[str, AngleAnalogues]]:
        """Every named point and link angle with its analogues over ``phi`` [rad]; NotAssemblable naming the
        group and the crank-angle ranges where it cannot be placed (for a group placed numerically or a passive
        link, the first angle where its loop does not close)."""
        phi = np.asarray(phi, dtype=float)
        if not self.numeric_groups:
            points, angles, gap = self._place_choosing(phi, self.steps, self.passive)
            _refuse_gap(self.passive, phi, gap)
            return points, angles
        # Continuation from the drawn assembly at crank angle 0 through the requested angles in small steps.
        path, idx = continuation_path(phi)
        points, angles, gap = self._place_choosing(path, self.steps, self.passive)
        _refuse_gap(self.passive, path, gap)
        return ({k: PointAnalogues(v.pos[idx], v.d1[idx], v.d2[idx]) for k, v in points.items()},
                {k: AngleAnalogues(v.angle[idx], v.d1[idx], v.d2[idx], None if v.unit is None else v.unit[idx])
                 for k, v in angles.items()})

    def closure_residual(self, points: Mapping[str, FloatArray], angles: Mapping[str, FloatArray]) -> float:
        """Largest distance [m] between where the two links of a pair put it, over every pair and sample: each
        revolute's point from each link's origin and angle, each slider point from its axis; positions
        ``points`` (N, 2) and link angles ``angles`` (N,) of a solved motion. Zero to rounding when every loop
        closes."""
        local = {link.name: link.local() for link in self.links}
        local[FRAME] = dict(self.frame_points)

        def where(link: str, name: str) -> FloatArray:
            if link == FRAME:
                xy = local[FRAME][name]
                return np.broadcast_to(np.array(xy, dtype=float), points[self.origins[self.crank_link]].shape)
            o, th = points[self.origins[link]], angles[link]
            x, y = local[link][name]
            c, s = np.cos(th), np.sin(th)
            return o + np.stack([c * x - s * y, s * x + c * y], axis=-1)

        worst = 0.0
        for j in self.joints:
            if j.kind == "revolute":
                p = _revolute_point(j)
                gap = np.hypot(*(where(j.links[0], p) - where(j.links[1], p)).T)
            else:
                axis, through, other, point = _axis_and_point(j, local)
                psi = j.axis_angle + (angles[axis] if axis != FRAME else 0.0)
                d = where(other, point) - where(axis, through)
                gap = np.abs(np.cos(psi) * d[:, 1] - np.sin(psi) * d[:, 0])
            worst = max(worst, float(np.max(gap)))
        return worst

    def _place_choosing(self, phi: FloatArray, steps: Sequence[Dyad | NumericGroup],
                        passive: Sequence[PassiveLink]
                        ) -> tuple[dict[str, PointAnalogues], dict[str, AngleAnalogues], FloatArray]:
        """:meth:`_place_choosing_plain`, with the analogues at change points taken from either side."""
        points, angles, gap = self._place_choosing_plain(phi, steps, passive)
        if passive and len(phi):
            points = _across_change_points(self, phi, steps, passive, points, angles)
        return points, angles, gap

    def _place_choosing_plain(self, phi: FloatArray, steps: Sequence[Dyad | NumericGroup],
                              passive: Sequence[PassiveLink]
                              ) -> tuple[dict[str, PointAnalogues], dict[str, AngleAnalogues], FloatArray]:
        """:meth:`_place`, with passive links choosing the dyads' branches at every angle.

        A parallelogram loop passes change points, where its dyad's two branches meet (the links in line): past
        one the closed form on a fixed branch turns into the crossed (anti-parallelogram) linkage, which is what
        a passive link prevents. So every combination of the dyads' branches is placed and at each angle the one
        whose passive pins keep their distance best is kept.
        """
        flips = [i for i, s in enumerate(steps) if isinstance(s, Dyad) and s.kind in ("RRR", "RRP", "RPR")]
        if not passive or not flips or len(flips) > MAX_BRANCH_FLIPS:
            return self._place(phi, steps, passive)
        runs = []
        failure: NotAssemblable | None = None
        for signs in itertools.product((1, -1), repeat=len(flips)):
            trial = list(steps)
            for i, sign in zip(flips, signs):
                d = trial[i]
                assert isinstance(d, Dyad)
                trial[i] = Dyad(d.kind, d.links, d.inner, d.outer, d.branch * sign)
            try:
                runs.append(self._place(phi, trial, passive))
            except NotAssemblable as exc:
                failure = exc
        if not runs:
            assert failure is not None
            raise failure
        pick = np.argmin(np.stack([r[2] for r in runs]), axis=0)
        at = np.arange(len(phi))
        if at.size == 0:
            return runs[0]

        def choose(arrays: Sequence[FloatArray]) -> FloatArray:
            return np.asarray(np.stack(arrays)[pick, at])

        points = {k: PointAnalogues(choose([r[0][k].pos for r in runs]), choose([r[0][k].d1 for r in runs]),
                                    choose([r[0][k].d2 for r in runs])) for k in runs[0][0]}
        angles = {}
        for k, first in runs[0][1].items():
            units = [r[1][k].unit for r in runs]
            angles[k] = AngleAnalogues(choose([r[1][k].angle for r in runs]), choose([r[1][k].d1 for r in runs]),
                                       choose([r[1][k].d2 for r in runs]),
                                       None if any(u is None for u in units) else
                                       choose([u for u in units if u is not None]))
        return points, angles, choose([r[2] for r in runs])

    def _place(self, phi: FloatArray, steps: Sequence[Dyad | NumericGroup], passive: Sequence[PassiveLink]
               ) -> tuple[dict[str, PointAnalogues], dict[str, AngleAnalogues], FloatArray]:
        """Place ``steps`` one after the other and the ``passive`` links on their pins; also by how much the
        passive links' pins miss their lengths at every angle [m]."""
        n = len(phi)
        local = {link.name: link.local() for link in self.links}
        local[FRAME] = dict(self.frame_points)
        frame = _Place(J.point((0.0, 0.0), n), (0.0, 0.0), _const_angle(0.0, n))
        fixed = {xy: J.point(xy, n) for _, xy in self.frame_points}
        frame._points.update(fixed)  # frame points stand still: no rotation to resolve them
        places: dict[str, _Place] = {
            FRAME: frame,
            self.crank_link: _Place(J.point((0.0, 0.0), n), (0.0, 0.0), Jet(phi.copy(), np.ones(n), np.zeros(n))),
        }
        joints = {j.name: j for j in self.joints}
        solved: dict[str, Jet] = {}
        for step in steps:
            if isinstance(step, NumericGroup):
                self._place_group(step, joints, local, places, phi)
                continue
            dyad = step
            # Where a dyad cannot close its square roots meet negative numbers: those samples are flagged and
            # refused below, so their NaNs never leave this loop.
            with np.errstate(invalid="ignore", divide="ignore"):
                first, second, bad, joint = _solve_dyad(dyad, joints, local, places, n)
                bad = bad | ~np.isfinite(first.angle.v) | ~np.isfinite(second.angle.v)
            if bad.any():
                raise NotAssemblable(
                    f"the {dyad.kind} dyad of links {list(dyad.links)} (inner joint {dyad.inner!r}) cannot be "
                    f"assembled at {int(bad.sum())} of {n} crank angles, ranges (deg): "
                    f"{angle_ranges_deg(phi, bad)}",
                    phi=phi[bad],
                    ranges_deg=angle_ranges_deg(phi, bad),
                )
            places[dyad.links[0]], places[dyad.links[1]] = first, second
            if joint is not None:  # the dyad's own closed form for its inner pin, not again from a link's pose
                solved[_revolute_point(joints[dyad.inner])] = joint
        gap = np.zeros(n)
        for link in passive:
            j0, j1 = joints[link.joints[0]], joints[link.joints[1]]
            p0, p1 = _revolute_point(j0), _revolute_point(j1)
            k0, k1 = _known(j0, link.link), _known(j1, link.link)
            a, b = places[k0].point(local[k0][p0]), places[k1].point(local[k1][p1])
            q0, q1 = local[link.link][p0], local[link.link][p1]
            v = J.sub(b, a)
            gap = np.maximum(gap, np.abs(np.abs(v.v) - math.hypot(q1[0] - q0[0], q1[1] - q0[1])))
            places[link.link] = _Place(a, q0, J.shift(J.angle(v), -math.atan2(q1[1] - q0[1], q1[0] - q0[0])))
        points: dict[str, PointAnalogues] = {name: J.analogues(jet) for name, jet in solved.items()}
        for name, xy in self.frame_points:
            points[name] = J.analogues(fixed[xy])
        for spec in self.links:
            place = places[spec.name]
            for name, xy in local[spec.name].items():
                if name not in points:
                    points[name] = J.analogues(place.point(xy))
        angles = {spec.name: AngleAnalogues(*places[spec.name].angle, places[spec.name].axis.v)
                  for spec in self.links}
        return points, angles, gap

    def _place_group(self, group: NumericGroup, joints: Mapping[str, JointSpec],
                     local: Mapping[str, Mapping[str, tuple[float, float]]], places: dict[str, _Place],
                     phi: FloatArray) -> None:
        """Place a group of class III or above by Newton continuation on its loop equations."""
        sides = []
        start = dict(self.assembly)
        fixed = set()
        for name in group.joints:
            j = joints[name]
            p = _revolute_point(j)
            pair = []
            for link, sign in zip(j.links, (1.0, -1.0)):
                if link in group.links:
                    xy = local[link][p]
                    pair.append(Side(sign, group.links.index(link), complex(xy[0], xy[1]), None))
                else:
                    known = places[link].point(local[link][p])
                    if p not in start:
                        start[p] = (float(known.v[0].real), float(known.v[0].imag))
                        fixed.add(p)
                    pair.append(Side(sign, -1, 0j, known))
            sides.append((pair[0], pair[1]))
        link_points = {link: {k: complex(xy[0], xy[1]) for k, xy in local[link].items()} for link in group.links}
        placed, _ = place_group(group, sides, phi, start, link_points, fixed)
        for link, (origin, angle) in zip(group.links, placed):
            places[link] = _Place(origin, (0.0, 0.0), angle)


def _across_change_points(mech: PlanarLinkage, phi: FloatArray, steps: Sequence[Dyad | NumericGroup],
                          passive: Sequence[PassiveLink], points: dict[str, PointAnalogues],
                          angles: dict[str, AngleAnalogues]) -> dict[str, PointAnalogues]:
    """At a change point the constraint Jacobian loses rank and the closed forms' analogues divide zero by
    zero, though the motion on the branch the passive links keep is smooth: there the analogues are the mean of
    those at CHANGE_STEP and twice that either side, combined by Richardson (exact to O(CHANGE_STEP⁴)). Angles
    are corrected in ``angles`` in place;
    the corrected points are returned."""
    jac = _jacobian(mech, points, angles)
    s = np.linalg.svd(jac, compute_uv=False)
    rank = int(np.max(np.sum(s > RANK_TOLERANCE * s[:, :1], axis=1)))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        weak = ~(s[:, rank - 1] / s[:, 0] > CHANGE_RATIO)
        # Where a dyad of the rest is singular but the passive link is not, the closed form's rates are huge
        # but finite: they break the whole linkage's velocity constraint J·q' = 0.
        names = [link.name for link in mech.links]
        rates = np.concatenate([np.column_stack([points[mech.origins[x]].d1, angles[x].d1]) for x in names], axis=1)
        miss = np.linalg.norm(np.einsum("nij,nj->ni", jac, rates), axis=1)
        size = np.linalg.norm(jac, axis=(1, 2)) * np.linalg.norm(rates, axis=1)
        broken = ~(miss <= CHANGE_RATIO * size)
    finite = np.all([np.isfinite(v.d1).all(axis=-1) & np.isfinite(v.d2).all(axis=-1) for v in points.values()],
                    axis=0)
    bad = np.flatnonzero(weak | broken | ~finite)
    if bad.size == 0:
        return points
    h = CHANGE_STEP
    near = np.concatenate([phi[bad] - h, phi[bad] + h, phi[bad] - 2 * h, phi[bad] + 2 * h])
    side_points, side_angles, _ = mech._place_choosing_plain(near, steps, passive)
    m = bad.size

    def limit(values: FloatArray) -> FloatArray:
        # Richardson on the means of both sides: (4·mean(h) - mean(2h))/3, exact to O(h⁴).
        near_mean = 0.5 * (values[:m] + values[m:2 * m])
        far_mean = 0.5 * (values[2 * m:3 * m] + values[3 * m:])
        return np.asarray((4.0 * near_mean - far_mean) / 3.0)

    out = {}
    for k, v in points.items():
        d1, d2 = v.d1.copy(), v.d2.copy()
        d1[bad] = limit(side_points[k].d1)
        d2[bad] = limit(side_points[k].d2)
        out[k] = PointAnalogues(v.pos, d1, d2)
    for k, a in angles.items():
        a.d1[bad] = limit(side_angles[k].d1)
        a.d2[bad] = limit(side_angles[k].d2)
    return out


def linkage_structure(mech: PlanarLinkage) -> Structure:
    """The structure of a linkage judged from its geometry as well as its pairs: the structural formula's
    counts of all its pairs; when passive links make W = 3n - 2p < 1 though it moves, the primary mechanism and
    the Assur groups of the rest and ``geometry`` (the mobility from the constraint Jacobian, the redundant
    pairs and why); ``placements`` says how each group is placed (a structure that cannot move is refused with
    the reason, InvalidInput)."""
    names = [link.name for link in mech.links]
    full = analyse_structure([FRAME, *names], [Pair(j.name, j.links, j.kind) for j in mech.joints], frame=FRAME,
                             input_links=None if mech.redundancy is not None else [mech.crank_link])
    placements = tuple("numerical" if isinstance(s, NumericGroup) else "closed_form" for s in mech.steps)
    r = mech.redundancy
    if r is None:
        return dataclasses.replace(full, placements=placements)
    skip = {p.link for p in r.passive}
    rest = analyse_structure([FRAME, *(x for x in names if x not in skip)],
                             [Pair(j.name, j.links, j.kind) for j in mech.joints if not set(j.links) & skip],
                             frame=FRAME, input_links=[mech.crank_link])
    return dataclasses.replace(
        full, primary_links=rest.primary_links, primary_pairs=rest.primary_pairs,
        primary_mobility=rest.primary_mobility, groups=rest.groups, mechanism_class=rest.mechanism_class,
        note=f"{r.explanation()}; the primary mechanism and Assur groups are those of the rest", geometry=r,
        placements=placements)


def _refuse_gap(passive: Sequence[PassiveLink], phi: FloatArray, gap: FloatArray) -> None:
    """NotAssemblable at the first angle where a passive link's pins miss its length."""
    bad = ~(gap <= CLOSURE_TOLERANCE)
    if passive and bad.any():
        k = int(np.argmax(bad))
        names = [p.link for p in passive]
        raise NotAssemblable(
            f"the passive link(s) {names} no longer fit their pins: by {gap[k]:.2e} m at crank angle "
            f"{math.degrees(phi[k]) % 360:.3f}° (first of {int(bad.sum())}); their constraints are not redundant "
            "there", phi=phi[bad], ranges_deg=angle_ranges_deg(phi, bad))


def _find_passive(mech: PlanarLinkage) -> tuple[tuple[Dyad | NumericGroup, ...], tuple[PassiveLink, ...],
                                                 Redundancy]:
    """W = 3n - 2p < 1: look for binary links whose pairs repeat the others' constraints. Each candidate set
    taken out must leave a linkage of one degree of freedom that decomposes, and its pins must keep their
    distance over a sampled cycle; else the chain is a structure and is refused."""
    joint_of = {j.name: j for j in mech.joints}
    w = 3 * len(mech.links) - 2 * len(mech.joints)
    candidates = []
    for link in reversed(mech.links):
        own = [j for j in mech.joints if link.name in j.links]
        if (link.name != mech.crank_link and len(own) == 2 and all(j.kind == "revolute" for j in own)
                and _revolute_point(own[0]) != _revolute_point(own[1])):
            first = own if link.local().get(_revolute_point(own[0])) == (0.0, 0.0) else own[::-1]
            candidates.append(PassiveLink(link.name, (first[0].name, first[1].name)))
    phi = np.linspace(0.0, 2 * math.pi, REDUNDANCY_SAMPLES, endpoint=False)
    reasons: list[str] = []
    tried = 0
    for combo in itertools.combinations(candidates, 1 - w):
        if tried >= MAX_PASSIVE_TRIES:
            break
        tried += 1
        try:
            steps = _decompose(mech, tuple(p.link for p in combo))
            if any(isinstance(step, NumericGroup) for step in steps):
                path, idx = continuation_path(phi)
                points, angles, gap = mech._place_choosing(path, steps, combo)
                points = {k: PointAnalogues(v.pos[idx], v.d1[idx], v.d2[idx]) for k, v in points.items()}
                angles = {k: AngleAnalogues(v.angle[idx], v.d1[idx], v.d2[idx]) for k, v in angles.items()}
                gap = gap[idx]
            else:
                points, angles, gap = mech._place_choosing(phi, steps, combo)
        except (InvalidInput, NotAssemblable) as exc:
            reasons.append(f"taking out {[p.link for p in combo]} leaves a linkage that does not work: {exc}")
            continue
        if not np.all(gap <= CLOSURE_TOLERANCE):
            k = int(np.argmax(gap))
            reasons.append(f"with {[p.link for p in combo]} taken out the rest moves, but the pins of "
                           f"{[p.joints for p in combo]} then move apart by up to {gap[k]:.3g} m (at crank angle "
                           f"{math.degrees(phi[k]):.1f}°)")
            continue
        jac = _jacobian(mech, points, angles)
        rank, dependent = rank_and_dependent(jac, [j.name for j in mech.joints])
        w_geom = 3 * len(mech.links) - rank
        if w_geom != 1:
            reasons.append(f"with {[p.link for p in combo]} taken out the constraint Jacobian has rank {rank}, so the "
                           f"geometry gives W = {w_geom}")
            continue
        return steps, combo, Redundancy(w, w_geom, rank, 2 * len(joint_of), REDUNDANCY_SAMPLES, combo, dependent,
                                        float(np.max(gap)))
    raise InvalidInput(f"W = 3n - 2p = 3·{len(mech.links)} - 2·{len(mech.joints)} = {w}: the chain does not move "
                       "as a crank-driven linkage: no pair repeats the others' constraints at every angle; "
                       + ("; ".join(reasons) if reasons else "no binary link of two revolute pairs can be taken out "
                          "to leave a linkage of one degree of freedom"), field="mechanism.joints")


def _jacobian(mech: PlanarLinkage, points: Mapping[str, PointAnalogues], angles: Mapping[str, AngleAnalogues]
              ) -> FloatArray:
    """The whole linkage's constraint Jacobian at every solved angle (see :func:`constraint_jacobian`)."""
    local = {link.name: link.local() for link in mech.links}
    local[FRAME] = dict(mech.frame_points)
    names = [link.name for link in mech.links]

    def axis_of(angle: float) -> Callable[[str], FloatArray]:
        def axis(link: str) -> FloatArray:
            th = angle + (angles[link].angle if link != FRAME else np.zeros(len(angles[names[0]].angle)))
            return np.stack([np.cos(th), np.sin(th)], axis=-1)
        return axis

    rows: list[tuple[str, str, tuple[str, str], FloatArray | None, Callable[[str], FloatArray]]] = []
    for j in mech.joints:
        if j.kind == "revolute":
            rows.append((j.name, "revolute", j.links, points[_revolute_point(j)].pos, axis_of(0.0)))
        else:
            axis, _, other, point = _axis_and_point(j, local)
            rows.append((j.name, "prismatic", (axis, other), points[point].pos, axis_of(j.axis_angle)))
    return constraint_jacobian(names, {x: points[mech.origins[x]].pos for x in names},
                               {x: angles[x].angle for x in names}, rows)


def _validate(mech: PlanarLinkage) -> None:
    names = [link.name for link in mech.links]
    if not names:
        raise InvalidInput("a linkage needs at least one moving link", field="mechanism.links")
    if FRAME in names or len(set(names)) != len(names):
        raise InvalidInput(f"link names must be unique and not {FRAME!r}: {names}", field="mechanism.links")
    frame_names = [p for p, _ in mech.frame_points]
    if len(set(frame_names)) != len(frame_names):
        raise InvalidInput("frame point names must be unique", field="mechanism.frame_points_m")
    for p, xy in mech.frame_points:
        if not all(math.isfinite(v) for v in xy):
            raise InvalidInput(f"frame point {p!r} must be finite", field=f"mechanism.frame_points_m.{p}")
    owners: dict[str, list[str]] = {p: [FRAME] for p in frame_names}
    for link in mech.links:
        where = f"mechanism.links.{link.name}"
        if not 1 <= len(link.joints) <= 2 or len(set(link.joints)) != len(link.joints):
            raise InvalidInput(f"link {link.name!r} names one or two distinct joints (its origin and the point on "
                               "its x-axis)", field=f"{where}.joints")
        if len(link.joints) == 2 and not (math.isfinite(link.length) and link.length > 0):
            raise InvalidInput(f"link {link.name!r} needs a positive length, got {link.length!r}",
                               field=f"{where}.length_m")
        extra = [p for p, _ in link.points]
        if len(set(extra)) != len(extra) or set(extra) & set(link.joints):
            raise InvalidInput(f"link {link.name!r} names a point twice", field=f"{where}.points_m")
        for p, xy in link.points:
            if not all(math.isfinite(v) for v in xy):
                raise InvalidInput(f"point {p!r} of link {link.name!r} must be finite", field=f"{where}.points_m.{p}")
        for p in link.local():
            owners.setdefault(p, []).append(link.name)
    joint_names = [j.name for j in mech.joints]
    if len(set(joint_names)) != len(joint_names):
        raise InvalidInput("joint names must be unique", field="mechanism.joints")
    local = {link.name: link.local() for link in mech.links}
    local[FRAME] = dict(mech.frame_points)
    revolute_at: dict[str, set[str]] = {}
    for j in mech.joints:
        where = f"mechanism.joints.{j.name}"
        unknown = [x for x in j.links if x not in local]
        if unknown:
            raise InvalidInput(f"joint {j.name!r} is on no link called {unknown[0]!r}; links are "
                               f"{[FRAME, *names]}", field=f"{where}.links")
        a, b = j.links
        if a == b:
            raise InvalidInput(f"joint {j.name!r} joins {a!r} to itself", field=f"{where}.links")
        if j.kind == "revolute":
            p = j.point or j.name
            missing = [x for x in j.links if p not in local[x]]
            if missing:
                raise InvalidInput(f"revolute joint {j.name!r} is at point {p!r}, which link {missing[0]!r} does not "
                                   "have", field=f"{where}.point")
            revolute_at.setdefault(p, set()).update(j.links)
        else:
            axis = j.axis_link or a
            if axis not in j.links:
                raise InvalidInput(f"prismatic joint {j.name!r}: the axis link must be one of {list(j.links)}",
                                   field=f"{where}.axis_link")
            other = b if axis == a else a
            through = j.through or (None if axis == FRAME else next(iter(local[axis])))
            if through is None or through not in local[axis]:
                raise InvalidInput(f"prismatic joint {j.name!r}: give the point of {axis!r} the slide axis passes "
                                   "through", field=f"{where}.through")
            point = j.point or (None if other == FRAME else next(iter(local[other])))
            if point is None or point not in local[other]:
                raise InvalidInput(f"prismatic joint {j.name!r}: give the point of {other!r} that runs on the slide "
                                   "axis", field=f"{where}.point")
            for v in (j.axis_angle, j.slider_angle):
                if not math.isfinite(v):
                    raise InvalidInput(f"prismatic joint {j.name!r}: angles must be finite", field=where)
    for p, on in owners.items():
        if len(on) > 1 and not set(on) <= revolute_at.get(p, set()):
            raise InvalidInput(f"point {p!r} is on {on} but no revolute joint joins them there: name the points of "
                               "different links differently, or join them", field=f"mechanism.links.{on[1]}")
    joined = {x for j in mech.joints for x in j.links}
    for name in names:
        if name not in joined:
            raise InvalidInput(f"link {name!r} is not connected: no joint joins it", field=f"mechanism.links.{name}")
    _connected(mech, names)
    n_links, n_pairs = len(names), len(mech.joints)
    if 3 * n_links - 2 * n_pairs > 1:
        # W < 1 may still move when constraints repeat each other: the decomposition judges it from the geometry.
        raise InvalidInput(f"a crank-driven linkage has one degree of freedom: W = 3n - 2p = 3·{n_links} - "
                           f"2·{n_pairs} = {3 * n_links - 2 * n_pairs} (n moving links, p lower pairs)",
                           field="mechanism.joints")
    if mech.crank_link not in names:
        raise InvalidInput(f"the crank {mech.crank_link!r} is not one of the links {names}", field="mechanism.crank")
    crank = next(link for link in mech.links if link.name == mech.crank_link)
    pivot = crank.joints[0]
    frame_pivot = dict(mech.frame_points).get(pivot)
    at_frame = any(j.kind == "revolute" and set(j.links) == {FRAME, crank.name} and (j.point or j.name) == pivot
                   for j in mech.joints)
    if len(crank.joints) < 2 or frame_pivot is None or not at_frame:
        raise InvalidInput(f"the crank {crank.name!r} turns about its first point, a frame point joined to it by a "
                           "revolute, and has a second point at its length", field="mechanism.crank")
    if frame_pivot != (0.0, 0.0):
        raise InvalidInput(f"the crank pivot {pivot!r} is the origin of the frame: put it at [0, 0] (shaking "
                           f"moments are taken about it), got {list(frame_pivot)}",
                           field=f"mechanism.frame_points_m.{pivot}")
    output = mech.output or names[-1]
    if output not in names:
        raise InvalidInput(f"the output {output!r} is not one of the links {names}", field="mechanism.output")
    if not any(FRAME in j.links and output in j.links for j in mech.joints):
        raise InvalidInput(f"the output {output!r} must be joined to the frame (a rocker or a slide), so that its "
                           "load is a torque or a force along the slide", field="mechanism.output")
    for key, xy in mech.assembly:
        if key not in owners:
            raise InvalidInput(f"assembly point {key!r} is no point of the linkage",
                               field=f"mechanism.assembly_m.{key}")
        if not all(math.isfinite(v) for v in xy):
            raise InvalidInput(f"assembly point {key!r} must be finite", field=f"mechanism.assembly_m.{key}")
    inner = {j.name for j in mech.joints}
    for key, value in mech.branches:
        if key not in inner:
            raise InvalidInput(f"branch given for {key!r}, which is not a joint", field=f"mechanism.branches.{key}")
        if value not in (1, -1):
            raise InvalidInput("a branch is +1 or -1", field=f"mechanism.branches.{key}")


def _connected(mech: PlanarLinkage, names: Sequence[str]) -> None:
    adj: dict[str, set[str]] = {x: set() for x in [FRAME, *names]}
    for j in mech.joints:
        a, b = j.links
        adj[a].add(b)
        adj[b].add(a)
    seen, todo = {FRAME}, [FRAME]
    while todo:
        for y in adj[todo.pop()] - seen:
            seen.add(y)
            todo.append(y)
    if left := [x for x in names if x not in seen]:
        raise InvalidInput(f"links {left} are not connected to the frame", field=f"mechanism.links.{left[0]}")


def _axis_and_point(j: JointSpec, local: Mapping[str, Mapping[str, tuple[float, float]]]) -> tuple[str, str, str, str]:
    """(axis link, its point on the axis, the other link, its point on the axis) of a prismatic joint."""
    a, b = j.links
    axis = j.axis_link or a
    other = b if axis == a else a
    through = j.through or next(iter(local[axis]))
    point = j.point or next(iter(local[other]))
    return axis, through, other, point


def _topology(mech: PlanarLinkage) -> Topology:
    local = {link.name: link.local() for link in mech.links}
    local[FRAME] = dict(mech.frame_points)
    joints = []
    output = mech.output or mech.links[-1].name
    motion: Literal["rotation", "translation"] = "rotation"
    axis_angle = 0.0
    for j in mech.joints:
        giver = None if j.links[0] == FRAME else j.links[0]
        if j.kind == "revolute":
            joints.append(Joint(j.name, "revolute", (giver, j.links[1]), at=j.point or j.name))
            continue
        axis, _, other, point = _axis_and_point(j, local)
        joints.append(Joint(j.name, "prismatic", (giver, j.links[1]), axis_link=None if axis == FRAME else axis,
                            axis_angle=j.axis_angle, at=point))
        if FRAME in j.links and output in j.links:
            motion = "translation"
            axis_angle = j.axis_angle if axis == FRAME else j.slider_angle
    return Topology(tuple(link.name for link in mech.links), tuple(joints), mech.crank_link, output, motion,
                    axis_angle)


def _decompose(mech: PlanarLinkage, skip: tuple[str, ...]) -> tuple[Dyad | NumericGroup, ...]:
    """The Assur groups in the order they can be placed, from the structural analysis of the linkage without
    the links ``skip``: dyads solved in closed form, larger groups of revolute pairs numerically."""
    names = [link.name for link in mech.links if link.name not in skip]
    pairs = [Pair(j.name, j.links, j.kind) for j in mech.joints if not set(j.links) & set(skip)]
    structure = analyse_structure([FRAME, *names], pairs, frame=FRAME, input_links=[mech.crank_link])
    if structure.groups is None:
        raise InvalidInput(f"the linkage does not split into a crank and Assur groups: {structure.note}",
                           field="mechanism.joints")
    kinds = {j.name: j for j in mech.joints}
    branches = dict(mech.branches)
    dyads: list[Dyad | NumericGroup] = []
    used: set[str] = set()
    for group in structure.groups:
        if group.n != 2:
            slides = [p for p in group.pairs if kinds[p].kind != "revolute"]
            if slides:
                raise InvalidInput(
                    f"links {list(group.links)} form a class-{group.group_class} Assur group of {group.n} links with "
                    f"prismatic pairs {slides}: a group of class III or above is placed numerically only when all "
                    "its pairs are revolute", field=f"mechanism.joints.{slides[0]}")
            dyads.append(NumericGroup(tuple(group.links), tuple(group.pairs), group.group_class))
            continue
        first, second = sorted(group.links, key=names.index)
        inners = [p for p in group.pairs if set(kinds[p].links) == {first, second}]
        outs1 = [p for p in group.pairs if p not in inners and first in kinds[p].links]
        outs2 = [p for p in group.pairs if p not in inners and second in kinds[p].links]
        if (len(inners), len(outs1), len(outs2)) != (1, 1, 1):
            raise InvalidInput(f"links {[first, second]} with pairs {list(group.pairs)} form a group that is not a "
                               "dyad of one inner and two outer pairs", field=f"mechanism.links.{first}")
        inner, out1, out2 = inners[0], outs1[0], outs2[0]
        letter = {"revolute": "R", "prismatic": "P"}
        code = letter[kinds[out1].kind] + letter[kinds[inner].kind] + letter[kinds[out2].kind]
        if code in ("PRR", "PPR"):  # the mirror images of RRP and RPP: solve with the links swapped
            first, second, out1, out2 = second, first, out2, out1
            code = code[::-1]
        if code == "PPP":
            raise InvalidInput(f"links {[first, second]} with three prismatic pairs cannot be positioned by the crank",
                               field=f"mechanism.joints.{inner}")
        used.add(inner)
        dyads.append(Dyad(code, (first, second), inner, (out1, out2), branches.get(inner, 1)))  # type: ignore[arg-type]
    for key, _ in mech.branches:
        if key not in used:
            raise InvalidInput(f"branch given for {key!r}, which is not the inner joint of a dyad",
                               field=f"mechanism.branches.{key}")
    return tuple(dyads)


def _line(j: JointSpec, known: str, unknown: str, local: Mapping[str, Mapping[str, tuple[float, float]]],
          places: Mapping[str, _Place]) -> _Line:
    """A prismatic pair between a placed link ``known`` and the link ``unknown``, as a fixed-frame axis."""
    axis, through, other, point = _axis_and_point(j, local)
    place = places[known]
    if axis == known:
        base = place.point(local[known][through])
        psi = J.shift(place.angle, j.axis_angle)
        return _Line(base, psi, J.shift(psi, -j.slider_angle), local[unknown][point], j.slider_angle)
    base = place.point(local[known][point])
    psi = J.shift(place.angle, j.slider_angle)
    return _Line(base, psi, J.shift(psi, -j.axis_angle), local[unknown][through], j.axis_angle)


def _apart(link: str, a: str, b: str, distance: float) -> None:
    """A bar of a dyad needs its two pins apart: at one point it would not set the link's direction."""
    if not distance > 0:
        raise InvalidInput(f"link {link!r} has its joints {a!r} and {b!r} at the same point",
                           field=f"mechanism.links.{link}.points_m")


def _revolute_point(j: JointSpec) -> str:
    return j.point or j.name


def _known(j: JointSpec, link: str) -> str:
    return j.links[1] if j.links[0] == link else j.links[0]


def _rrr(a1: Jet, a3: Jet, r1: float, r2: float, branch: int, g1: float,
         g2: float) -> tuple[Jet, tuple[Jet, Jet], tuple[Jet, Jet], BoolArray]:
    """An RRR dyad on the known pivots ``a1`` and ``a3`` (vector jets) with arms ``r1``, ``r2`` [m] to the inner
    pin, the pin's angle in each link's frame ``g1``, ``g2`` [rad]: the pin, each link's angle and x-axis, and the
    samples where it cannot close.

    The pin by circle intersection; the arms' rates from the loop a1 + r1·u1 = a3 + r2·u2 differentiated once
    and twice (i·r1·w1·u1 - i·r2·w2·u2 = a3' - a1', and the same with the second analogues), each a 2 x 2 system
    solved by Cramer's rule with determinant r1·r2·cross(u1, u2).
    """
    e = a3.v - a1.v
    d2 = dot_c(e, e)
    dist = np.sqrt(d2)
    x = (d2 + r1 * r1 - r2 * r2) / (2.0 * dist)
    h2 = r1 * r1 - x * x
    pin = a1.v + (e / dist) * (x + (1j * branch) * np.sqrt(np.clip(h2, 0.0, None)))
    u1, u2 = (pin - a1.v) / r1, (pin - a3.v) / r2
    s = cross_c(u1, u2)
    rhs = a3.d1 - a1.d1
    w1 = dot_c(rhs, u2) / (r1 * s)
    w2 = dot_c(rhs, u1) / (r2 * s)
    rhs = a3.d2 - a1.d2 + (r1 * w1 * w1) * u1 - (r2 * w2 * w2) * u2
    w1d = dot_c(rhs, u2) / (r1 * s)
    w2d = dot_c(rhs, u1) / (r2 * s)
    arm1 = r1 * u1
    joint = Jet(pin, a1.d1 + (1j * w1) * arm1, a1.d2 + (1j * w1d - w1 * w1) * arm1)
    bad = (h2 < -1e-12 * max(r1 * r1, r2 * r2)) | (d2 == 0)

    def link(u: np.ndarray, w: FloatArray, wd: FloatArray, g: float) -> tuple[Jet, Jet]:
        # |u| = 1 at every angle: the link's x-axis follows from it without a sine or cosine.
        axis = u * complex(math.cos(g), -math.sin(g))
        return Jet(np.angle(u) - g, w, wd), Jet(axis, (1j * w) * axis, (1j * wd - w * w) * axis)

    return joint, link(u1, w1, w1d, g1), link(u2, w2, w2d, g2), bad


def _solve_dyad(d: Dyad, joints: Mapping[str, JointSpec], local: Mapping[str, Mapping[str, tuple[float, float]]],
                places: Mapping[str, _Place], n: int) -> tuple[_Place, _Place, BoolArray, Jet | None]:
    """Place the dyad's two links on the ones known; also the samples where it cannot close, and the inner pin
    when it is a revolute."""
    l1, l2 = d.links
    o1, o2, inner = joints[d.outer[0]], joints[d.outer[1]], joints[d.inner]
    k1, k2 = _known(o1, l1), _known(o2, l2)
    if d.kind == "RRR":
        p1, p3, pj = _revolute_point(o1), _revolute_point(o2), _revolute_point(inner)
        a1, a3 = places[k1].point(local[k1][p1]), places[k2].point(local[k2][p3])
        q1, q3 = local[l1][p1], local[l2][p3]
        j1, j2 = local[l1][pj], local[l2][pj]
        r1, r2 = math.hypot(j1[0] - q1[0], j1[1] - q1[1]), math.hypot(j2[0] - q3[0], j2[1] - q3[1])
        _apart(l1, p1, pj, r1)
        _apart(l2, p3, pj, r2)
        g1, g2 = math.atan2(j1[1] - q1[1], j1[0] - q1[0]), math.atan2(j2[1] - q3[1], j2[0] - q3[0])
        joint, (th1, axis1), (th2, axis2), bad = _rrr(a1, a3, r1, r2, d.branch, g1, g2)
        return _Place(a1, q1, th1, axis1), _Place(a3, q3, th2, axis2), bad, joint
    if d.kind == "RRP":
        p1, pj = _revolute_point(o1), _revolute_point(inner)
        a1 = places[k1].point(local[k1][p1])
        q1, j1, j2 = local[l1][p1], local[l1][pj], local[l2][pj]
        r1 = math.hypot(j1[0] - q1[0], j1[1] - q1[1])
        _apart(l1, p1, pj, r1)
        line = _line(o2, k2, l2, local, places)
        u = J.unit(line.psi)
        base = J.add(line.base, J.scale(line.offset(j2), J.perp(u)))
        w = J.sub(a1, base)
        c = J.cross(u, w)
        h2 = J.shift(J.scale(-1.0, J.mul(c, c)), r1 * r1)
        t = J.add(J.dot(w, u), J.scale(d.branch, J.sqrt(h2)))
        joint = J.add(base, J.mul(t, u))
        bad = h2.v < -1e-12 * r1 * r1
        g1 = math.atan2(j1[1] - q1[1], j1[0] - q1[0])
        v1 = J.sub(joint, a1)
        th1 = J.shift(J.angle(v1), -g1)
        return (_Place(a1, q1, th1, J.turn(J.scale(1.0 / r1, v1), -g1)),
                _Place(joint, j2, line.angle, J.turn(u, -line.local_angle)), bad, joint)
    if d.kind == "RPR":
        pa, pb = _revolute_point(o1), _revolute_point(o2)
        axis, through, other, point = _axis_and_point(inner, local)
        g_link, s_link = (l1, l2) if axis == l1 else (l2, l1)
        g_pivot, s_pivot = (pa, pb) if axis == l1 else (pb, pa)
        g_known, s_known = (k1, k2) if axis == l1 else (k2, k1)
        pg = places[g_known].point(local[g_known][g_pivot])
        ps = places[s_known].point(local[s_known][s_pivot])
        qg, qs = local[g_link][g_pivot], local[s_link][s_pivot]
        cg, cs = local[g_link][through], local[s_link][point]
        off_g = math.cos(inner.axis_angle) * (qg[1] - cg[1]) - math.sin(inner.axis_angle) * (qg[0] - cg[0])
        off_s = math.cos(inner.slider_angle) * (qs[1] - cs[1]) - math.sin(inner.slider_angle) * (qs[0] - cs[0])
        gap = off_s - off_g
        v = J.sub(ps, pg)
        rest = J.shift(J.dot(v, v), -gap * gap)
        t = J.scale(d.branch, J.sqrt(rest))
        psi = J.angle(J.sub(J.mul(t, v), J.scale(gap, J.perp(v))))
        bad = rest.v < -1e-12 * max(1.0, gap * gap)
        g_place = _Place(pg, qg, J.shift(psi, -inner.axis_angle))
        s_place = _Place(ps, qs, J.shift(psi, -inner.slider_angle))
        return (g_place, s_place, bad, None) if axis == l1 else (s_place, g_place, bad, None)
    if d.kind == "PRP":
        pj = _revolute_point(inner)
        j1, j2 = local[l1][pj], local[l2][pj]
        line1, line2 = _line(o1, k1, l1, local, places), _line(o2, k2, l2, local, places)
        u1, u2 = J.unit(line1.psi), J.unit(line2.psi)
        b1 = J.add(line1.base, J.scale(line1.offset(j1), J.perp(u1)))
        b2 = J.add(line2.base, J.scale(line2.offset(j2), J.perp(u2)))
        s = J.cross(u1, u2)
        t1 = J.div(J.cross(J.sub(b2, b1), u2), s)
        joint = J.add(b1, J.mul(t1, u1))
        bad = np.abs(s.v) < PARALLEL
        return _Place(joint, j1, line1.angle), _Place(joint, j2, line2.angle), bad, joint
    # RPP: l1 turns about a known point and slides in l2, which slides on a known axis.
    p1 = _revolute_point(o1)
    a1 = places[k1].point(local[k1][p1])
    q1 = local[l1][p1]
    outer = _line(o2, k2, l2, local, places)
    axis, through, other, point = _axis_and_point(inner, local)
    if axis == l2:
        psi_in = J.shift(outer.angle, inner.axis_angle)
        th1 = J.shift(psi_in, -inner.slider_angle)
        q2 = local[l2][through]
        s1, beta = local[l1][point], inner.slider_angle
    else:
        psi_in = J.shift(outer.angle, inner.slider_angle)
        th1 = J.shift(psi_in, -inner.axis_angle)
        q2 = local[l2][point]
        s1, beta = local[l1][through], inner.axis_angle
    off = math.cos(beta) * (q1[1] - s1[1]) - math.sin(beta) * (q1[0] - s1[0])
    u, w = J.unit(outer.psi), J.unit(psi_in)
    rho = J.rotate(outer.angle, (q2[0] - outer.on_axis[0], q2[1] - outer.on_axis[1]))
    m = J.sub(J.sub(a1, outer.base), rho)
    s = J.cross(w, u)
    slide = J.div(J.shift(J.cross(w, m), -off), s)
    x2 = J.add(outer.base, J.mul(slide, u))
    bad = np.abs(s.v) < PARALLEL
    return _Place(a1, q1, th1), _Place(x2, outer.on_axis, outer.angle), bad, None


__all__ = ["Dyad", "JointSpec", "LinkSpec", "NumericGroup", "PassiveLink", "PlanarLinkage", "Redundancy",
           "linkage_structure"]
