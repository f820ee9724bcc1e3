"""Mechanisms (the named families and any linkage of dyads), each producing the same Motion object, vectorised
over crank angles."""

from __future__ import annotations

import math

import numpy as np

from ..errors import InvalidInput, TooLarge
from ..mechanism import FloatArray, Mechanism
from .fourbar import FourBar, transmission_angle
from .linkage import JointSpec, LinkSpec, PlanarLinkage, linkage_structure
from .motion import Motion, PointState, build_motion
from .slider_crank import SliderCrank
from .slotted_lever import SlottedLever

MAX_SAMPLES = 100_000


def cycle_angles(samples: int, cycle: float = 2 * math.pi, max_samples: int = MAX_SAMPLES) -> FloatArray:
    """Uniform grid of ``samples`` crank angles over one cycle [rad], endpoint excluded."""
    if samples < 3:
        raise InvalidInput(f"samples must be at least 3, got {samples}", field="samples")
    if samples > max_samples:
        raise TooLarge("samples per cycle", max_samples, samples, field="samples")
    # np.linspace's own arithmetic for this grid (index times step), without its Python-level checks
    return np.arange(samples, dtype=float) * (cycle / samples)


def motion(mechanism: Mechanism, phi: FloatArray, omega: float, alpha: float = 0.0) -> Motion:
    """Motion of ``mechanism`` at crank angles ``phi`` [rad], crank speed ``omega`` [rad/s], acceleration [rad/s²].

    Raises NotAssemblable with the failing angle ranges where the loop does not close.
    """
    phi = np.asarray(phi, dtype=float).reshape(-1)
    if phi.size == 0:
        raise InvalidInput("at least one crank angle is needed", field="crank_angle_deg")
    if not np.isfinite(phi).all():
        raise InvalidInput("crank angles must be finite", field="crank_angle_deg")
    if not (math.isfinite(omega) and omega > 0):
        raise InvalidInput(f"crank speed must be positive, got {omega!r} rad/s", field="speed_rpm")
    if not math.isfinite(alpha):
        raise InvalidInput("crank angular acceleration must be finite", field="crank_acceleration_rad_s2")
    points, angles = mechanism.solve(phi)
    return build_motion(phi, omega, alpha, points, angles, mechanism.origins)


__all__ = [
    "FourBar",
    "JointSpec",
    "LinkSpec",
    "PlanarLinkage",
    "SliderCrank",
    "SlottedLever",
    "Mechanism",
    "Motion",
    "PointState",
    "cycle_angles",
    "linkage_structure",
    "motion",
    "transmission_angle",
]
