"""Buckling of a member in compression: Euler's column, and J. B. Johnson's parabola below its tangent point.

Shigley, Mechanical Engineering Design, §4-12..4-13: with the slenderness l/k = K L / k (K the effective-length
factor of the ends, k = sqrt(I/A)), the tangent point (l/k)_1 = sqrt(2 pi² E / Sy) (eq. 4-45) separates Euler's
P_cr = pi² E A / (l/k)² (eq. 4-44) from Johnson's P_cr = A [Sy - (Sy l/k / 2 pi)² / E] (eq. 4-48), which meets
the yield strength at l/k = 0 and Euler's curve tangentially at (l/k)_1.
"""

from __future__ import annotations

import math

import numpy as np

from ..model import FloatArray

#: Effective-length factors K of ends as the joints hold them (the recommended design values of AISC's
#: commentary, Table C-A-7.1): pinned-pinned 1.0, fixed-fixed 0.65, fixed-pinned 0.8, fixed-free 2.1.
END_FACTORS: dict[str, float] = {"pinned-pinned": 1.0, "fixed-fixed": 0.65, "fixed-pinned": 0.8,
                                 "fixed-free": 2.1}


def tangent_slenderness(elastic_modulus: float, yield_strength: float) -> float:
    """(l/k)_1 = sqrt(2 pi² E / Sy), Shigley eq. 4-45 [-]."""
    return math.sqrt(2 * math.pi**2 * elastic_modulus / yield_strength)


def euler_load(area: FloatArray | float, slenderness: FloatArray | float, elastic_modulus: float) -> FloatArray:
    """Euler's critical load pi² E A / (l/k)² [N], Shigley eq. 4-44."""
    lk = np.maximum(np.asarray(slenderness, dtype=float), 1e-300)
    return np.asarray(math.pi**2 * elastic_modulus * np.asarray(area, dtype=float) / lk**2)


def johnson_load(area: FloatArray | float, slenderness: FloatArray | float, elastic_modulus: float,
                 yield_strength: float) -> FloatArray:
    """Johnson's critical load A [Sy - (Sy (l/k) / 2 pi)² / E] [N], Shigley eq. 4-48."""
    lk = np.asarray(slenderness, dtype=float)
    return np.asarray(np.asarray(area, dtype=float)
                      * (yield_strength - (yield_strength * lk / (2 * math.pi)) ** 2 / elastic_modulus))


def critical_load(area: FloatArray | float, radius_of_gyration: FloatArray | float, effective_length: float,
                  elastic_modulus: float, yield_strength: float) -> FloatArray:
    """Critical load [N] of a column of ``effective_length`` K L [m]: Euler above the tangent slenderness,
    Johnson below it."""
    slender = effective_length / np.asarray(radius_of_gyration, dtype=float)
    return np.where(slender >= tangent_slenderness(elastic_modulus, yield_strength),
                    euler_load(area, slender, elastic_modulus),
                    johnson_load(area, slender, elastic_modulus, yield_strength))
