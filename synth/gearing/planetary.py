"""Tooth numbers of trains with planetary stages: sun, planets and ring under their real constraints.

A simple planetary stage (sun input, ring held, carrier output) has the ratio 1 + z_r/z_s. Its wheels obey:

- coaxiality with one module: z_r = z_s + 2·z_p;
- equal spacing of ``planets`` planets: (z_s + z_r)/planets an integer (assembly condition);
- neighbour clearance: adjacent planets' tip circles do not touch, (z_s + z_p)·sin(pi/planets) > z_p + 2·h_a;
- sun and planet at or above the undercut limit (or the user's ``min_teeth``), the sun-planet external mesh
  free of interference, the ring at most ``max_teeth``; with hunting teeth, no common factor of sun and planet.

Stages are searched exactly: every stage's candidates (one per reduced ratio, the fewest teeth), all products of
all stages but the last, and the last by binary search (closest ratio) or by its window (fewest teeth within a
tolerance). A plain enumeration of every combination checks the answer when it is small enough.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..errors import Infeasible, InvalidInput, TooLarge
from .stages import Stage, stage_name, stage_types
from .train import PlanetaryStage
from .teeth import (
    ENUMERATION_CHECK_LIMIT,
    MAX_PRODUCTS,
    MAX_TEETH_LIMIT,
    TIE,
    Mesh,
    ToothChecks,
    ToothResult,
    ToothRules,
    interference_limit,
    pairs_admissible,
    undercut_limit,
)

IntArray = NDArray[np.int64]
FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class PlanetaryMesh(Mesh):
    """A planetary stage's teeth: sun (``pinion_teeth``), ring (``gear_teeth``), ``planet_teeth`` and the number
    of ``planets``; ``ratio`` = 1 + z_r/z_s (sun in, ring held, carrier out) [-]; ``efficiency`` sun driving the
    carrier and ``back_efficiency`` the carrier driving the sun [-], by the direction of the power in the
    relative train with two closed spur meshes' basic efficiency (:func:`synth.gearing.train.planetary_efficiency`)."""

    planet_teeth: int = 0
    planets: int = 3
    efficiency: float = 1.0
    back_efficiency: float = 1.0


@dataclass(frozen=True, slots=True)
class _Candidates:
    """One stage's candidates: ratio as a reduced fraction, tooth count, and the wheels (two or three)."""

    num: IntArray
    den: IntArray
    teeth: IntArray
    wheels: IntArray  # (k, 3): pinion or sun, gear or ring, planet (0 for a simple pair)

    @property
    def ratio(self) -> FloatArray:
        return self.num / self.den


def _planetary_candidates(stage: Stage, rules: ToothRules, planets: int) -> tuple[IntArray, IntArray, IntArray]:
    """Every admissible (sun, planet, ring) of one planetary stage within its ratio range, vectorised."""
    lowest = rules.min_teeth if rules.min_teeth is not None else max(
        1, math.ceil(undercut_limit(rules.pressure_angle, rules.addendum, rules.profile_shift) - 1e-9))
    z = np.arange(lowest, rules.max_teeth + 1, dtype=np.int64)
    zs, zp = (a.ravel() for a in np.meshgrid(z, z, indexing="ij"))
    zr = zs + 2 * zp
    ratio = 1 + zr / zs
    ok = (zr <= rules.max_teeth) & ((zs + zr) % planets == 0)
    ok &= (zs + zp) * math.sin(math.pi / planets) > zp + 2 * rules.addendum
    small, large = np.minimum(zs, zp), np.maximum(zs, zp)
    ok &= large <= interference_limit(small, rules.pressure_angle, rules.addendum, rules.profile_shift) + 1e-9
    ok &= (ratio >= stage.ratio_min * (1 - 1e-12)) & (ratio <= stage.ratio_max * (1 + 1e-12))
    if rules.hunting:
        ok &= np.gcd(zs, zp) == 1
    return zs[ok], zp[ok], zr[ok]


def _stage_candidates(stage: Stage, rules: ToothRules, planets: int, dedupe: bool) -> _Candidates:
    if stage.type == "planetary":
        zs, zp, zr = _planetary_candidates(stage, rules, planets)
        num, den, teeth = zs + zr, zs, zs + zp + zr
        wheels = np.stack([zs, zr, zp], axis=1)
    else:
        z = np.arange(1, rules.max_teeth + 1, dtype=np.int64)
        p, g = (a.ravel() for a in np.meshgrid(z, z, indexing="ij"))
        ok = pairs_admissible(p, g, stage, rules)
        p, g = p[ok], g[ok]
        num, den, teeth = g, p, p + g
        wheels = np.stack([p, g, np.zeros_like(p)], axis=1)
    if not dedupe:
        return _Candidates(num, den, teeth, wheels)
    gcd = np.gcd(num, den)
    num, den = num // gcd, den // gcd
    order = np.lexsort((teeth, den, num))
    num, den, teeth, wheels = num[order], den[order], teeth[order], wheels[order]
    first = np.ones(len(num), dtype=bool)
    first[1:] = (num[1:] != num[:-1]) | (den[1:] != den[:-1])
    return _Candidates(num[first], den[first], teeth[first], wheels[first])


