"""Life of a pair under the real load: a torque spectrum over the machine cycle, Miner's rule on the S-N curves.

The pinion torque is sampled at equal time steps over one machine cycle; every sample carries an equal share of
the load cycles each wheel sees in the required life (60 n L_h for the pinion, that over u for the gear). The
S-N curve of each wheel is its endurance stress times Z_NT (contact) or Y_NT (root) as functions of the load
cycles (ISO 6336-2/-3 method B), so a stress sigma allows N(sigma) cycles where the curve reaches it. Damage
is D = sum n_i / N(sigma_i) (Miner, as ISO 6336-6 uses it); the safety factor on the spectrum is the factor
S by which every stress may grow before D reaches 1, found by bisection in log S (replayed on a bracket of the
root found in a few sums: the same factor to the last bit). Torques of either sign count with their magnitude:
reversed torque loads the other flank, so counting both on one flank errs safe.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..errors import InvalidInput, TooLarge
from ..model import FloatArray
from .materials import contact_life_curve, cycles_to_failure, root_life_curve
from .rating import Duty, GearPairSpec, PairModel, RatingResult, _pair, _result

MAX_SPECTRUM_SAMPLES = 100_000
_BISECTION_STEPS = 36
_BRACKET = 1e-11     # [log S]
_JUMP = 4e-12        # [log S], above the rounding of log S at a curve's static value
_NEAR = 1e-10        # [log S]
_CAP = 1e3           # |log D| beyond this counts as this: no load, or past a static value
_CLEAR = 1e-6        # |log D| at the minimum factors beyond which a lane's verdict is its safety factor's
_SURE = 1e-6         # a bound on a Miner sum this far within 1 decides it, whatever the rounding
_SLOPE_STEP = 1e-3   # [log S], the step that measures log D's slope
_SECANT_SUMS = 24    # then halvings only: 45 bring [-12, 12] itself below _BRACKET
_BRACKET_SUMS = 72   # at most, whatever D does


@dataclass(frozen=True, slots=True)
class SpectrumRating:
    """A pair rated on a load spectrum.

    ``peak`` the ordinary rating at the largest torque; ``rms_torque`` and ``mean_torque`` of the samples'
    magnitudes [N·m]; ``damage_contact``/``damage_root`` Miner sums over the required life per wheel [-];
    ``life_contact``/``life_root`` hours until the sum reaches 1 [h] (inf: no sample damages);
    ``safety_contact``/``safety_root`` the factor on every stress that brings the sum to 1 [-];
    ``equivalent_torque_contact``/``_root`` the constant pinion torque with the same damage per wheel, stress
    taken as growing with sqrt(T) in contact and with T at the root, the peak's K factors held [N·m].
    """

    peak: RatingResult
    samples: int
    rms_torque: float
    mean_torque: float
    damage_contact: tuple[float, float]
    damage_root: tuple[float, float]
    life_contact: tuple[float, float]
    life_root: tuple[float, float]
    safety_contact: tuple[float, float]
    safety_root: tuple[float, float]
    equivalent_torque_contact: tuple[float, float]
    equivalent_torque_root: tuple[float, float]


Knots = tuple[tuple[float, float], ...]


def _damage(stress: FloatArray, reference: FloatArray, knots: list[Knots], cycles_each: FloatArray,
            scale: FloatArray) -> FloatArray:
    """Miner sums per lane (L,) for stresses (N, L) each multiplied by ``scale`` (L,); ``cycles_each`` (L, N)
    the load cycles each sample carries per lane. A lane is one wheel's flank or root, on its own S-N curve."""
    return np.asarray(_damages(stress, reference, knots, cycles_each, np.asarray(scale, dtype=float)[None, :])[0])


def _damages(stress: FloatArray, reference: FloatArray, knots: list[Knots], cycles_each: FloatArray,
             scales: FloatArray) -> FloatArray:
    """Miner sums (M, L) for M sets of stress factors ``scales`` (M, L) at once, vectorised over the factors,
    the lanes (wheels, flank and root) and the spectrum.

    Lane-major, so each sum runs over contiguous samples in the order a single wheel's would: the same sums to
    the last bit as one factor and one lane at a time.
    """
    factor = (scales[:, :, None] * np.ascontiguousarray(np.asarray(stress, dtype=float).T)[None, :, :]
              / np.asarray(reference, dtype=float)[None, :, None])
    allowed = np.empty_like(factor)
    for curve, lanes in _by_curve(tuple(knots)):
        allowed[:, lanes] = cycles_to_failure(curve, factor[:, lanes])
    positive = factor > 0
    with np.errstate(divide="ignore"):
        if positive.all():               # no idle sample: nothing to mask
            per_sample = cycles_each[None, :, :] / allowed
        else:
            per_sample = np.where(positive, cycles_each[None, :, :] / np.where(positive, allowed, 1.0), 0.0)
    return np.asarray(np.sum(per_sample, axis=2), dtype=float)


