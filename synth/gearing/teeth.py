"""Tooth numbers of a gear train: the whole train's ratio as close as possible to a target, solved exactly.

Method: an exhaustive search that is provably complete, vectorised with NumPy (no MILP).

1. Per stage, every admissible (pinion, gear) pair: teeth in [min, max_teeth], the smaller wheel at or above
   its undercut limit 2 (h_a - x)/sin² alpha (17.1 at 20 deg full depth; a profile shift x on the smaller
   wheel and -x on the larger keeps the centre distance), the larger wheel at or above 2 (h_a + x)/sin² alpha and
   at or below the interference limit of the smaller one, the ratio inside the stage's range, optionally no
   common factor (hunting teeth). A user's ``min_teeth`` replaces both undercut limits.
2. Pairs with the same ratio are interchangeable but for their tooth count, so each stage keeps one pair per
   reduced fraction, the one with the fewest teeth. Stages whose ratio range cannot meet the target window
   given the others' extreme ratios are pruned by those bounds.
3. Meet in the middle: the first half of the stages forms a table, their products (pruned to those that can
   still reach the target window) sorted by ratio, with a uniform grid over log ratio whose cells are about
   twice the window wide. The other half is never materialised: the products of all but its last stage times
   the last stage's candidates are streamed in chunks of ``_CHUNK``, each product screened in O(1) on the
   grid (no table product within its window means no match) and only the survivors matched by binary search.
   Closest mode starts with a window expected to hold ~1e5 products and widens tenfold while it is empty; the
   window shrinks to the best error found so far. Tolerance mode streams by ascending teeth and stops when
   no later product can beat the fewest teeth found; the fewest teeth in a matched range come from a
   sparse-table range minimum. Memory is the table, the grid and one chunk, whatever the tooth range.
4. Reverted (coaxial) trains need equal tooth sums z1 + z2 = z3 + z4 = S (same module, equal centre distances):
   the search runs once per S, ascending.

Objective: closest ratio (relative error |ratio/U - 1|), ties (errors within 1e-12) broken by fewer teeth; or,
with a tolerance, the fewest teeth within it, ties broken by the smaller error. Nothing is discarded that could
be optimal, so the answer equals a plain enumeration of all combinations (:func:`enumerate_tooth_numbers`).
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np
from numpy.typing import NDArray

from ..errors import Infeasible, InvalidInput, TooLarge
from ..warnings import DesignWarning
from .stages import Stage, stage_name, stage_types

IntArray = NDArray[np.int64]
FloatArray = NDArray[np.float64]

TIE = 1e-12
MAX_TEETH_LIMIT = 1000
MAX_PRODUCTS = 20_000_000
MAX_TABLE = 2_000_000
# Products of the streamed half per pass, before the window prunes them: each pass costs about 1 ns per product
# on one core (3 stages: 0.07 s at 100 teeth, 0.9 s at 200, 4 s at 300); beyond this the search is refused
# before it starts instead of running into the request's deadline.
MAX_STREAMED = 1_500_000_000
ENUMERATION_CHECK_LIMIT = 1_000_000
# Products of the streamed half handled at once: bounds the search's memory whatever the tooth range.
_CHUNK = 1 << 17
_MAX_CELLS = 1 << 22
_NEIGHBOURS = np.array([-1, 0], dtype=np.int64)
_NEIGHBOURS.setflags(write=False)


#: Pressure angles of the racks in use span 14.5 to 25 deg; beyond these bounds no rack is cut.
MIN_PRESSURE_ANGLE_DEG = 10.0
MAX_PRESSURE_ANGLE_DEG = 30.0


@dataclass(frozen=True, slots=True)
class ToothRules:
    """Rules every mesh of the train obeys.

    ``pressure_angle`` [rad]; ``addendum`` coefficient h_a [-]; ``profile_shift`` x on the smaller wheel, -x
    on the larger [-]; ``min_teeth`` the user's bound replacing the undercut limits, or None; ``max_teeth``;
    ``hunting``: no common factor in a pair; ``reverted``: equal tooth sums (coaxial input and output).
    """

    pressure_angle: float = math.radians(20.0)
    addendum: float = 1.0
    profile_shift: float = 0.0
    min_teeth: int | None = None
    max_teeth: int = 100
    hunting: bool = False
    reverted: bool = False

    def __post_init__(self) -> None:
        # The undercut limit 2 (h_a - x)/sin² alpha grows without bound as the angle goes to zero.
        if not (math.radians(MIN_PRESSURE_ANGLE_DEG) - 1e-12 <= self.pressure_angle
                <= math.radians(MAX_PRESSURE_ANGLE_DEG) + 1e-12):
            raise InvalidInput(f"the pressure angle must be within [{MIN_PRESSURE_ANGLE_DEG:g}, "
                               f"{MAX_PRESSURE_ANGLE_DEG:g}] deg, got {math.degrees(self.pressure_angle):.6g} deg",
                               field="pressure_angle_deg")


@dataclass(frozen=True, slots=True)
class Mesh:
    """One stage's tooth numbers: driving ``pinion_teeth``, driven ``gear_teeth``, ``ratio`` = gear/pinion [-]."""

    pinion_teeth: int
    gear_teeth: int
    ratio: float


@dataclass(frozen=True, slots=True)
class ToothChecks:
    """Independent check: a plain enumeration of every combination, when there are at most
    ``ENUMERATION_CHECK_LIMIT`` (else None): its combination count, best error [-], tooth count, agreement."""

    enumeration_combinations: int | None
    enumeration_ratio_error: float | None
    enumeration_total_teeth: int | None
    agrees: bool | None