def _products(sets: Sequence[_Candidates]) -> tuple[FloatArray, IntArray, IntArray, int]:
    """All products of ``sets``: ratio, tooth count, and each stage's candidate index (P, len(sets))."""
    ratio, teeth = np.ones(1), np.zeros(1, dtype=np.int64)
    idx = np.zeros((1, 0), dtype=np.int64)
    examined = 0
    for s in sets:
        size = len(ratio) * len(s.num)
        if size > MAX_PRODUCTS:
            raise TooLarge("tooth search partial products (narrow max_teeth, the stage ranges or the tolerance)",
                           MAX_PRODUCTS, size)
        examined += size
        k = len(s.num)
        ratio = (ratio[:, None] * s.ratio[None, :]).ravel()
        teeth = (teeth[:, None] + s.teeth[None, :]).ravel()
        idx = np.concatenate([np.repeat(idx, k, axis=0), np.tile(np.arange(k), len(idx))[:, None]], axis=1)
    return ratio, teeth, idx, examined


def _pick(err: FloatArray, teeth: IntArray, tolerance: float | None) -> int | None:
    """Index of the best combination: closest ratio then fewest teeth, or fewest teeth within the tolerance
    then the smaller error."""
    if tolerance is None:
        near = np.flatnonzero(err <= err.min() + TIE)
        return int(near[np.argmin(teeth[near])])
    inside = np.flatnonzero(err <= tolerance * (1 + 1e-12))
    if inside.size == 0:
        return None
    fewest = inside[teeth[inside] == teeth[inside].min()]
    return int(fewest[np.argmin(err[fewest])])


def _search(sets: Sequence[_Candidates], target: float,
            tolerance: float | None) -> tuple[list[int], float, int, int] | None:
    """Best combination (per-stage indices, error, teeth) over all stages, and the products examined."""
    ratio, teeth, idx, examined = _products(sets[:-1])
    last = sets[-1]
    order = np.argsort(last.ratio, kind="stable")
    r_last, t_last = last.ratio[order], last.teeth[order]
    if tolerance is None:
        at = np.searchsorted(r_last, target / ratio)
        cols = np.clip(np.stack([at - 1, at], axis=1), 0, len(r_last) - 1)
        rows = np.repeat(np.arange(len(ratio)), 2)
        cols = cols.ravel()
    else:
        lo = np.searchsorted(r_last, target * (1 - tolerance) * (1 - 1e-12) / ratio, side="left")
        hi = np.searchsorted(r_last, target * (1 + tolerance) * (1 + 1e-12) / ratio, side="right")
        counts = np.maximum(hi - lo, 0)
        if int(counts.sum()) > MAX_PRODUCTS:
            raise TooLarge("combinations inside the tolerance (narrow it, or max_teeth)", MAX_PRODUCTS,
                           int(counts.sum()))
        rows = np.repeat(np.arange(len(ratio)), counts)
        starts = np.repeat(lo - np.concatenate([[0], np.cumsum(counts)[:-1]]), counts)
        cols = np.arange(int(counts.sum())) + starts
    examined += len(cols)
    if len(cols) == 0:
        return None
    err = np.abs(ratio[rows] * r_last[cols] / target - 1)
    total = teeth[rows] + t_last[cols]
    best = _pick(err, total, tolerance)
    if best is None:
        return None
    chosen = [int(i) for i in idx[rows[best]]] + [int(order[cols[best]])]
    return chosen, float(err[best]), int(total[best]), examined


def _plain_enumeration(sets: Sequence[_Candidates], target: float,
                       tolerance: float | None) -> tuple[int, float | None, int | None]:
    """Every combination of every stage's raw candidates, scored the same way (the independent check)."""
    ratio, teeth, _, examined = _products(sets)
    err = np.abs(ratio / target - 1)
    best = _pick(err, teeth, tolerance) if len(err) else None
    return examined, (None if best is None else float(err[best])), (None if best is None else int(teeth[best]))