@lru_cache(maxsize=64)
def _by_curve(knots: tuple[Knots, ...]) -> list[tuple[Knots, slice | list[int]]]:
    """The lanes on each distinct S-N curve (a slice where they are adjacent): one evaluation per curve."""
    groups: dict[Knots, list[int]] = {}
    for j, curve in enumerate(knots):
        groups.setdefault(curve, []).append(j)
    return [(curve, slice(js[0], js[-1] + 1) if js[-1] - js[0] == len(js) - 1 else js)
            for curve, js in groups.items()]


def _safety(stress: FloatArray, reference: FloatArray, knots: list[Knots], cycles_each: FloatArray) -> FloatArray:
    """The factor S per lane (L,) with D(S) = 1, as the bisection in log S that halves [-12, 12]
    ``_BISECTION_STEPS`` times finds it (D grows with S), every lane in step.

    Each lane's root is bracketed first (:func:`_root_bracket`, a few sums); the halvings are then replayed on
    the bracket: a midpoint more than ``_NEAR`` outside it is decided by D's growth (on every S-N curve log D
    rises by at least 6 per unit of log S, so D moves by parts in 1e9 there, far above its rounding), and a
    midpoint nearer by the sum itself. The answer is the plain bisection's to the last bit at a fraction of its
    sums. A spectrum with a sample that carries no cycles (D may then be undefined) takes the plain bisection.
    """
    bracket = _root_bracket(stress, reference, knots, cycles_each) if np.all(cycles_each > 0) else None
    lo, hi = np.full(len(knots), -12.0), np.full(len(knots), 12.0)
    for _ in range(_BISECTION_STEPS):
        mid = (lo + hi) / 2
        if bracket is None:
            over = _damage(stress, reference, knots, cycles_each, np.exp(mid)) > 1
        else:
            a, b = bracket
            over = mid >= b
            near = (mid > a - _NEAR) & (mid < b + _NEAR)
            if near.any():
                j = np.flatnonzero(near)
                over[j] = _damage(stress[:, j], reference[j], [knots[k] for k in j], cycles_each[j],
                                  np.exp(mid[j])) > 1
        hi = np.where(over, mid, hi)
        lo = np.where(over, lo, mid)
    return np.asarray(np.exp((lo + hi) / 2), dtype=float)


def _root_bracket(stress: FloatArray, reference: FloatArray, knots: list[Knots], cycles_each: FloatArray
                  ) -> tuple[FloatArray, FloatArray]:
    """Per lane an interval [a, b] of log S no wider than ``_BRACKET`` with D(e^a) <= 1 < D(e^b); a = b = 12
    where D stays within 1 up to e^12, a = b = -12 where it exceeds 1 from e^-12 on.

    D is infinite once the most stressed sample passes its curve's static value, at log S = ``jump``: the root
    is often that jump (a sum just below it decides), else it lies below, where log D is nearly straight in
    log S (the curves are straight in log-log). A Newton step on the slope measured just below the jump lands
    near the root, and regula falsi on log D (the Illinois variant, each step kept ``_BRACKET``/4 inside the
    bracket so that a point next to the root closes it) ends in a few sums.
    """

    def log_damage(t: FloatArray) -> FloatArray:
        t = np.atleast_2d(t)
        with np.errstate(divide="ignore"):
            d = _damages(stress, reference, knots, cycles_each, np.exp(t))
            return np.clip(np.log(d), -_CAP, _CAP)

    lanes = len(knots)
    peak = np.max(np.asarray(stress, dtype=float), axis=0, initial=0.0) / reference
    static = np.array([math.log(k[0][1]) for k in knots]) * (1 + 1e-12)
    with np.errstate(divide="ignore"):
        jump = np.where(peak > 0, static - np.log(np.where(peak > 0, peak, 1.0)), np.inf)
    t1 = np.clip(jump - _JUMP, -12.0, 12.0)
    t2 = np.maximum(t1 - _SLOPE_STEP, -12.0)
    g1, g2 = log_damage(np.stack([t1, t2]))
    over1, over2 = g1 > 0, g2 > 0
    # D within 1 just below the jump: the root is the jump (or beyond e^12)
    a = np.where(~over1, t1, np.where(~over2, t2, -12.0))
    b = np.where(~over1, np.where(t1 < 12.0, jump + _JUMP, 12.0), np.where(over2, t2, t1))
    ga = np.where(~over1, g1, np.where(~over2, g2, -_CAP))
    gb = np.where(~over1, _CAP, np.where(over2, g2, g1))
    have_a = ~over1 | ~over2 | (t2 <= -12.0)
    slope = np.where((g1 - g2 > 0) & (np.abs(g1) < _CAP), (g1 - g2) / np.maximum(t1 - t2, 1e-300), 6.0)
    side = np.zeros(lanes)
    guard = _BRACKET / 4
    for step in range(_BRACKET_SUMS):
        active = ~have_a | (b - a > _BRACKET)
        if not active.any():
            break
        secant = b - gb * (b - a) / np.where(gb > ga, gb - ga, 1.0)
        plain = (step >= _SECANT_SUMS) | (np.abs(ga) >= _CAP) | (np.abs(gb) >= _CAP) | ~(b - a > 4 * guard)
        inside = np.where(plain | ~np.isfinite(secant), (a + b) / 2, np.clip(secant, a + guard, b - guard))
        newton = np.maximum(b - gb / np.maximum(slope, 1.0), -12.0)
        t = np.where(active, np.where(have_a, inside, newton), b)
        g = log_damage(t)[0]
        up, down = active & (g > 0), active & ~(g > 0)
        # Illinois: an end kept twice has its value halved, so both ends close in
        ga = np.where(up & (side > 0) & have_a, ga / 2, np.where(down, g, ga))
        gb = np.where(down & (side < 0), gb / 2, np.where(up, g, gb))
        a, b = np.where(down, t, a), np.where(up, t, b)
        side = np.where(up & have_a, 1.0, np.where(down, -1.0, side))
        stuck = up & ~have_a & (t <= -12.0)          # over 1 even at e^-12
        a = np.where(stuck, -12.0, a)
        have_a = have_a | down | stuck
    return a, b


