"""The bearing of a revolute joint or a shaft over the cycle: a plain bushing, or a rolling bearing from a catalogue.

Inputs, for every function: the radial load at every crank angle, shape (N, 2) or (N,) [N]; the relative angular
speed of the two members at the same angles, shape (N,) [rad/s]; the cycle's duration [s] (the samples are taken
uniformly over one cycle at constant crank speed). Outputs: :func:`size_bushing` gives a :class:`BushingResult`
(pressure, sliding speed and p·v over the cycle, the length, the checks); :func:`select_rolling_bearing` gives a
:class:`RollingBearingResult` (the catalogue bearing, its equivalent load, basic rating life and static safety).

Models
------
- Plain bushing: mean pressure p = F/(d b) on the projected area, sliding speed v = |w_rel| d/2, and p·v. The
  peaks of p and v are held under the material's limits, the cycle's mean of p·v (the heat the bushing sheds,
  averaged over a cycle far shorter than its thermal time) under its p·v limit. For an oscillating joint the mean
  sliding speed is the manufacturers' v = 4 beta f d/2 (GLYCODUR: v = 5.82e-7 d beta f, d [mm], beta the half
  angle [deg], f oscillations per minute).
- Rolling bearing, ISO 281: basic rating life L10 = (C/P)^p million revolutions, p = 3 ball, 10/3 roller bearings.
  In a planar linkage the joint's reaction is radial, so P = F_r. The cycle's varying load becomes the mean load
  P = (sum F^p |w_rel| / sum |w_rel|)^(1/p): each sample weighted by the revolutions made under it (ISO 281 and
  the manufacturers' mean load for a varying load; at constant speed it is the cubic mean over the cycle).
  Life in hours counts the revolutions actually swept: sum |w_rel| dt / 2 pi per cycle. For a joint that only
  oscillates this is the manufacturers' equivalent speed n = n_osc 2 gamma/180 (SKF's rolling bearings
  catalogue, "oscillating movement"; the Harmonic Drive output-bearing life L_OC = 10^6/(60 n_1) 180/phi
  (C/P)^p with phi the full swing), the same number of revolutions counted the same way.
- Static safety s0 = C0/P0 with P0 the peak radial load (ISO 76), held at least ``static_safety``.

Where it stops: below a swing of about 5 degrees (the manufacturers' bound; Houpert's critical angle depends on
the number of rolling elements) the elements no longer roll over fresh track and the basic life does not hold:
the life is given with the warning ``bearing_small_oscillation`` (false brinelling, fretting). Above P = C/2 the
life equation is outside its validated range (``bearing_heavy_load``). No lubrication or contamination factor
(a_ISO = 1): the basic life only.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from functools import cache
from importlib import resources
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike

from ..errors import Infeasible, InvalidInput
from ..model import FloatArray
from ..warnings import DesignWarning
from .checks import PartCheck

BearingType = Literal["deep_groove_ball", "cylindrical_roller", "needle_roller"]
BALL_TYPES = ("deep_groove_ball",)
#: Below this full swing an oscillating rolling bearing's elements no longer overlap their tracks [rad].
SMALL_SWING = math.radians(5.0)
#: Net rotation per cycle under which a joint counts as oscillating [revolutions].
_NET_ROTATION_TOL = 1e-6


@dataclass(frozen=True, slots=True)
class RollingBearing:
    """A catalogue rolling bearing: ``bore`` d, ``outer`` D, ``width`` B [m]; ``dynamic_rating`` C and
    ``static_rating`` C0 [N]."""

    designation: str
    type: BearingType
    bore: float
    outer: float
    width: float
    dynamic_rating: float
    static_rating: float

    @property
    def exponent(self) -> float:
        """ISO 281 life exponent p: 3 for ball bearings, 10/3 for roller bearings [-]."""
        return 3.0 if self.type in BALL_TYPES else 10.0 / 3.0


@dataclass(frozen=True, slots=True)
class BushingMaterial:
    """A plain bushing material's limits: ``pressure_limit`` p [Pa], ``speed_limit`` v [m/s], ``pv_limit`` [Pa·m/s]."""

    name: str
    pressure_limit: float
    speed_limit: float
    pv_limit: float