def _validate(target: float, stages: Sequence[Stage], rules: ToothRules, tolerance: float | None,
              planets: int) -> None:
    if not (math.isfinite(target) and target > 0):
        raise InvalidInput(f"total_ratio must be positive, got {target}", field="total_ratio")
    for i, s in enumerate(stages):
        if s.type != "planetary" and not stage_types()[s.type].toothed:
            raise InvalidInput(f"stage type {s.type!r} has no tooth numbers to choose", field=f"stages[{i}].type")
        if s.ratio is not None:
            raise InvalidInput("the tooth search chooses every stage's ratio; give a range instead of a ratio",
                               field=f"stages[{i}].ratio")
    if rules.max_teeth > MAX_TEETH_LIMIT:
        raise TooLarge("max_teeth", MAX_TEETH_LIMIT, rules.max_teeth, field="max_teeth")
    if rules.min_teeth is not None and not 1 <= rules.min_teeth <= rules.max_teeth:
        raise InvalidInput(f"min_teeth must lie in [1, max_teeth = {rules.max_teeth}]", field="min_teeth")
    if not 0 < rules.pressure_angle < math.pi / 2:
        raise InvalidInput("pressure angle must lie strictly between 0 and 90 deg", field="pressure_angle_deg")
    if tolerance is not None and not 0 <= tolerance < 1:
        raise InvalidInput(f"tolerance must lie in [0, 1), got {tolerance}", field="tolerance")
    if rules.reverted:
        raise InvalidInput("a planetary stage is coaxial already; reverted applies to trains of simple pairs",
                           field="reverted")
    if not 2 <= planets <= 12:
        raise InvalidInput(f"planets must lie in [2, 12], got {planets}", field="planets")


def planetary_tooth_numbers(target: float, stages: Sequence[Stage], rules: ToothRules | None = None,
                            tolerance: float | None = None, *, planets: int = 3,
                            check_limit: int = ENUMERATION_CHECK_LIMIT) -> ToothResult:
    """Tooth numbers of a serial train with planetary stages whose ratio best meets ``target`` [-].

    Parameters
    ----------
    target : total ratio U [-].
    stages : toothed and planetary stages, motor side first (their ratio ranges bound each stage).
    rules : pressure angle [rad], addendum and profile shift [-], min/max teeth, hunting.
    tolerance : relative ratio tolerance [-]; given, the fewest teeth within it, else the closest ratio.
    planets : planets per planetary stage [-].
    check_limit : run the plain enumeration as a check when it has at most this many combinations.

    Raises Infeasible when a stage admits no wheels or no combination meets the tolerance, InvalidInput, TooLarge.
    """
    rules = rules or ToothRules()
    _validate(target, stages, rules, tolerance, planets)
    t0 = time.perf_counter()
    sets = [_stage_candidates(s, rules, planets, dedupe=True) for s in stages]
    for i, s in enumerate(sets):
        if len(s.num) == 0:
            what = ("no sun, planet and ring meet coaxiality, equal spacing, neighbour clearance and the tooth "
                    "limits within its ratio range" if stages[i].type == "planetary" else
                    "no pinion and gear meet the tooth limits within its ratio range")
            raise Infeasible(f"{stage_name(i)} ({stages[i].type}): {what}", constraint=f"stages[{i}]")
    found = _search(sets, target, tolerance)
    elapsed = time.perf_counter() - t0
    if found is None:
        raise Infeasible(f"no tooth numbers reach the ratio {target:.6g} within the tolerance {tolerance}",
                         constraint="tolerance")
    chosen, err, teeth, examined = found
    meshes: list[Mesh] = []
    total = 1.0
    for s, c in zip(sets, chosen):
        a, b, p = (int(v) for v in s.wheels[c])
        if p:
            stage = PlanetaryStage(a, p, b)
            meshes.append(PlanetaryMesh(a, b, 1 + b / a, p, planets, stage.stage_efficiency(),
                                        stage.back_efficiency()))
            total *= 1 + b / a
        else:
            meshes.append(Mesh(a, b, b / a))
            total *= b / a
    raw = [_stage_candidates(s, rules, planets, dedupe=False) for s in stages]
    size = math.prod(len(r.num) for r in raw)
    if size <= check_limit:
        combos, e_err, e_teeth = _plain_enumeration(raw, target, tolerance)
        agrees = e_err is not None and abs(e_err - err) <= TIE and e_teeth == teeth
        checks = ToothChecks(combos, e_err, e_teeth, agrees)
    else:
        checks = ToothChecks(None, None, None, None)
    lowest = rules.min_teeth if rules.min_teeth is not None else max(
        1, math.ceil(undercut_limit(rules.pressure_angle, rules.addendum, rules.profile_shift) - 1e-9))
    return ToothResult(tuple(meshes), total, target, abs(total / target - 1), teeth, tolerance,
                       "exhaustive: all stages but the last enumerated, the last by binary search", elapsed,
                       examined, undercut_limit(rules.pressure_angle, rules.addendum, rules.profile_shift),
                       lowest, lowest, checks)
