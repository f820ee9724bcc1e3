"""Fatigue of a part under the cycle's stresses: Marin's endurance limit and the modified Goodman line.

Shigley's Mechanical Engineering Design (9th ed., ch. 6): the endurance limit at the part
Se = ka kb kc kd ke S'e (eq. 6-18) with the surface factor ka = a Sut^b (eq. 6-19, Table 6-2), the size factor kb
(eq. 6-20) of the equivalent diameter (Table 6-3), the load factor kc (0.85 axial, eq. 6-26) and the reliability
factor ke (Table 6-5); a notch enters as the fatigue stress-concentration factor Kf on the stresses. Mean and
alternating stresses of a combined load are combined by von Mises (eq. 6-55 and 6-56), and the factor of safety of
the modified Goodman line is 1/n = sigma_a/Se + sigma_m/Sut (Table 6-6); a compressive mean does not lower the
strength, so there n = Se/sigma_a (Shigley §6-12).
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np

from ..errors import InvalidInput
from ..model import FloatArray

MPA = 1e6
Surface = Literal["ground", "machined", "hot_rolled", "forged"]

#: Shigley Table 6-2, Sut in MPa: ka = a Sut^b.
SURFACE_FACTORS: dict[str, tuple[float, float]] = {
    "ground": (1.58, -0.085),
    "machined": (4.51, -0.265),
    "hot_rolled": (57.7, -0.718),
    "forged": (272.0, -0.995),
}
#: Shigley Table 6-5: reliability -> ke.
RELIABILITY_FACTORS: dict[float, float] = {0.5: 1.0, 0.9: 0.897, 0.95: 0.868, 0.99: 0.814, 0.999: 0.753,
                                           0.9999: 0.702}
#: Shigley eq. 6-26: an axial load's endurance limit is 0.85 of the bending one.
AXIAL_LOAD_FACTOR = 0.85


def surface_factor(ultimate_strength: float, surface: str) -> float:
    """ka of Shigley eq. 6-19 for the finish ``surface`` and ultimate strength [Pa]."""
    try:
        a, b = SURFACE_FACTORS[surface]
    except KeyError:
        raise InvalidInput(f"unknown surface {surface!r}; one of {list(SURFACE_FACTORS)}", field="limits.surface") from None
    return min(1.0, float(a * (ultimate_strength / MPA) ** b))


def size_factor(equivalent_diameter: float) -> float:
    """kb of Shigley eq. 6-20 for an equivalent diameter [m]: 1.24 d^-0.107 (2.79..51 mm), 1.51 d^-0.157
    (51..254 mm, d in mm); 1 below 2.79 mm; beyond 254 mm the fit's end value 0.6 (Shigley: 0.6 to 0.75)."""
    d = equivalent_diameter * 1e3
    if d <= 2.79:
        return 1.0
    if d <= 51:
        return float(1.24 * d**-0.107)
    if d <= 254:
        return float(1.51 * d**-0.157)
    return 0.6


def reliability_factor(reliability: float) -> float:
    """ke of Shigley Table 6-5 for one of its reliabilities."""
    try:
        return RELIABILITY_FACTORS[reliability]
    except KeyError:
        raise InvalidInput(f"reliability must be one of {sorted(RELIABILITY_FACTORS)}, got {reliability!r}",
                           field="limits.reliability") from None


def endurance_limit(fatigue_limit: float, ultimate_strength: float, surface: str, equivalent_diameter: float,
                    reliability: float = 0.5) -> float:
    """Marin's endurance limit at the part for bending [Pa] (kc = 1; the axial share is divided by 0.85 where
    the stresses are combined)."""
    return (surface_factor(ultimate_strength, surface) * size_factor(equivalent_diameter)
            * reliability_factor(reliability) * fatigue_limit)


def amplitude_mean(history: FloatArray, axis: int = -1) -> tuple[FloatArray, FloatArray]:
    """Alternating and mean stress of a history over the cycle along ``axis``: half the range between its
    extremes and their middle (the largest cycle of the history; the smaller ones it holds are left out)."""
    hi, lo = np.max(history, axis=axis), np.min(history, axis=axis)
    return 0.5 * (hi - lo), 0.5 * (hi + lo)


def von_mises_amplitude_mean(sigma: FloatArray, tau: FloatArray, axis: int = -1) -> tuple[FloatArray, FloatArray]:
    """Von Mises alternating and mean stress of a normal stress and a shear stress history at one point
    (Shigley eqs. 6-55 and 6-56 with the factors already on the stresses)."""
    sa, sm = amplitude_mean(sigma, axis)
    ta, tm = amplitude_mean(tau, axis)
    return np.sqrt(sa * sa + 3 * ta * ta), np.sqrt(sm * sm + 3 * tm * tm) * np.where(sm < 0, -1.0, 1.0)


def goodman_safety(sigma_a: FloatArray, sigma_m: FloatArray, endurance: float, ultimate_strength: float
                   ) -> FloatArray:
    """Factor of safety of the modified Goodman line, 1/n = sigma_a/Se + sigma_m/Sut; with a compressive mean
    n = Se/sigma_a; infinite for a stress that does not vary and does not pull."""
    sa = np.asarray(sigma_a, dtype=float)
    sm = np.maximum(np.asarray(sigma_m, dtype=float), 0.0)
    demand = sa / endurance + sm / ultimate_strength
    with np.errstate(divide="ignore"):
        return np.where(demand > 0, 1.0 / np.where(demand > 0, demand, 1.0), math.inf)