@dataclass(frozen=True, slots=True)
class ToothResult:
    """Tooth numbers of a train, motor side first.

    ``total_ratio`` achieved and ``target_ratio`` [-]; ``ratio_error`` |achieved/target - 1| [-]; ``search_time``
    [s]; ``products_examined`` partial products enumerated; ``undercut_limit`` 2 (h_a - x)/sin² alpha [-];
    ``min_pinion_teeth``/``min_gear_teeth`` the bounds applied.
    """

    stages: tuple[Mesh, ...]
    total_ratio: float
    target_ratio: float
    ratio_error: float
    total_teeth: int
    tolerance: float | None
    method: str
    search_time: float
    products_examined: int
    undercut_limit: float
    min_pinion_teeth: int
    min_gear_teeth: int
    checks: ToothChecks
    warnings: tuple[DesignWarning, ...] = field(default=())


def undercut_limit(pressure_angle: float, addendum: float = 1.0, profile_shift: float = 0.0) -> float:
    """Fewest teeth cut by a rack without undercut, 2 (h_a - x)/sin² alpha [-] (17.1 at 20 deg, h_a = 1)."""
    return 2 * (addendum - profile_shift) / math.sin(pressure_angle) ** 2


def interference_limit(small_teeth: int | IntArray, pressure_angle: float, addendum: float = 1.0,
                       profile_shift: float = 0.0) -> FloatArray:
    """Largest wheel a wheel of ``small_teeth`` may mesh with, externally, without interference [-].

    The larger wheel's tip circle (addendum h_a - x) must stay inside the line of action's tangent point on the
    smaller wheel's base circle: z2 (4h - 2 z1 sin² a) <= z1² sin² a - 4 h²; infinite when the left factor is
    not positive (the smaller wheel then meshes with a rack). 13 -> 16, 14 -> 26, 15 -> 45, 16 -> 101 at 20 deg.
    """
    z = np.asarray(small_teeth, dtype=float)
    s = math.sin(pressure_angle) ** 2
    h = addendum - profile_shift
    den = 4 * h - 2 * z * s
    num = z**2 * s - 4 * h**2
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(den > 0, num / np.where(den > 0, den, 1.0), np.inf)


def train_ratio(meshes: Sequence[tuple[int, int]], external_meshes: int | None = None) -> float:
    """Ratio w_in/w_out of a serial train of (driving, driven) tooth pairs [-] (seed 004:570-590).

    The magnitude is the product of driven over driving teeth; with ``external_meshes`` k given, the sign is
    (-1)^k (negative: the output turns the other way). Idlers appear as two pairs and cancel.
    """
    if not meshes:
        raise InvalidInput("a train needs at least one mesh", field="meshes")
    for i, (zp, zg) in enumerate(meshes):
        if zp < 1 or zg < 1:
            raise InvalidInput(f"tooth numbers must be positive, got ({zp}, {zg})", field=f"meshes[{i}]")
    magnitude = math.prod(zg / zp for zp, zg in meshes)
    return magnitude if external_meshes is None else (-1) ** external_meshes * magnitude


def _wheel_minimums(rules: ToothRules) -> tuple[int, int]:
    if rules.min_teeth is not None:
        return rules.min_teeth, rules.min_teeth
    s = math.sin(rules.pressure_angle) ** 2
    small = 2 * (rules.addendum - rules.profile_shift) / s
    large = 2 * (rules.addendum + rules.profile_shift) / s
    return max(1, math.ceil(small - 1e-9)), max(1, math.ceil(large - 1e-9))


def _rules_admit(zp: IntArray, zg: IntArray, rules: ToothRules) -> NDArray[np.bool_]:
    """Which (pinion, gear) pairs ``rules`` admit, whatever their ratio (vectorised)."""
    small, large = np.minimum(zp, zg), np.maximum(zp, zg)
    min_small, min_large = _wheel_minimums(rules)
    ok = (small >= min_small) & (large >= min_large) & (large <= rules.max_teeth)
    ok &= large <= interference_limit(small, rules.pressure_angle, rules.addendum, rules.profile_shift) + 1e-9
    if rules.hunting:
        ok &= np.gcd(zp, zg) == 1
    return ok


def _in_range(ratio: FloatArray, stage: Stage) -> NDArray[np.bool_]:
    return (ratio >= stage.ratio_min * (1 - 1e-12)) & (ratio <= stage.ratio_max * (1 + 1e-12))


def pairs_admissible(zp: IntArray, zg: IntArray, stage: Stage, rules: ToothRules) -> NDArray[np.bool_]:
    """Which (pinion, gear) pairs one stage admits under ``rules`` (vectorised; reverted sums aside)."""
    return _rules_admit(zp, zg, rules) & _in_range(zg / zp, stage)


@functools.lru_cache(maxsize=16)
def _grid_pairs(rules: ToothRules) -> tuple[IntArray, IntArray, FloatArray]:
    """Every (pinion, gear) pair of 1..max_teeth teeth the rules admit whatever the ratio, pinion-major, and
    their ratios: the same for every stage and every member an optimisation designs, so made once."""
    z = np.arange(1, rules.max_teeth + 1, dtype=np.int64)
    zp, zg = (g.ravel() for g in np.meshgrid(z, z, indexing="ij"))
    ok = _rules_admit(zp, zg, rules)
    zp, zg = zp[ok], zg[ok]
    ratio = zg / zp
    for a in (zp, zg, ratio):
        a.setflags(write=False)
    return zp, zg, ratio


def grid_pairs(stage: Stage, rules: ToothRules) -> tuple[IntArray, IntArray]:
    """The (pinion, gear) pairs of 1..max_teeth teeth one stage admits, pinion-major: the pairs of the whole grid
    :func:`pairs_admissible` admits, in the grid's order."""
    zp, zg, ratio = _grid_pairs(rules)
    ok = _in_range(ratio, stage)
    return zp[ok], zg[ok]


@functools.cache
def _toothed_types() -> Mapping[str, bool]:
    """Whether each stage type of the shipped table is toothed (package data, fixed while the process runs)."""
    return MappingProxyType({n: t.toothed for n, t in stage_types().items()})