def rolling_bearing_from_row(row: Mapping[str, Any]) -> RollingBearing:
    """One catalogue row (``designation``, ``type``, ``bore_mm``, ``outer_mm``, ``width_mm``,
    ``dynamic_rating_kN``, ``static_rating_kN``) as a :class:`RollingBearing` in SI units."""
    try:
        b = RollingBearing(str(row["designation"]), row["type"], row["bore_mm"] / 1e3, row["outer_mm"] / 1e3,
                           row["width_mm"] / 1e3, row["dynamic_rating_kN"] * 1e3, row["static_rating_kN"] * 1e3)
    except (KeyError, TypeError) as exc:
        raise InvalidInput(f"bearing catalogue row {row!r} lacks or mistypes {exc}", field="bearings") from exc
    _validate_bearing(b)
    return b


def _validate_bearing(b: RollingBearing) -> None:
    if b.type not in ("deep_groove_ball", "cylindrical_roller", "needle_roller"):
        raise InvalidInput(f"bearing {b.designation}: unknown type {b.type!r}", field="bearings.type")
    for name in ("bore", "outer", "width", "dynamic_rating", "static_rating"):
        v = getattr(b, name)
        if not (isinstance(v, float) and math.isfinite(v) and v > 0.0):
            raise InvalidInput(f"bearing {b.designation}: {name} must be positive, got {v!r}",
                               field=f"bearings.{name}")
    if b.outer <= b.bore:
        raise InvalidInput(f"bearing {b.designation}: outer diameter not above the bore", field="bearings.outer_mm")


@cache
def _catalogue_document() -> dict[str, Any]:
    text = resources.files(__package__).joinpath("bearings.json").read_text(encoding="utf-8")
    doc: dict[str, Any] = json.loads(text)
    return doc


@cache
def bearing_catalogue() -> tuple[RollingBearing, ...]:
    """The shipped catalogue of indicative rolling bearings, in SI units, smallest outer diameter first."""
    rows = [rolling_bearing_from_row(r) for r in _catalogue_document()["rolling_bearings"]]
    return tuple(sorted(rows, key=_size_key))


@cache
def bushing_materials() -> dict[str, BushingMaterial]:
    """The shipped indicative plain-bushing materials by name, limits in SI units."""
    return {r["name"]: BushingMaterial(r["name"], r["pressure_limit_MPa"] * 1e6, float(r["speed_limit_m_s"]),
                                       r["pv_limit_MPa_m_s"] * 1e6)
            for r in _catalogue_document()["bushing_materials"]}


def _size_key(b: RollingBearing) -> tuple[float, float, float, str]:
    return (b.outer, b.width, b.bore, b.designation)


def _load_magnitude(load: ArrayLike, part: str) -> FloatArray:
    f = np.asarray(load, dtype=float)
    if f.ndim == 2 and f.shape[1] == 2:
        f = np.hypot(f[:, 0], f[:, 1])
    if f.ndim != 1 or f.size == 0 or not np.all(np.isfinite(f)):
        raise InvalidInput(f"{part}: the load must be finite, shape (N,) or (N, 2), got {np.shape(load)}",
                           field=f"{part}.load")
    out: FloatArray = np.abs(f)
    return out


def _speed(relative_speed: ArrayLike, n: int, part: str) -> FloatArray:
    w = np.asarray(relative_speed, dtype=float)
    if w.shape != (n,) or not np.all(np.isfinite(w)):
        raise InvalidInput(f"{part}: the relative speed must be finite, shape ({n},), got {w.shape}",
                           field=f"{part}.relative_speed")
    return w


def _cycle_time(cycle_time: float, part: str) -> float:
    if not (math.isfinite(cycle_time) and cycle_time > 0.0):
        raise InvalidInput(f"{part}: the cycle time must be positive, got {cycle_time!r}", field="cycle_time")
    return cycle_time


