"""Rotor balancing: single-plane static balance and two-plane dynamic balance of point masses (seed 003:542-588,
004:635-679)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import InvalidInput

#: Two correction planes closer than this share of the rotor's length (over its masses and planes), or than
#: the absolute gap, are refused.
MIN_PLANE_GAP_FRACTION = 0.01
MIN_PLANE_GAP_M = 1e-6


@dataclass(frozen=True, slots=True)
class RotorMass:
    """An unbalanced point mass [kg] at ``radius`` [m] and ``angle`` [rad] in the plane at ``axial`` [m]."""

    mass: float
    radius: float
    angle: float
    axial: float = 0.0

    @property
    def unbalance(self) -> complex:
        """Static moment m·r as a complex number [kg·m]."""
        return self.mass * self.radius * complex(math.cos(self.angle), math.sin(self.angle))


@dataclass(frozen=True, slots=True)
class Correction:
    """A correction mass [kg] at ``radius`` [m] and ``angle`` [rad] in the plane at ``axial`` [m]."""

    mass: float
    radius: float
    angle: float
    axial: float


@dataclass(frozen=True, slots=True)
class RotorBalance:
    """Corrections and the check: residual static moment [kg·m] and moment of unbalance [kg·m²] with them added."""

    corrections: tuple[Correction, ...]
    unbalance_before: float
    moment_before: float
    residual_unbalance: float
    residual_moment: float


def _validate(masses: Sequence[RotorMass]) -> None:
    if not masses:
        raise InvalidInput("at least one unbalanced mass is needed", field="masses")
    for i, m in enumerate(masses):
        for name, v in (("mass_kg", m.mass), ("radius_m", m.radius)):
            if not (math.isfinite(v) and v >= 0):
                raise InvalidInput(f"masses[{i}].{name} must be a non-negative number", field=f"masses[{i}].{name}")
        if not (math.isfinite(m.angle) and math.isfinite(m.axial)):
            raise InvalidInput(f"masses[{i}] angle and axial position must be finite", field=f"masses[{i}]")


def _correction(u: complex, radius: float, axial: float, field: str) -> Correction:
    if not (math.isfinite(radius) and radius > 0):
        raise InvalidInput(f"{field} must be positive", field=field)
    need = -u
    # Reported in [0, 2·pi) so the angle reads as a position on the rotor, not a signed turn.
    angle = math.atan2(need.imag, need.real) % (2 * math.pi) if abs(need) > 0 else 0.0
    return Correction(abs(need) / radius, radius, angle, axial)


def _sums(masses: Sequence[RotorMass], corrections: Sequence[Correction]) -> tuple[float, float]:
    parts = [(m.unbalance, m.axial) for m in masses]
    parts += [(c.mass * c.radius * complex(math.cos(c.angle), math.sin(c.angle)), c.axial) for c in corrections]
    return abs(sum(u for u, _ in parts)), abs(sum(u * z for u, z in parts))


def balance_rotor_static(masses: Sequence[RotorMass], radius: float, axial: float = 0.0) -> RotorBalance:
    """One correction mass on ``radius`` [m] opposite the resultant static moment: sum m·r = 0."""
    _validate(masses)
    before = _sums(masses, [])
    corr = _correction(sum((m.unbalance for m in masses), 0j), radius, axial, "correction_radius_m")
    after = _sums(masses, [corr])
    return RotorBalance((corr,), before[0], before[1], after[0], after[1])


def balance_rotor_dynamic(masses: Sequence[RotorMass], planes: tuple[float, float],
                          radii: tuple[float, float]) -> RotorBalance:
    """Correction masses in two planes at axial ``planes`` [m], on ``radii`` [m]: sum m·r = 0 and sum m·r·z = 0.

    The two complex equations U1 + U2 = -sum U and U1·z1 + U2·z2 = -sum U·z give, for a force F at distances
    l1, l2 from the planes, the seed's split F1 = F·l2/(l1+l2), F2 = F·l1/(l1+l2) [004:659-679].
    """
    _validate(masses)
    z1, z2 = planes
    if not (math.isfinite(z1) and math.isfinite(z2)) or z1 == z2:
        raise InvalidInput("the two correction planes must be distinct", field="planes_m")
    axial = [m.axial for m in masses] + [z1, z2]
    length = max(axial) - min(axial)
    gap = abs(z2 - z1)
    # The corrections grow as length/gap: planes nearly together ask for masses no rotor carries, and at a
    # gap of round-off size for numbers beyond any float.
    least = max(MIN_PLANE_GAP_M, MIN_PLANE_GAP_FRACTION * length)
    if gap < least:
        raise InvalidInput(f"the correction planes are {gap:.3g} m apart, closer than {least:.3g} m "
                           f"({MIN_PLANE_GAP_FRACTION:.0%} of the rotor's length {length:.3g} m over its masses "
                           f"and planes, and at least {MIN_PLANE_GAP_M:g} m): place them further apart",
                           field="planes_m")
    total = sum((m.unbalance for m in masses), 0j)
    moment = sum((m.unbalance * m.axial for m in masses), 0j)
    a = np.array([[1.0, 1.0], [z1, z2]], dtype=complex)
    u1, u2 = np.linalg.solve(a, np.array([-total, -moment]))
    corr = (_correction(-complex(u1), radii[0], z1, "radii_m[0]"), _correction(-complex(u2), radii[1], z2, "radii_m[1]"))
    before = _sums(masses, [])
    after = _sums(masses, corr)
    return RotorBalance(corr, before[0], before[1], after[0], after[1])