def _validate(target: float, stages: Sequence[Stage], rules: ToothRules, tolerance: float | None) -> None:
    if not (math.isfinite(target) and target > 0):
        raise InvalidInput(f"total_ratio must be positive, got {target}", field="total_ratio")
    toothed = _toothed_types()
    for i, s in enumerate(stages):
        if not toothed[s.type]:
            names = sorted(n for n, t in toothed.items() if t)
            raise InvalidInput(f"stage type {s.type!r} has no pinion/gear tooth numbers to choose; toothed "
                               f"types: {', '.join(names)}", field=f"stages[{i}].type")
        if s.ratio is not None:
            raise InvalidInput("the tooth search chooses every stage's ratio; give a range instead of a ratio",
                               field=f"stages[{i}].ratio")
    if rules.max_teeth > MAX_TEETH_LIMIT:
        raise TooLarge("max_teeth", MAX_TEETH_LIMIT, rules.max_teeth, field="max_teeth")
    if rules.min_teeth is not None and not 1 <= rules.min_teeth <= rules.max_teeth:
        raise InvalidInput(f"min_teeth must lie in [1, max_teeth = {rules.max_teeth}], got {rules.min_teeth}",
                           field="min_teeth")
    if not 0 < rules.pressure_angle < math.pi / 2:
        raise InvalidInput("pressure angle must lie strictly between 0 and 90 deg", field="pressure_angle_deg")
    if tolerance is not None and not 0 <= tolerance < 1:
        raise InvalidInput(f"tolerance must lie in [0, 1), got {tolerance}", field="tolerance")
    if rules.reverted and len(stages) < 2:
        raise InvalidInput("a reverted (coaxial) train needs at least two stages", field="reverted")


@dataclass(frozen=True, slots=True)
class _Set:
    """Candidate products: reduced fraction num/den, its float ratio, tooth count, per-stage pair indices."""

    num: IntArray
    den: IntArray
    teeth: IntArray
    idx: IntArray
    ratio: FloatArray = field(init=False)

    def __post_init__(self) -> None:
        # every step of the search reads the ratios: divided out once
        object.__setattr__(self, "ratio", self.num / self.den)


def _dedupe(num: IntArray, den: IntArray, teeth: IntArray, idx: IntArray) -> _Set:
    g = np.gcd(num, den)
    num, den = num // g, den // g
    order = np.lexsort((teeth, den, num))
    num, den, teeth, idx = num[order], den[order], teeth[order], idx[order]
    first = np.ones(len(num), dtype=bool)
    first[1:] = (num[1:] != num[:-1]) | (den[1:] != den[:-1])
    return _Set(num[first], den[first], teeth[first], idx[first])


@dataclass(frozen=True, slots=True)
class _Half:
    """Products of some stages: float ratio, tooth count, flat index into those stages' candidate grid."""

    ratio: FloatArray
    teeth: IntArray
    flat: IntArray
    sizes: tuple[int, ...]

    def pick(self, row: int) -> list[int]:
        return [int(i) for i in np.unravel_index(int(self.flat[row]), self.sizes)] if self.sizes else []


def _combine(sets: Sequence[_Set], lo: float, hi: float, rest: Sequence[tuple[float, float]],
             limit: int = MAX_PRODUCTS) -> tuple[_Half, int]:
    """All products of ``sets`` whose ratio, times what the remaining stages ``rest`` reach, can land in [lo, hi].

    Products are kept as floats (a few factors carry ~1e-15 relative error, far below the 1e-12 tie rule) with
    their position in the stages' grid, so no duplicate needs removing. Raises TooLarge past ``limit``.
    """
    ratio, teeth, flat = np.ones(1), np.zeros(1, np.int64), np.zeros(1, np.int64)
    examined = 0
    for k, s in enumerate(sets):
        size = len(ratio) * len(s.num)
        if size > limit:
            raise TooLarge("tooth search partial products (narrow max_teeth, the stage ranges or the tolerance)",
                           limit, size)
        examined += size
        ratio = (ratio[:, None] * s.ratio[None, :]).ravel()
        teeth = (teeth[:, None] + s.teeth[None, :]).ravel()
        flat = (flat[:, None] * len(s.num) + np.arange(len(s.num))[None, :]).ravel()
        r_lo = math.prod(r[0] for r in rest[k + 1:])
        r_hi = math.prod(r[1] for r in rest[k + 1:])
        keep = (ratio * r_hi >= lo * (1 - 1e-12)) & (ratio * r_lo <= hi * (1 + 1e-12))
        ratio, teeth, flat = ratio[keep], teeth[keep], flat[keep]
    return _Half(ratio, teeth, flat, tuple(len(s.num) for s in sets)), examined


def _sparse_table(values: IntArray) -> list[IntArray]:
    """Levels of a sparse table for range minima: level k holds min(values[i : i + 2^k])."""
    table = [values.astype(np.int64)]
    while 2 ** len(table) <= len(values):
        prev, half = table[-1], 2 ** (len(table) - 1)
        table.append(np.minimum(prev[:-half], prev[half:]))
    return table


def _range_min(table: list[IntArray], lo: IntArray, hi: IntArray) -> IntArray:
    """min(values[lo:hi]) for every query (all hi > lo) from a sparse table of the values."""
    level = np.floor(np.log2(hi - lo)).astype(np.int64)
    out = np.empty(len(lo), dtype=np.int64)
    for lev in np.unique(level):
        m = level == lev
        t = table[int(lev)]
        out[m] = np.minimum(t[lo[m]], t[hi[m] - 2 ** int(lev)])
    return out