def _shares(torque: FloatArray, weights: FloatArray | None) -> FloatArray:
    """Each sample's share of the time (N,): equal, or the given weights normalised."""
    if weights is None:
        return np.full(torque.size, 1.0 / torque.size)
    w = np.asarray(weights, dtype=float).ravel()
    if w.shape != torque.shape or not np.all(np.isfinite(w)) or np.any(w < 0) or not w.sum() > 0:
        raise InvalidInput("the spectrum's time weights need one non-negative value per torque sample",
                           field="load_spectrum.weights")
    return np.asarray(w / w.sum(), dtype=float)


@dataclass(frozen=True, slots=True)
class SpectrumLanes:
    """A pair's four Miner sums on one spectrum, less the stresses: ``torque`` magnitudes [N·m] (N,), and per
    lane (contact pinion, contact gear, root pinion, root gear) the S-N curve's ``reference`` stress (its limit
    over its life factor) [Pa], its ``knots`` and the load cycles each sample carries ``cycles_each`` (4, N).
    None of it depends on the face width: a width search builds it once per module."""

    torque: FloatArray
    reference: FloatArray
    knots: list[Knots]
    cycles_each: FloatArray

    @classmethod
    def of(cls, model: PairModel, torque: FloatArray, weights: FloatArray | None = None) -> SpectrumLanes:
        """The lanes of ``model`` for pinion torque magnitudes [N·m] with time ``weights`` (None: equal)."""
        cycles = np.asarray(model.cycles)[:, None] * _shares(torque, weights)[None, :]
        knots = ([contact_life_curve(m, model.duty.pitting_permitted) for m in model.mats]
                 + [root_life_curve(m) for m in model.mats])
        # Reference stresses: the S-N curve's stress over its life factor, i.e. everything but Z_NT (Y_NT).
        reference = np.concatenate([model.sigma_hg / model.z_nt, model.sigma_fg / model.y_nt])
        return cls(torque, reference, knots, np.concatenate([cycles, cycles]))

    def stresses(self, model: PairModel) -> FloatArray:
        """Contact and root stresses (N, 4) [Pa] of ``model`` at the spectrum's torques."""
        return model.lane_stresses(self.torque)[1].T

    def safety(self, model: PairModel) -> FloatArray:
        """Safety factors (4,) on the spectrum: S_H1, S_H2, S_F1, S_F2."""
        return _safety(self.stresses(model), self.reference, self.knots, self.cycles_each)

    def failing(self, model: PairModel) -> list[int] | None:
        """The lanes whose spectrum safety factor falls short of its minimum, from one Miner sum per lane at the
        minimum factors instead of the factors themselves; None where a sum lies so near 1 that only the factors
        tell (within ``_CLEAR`` in log D: on the steepest S-N branch, ~52, that is 2e-8 in log S, a hundred times
        the bisection's resolution), or a lane's static value lies within 1e-9 of its minimum factor."""
        duty = model.duty
        stress = self.stresses(model)
        need = np.array([duty.min_safety_contact] * 2 + [duty.min_safety_root] * 2)
        with np.errstate(divide="ignore"):
            log_d = np.log(_damage(stress, self.reference, self.knots, self.cycles_each, need))
        peak = np.max(stress, axis=0, initial=0.0) / self.reference
        static = np.array([math.log(k[0][1]) for k in self.knots]) * (1 + 1e-12)
        with np.errstate(divide="ignore"):
            jump = static - np.log(peak)
        near_jump = np.abs(np.log(need) - jump) <= 1e-9
        if np.any(np.isnan(log_d)) or np.any(np.abs(log_d) <= _CLEAR) or np.any(near_jump):
            return None
        return [int(j) for j in np.flatnonzero(log_d > 0)]

    def feasible(self, model: PairModel) -> bool:
        """Whether every Miner sum with the stresses times S_Hmin (contact) and S_Fmin (root) stays within 1,
        i.e. the spectrum's safety factors reach their minimums."""
        duty = model.duty
        stress = self.stresses(model)
        # flank first, root only if the flanks hold: a width that fails is known at half the sums
        for rows, need in ((slice(0, 2), duty.min_safety_contact), (slice(2, 4), duty.min_safety_root)):
            scale = np.full(2, need)
            # Every cycle at the lane's peak stress bounds its sum: a sample's allowed cycles never grow with its
            # stress, so a bound within 1 by far more than the sums' rounding settles the lanes without them.
            bound = _damage(np.max(stress[:, rows], axis=0)[None, :], self.reference[rows], self.knots[rows],
                            np.sum(self.cycles_each[rows], axis=1)[:, None], scale)
            if np.all(bound <= 1 - _SURE):
                continue
            d = _damage(stress[:, rows], self.reference[rows], self.knots[rows], self.cycles_each[rows], scale)
            if not np.all(d <= 1):
                return False
        return True