def mean_load(load: ArrayLike, relative_speed: ArrayLike, exponent: float) -> float:
    """The load giving the same rating life as the cycle's: (sum F^p |w| / sum |w|)^(1/p) [N], samples uniform in
    time; the peak load when the joint does not turn at all."""
    f = _load_magnitude(load, "bearing")
    w = np.abs(_speed(relative_speed, f.size, "bearing"))
    total = float(w.sum())
    if total == 0.0:
        return float(f.max())
    return float((np.sum(f**exponent * w) / total) ** (1.0 / exponent))


@dataclass(frozen=True, slots=True)
class JointRotation:
    """What the joint's relative rotation does over one cycle: ``revolutions`` swept (sum |w| dt / 2 pi) [-],
    ``net_revolutions`` the net turn [-], ``swing`` the full angle between the extremes of an oscillation [rad]
    (2 pi or more for a joint that turns on), ``oscillating`` when the net turn is nil."""

    revolutions: float
    net_revolutions: float
    swing: float
    oscillating: bool


def joint_rotation(relative_speed: ArrayLike, cycle_time: float) -> JointRotation:
    """The relative rotation over one cycle from the relative speed at N uniform samples [rad/s] and the cycle's
    duration [s] (rectangle rule, exact for the periodic trigonometric content the samples resolve)."""
    w = np.asarray(relative_speed, dtype=float)
    dt = _cycle_time(cycle_time, "joint") / w.size
    revs = float(np.sum(np.abs(w)) * dt / (2.0 * math.pi))
    angle = np.concatenate([[0.0], np.cumsum(w) * dt])
    net = float(angle[-1] / (2.0 * math.pi))
    oscillating = abs(net) <= _NET_ROTATION_TOL * max(revs, 1.0)
    swing = float(angle.max() - angle.min()) if oscillating else max(2.0 * math.pi, float(angle.max() - angle.min()))
    return JointRotation(revs, net, swing, oscillating)


def rating_life(dynamic_rating: float, load: float, exponent: float) -> float:
    """ISO 281 basic rating life L10 = (C/P)^p [million revolutions]; infinite under no load."""
    return math.inf if load <= 0.0 else (dynamic_rating / load) ** exponent


def required_dynamic_rating(load: float, life: float, exponent: float) -> float:
    """The dynamic rating C that gives ``life`` million revolutions under ``load`` [N]: C = P L^(1/p)."""
    return float(load * life ** (1.0 / exponent))


@dataclass(frozen=True, slots=True)
class RollingBearingResult:
    """A joint's or shaft support's rolling bearing: the catalogue ``bearing``; ``mean_load`` P [N];
    ``peak_load`` P0 [N]; ``rotation`` over the cycle; ``life`` L10 [million revolutions] and ``life_hours``
    L10h [h]; ``static_safety`` s0 = C0/P0 [-]; ``checks`` life and static safety; ``warnings`` named notes."""

    part: str
    bearing: RollingBearing
    mean_load: float
    peak_load: float
    rotation: JointRotation
    life: float
    life_hours: float
    static_safety: float
    checks: tuple[PartCheck, ...]
    warnings: tuple[DesignWarning, ...]