@dataclass(frozen=True, slots=True)
class _Table:
    """The sorted half of the meet in the middle: products ascending by ratio, with their teeth and grid index.

    A uniform grid over log ratio, its cells about twice the search window wide (at most ``_MAX_CELLS``),
    screens queries in O(1): ``edges[k]`` is the first product at or above cell k, ``pair[k]`` whether cells
    k - 1 or k hold one (``pair[0]``: cell 0).
    """

    half: _Half
    base: float
    inv_step: float
    edges: NDArray[np.int32]
    pair: NDArray[np.bool_]

    @classmethod
    def build(cls, half: _Half, window: float) -> _Table:
        """Sort ``half`` and lay its grid for a relative search window ``window``."""
        order = np.argsort(half.ratio, kind="stable")
        half = _Half(half.ratio[order], half.teeth[order], half.flat[order], half.sizes)
        logs = np.log(half.ratio)
        span = float(logs[-1] - logs[0])
        step = max(2 * window, span / _MAX_CELLS, 1e-15)
        cells = int(span / step) + 1
        cell = np.minimum(((logs - logs[0]) / step).astype(np.int64), cells - 1)
        edges = np.zeros(cells + 3, dtype=np.int32)
        np.cumsum(np.bincount(cell, minlength=cells), out=edges[1 : cells + 1])
        edges[cells + 1 :] = len(logs)
        pair = np.empty(cells + 2, dtype=bool)
        pair[0] = edges[1] > edges[0]
        pair[1:] = edges[2:] > edges[:-2]
        return cls(half, float(logs[0]), 1.0 / step, edges, pair)

    def screen(self, x_lo: FloatArray, width: float) -> IntArray:
        """Flat indices of the queries [x_lo - 1, x_lo - 1 + width] (in grid cells from the base; note the
        offset of one cell) that may hold a product; those left out certainly hold none. ``x_lo`` is
        overwritten."""
        top = len(self.edges) - 2
        if width <= 1.0:
            # The query spans at most two cells, k - 1 and k with k = floor(x_lo): one look-up answers for both.
            np.clip(x_lo, 0.0, top, out=x_lo)
            return np.flatnonzero(self.pair[x_lo.astype(np.intp)])
        ka = np.minimum(np.maximum(np.floor(x_lo - 1).astype(np.intp), 0), top)
        kb = np.minimum(np.maximum(np.floor(x_lo - 1 + width).astype(np.intp), 0), top) + 1
        return np.flatnonzero(self.edges[kb] > self.edges[ka])


