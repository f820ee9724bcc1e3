"""The spectrum's Miner sums and safety factors, vectorised over the factors, the wheels and the samples, against
the scalar formula written here sample by sample: ISO 6336-2/-3 method B S-N curves as straight lines between
their knots in log-log (the last line extended past its knot, no life left above the static value), D = sum of
n_i / N(S·sigma_i) (Miner), and the safety S with D(S) = 1 found by Brent's method on that scalar sum."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from synth.gearing.life import _damage, _damages, _safety
from synth.gearing.materials import _YNT, _ZNT

CURVES = [_ZNT["St"], _ZNT["GG"], _ZNT["pitting_permitted"], _YNT["V"], _YNT["Eh"], _YNT["NT"]]


def _cycles(knots: tuple[tuple[float, float], ...], factor: float) -> float:
    """Load cycles to failure at ``factor`` times the endurance stress, one sample (written here)."""
    n = [math.log(k[0]) for k in knots]
    f = [math.log(k[1]) for k in knots]
    lf = math.log(factor)
    if lf > f[0] * (1 + 1e-12):
        return 0.0
    if lf >= f[0]:
        return math.exp(n[0])
    for a in range(len(knots) - 1):
        if f[a + 1] <= lf <= f[a]:
            return math.exp(n[a] + (lf - f[a]) * (n[a + 1] - n[a]) / (f[a + 1] - f[a]))
    # far below the endurance limit the extended line gives more than e^700 cycles: counted as e^700 (no damage
    # worth a figure), as the service does
    return math.exp(min(n[-1] + (lf - f[-1]) * (n[-1] - n[-2]) / (f[-1] - f[-2]), 700.0))


def _miner(stress: np.ndarray, ref: np.ndarray, knots: list, cycles: np.ndarray, scale: np.ndarray) -> list[float]:
    out = []
    for j in (0, 1):
        total = 0.0
        for i in range(stress.shape[0]):
            factor = scale[j] * stress[i, j] / ref[j]
            if factor > 0:
                allowed = _cycles(knots[j], factor)
                total += math.inf if allowed == 0 else cycles[j, i] / allowed
        out.append(total)
    return out


def _case(rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray, list, np.ndarray]:
    stress = rng.uniform(0.0, 1.0, (n, 2)) ** 2 * 900e6
    stress[rng.random(n) < 0.1] = 0.0          # idle samples do no damage
    ref = rng.uniform(300e6, 900e6, 2)
    knots = [CURVES[rng.integers(len(CURVES))], CURVES[rng.integers(len(CURVES))]]
    cycles = rng.uniform(1e5, 1e8, 2)[:, None] * np.full((2, n), 1.0 / n)
    return stress, ref, knots, cycles


@pytest.mark.parametrize("seed", range(8))
def test_vectorised_miner_sums_are_the_scalar_formula(seed: int) -> None:
    rng = np.random.default_rng(seed)
    stress, ref, knots, cycles = _case(rng, 97)
    scales = np.exp(rng.uniform(-1.5, 0.4, (5, 2)))
    batch = _damages(stress, ref, knots, cycles, scales)
    for row, scale in zip(batch, scales, strict=True):
        expected = _miner(stress, ref, knots, cycles, scale)
        assert row == pytest.approx(expected, rel=1e-12)
        # one factor pair at a time gives the same sums to the last bit
        assert np.array_equal(_damage(stress, ref, knots, cycles, scale), row)


@pytest.mark.parametrize("seed", range(4))
def test_spectrum_safety_is_the_root_of_the_scalar_sum(seed: int) -> None:
    rng = np.random.default_rng(100 + seed)
    stress, ref, knots, cycles = _case(rng, 61)
    safety = _safety(stress, ref, knots, cycles)
    for j in (0, 1):
        def excess(log_s: float) -> float:
            scale = np.full(2, math.exp(log_s))
            return _miner(stress, ref, knots, cycles, scale)[j] - 1.0

        root = brentq(excess, -12.0, 12.0, xtol=1e-13)
        # the bisection's 36 halvings of [-12, 12] in log S: 24/2^36 = 3.5e-10
        assert math.log(safety[j]) == pytest.approx(root, abs=4e-10)


def _halvings(stress: np.ndarray, ref: np.ndarray, knots: list, cycles: np.ndarray) -> np.ndarray:
    """The plain bisection, written here: 36 halvings of [-12, 12] in log S, a Miner sum at every midpoint."""
    lo, hi = np.full(len(knots), -12.0), np.full(len(knots), 12.0)
    for _ in range(36):
        mid = (lo + hi) / 2
        over = _damage(stress, ref, knots, cycles, np.exp(mid)) > 1
        hi, lo = np.where(over, mid, hi), np.where(over, lo, mid)
    return np.exp((lo + hi) / 2)


@pytest.mark.parametrize("seed", range(6))
def test_spectrum_safety_is_the_plain_bisection_to_the_last_bit(seed: int) -> None:
    # The safety brackets each root in a few sums and replays the halvings on the bracket: it must land on the
    # same midpoint as the plain bisection, whether the root is smooth, at a curve's static value (D jumps to
    # infinity), beyond e^12 (no load), or the spectrum has samples without cycles (the plain path).
    rng = np.random.default_rng(300 + seed)
    for _ in range(60):
        n = int(rng.choice([1, 7, 61, 400]))
        stress = rng.uniform(0.0, 1.0, (n, 4)) ** rng.uniform(0.5, 4.0) * 10 ** rng.uniform(6.0, 10.0)
        stress[rng.random(n) < 0.2] = 0.0
        if rng.random() < 0.1:
            stress[:, rng.integers(4)] = 0.0
        ref = rng.uniform(300e6, 900e6, 4)
        knots = [CURVES[rng.integers(len(CURVES))] for _ in range(4)]
        cycles = rng.uniform(1e2, 1e12, 4)[:, None] * np.full((4, n), 1.0 / n)
        if rng.random() < 0.1:
            cycles[:, rng.integers(n)] = 0.0
        with np.errstate(invalid="ignore"):      # a sample without cycles past its static value: 0/0
            assert np.array_equal(_safety(stress, ref, knots, cycles), _halvings(stress, ref, knots, cycles))