def select_rolling_bearing(
    part: str,
    load: ArrayLike,
    relative_speed: ArrayLike,
    cycle_time: float,
    *,
    min_bore: float,
    required_life_hours: float,
    static_safety: float = 1.0,
    types: Iterable[BearingType] | None = None,
    catalogue: Sequence[RollingBearing] | None = None,
) -> RollingBearingResult:
    """The smallest catalogue bearing (by outer diameter, then width) with a bore of at least ``min_bore`` [m]
    whose basic rating life reaches ``required_life_hours`` [h] and whose static safety reaches ``static_safety``.

    ``load`` the radial load over the cycle, (N, 2) or (N,) [N]; ``relative_speed`` of the rings, (N,) [rad/s];
    ``cycle_time`` [s]; ``types`` the bearing types allowed (all by default); ``catalogue`` replaces the shipped
    one. :class:`Infeasible` (constraint ``bearing_life``) names the part when no entry carries the load.
    """
    f = _load_magnitude(load, part)
    w = _speed(relative_speed, f.size, part)
    rot = joint_rotation(w, _cycle_time(cycle_time, part))
    for name, v in (("min_bore", min_bore), ("required_life_hours", required_life_hours),
                    ("static_safety", static_safety)):
        if not (math.isfinite(v) and v > 0.0):
            raise InvalidInput(f"{part}: {name} must be positive, got {v!r}", field=f"{part}.{name}")
    pool = list(catalogue) if catalogue is not None else list(bearing_catalogue())
    for b in pool:
        _validate_bearing(b)
    allowed = set(types) if types is not None else None
    rev_per_hour = rot.revolutions * 3600.0 / cycle_time
    peak = float(f.max())
    best_miss: tuple[float, RollingBearing] | None = None
    for b in sorted(pool, key=_size_key):
        if b.bore < min_bore * (1.0 - 1e-12) or (allowed is not None and b.type not in allowed):
            continue
        p = mean_load(f, w, b.exponent)
        life = rating_life(b.dynamic_rating, p, b.exponent)
        hours = math.inf if rev_per_hour == 0.0 else life * 1e6 / rev_per_hour
        s0 = math.inf if peak == 0.0 else b.static_rating / peak
        if hours >= required_life_hours and s0 >= static_safety:
            return _rolling_result(part, b, p, peak, rot, life, hours, s0, required_life_hours, static_safety)
        if best_miss is None or min(hours / required_life_hours, s0 / static_safety) > best_miss[0]:
            best_miss = (min(hours / required_life_hours, s0 / static_safety), b)
    detail = (f"; the best, {best_miss[1].designation}, reaches {best_miss[0]:.0%} of the need" if best_miss
              else "")
    raise Infeasible(f"{part}: no catalogue bearing with a bore of at least {min_bore * 1e3:.1f} mm gives "
                     f"{required_life_hours:g} h of basic rating life and a static safety of {static_safety:g}"
                     f"{detail}", constraint="bearing_life", part=part, peak_load_N=peak)


def _rolling_result(part: str, b: RollingBearing, p: float, peak: float, rot: JointRotation, life: float,
                    hours: float, s0: float, need_hours: float, need_s0: float) -> RollingBearingResult:
    checks = (
        PartCheck(part, "bearing_life", hours, need_hours, "h",
                  f"ISO 281 basic rating life L10h of {b.designation} under the cycle's mean load", at_least=True),
        PartCheck(part, "bearing_static_safety", s0, need_s0, "1",
                  f"static safety C0/P0 of {b.designation} under the cycle's peak load (ISO 76)", at_least=True),
    )
    notes: list[DesignWarning] = []
    if rot.oscillating and 0.0 < rot.swing < SMALL_SWING:
        notes.append(DesignWarning("bearing_small_oscillation", part, rot.swing,
                                   f"{part} oscillates through {math.degrees(rot.swing):.1f}°, less than 5°: the "
                                   "rolling elements do not overlap their tracks, the rating life does not hold "
                                   "(false brinelling); a plain bushing suits it better", "rad"))
    if p > 0.5 * b.dynamic_rating:
        notes.append(DesignWarning("bearing_heavy_load", part, p / b.dynamic_rating,
                                   f"{b.designation} carries P/C = {p / b.dynamic_rating:.2f}, above 0.5: outside "
                                   "the rating life's validated range", "1"))
    return RollingBearingResult(part, b, p, peak, rot, life, hours, s0, checks, tuple(notes))


@dataclass(frozen=True, slots=True)
class BushingResult:
    """A plain bushing: ``material``; bore ``diameter`` and ``length`` [m]; over the cycle, shape (N,):
    ``pressure`` p [Pa], ``sliding_speed`` v [m/s], ``pv`` [Pa·m/s]; ``checks`` peak p, peak v, mean p·v."""

    part: str
    material: BushingMaterial
    diameter: float
    length: float
    pressure: FloatArray
    sliding_speed: FloatArray
    pv: FloatArray
    checks: tuple[PartCheck, ...]

    @property
    def pv_mean(self) -> float:
        """The cycle's mean p·v [Pa·m/s]."""
        return float(self.pv.mean())