@dataclass(frozen=True, slots=True)
class _Stream:
    """The other half of the meet in the middle, never materialised: the products of all but its last stage
    (pruned by bounds) times the last stage's candidates, taken ``rows`` outer products at a time.

    In closest mode both are sorted by ratio, so a chunk of outer products can only pair with a contiguous run
    of the last stage (bounded by the target window over the table's range); only that run is screened.
    """

    outer: _Half
    outer_log: FloatArray
    last: _Set
    last_log: FloatArray
    sizes: tuple[int, ...]
    rows: int
    reach: tuple[float, float] | None   # closest mode: the last stage's ratio lies in reach / (outer ratio)

    @classmethod
    def build(cls, sets: Sequence[_Set], lo: float, hi: float, table_range: tuple[float, float],
              by_teeth: bool) -> tuple[_Stream, int]:
        """With ``by_teeth`` the outer products and the last stage come in ascending order of teeth."""
        bounds = [(float(s.ratio.min()), float(s.ratio.max())) for s in sets]
        outer, work = _combine(sets[:-1], lo, hi, bounds + [table_range], limit=MAX_TABLE)
        last = sets[-1]
        if by_teeth:
            order = np.argsort(outer.teeth, kind="stable")
            outer = _Half(outer.ratio[order], outer.teeth[order], outer.flat[order], outer.sizes)
            k = np.argsort(last.teeth, kind="stable")
            last = _Set(last.num[k], last.den[k], last.teeth[k], k[:, None])
        else:
            order = np.argsort(outer.ratio, kind="stable")
            outer = _Half(outer.ratio[order], outer.teeth[order], outer.flat[order], outer.sizes)
            k = np.argsort(last.ratio, kind="stable")
            last = _Set(last.num[k], last.den[k], last.teeth[k], k[:, None])
        reach = None if by_teeth else (lo * (1 - 1e-12) / table_range[1], hi * (1 + 1e-12) / table_range[0])
        return cls(outer, np.log(outer.ratio), last, np.log(last.ratio), outer.sizes + (len(last.num),),
                   max(1, _CHUNK // len(last.num)), reach), work

    def starts(self) -> range:
        """First outer row of every chunk."""
        return range(0, len(self.outer.ratio), self.rows)

    def take(self, start: int, flat: IntArray, first: int = 0, width: int | None = None) -> _Half:
        """Products of the chunk from outer row ``start`` at chunk-local flat positions ``flat`` over the last
        stage's run ``first .. first + width``; their ``flat`` field indexes the stages' candidate grid."""
        r, j = np.divmod(flat, len(self.last.num) if width is None else width)
        r = r + start
        j = j + first
        col = self.last.idx[j, 0]
        return _Half(self.outer.ratio[r] * self.last.ratio[j], self.outer.teeth[r] + self.last.teeth[j],
                     self.outer.flat[r] * len(self.last.num) + col, self.sizes)

    def screened(self, table: _Table, start: int, log_lo: float, log_hi: float) -> _Half:
        """The chunk's products that may land in [log_lo, log_hi] with some table product."""
        sl = slice(start, start + self.rows)
        outer = self.outer.ratio[sl]
        # Both sorted by ratio: the chunk's largest outer ratio sets the run's start, its smallest the end.
        first, stop = 0, len(self.last.num)
        if self.reach is not None:
            # (ascending: the chunk's largest outer ratio is its last, its smallest its first)
            first = int(np.searchsorted(self.last.ratio, self.reach[0] / outer[-1], side="left"))
            stop = int(np.searchsorted(self.last.ratio, self.reach[1] / outer[0], side="right"))
        if stop <= first:
            return self.take(start, np.zeros(0, dtype=np.intp))
        a = (log_lo - self.outer_log[sl] - table.base) * table.inv_step + 1.0
        x = a[:, None] - (self.last_log[first:stop] * table.inv_step)[None, :]
        return self.take(start, table.screen(x.ravel(), (log_hi - log_lo) * table.inv_step), first, stop - first)


def _closest(table: _Table, stream: _Stream, target: float,
             window: float) -> tuple[tuple[float, int, int, int] | None, int]:
    """Closest product within ``window`` (relative), ties within TIE broken by fewer teeth: each chunk is
    screened on the table's grid and only its survivors are matched exactly by binary search.

    Returns (error, teeth, streamed grid index, table row) or None, and the products screened.
    """
    tb = table.half
    best = math.inf
    found: list[tuple[FloatArray, IntArray, IntArray, IntArray]] = []
    work = 0
    for start in stream.starts():
        w = min(window, best + 2 * TIE)
        w_lo, w_hi = target * max(1e-300, 1 - w - 2 * TIE), target * (1 + w + 2 * TIE)
        chunk = stream.screened(table, start, math.log(w_lo) - 1e-12, math.log(w_hi) + 1e-12)
        work += min(stream.rows, len(stream.outer.ratio) - start) * len(stream.last.num)
        if len(chunk.ratio) == 0:
            continue
        ar = chunk.ratio
        # The nearest table products first: they bound the best error, so only near-ties are expanded.
        j = np.searchsorted(tb.ratio, target / ar)
        # the neighbours j - 1 and j of each query, kept within the table
        near = np.minimum(np.maximum(j[:, None] + _NEIGHBOURS, 0), len(tb.ratio) - 1)
        best = min(best, float(np.min(np.abs(ar[:, None] * tb.ratio[near] / target - 1))))
        w = min(window, best + 2 * TIE)
        w_lo, w_hi = target * max(0.0, 1 - w - 2 * TIE), target * (1 + w + 2 * TIE)
        lo = np.searchsorted(tb.ratio, w_lo / ar, side="left")
        hi = np.searchsorted(tb.ratio, w_hi / ar, side="right")
        ai = np.nonzero(hi > lo)[0]
        if ai.size == 0:
            continue
        lo, hi = lo[ai], hi[ai]
        counts = hi - lo
        a_rows = np.repeat(ai, counts)
        b_rows = np.repeat(lo - (np.cumsum(counts) - counts), counts) + np.arange(counts.sum())
        err = np.abs(ar[a_rows] * tb.ratio[b_rows] / target - 1)
        teeth = chunk.teeth[a_rows] + tb.teeth[b_rows]
        keep = err <= best + TIE
        found.append((err[keep], teeth[keep], chunk.flat[a_rows[keep]], b_rows[keep]))
    if not found or best > window:
        return None, work
    err = np.concatenate([f[0] for f in found])
    teeth = np.concatenate([f[1] for f in found])
    a_flat = np.concatenate([f[2] for f in found])
    b_rows = np.concatenate([f[3] for f in found])
    keep = err <= best + TIE
    err, teeth, a_flat, b_rows = err[keep], teeth[keep], a_flat[keep], b_rows[keep]
    k = int(np.lexsort((err, teeth))[0])
    return (float(err[k]), int(teeth[k]), int(a_flat[k]), int(b_rows[k])), work


def _table_runs(table: FloatArray, low: FloatArray, high: FloatArray) -> tuple[IntArray, IntArray]:
    """Where each [low, high] starts and stops in the sorted ``table``; the queries are looked up in ascending
    order, which keeps the binary searches within the cache (random queries cost several times more)."""
    order = np.argsort(low)
    lo, hi = np.empty(len(low), np.int64), np.empty(len(low), np.int64)
    lo[order] = np.searchsorted(table, low[order], side="left")
    hi[order] = np.searchsorted(table, high[order], side="right")
    return lo, hi


def _fewest(table: _Table, stream: _Stream, target: float,
            tolerance: float) -> tuple[tuple[float, int, int, int] | None, int]:
    """Fewest teeth with a product within ``tolerance``, ties broken by the smaller error.

    The stream comes in ascending order of teeth (outer products and last stage both sorted), so each outer
    product pairs only with a prefix of the last stage once a best is known, and the search stops when no
    later chunk can beat it.
    """
    tb = table.half
    w_lo, w_hi = target * (1 - tolerance) * (1 - 1e-12), target * (1 + tolerance) * (1 + 1e-12)
    levels = _sparse_table(tb.teeth)
    min_table = int(tb.teeth.min())
    min_last = int(stream.last.teeth.min())
    best: tuple[float, int, int, int] | None = None   # error, teeth, streamed grid index, table row
    work = 0
    n_last = len(stream.last.num)
    for start in stream.starts():
        stop = min(start + stream.rows, len(stream.outer.ratio))
        if best is not None and int(stream.outer.teeth[start]) + min_last + min_table > best[1]:
            break
        if best is None:
            chunk = stream.screened(table, start, math.log(w_lo) - 1e-12, math.log(w_hi) + 1e-12)
            work += (stop - start) * n_last
        else:
            # Only the last stage's prefix that can still tie or beat the best teeth.
            room = best[1] - min_table - stream.outer.teeth[start:stop]
            count = np.searchsorted(stream.last.teeth, room, side="right")
            total = int(count.sum())
            work += total
            if total == 0:
                continue
            rows = np.repeat(np.arange(stop - start), count)
            cols = np.arange(total) - np.repeat(np.cumsum(count) - count, count)
            # Screened on sums of the factors' logarithms (the screen's margins dwarf their rounding); only the
            # survivors are multiplied out.
            logs = stream.outer_log[start + rows] + stream.last_log[cols]
            x = (math.log(w_lo) - 1e-12 - logs - table.base) * table.inv_step + 1.0
            keep = table.screen(x, (math.log(w_hi) - math.log(w_lo) + 2e-12) * table.inv_step)
            chunk = stream.take(start, (rows * n_last + cols)[keep])
        if len(chunk.ratio) == 0:
            continue
        ar = chunk.ratio
        lo, hi = _table_runs(tb.ratio, w_lo / ar, w_hi / ar)
        has = np.nonzero(hi > lo)[0]
        if has.size == 0:
            continue
        fewest = chunk.teeth[has] + _range_min(levels, lo[has], hi[has])
        t_best = int(fewest.min())
        if best is not None and t_best > best[1]:
            continue
        for r in has[fewest == t_best]:
            seg = np.arange(lo[r], hi[r])
            seg = seg[tb.teeth[seg] == t_best - chunk.teeth[r]]
            err = np.abs(ar[r] * tb.ratio[seg] / target - 1)
            i = int(np.argmin(err))
            cand = (float(err[i]), t_best, int(chunk.flat[r]), int(seg[i]))
            if best is None or cand[1] < best[1] or (cand[1] == best[1] and cand[0] < best[0]):
                best = cand
    return best, work


def _stage_sets(stages: Sequence[Stage], rules: ToothRules, total_sum: int | None) -> list[tuple[IntArray, IntArray]]:
    z = np.arange(1, rules.max_teeth + 1, dtype=np.int64)
    zp = z[z < total_sum] if total_sum is not None else z
    zg = total_sum - zp if total_sum is not None else z
    out = []
    # Stages with the same ratio range admit the same pairs: the same arrays, so the search deduplicates them once.
    made: dict[tuple[float, float], tuple[IntArray, IntArray]] = {}
    for s in stages:
        key = (s.ratio_min, s.ratio_max)
        if key not in made:
            if total_sum is None:
                made[key] = grid_pairs(s, rules)
            else:
                ok = pairs_admissible(zp, zg, s, rules)
                made[key] = (zp[ok], zg[ok])
        out.append(made[key])
    return out


def _windows(first: float) -> list[float]:
    """Closest-mode windows, widening tenfold from ``first`` to 0.1, then a last one reaching everything."""
    out = [first]
    while out[-1] < 0.1:
        out.append(out[-1] * 10)
    return out + [10.0]


def _probe_reverted(stages: Sequence[Stage], rules: ToothRules, sums: range, target: float) -> None:
    """Build the largest tables of a reverted train's search before the search starts.

    The closest-ratio search visits every tooth sum in ascending order; the pairs per stage peak at a middle sum
    (small sums have few pairs in the ratio range, large ones few within max_teeth). Building the tables of the
    sampled sum with the most pairs first, with the window the search would use, raises TooLarge at once
    instead of after every smaller sum has been searched.
    """
    k = len(stages) // 2
    samples = sums[:: max(1, len(sums) // 16)]
    sized = [(math.prod(len(zp) for zp, _ in family[:k]), family)
             for family in (_stage_sets(stages, rules, s) for s in samples)]
    _, pairs = max(sized, key=lambda item: item[0])
    sets = [_Set(zg, zp, zp + zg, np.arange(len(zp))[:, None]) for zp, zg in pairs]
    if all(len(s.num) for s in sets):
        _tables(sets, target, None, _first_window(sets))


def _search(pairs: Sequence[tuple[IntArray, IntArray]], target: float, tolerance: float | None,
            deduped: bool) -> tuple[tuple[float, int, list[tuple[int, int]]] | None, int]:
    """Exact best over one family of per-stage pair sets; returns (error, teeth, pairs) or None, and the work.

    Closest mode first searches narrow windows around the target, widening tenfold until one holds a product:
    a best found inside a window is the global best, since everything better lies inside it too.
    """
    made: dict[int, _Set] = {}
    for zp, zg in pairs:
        if id(zp) not in made:
            made[id(zp)] = (_dedupe(zg, zp, zp + zg, np.arange(len(zp))[:, None]) if deduped else
                            _Set(zg, zp, zp + zg, np.arange(len(zp))[:, None]))
    sets = [made[id(zp)] for zp, _ in pairs]
    if any(len(s.num) == 0 for s in sets):
        return None, 0
    streamed = math.prod(len(s.num) for s in sets[len(sets) // 2:])
    if streamed > MAX_STREAMED:
        raise TooLarge("tooth search products per pass", MAX_STREAMED, streamed,
                       f"the tooth search would stream about {streamed:.2g} products per pass over its "
                       f"{len(sets)} stages ({' x '.join(str(len(s.num)) for s in sets[len(sets) // 2:])} "
                       f"candidate pairs), beyond the {MAX_STREAMED:.2g} it searches within a request's time: "
                       "lower max_teeth, use fewer stages or narrow the stages' ratio ranges", field="max_teeth")
    windows = [tolerance] if tolerance is not None else _windows(_first_window(sets))
    examined = 0
    for window in windows:
        found, work = _search_window(sets, target, tolerance, window)
        examined += work
        if found is not None:
            err, teeth, picks = found
            rows = [int(s.idx[i, 0]) for s, i in zip(sets, picks, strict=True)]
            chosen = [(int(zp[r]), int(zg[r])) for (zp, zg), r in zip(pairs, rows, strict=True)]
            return (err, teeth, chosen), examined
    return None, examined


def _first_window(sets: Sequence[_Set]) -> float:
    """A first closest-mode window that holds about 1e5 products if they spread evenly over their range: wide
    enough that it rarely comes back empty (each window is a pass over all products), narrow enough that few
    products survive its screening."""
    logs = [np.log(s.ratio) for s in sets]
    span = sum(float(v.max() - v.min()) for v in logs) or 1.0
    count = math.prod(float(len(s.num)) for s in sets)
    return float(min(1e-3, max(1e-11, 1e5 * span / (2 * count))))


def _tables(sets: Sequence[_Set], target: float, tolerance: float | None,
            window: float) -> tuple[tuple[_Table, _Stream] | None, int]:
    """The meet in the middle's sorted table (the first half of the stages) and the stream of the rest, pruned to
    what can land within ``window`` (closest mode) or ``tolerance``; None when either is empty. Raises TooLarge
    when a partial product would pass MAX_TABLE."""
    bounds = [(float(s.ratio.min()), float(s.ratio.max())) for s in sets]
    pad = (tolerance if tolerance is not None else window) + 4 * TIE
    lo, hi = target * max(0.0, 1 - pad), target * (1 + pad)
    k = len(sets) // 2
    half, w1 = _combine(sets[:k], lo, hi, bounds, limit=MAX_TABLE)
    if len(half.ratio) == 0:
        return None, w1
    stream, w2 = _Stream.build(sets[k:], lo, hi, (float(half.ratio.min()), float(half.ratio.max())),
                               by_teeth=tolerance is not None)
    if len(stream.outer.ratio) == 0:
        return None, w1 + w2
    return (_Table.build(half, pad), stream), w1 + w2


def _search_window(sets: Sequence[_Set], target: float, tolerance: float | None,
                   window: float) -> tuple[tuple[float, int, list[int]] | None, int]:
    """Best product within ``window`` (closest mode) or ``tolerance``: the first half of the stages forms a
    sorted table, the rest is streamed against it chunk by chunk."""
    tables, work = _tables(sets, target, tolerance, window)
    if tables is None:
        return None, work
    table, stream = tables
    if tolerance is None:
        found, more = _closest(table, stream, target, window)
    else:
        found, more = _fewest(table, stream, target, tolerance)
    if found is None:
        return None, work + more
    err, teeth, stream_flat, table_row = found
    picks = table.half.pick(table_row) + [int(i) for i in np.unravel_index(stream_flat, stream.sizes)]
    return (err, teeth, picks), work + more


def enumerate_tooth_numbers(target: float, stages: Sequence[Stage], rules: ToothRules,
                            tolerance: float | None = None) -> tuple[float, int, list[tuple[int, int]], int] | None:
    """Plain enumeration of every combination of admissible pairs (the baseline and the check).

    Returns (ratio error, total teeth, pairs, combinations) of the best combination by the same objective and
    tie rule as :func:`serial_tooth_numbers`, or None when none qualifies.
    """
    return _enumerate(target, _stage_sets(stages, rules, None), rules, tolerance)


def _enumerate(target: float, pairs: Sequence[tuple[IntArray, IntArray]], rules: ToothRules,
               tolerance: float | None) -> tuple[float, int, list[tuple[int, int]], int] | None:
    """:func:`enumerate_tooth_numbers` over the stages' admissible pairs: every combination's ratio as an outer
    product over the stages, flattened in the stages' order; tooth counts are summed for the candidates only."""
    shape = tuple(len(zp) for zp, _ in pairs)
    ratio: FloatArray = np.ones(())
    for zp, zg in pairs:
        ratio = ratio[..., None] * (zg / zp)
    ratio = ratio.ravel()
    err = ratio / target
    err -= 1
    np.abs(err, out=err)
    if rules.reverted or tolerance is not None:
        ok = np.ones(ratio.shape, dtype=bool)
        if rules.reverted:
            full = ok.reshape(shape)
            sums = [(zp + zg)[(slice(None),) + (None,) * (len(pairs) - 1 - j)] for j, (zp, zg) in enumerate(pairs)]
            for s in sums[1:]:
                full &= s == sums[0]
        if tolerance is not None:
            ok &= err <= tolerance * (1 + 1e-12) + 1e-15
        if not ok.any():
            return None
        cand = np.nonzero(ok)[0]
    elif not ratio.size:
        return None
    if tolerance is None:
        if rules.reverted:
            cand = cand[err[cand] <= err[cand].min() + TIE]
        else:
            # every combination is a candidate: no index of them all is made
            cand = np.flatnonzero(err <= err.min() + TIE)
        teeth = _teeth_of(cand, pairs, shape)
        k = cand[np.lexsort((err[cand], teeth))[0]]
    else:
        teeth = _teeth_of(cand, pairs, shape)
        fewest = teeth.min()
        cand = cand[teeth == fewest]
        k = cand[np.argmin(err[cand])]
    rows = np.unravel_index(int(k), shape)
    chosen = [(int(zp[i]), int(zg[i])) for (zp, zg), i in zip(pairs, rows, strict=True)]
    return float(err[k]), sum(zp + zg for zp, zg in chosen), chosen, int(ratio.size)


def _teeth_of(flat: IntArray, pairs: Sequence[tuple[IntArray, IntArray]], shape: tuple[int, ...]) -> IntArray:
    """Total teeth of the combinations at flat positions ``flat`` of the stages' grid."""
    teeth = np.zeros(len(flat), dtype=np.int64)
    for (zp, zg), i in zip(pairs, np.unravel_index(flat, shape), strict=True):
        teeth += zp[i] + zg[i]
    return teeth


def _check_reach(target: float, stages: Sequence[Stage], pairs: Sequence[tuple[IntArray, IntArray]],
                 tolerance: float | None) -> None:
    if any(len(zp) == 0 for zp, _ in pairs):
        return
    reach_lo = math.prod(float(np.min(zg / zp)) for zp, zg in pairs)
    reach_hi = math.prod(float(np.max(zg / zp)) for zp, zg in pairs)
    slack = tolerance or 0.0
    if target > reach_hi * (1 + slack):
        raise Infeasible(
            f"total ratio {target:g} exceeds the largest these tooth bounds and stage ranges reach ({reach_hi:.4g}): "
            "raise max_teeth, a stage's ratio_max or the number of stages",
            constraint="max_teeth", reachable_min=reach_lo, reachable_max=reach_hi)
    if target < reach_lo * (1 - slack):
        raise Infeasible(
            f"total ratio {target:g} is below the smallest these tooth bounds and stage ranges reach "
            f"({reach_lo:.4g}): lower a stage's ratio_min or the number of stages",
            constraint="stage_ratio_min", reachable_min=reach_lo, reachable_max=reach_hi)


def _empty_reason(stages: Sequence[Stage], pairs: Sequence[tuple[IntArray, IntArray]], rules: ToothRules,
                  tolerance: float | None) -> Infeasible:
    for i, (zp, _) in enumerate(pairs):
        if len(zp) == 0:
            s = stages[i]
            return Infeasible(
                f"no tooth pair for stage {i} ({s.type}) within the teeth bounds, the interference limit and its "
                f"ratio range [{s.ratio_min:g}, {s.ratio_max:g}]: raise max_teeth, lower min_teeth or widen the range",
                constraint="max_teeth", stage_index=i)
    if rules.reverted:
        return Infeasible("no reverted train (equal tooth sums in every stage) meets the target: relax tolerance, "
                          "raise max_teeth or drop reverted", constraint="reverted")
    if rules.hunting:
        return Infeasible("no hunting-tooth train meets the target: relax tolerance, raise max_teeth or drop "
                          "hunting", constraint="tolerance" if tolerance is not None else "hunting")
    return Infeasible("no tooth numbers meet the target ratio within the tolerance: relax tolerance or raise "
                      "max_teeth", constraint="tolerance", tolerance=tolerance)


def serial_tooth_numbers(target: float, stages: Sequence[Stage], rules: ToothRules | None = None,
                         tolerance: float | None = None, *,
                         check_limit: int = ENUMERATION_CHECK_LIMIT) -> ToothResult:
    """Integer tooth numbers of a serial train of external meshes whose ratio best meets ``target`` [-], motor
    side first.

    Parameters
    ----------
    target : total ratio U [-].
    stages : the train's toothed stages (their ratio ranges bound each mesh).
    rules : pressure angle [rad], addendum and profile shift [-], min/max teeth, hunting, reverted.
    tolerance : relative ratio tolerance [-]; given, the fewest teeth within it, else the closest ratio.
    check_limit : run the plain enumeration as a check when it has at most this many combinations.

    Raises Infeasible when the search is empty (``constraint`` names what to relax), InvalidInput, TooLarge.
    """
    rules = rules or ToothRules()
    _validate(target, stages, rules, tolerance)
    t0 = time.perf_counter()
    pairs = _stage_sets(stages, rules, None)
    _check_reach(target, stages, pairs, tolerance)
    best: tuple[float, int, list[tuple[int, int]]] | None = None
    examined = 0
    if not rules.reverted:
        best, examined = _search(pairs, target, tolerance, deduped=True)
    elif all(len(p[0]) for p in pairs):
        min_small, min_large = _wheel_minimums(rules)
        sums = range(min_small + min_large, 2 * rules.max_teeth + 1)
        if tolerance is None:
            _probe_reverted(stages, rules, sums, target)
        for total_sum in sums:
            found, work = _search(_stage_sets(stages, rules, total_sum), target, tolerance, deduped=False)
            examined += work
            if found is None:
                continue
            # Every stage has the same tooth sum, so fewer teeth means a smaller sum: ascending order decides.
            if tolerance is not None:
                best = found
                break
            if best is None or found[0] < best[0] - TIE:
                best = found
    elapsed = time.perf_counter() - t0
    if best is None:
        raise _empty_reason(stages, pairs, rules, tolerance)
    err, teeth, chosen = best
    meshes = tuple(Mesh(zp, zg, zg / zp) for zp, zg in chosen)
    achieved = math.prod(m.ratio for m in meshes)
    warnings = _warnings(rules, chosen)
    checks = ToothChecks(None, None, None, None)
    combos = math.prod(len(p[0]) for p in pairs)
    if combos <= check_limit:
        ref = _enumerate(target, pairs, rules, tolerance)
        assert ref is not None
        agrees = abs(ref[0] - err) <= TIE and ref[1] == teeth
        checks = ToothChecks(ref[3], ref[0], ref[1], agrees)
    min_small, min_large = _wheel_minimums(rules)
    return ToothResult(meshes, achieved, target, abs(achieved / target - 1), teeth, tolerance,
                       "exhaustive search, provably complete: per-stage pairs deduplicated by reduced "
                       "fraction, meet in the middle: one half's products sorted, the other's streamed "
                       "against them in chunks",
                       elapsed, examined,
                       undercut_limit(rules.pressure_angle, rules.addendum, rules.profile_shift),
                       min_small, min_large, checks, tuple(warnings))


def _warnings(rules: ToothRules, chosen: Sequence[tuple[int, int]]) -> list[DesignWarning]:
    out = []
    limit = undercut_limit(rules.pressure_angle, rules.addendum, rules.profile_shift)
    if rules.min_teeth is not None and rules.min_teeth < limit:
        out.append(DesignWarning(
            "below_undercut_limit", "min_teeth", float(rules.min_teeth),
            f"min_teeth {rules.min_teeth} is below the undercut limit {limit:.1f} for this pressure angle, "
            "addendum and profile shift; the interference limit still applies"))
        for i, (zp, zg) in enumerate(chosen):
            small = min(zp, zg)
            if small < limit:
                out.append(DesignWarning(
                    "undercut", f"stages[{i}]", float(small),
                    f"{stage_name(i)}: the {small}-tooth wheel is undercut (limit {limit:.1f}); a profile shift "
                    f"of at least {rules.addendum - small * math.sin(rules.pressure_angle) ** 2 / 2:.3f} avoids it"))
    return out
