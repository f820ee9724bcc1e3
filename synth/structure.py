"""Structure of a mechanism from its links and pairs: mobility, redundant constraints, Assur groups.

Pair class S = 6 - H (H relative freedoms); Somov-Malyshev W = 6n - 5p5 - 4p4 - 3p3 - 2p2 - p1 for any
mechanism, Chebyshev W = 3n - 2p5 - p4 for a planar one (n moving links). A planar mechanism built in space
with those pairs has q = W_Chebyshev - W_Somov-Malyshev redundant constraints. A planar linkage with lower pairs
splits into the primary mechanism (the frame and the input links) and Assur groups, the smallest chains of links
with 3n = 2p5 (W = 0, statically determinate), added one after the other (seed 001:767-1190, 003:196-206; the
seed digest's section 1). A higher pair is first replaced by a link with two lower pairs at its centres of
curvature.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

from .errors import InvalidInput, TooLarge

PairKind = Literal["revolute", "prismatic", "higher"]

#: Largest Assur group searched for (links); groups of 2, 4, 6 and 8 links are the ones met in practice.
MAX_GROUP_LINKS = 8
#: Connected candidate sets examined before the decomposition gives up.
MAX_CANDIDATES = 200_000
ROMAN = ("0", "I", "II", "III", "IV", "V", "VI", "VII", "VIII", "IX", "X", "XI", "XII")


@dataclass(frozen=True, slots=True)
class Pair:
    """A kinematic pair between two links (``frame`` is the fixed link).

    Planar: ``kind`` revolute or prismatic (lower, 2 constraints in the plane, class V in space) or higher (1
    constraint in the plane, class IV in space). Spatial: ``constraints`` S in 1..5 (the pair's class); or
    ``dof`` H = 6 - S. ``higher`` marks point or line contact (classes I and II always are).
    """

    name: str
    links: tuple[str, str]
    kind: PairKind | None = None
    constraints: int | None = None
    dof: int | None = None
    higher: bool | None = None

    def spatial_class(self) -> int:
        """The pair's class S = 6 - H [-]."""
        if self.constraints is not None:
            return self.constraints
        if self.dof is not None:
            return 6 - self.dof
        return 4 if self.kind == "higher" else 5

    def is_higher(self) -> bool:
        """Point or line contact."""
        if self.higher is not None:
            return self.higher
        if self.kind is not None:
            return self.kind == "higher"
        return self.spatial_class() <= 2


@dataclass(frozen=True, slots=True)
class PairReport:
    """A pair with its class S [-], freedoms H = 6 - S [-], and whether it is a higher pair."""

    name: str
    links: tuple[str, str]
    constraints: int
    dof: int
    pair_class: str
    higher: bool


@dataclass(frozen=True, slots=True)
class AssurGroup:
    """An Assur group: its links and pairs, n and p5, W = 3n - 2p5 = 0, class and order (outer pairs)."""

    links: tuple[str, ...]
    pairs: tuple[str, ...]
    n: int
    p5: int
    mobility: int
    group_class: int
    order: int

    @property
    def statically_determinate(self) -> bool:
        """3n = 2p5: as many equations of equilibrium as unknown reactions."""
        return 3 * self.n == 2 * self.p5


@dataclass(frozen=True, slots=True)
class PassiveLink:
    """A binary link whose two revolute pairs repeat constraints of the others: placed on its two pins."""

    link: str
    joints: tuple[str, str]


@dataclass(frozen=True, slots=True)
class Redundancy:
    """Mobility from the geometry of a linkage whose structural formula says less.

    ``mobility_structural`` 3n - 2p; ``mobility_geometric`` 3n - rank of the constraint Jacobian (its largest
    rank over ``samples`` crank angles of the cycle); ``rows`` 2p constraint equations; ``passive`` the links
    taken out for the placement; ``dependent_pairs`` the pairs whose constraint rows are linearly dependent on
    the others' (the left null space of the Jacobian touches them); ``max_residual`` the largest distance [m]
    by which the passive links' pins miss their lengths over those angles.
    """

    mobility_structural: int
    mobility_geometric: int
    rank: int
    rows: int
    samples: int
    passive: tuple[PassiveLink, ...]
    dependent_pairs: tuple[str, ...]
    max_residual: float

    @property
    def redundant_pairs(self) -> tuple[str, ...]:
        """The pairs of the passive links: the constraints taken as redundant."""
        return tuple(j for p in self.passive for j in p.joints)

    def explanation(self) -> str:
        """One sentence: which pairs are redundant and why."""
        links = ", ".join(p.link for p in self.passive)
        return (f"W = 3n - 2p = {self.mobility_structural} counts the pairs {list(self.redundant_pairs)} of the "
                f"passive link(s) {links}, but the constraint Jacobian has rank {self.rank} of its {self.rows} rows "
                f"at its most over {self.samples} crank angles of the cycle: the rows of pairs "
                f"{list(self.dependent_pairs)} are "
                f"linearly dependent, so the geometry gives W = {self.mobility_geometric}; with {links} taken out "
                f"the rest moves and its pins keep their distance to {self.max_residual:.1e} m")


@dataclass(frozen=True, slots=True)
class Structure:
    """Structural analysis of one mechanism.

    ``moving_links`` n; ``pair_counts`` p1..p5 by class; ``mobility_somov`` 6n - sum k·p_k; for a planar
    mechanism ``mobility_chebyshev`` 3n - 2p5 - p4, ``redundant_constraints`` their difference (else the given
    ``known_mobility`` minus the Somov-Malyshev figure, or None); ``primary`` the frame and the input links with
    their pairs, ``groups`` the Assur groups in the order they are added (None when not decomposed, with the
    reason in ``note``), ``mechanism_class`` the highest group class (1 for the primary mechanism alone).
    From a linkage with its dimensions (:func:`synth.kinematics.linkage.linkage_structure`) also ``geometry``,
    the mobility from the constraint Jacobian when the formula says less (passive links), and ``placements``,
    how each group is placed (``closed_form`` or ``numerical``).
    """

    moving_links: int
    pairs: tuple[PairReport, ...]
    pair_counts: tuple[int, int, int, int, int]
    mobility_somov: int
    mobility_chebyshev: int | None
    redundant_constraints: int | None
    primary_links: tuple[str, ...]
    primary_pairs: tuple[str, ...]
    primary_mobility: int | None
    groups: tuple[AssurGroup, ...] | None
    mechanism_class: int | None
    replaced_higher_pairs: tuple[str, ...]
    note: str
    geometry: Redundancy | None = None
    placements: tuple[str, ...] | None = None


def _validate(links: Sequence[str], pairs: Sequence[Pair], frame: str, planar: bool) -> None:
    if frame not in links:
        raise InvalidInput(f"the frame {frame!r} must be one of the links", field="frame")
    if len(set(links)) != len(links):
        raise InvalidInput("link names must be unique", field="links")
    if len(set(p.name for p in pairs)) != len(pairs):
        raise InvalidInput("pair names must be unique", field="pairs")
    for i, p in enumerate(pairs):
        a, b = p.links
        if a not in links or b not in links:
            raise InvalidInput(f"pair {p.name!r} joins unknown links {p.links}", field=f"pairs[{i}].links")
        if a == b:
            raise InvalidInput(f"pair {p.name!r} joins {a!r} to itself", field=f"pairs[{i}].links")
        given = [v is not None for v in (p.kind, p.constraints, p.dof)]
        if sum(given) > 1:
            raise InvalidInput("give a pair's kind, class or freedoms, one of them", field=f"pairs[{i}]")
        if planar and p.kind is None:
            raise InvalidInput("a planar pair is revolute, prismatic or higher", field=f"pairs[{i}].kind")
        if not planar and not (p.constraints or p.dof):
            raise InvalidInput("a spatial pair needs its class (constraints) or its freedoms", field=f"pairs[{i}]")
        if not 1 <= p.spatial_class() <= 5:
            raise InvalidInput("a pair has 1 to 5 constraints (classes I to V)", field=f"pairs[{i}]")


def analyse_structure(links: Sequence[str], pairs: Sequence[Pair], *, frame: str = "frame", planar: bool = True,
                      input_links: Sequence[str] | None = None, known_mobility: int | None = None) -> Structure:
    """Mobility by Somov-Malyshev (and Chebyshev when planar), redundant constraints, and for a planar linkage
    the primary mechanism and its Assur groups with their classes.

    Parameters
    ----------
    links : link names, the frame among them.
    pairs : the kinematic pairs, each joining two links.
    frame : the fixed link's name.
    planar : a planar mechanism (pairs by kind) or a spatial one (pairs by class or freedoms).
    input_links : the driven links of the primary mechanism, each paired with the frame; default the first W
        links (in ``links`` order) that are.
    known_mobility : a spatial mechanism's actual mobility [-], for its redundant constraints.
    """
    _validate(links, pairs, frame, planar)
    n = len(links) - 1
    reports = tuple(PairReport(p.name, p.links, p.spatial_class(), 6 - p.spatial_class(),
                               ROMAN[p.spatial_class()], p.is_higher()) for p in pairs)
    counts = tuple(sum(1 for r in reports if r.constraints == k) for k in range(1, 6))
    w_somov = 6 * n - sum(k * c for k, c in zip(range(1, 6), counts))
    if not planar:
        redundant = None if known_mobility is None else known_mobility - w_somov
        return Structure(n, reports, (counts[0], counts[1], counts[2], counts[3], counts[4]), w_somov, None,
                         redundant, (), (), None, None, None, (),
                         "Assur groups are defined for planar linkages")
    p5 = sum(1 for p in pairs if p.kind != "higher")
    p4 = len(pairs) - p5
    w = 3 * n - 2 * p5 - p4
    base = Structure(n, reports, (counts[0], counts[1], counts[2], counts[3], counts[4]), w_somov, w,
                     w - w_somov, (), (), None, None, None, (), "")
    if w < 1:
        return _replace_note(base, f"W = {w}: by the structural formula the chain does not move, so it has no "
                             "primary mechanism (unless pairs repeat each other's constraints: give the linkage with "
                             "its dimensions to judge from the geometry)")
    # Each higher pair becomes a link with two revolutes, which keeps 3n - 2p5 - p4 (3 - 2·2 = -1).
    lower: list[Pair] = [p for p in pairs if p.kind != "higher"]
    all_links = list(links)
    replaced = []
    for p in pairs:
        if p.kind == "higher":
            extra = f"{p.name}'"
            while extra in all_links:
                extra += "'"
            all_links.append(extra)
            lower += [Pair(f"{p.name}:{p.links[0]}", (p.links[0], extra), "revolute"),
                      Pair(f"{p.name}:{p.links[1]}", (extra, p.links[1]), "revolute")]
            replaced.append(p.name)
    drivers = _drivers(all_links, lower, frame, w, input_links)
    primary_pairs = tuple(p.name for p in lower if frame in p.links and set(p.links) & set(drivers))
    groups, left = _groups(all_links, lower, {frame, *drivers})
    note = ("" if not left else f"links {sorted(left)} form no Assur group of at most {MAX_GROUP_LINKS} links "
            f"on the known ones: check the pairs and the input links")
    primary_w = 3 * len(drivers) - 2 * len(primary_pairs)
    return Structure(base.moving_links, reports, base.pair_counts, w_somov, w, w - w_somov, (frame, *drivers),
                     primary_pairs, primary_w, None if left else tuple(groups),
                     None if left else max([1, *(g.group_class for g in groups)]), tuple(replaced), note)


def _replace_note(s: Structure, note: str) -> Structure:
    return Structure(s.moving_links, s.pairs, s.pair_counts, s.mobility_somov, s.mobility_chebyshev,
                     s.redundant_constraints, (), (), None, None, None, (), note)


def _drivers(links: Sequence[str], pairs: Sequence[Pair], frame: str, w: int,
             input_links: Sequence[str] | None) -> tuple[str, ...]:
    grounded = [x for x in links if x != frame and any(set(p.links) == {x, frame} for p in pairs)]
    if input_links is None:
        if len(grounded) < w:
            raise InvalidInput(f"W = {w} needs {w} input links paired with the frame; only {grounded} are",
                               field="input_links")
        return tuple(grounded[:w])
    if len(set(input_links)) != len(input_links):
        raise InvalidInput("input links must be distinct", field="input_links")
    if len(input_links) != w:
        raise InvalidInput(f"W = {w}: give {w} input links, got {len(input_links)}", field="input_links")
    for x in input_links:
        if x not in grounded:
            raise InvalidInput(f"input link {x!r} has no pair with the frame", field="input_links")
    return tuple(input_links)


def _groups(links: Sequence[str], pairs: Sequence[Pair], known: set[str]) -> tuple[list[AssurGroup], set[str]]:
    """Assur groups in order of formation: the smallest connected set of unknown links whose pairs among
    themselves and with the known links number 3n/2, again and again."""
    known = set(known)
    left = {x for x in links if x not in known}
    adj: dict[str, set[str]] = {x: set() for x in links}
    for p in pairs:
        a, b = p.links
        adj[a].add(b)
        adj[b].add(a)
    groups: list[AssurGroup] = []
    while left:
        found = None
        for size in range(2, min(MAX_GROUP_LINKS, len(left)) + 1, 2):
            for cand in _connected_sets(sorted(left), adj, size):
                inner = [p for p in pairs if set(p.links) <= cand]
                outer = [p for p in pairs if len(set(p.links) & cand) == 1 and set(p.links) - cand <= known]
                if 3 * size == 2 * (len(inner) + len(outer)) and outer:
                    found = (cand, inner, outer)
                    break
            if found:
                break
        if found is None:
            return groups, left
        cand, inner, outer = found
        order = [x for x in links if x in cand]
        groups.append(AssurGroup(tuple(order), tuple(p.name for p in inner + outer), len(cand),
                                 len(inner) + len(outer), 0, _group_class(cand, inner, outer), len(outer)))
        known |= cand
        left -= cand
    return groups, left


def _connected_sets(pool: Sequence[str], adj: dict[str, set[str]], size: int) -> list[frozenset[str]]:
    """Every connected set of ``size`` links from ``pool`` (adjacency ``adj``), each once, in a fixed order."""
    inside = set(pool)
    level = {frozenset([x]) for x in pool}
    for _ in range(size - 1):
        level = {s | {y} for s in level for x in s for y in adj[x] if y in inside and y not in s}
        if len(level) > MAX_CANDIDATES:
            raise TooLarge("Assur-group candidates (fewer links, or give the input links)", MAX_CANDIDATES,
                           len(level))
    return sorted(level, key=sorted)


def _group_class(cand: frozenset[str], inner: Sequence[Pair], outer: Sequence[Pair]) -> int:
    """Class of an Assur group: II for a dyad; else the larger of the most pairs on one link (a base link) and
    the longest closed contour of its inner pairs."""
    if len(cand) == 2:
        return 2
    degree = {x: 0 for x in cand}
    adj: dict[str, set[str]] = {x: set() for x in cand}
    for p in [*inner, *outer]:
        for x in p.links:
            if x in degree:
                degree[x] += 1
    for p in inner:
        a, b = p.links
        adj[a].add(b)
        adj[b].add(a)
    longest = 0
    for path_len in range(len(cand), 2, -1):
        if any(_is_cycle(c, adj) for c in itertools.permutations(sorted(cand), path_len) if c[0] == min(c)):
            longest = path_len
            break
    return max(max(degree.values()), longest)


def _is_cycle(order: Sequence[str], adj: dict[str, set[str]]) -> bool:
    return all(order[(i + 1) % len(order)] in adj[order[i]] for i in range(len(order)))