def spectrum_safety(model: PairModel, torque: FloatArray, weights: FloatArray | None = None
                    ) -> tuple[FloatArray, FloatArray, tuple[float, float], tuple[float, float]]:
    """Miner sums over the life (contact, root) and the spectrum's safety factors (contact, root) per wheel for
    pinion torque magnitudes [N·m] sampled over the cycle, evenly or with time ``weights``."""
    lanes = SpectrumLanes.of(model, torque, weights)
    stress = lanes.stresses(model)
    d = _damage(stress, lanes.reference, lanes.knots, lanes.cycles_each, np.ones(4))
    s = _safety(stress, lanes.reference, lanes.knots, lanes.cycles_each)
    return d[:2], d[2:], _pair(s[:2]), _pair(s[2:])


def spectrum_feasible(model: PairModel, torque: FloatArray, weights: FloatArray | None = None) -> bool:
    """Whether the Miner sums with every stress times S_Hmin (contact) and S_Fmin (root) stay within 1, i.e. the
    spectrum's safety factors reach their minimums, for pinion torque magnitudes [N·m]."""
    return SpectrumLanes.of(model, torque, weights).feasible(model)


def rate_spectrum(spec: GearPairSpec, pinion_torque: FloatArray, pinion_speed: float, duty: Duty | None = None,
                  weights: FloatArray | None = None) -> SpectrumRating:
    """Rate a pair on pinion torques [N·m] sampled over one machine cycle at a mean speed [rad/s]; ``weights``
    each sample's share of the cycle's time (default equal: samples at equal time steps).

    ``duty.application_factor`` multiplies every sample (1 for a spectrum that is the real load).
    Raises InvalidInput for an empty, all-zero or non-finite spectrum, TooLarge beyond MAX_SPECTRUM_SAMPLES.
    """
    duty = duty or Duty()
    torque = np.abs(np.asarray(pinion_torque, dtype=float).ravel())
    if torque.size > MAX_SPECTRUM_SAMPLES:
        raise TooLarge("load_spectrum.torque_Nm", MAX_SPECTRUM_SAMPLES, int(torque.size),
                       field="load_spectrum.torque_Nm")
    if torque.size == 0 or not np.all(np.isfinite(torque)) or not np.any(torque > 0):
        raise InvalidInput("the load spectrum needs finite torques, not all zero", field="load_spectrum.torque_Nm")
    model = PairModel(spec, duty, pinion_speed)
    peak = _result(model, float(torque.max()))
    d_h, d_f, s_h, s_f = spectrum_safety(model, torque, weights)

    def life(d: FloatArray) -> tuple[float, float]:
        return _pair(np.where(d > 0, duty.life / np.where(d > 0, d, 1.0), math.inf))

    # A constant torque T_eq gives the same damage: its stress is the spectrum's safety over the rating's.
    eq_h = _pair(peak.pinion_torque * (np.array(peak.safety_contact) / np.array(s_h)) ** 2)
    eq_f = _pair(peak.pinion_torque * np.array(peak.safety_root) / np.array(s_f))
    share = _shares(torque, weights)
    return SpectrumRating(peak, int(torque.size), float(np.sqrt(share @ torque**2)), float(share @ torque), _pair(d_h),
                          _pair(d_f), life(d_h), life(d_f), s_h, s_f, eq_h, eq_f)