def size_bushing(
    part: str,
    load: ArrayLike,
    relative_speed: ArrayLike,
    diameter: float,
    material: BushingMaterial,
    *,
    length: float | None = None,
    length_ratio: tuple[float, float] = (0.5, 1.5),
) -> BushingResult:
    """A plain bushing of bore ``diameter`` [m] for the radial ``load`` (N, 2) or (N,) [N] at the relative
    ``relative_speed`` (N,) [rad/s]: the given ``length`` [m] checked, or the least length (whole millimetres,
    within ``length_ratio`` b/d) that keeps the peak pressure and the mean p·v within the material's limits.
    :class:`Infeasible` names the part and the check (``bushing_speed``, ``bushing_pressure``, ``bushing_pv``)
    when no length within the ratio does."""
    f = _load_magnitude(load, part)
    w = np.abs(_speed(relative_speed, f.size, part))
    _validate_material(part, material)
    if not (math.isfinite(diameter) and diameter > 0.0):
        raise InvalidInput(f"{part}: the bushing bore must be positive, got {diameter!r}", field=f"{part}.diameter")
    v = w * diameter / 2.0
    if float(v.max()) > material.speed_limit:
        raise Infeasible(f"{part}: the sliding speed reaches {float(v.max()):.3g} m/s, above the "
                         f"{material.name} bushing's limit of {material.speed_limit:g} m/s at any length",
                         constraint="bushing_speed", part=part)
    lo, hi = length_ratio
    if length is None:
        need_p = float(f.max()) / (diameter * material.pressure_limit)
        need_pv = float(np.mean(f * v)) / (diameter * material.pv_limit)
        need = max(lo * diameter, need_p, need_pv)
        length = math.ceil(need * 1e3 - 1e-9) / 1e3
        if length > hi * diameter and need <= hi * diameter * (1.0 + 1e-12):
            # a small bore whose next whole millimetre passes b/d, although the length it needs does not: b/d itself
            length = hi * diameter
        if need > hi * diameter * (1.0 + 1e-12):
            which = "bushing_pressure" if need_p >= need_pv else "bushing_pv"
            raise Infeasible(f"{part}: a {material.name} bushing of {diameter * 1e3:.1f} mm bore needs "
                             f"{need * 1e3:.1f} mm of length for {which.split('_')[1]}, beyond b/d = {hi:g}",
                             constraint=which, part=part, length_required_m=need)
    elif not (math.isfinite(length) and length > 0.0):
        raise InvalidInput(f"{part}: the bushing length must be positive, got {length!r}", field=f"{part}.length")
    p = f / (diameter * length)
    pv = p * v
    checks = (
        PartCheck(part, "bushing_pressure", float(p.max()), material.pressure_limit, "Pa",
                  "peak mean pressure F/(d b) on the bushing's projected area"),
        PartCheck(part, "bushing_speed", float(v.max()), material.speed_limit, "m/s",
                  "peak sliding speed |w| d/2 of the bushing"),
        PartCheck(part, "bushing_pv", float(pv.mean()), material.pv_limit, "Pa·m/s",
                  "cycle's mean of p·v, the heat per unit area the bushing sheds"),
    )
    return BushingResult(part, material, diameter, length, p, v, pv, checks)


def bushing_min_diameter(load: ArrayLike, relative_speed: ArrayLike, material: BushingMaterial,
                         max_length_ratio: float = 1.5) -> float:
    """The least bore [m] at which a bushing no longer than ``max_length_ratio`` bores keeps the peak pressure
    and the mean p·v within the material's limits: F_max/(r d²) <= p and mean(F |w|)/(2 r d) <= p·v."""
    f = _load_magnitude(load, "bushing")
    w = np.abs(_speed(relative_speed, f.size, "bushing"))
    _validate_material("bushing", material)
    by_p = math.sqrt(float(f.max()) / (max_length_ratio * material.pressure_limit))
    by_pv = float(np.mean(f * w)) / (2.0 * max_length_ratio * material.pv_limit)
    return max(by_p, by_pv)


def _validate_material(part: str, m: BushingMaterial) -> None:
    for name in ("pressure_limit", "speed_limit", "pv_limit"):
        v = getattr(m, name)
        if not (math.isfinite(v) and v > 0.0):
            raise InvalidInput(f"{part}: bushing material {m.name!r} has no {name} (got {v!r})",
                               field=f"{part}.material.{name}")
