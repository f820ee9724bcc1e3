"""What every mechanism provides, in the model layer: its topology, link frame origins and a position solve.

The named families and the general linkage of dyads (``synth.kinematics``) all satisfy :class:`Mechanism`; the
model (``synth.model.Linkage``) holds one without importing the kinematics that solve it.
"""

from __future__ import annotations

from typing import Any, NamedTuple, Protocol

import numpy as np
from numpy.typing import NDArray

from .topology import Topology

FloatArray = NDArray[np.float64]


class PointAnalogues(NamedTuple):
    """Position [m] and its first and second derivatives with respect to the crank angle, each (N, 2)."""

    pos: FloatArray
    d1: FloatArray
    d2: FloatArray


class AngleAnalogues(NamedTuple):
    """Link angle [rad] and its first and second derivatives with respect to the crank angle, each (N,); and the
    unit vector along the link's x-axis as complex numbers cos + i·sin (N,), when the position solve has it (it
    saves the kinetostatics a cosine and a sine per link and angle)."""

    angle: FloatArray
    d1: FloatArray
    d2: FloatArray
    unit: NDArray[Any] | None = None


class Mechanism(Protocol):
    """What a mechanism provides: its family name, topology, link frame origins and a vectorised position solve."""

    @property
    def family(self) -> str:
        """Family name: ``fourbar``, ``slider_crank``, ``slotted_lever`` or ``linkage``."""
        ...

    @property
    def topology(self) -> Topology:
        """Links, joints, the crank and the output member."""
        ...

    @property
    def origins(self) -> dict[str, str]:
        """Link -> the point where its frame has its origin (its first joint)."""
        ...

    @property
    def crank(self) -> float:
        """Crank length [m]: every mechanism is driven by one, and it sets the scale of its inertias."""
        ...

    def solve(self, phi: FloatArray) -> tuple[dict[str, PointAnalogues], dict[str, AngleAnalogues]]:
        """Joint positions and link angles with their first and second analogues over ``phi`` [rad]."""
        ...


__all__ = ["AngleAnalogues", "FloatArray", "Mechanism", "PointAnalogues"]
