"""Roberts-Chebyshev cognates: the two other four-bars whose coupler point traces the same curve, in closed form.

With the crank pivot O_A, the rocker pivot O_B, crank r1 = A - O_A, coupler r2 = B - A, rocker r3 = B - O_B and the
coupler point P = A + w·r2 (w complex, fixed by the coupler triangle), the loop r1 + r2 = (O_B - O_A) + r3 gives

    P = O_C + (1 - w)·r1 + w·r3,    O_C = O_A + w·(O_B - O_A)

so a third ground pivot O_C (the triangle O_A O_B O_C similar to A B P) carries two more four-bars through P
(Hartenberg and Denavit, Kinematic Synthesis of Linkages, 1964, section 6.7; Roberts' law):

- on O_C and O_B: crank O_C H = (1 - w)·r1 turning with the original crank, coupler H J = (w - 1)·r3, rocker
  O_B J = (w - 1)·r2, P = H + w·r3; its links are those of the original scaled by |1 - w|;
- on O_A and O_C: driver O_A D = w·r2 turning with the original coupler, coupler D F = w·r1, rocker
  O_C F = w·r3, P = D + r1; its links are those of the original scaled by |w|.

The first is driven in step with the original crank, so it traces the whole curve at the same crank angles
shifted by arg(1 - w); the second's driver swings with the original coupler.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..kinematics import FourBar
from ..model import FloatArray


@dataclass(frozen=True, slots=True)
class Cognate:
    """A four-bar placed in the plane: ``fourbar`` in its own frame, its driving pivot ``crank_pivot`` [m] and
    ground direction ``ground_angle`` [rad] in the targets' frame, the coupler point in its coupler frame [m] and
    its driver's angle at each of the original's configurations [rad]; ``driven_by``: which link of the original
    its driver turns with (``crank`` or ``coupler``)."""

    fourbar: FourBar
    crank_pivot: tuple[float, float]
    ground_angle: float
    coupler_point: tuple[float, float]
    crank_angles: FloatArray
    driven_by: str


def _placed(driver_pivot: complex, other_pivot: complex, pin: FloatArray, other_pin: FloatArray, point: FloatArray,
            driven_by: str) -> Cognate:
    """The four-bar with driver ``driver_pivot``-``pin``, coupler ``pin``-``other_pin``, rocker
    ``other_pivot``-``other_pin`` and coupler point ``point`` (complex positions, one per configuration)."""
    ground = other_pivot - driver_pivot
    theta = math.atan2(ground.imag, ground.real)
    coupler = other_pin[0] - pin[0]
    local = (point[0] - pin[0]) * np.conj(coupler) / abs(coupler)
    # Branch +1 when B lies to the left of the directed line A -> Q (the project's convention).
    side = (np.conj(other_pivot - pin[0]) * coupler).imag
    fb = FourBar(float(abs(ground)), float(abs(pin[0] - driver_pivot)), float(abs(coupler)),
                 float(abs(other_pin[0] - other_pivot)), 1 if side > 0 else -1)
    angles = np.mod(np.angle(pin - driver_pivot) - theta, 2 * math.pi)
    return Cognate(fb, (driver_pivot.real, driver_pivot.imag), theta, (float(local.real), float(local.imag)),
                   np.asarray(angles), driven_by)


def cognates(fb: FourBar, crank_pivot: tuple[float, float], ground_angle: float, coupler_point: tuple[float, float],
             crank_angles: FloatArray) -> tuple[Cognate, Cognate]:
    """The two cognates of ``fb`` placed at ``crank_pivot`` [m] with ground direction ``ground_angle`` [rad] and
    coupler point ``coupler_point`` [m] (coupler frame), at its crank angles ``crank_angles`` [rad]: first the
    one driven in step with the crank, then the one whose driver turns with the coupler."""
    o_a = complex(*crank_pivot)
    turn = np.exp(1j * ground_angle)
    o_b = o_a + fb.ground * turn
    _, links = fb.solve(np.asarray(crank_angles, dtype=float))
    a = o_a + fb.crank * np.exp(1j * (ground_angle + np.asarray(crank_angles)))
    b = a + fb.coupler * np.exp(1j * (ground_angle + links["coupler"].angle))
    w = complex(*coupler_point) / fb.coupler
    p = a + w * (b - a)
    o_c = o_a + w * (o_b - o_a)
    r1, r2, r3 = a - o_a, b - a, b - o_b
    h, j = o_c + (1 - w) * r1, o_b + (w - 1) * r2
    d, f = o_a + w * r2, o_c + w * r3
    return (_placed(o_c, o_b, h, j, p, "crank"), _placed(o_a, o_c, d, f, p, "coupler"))
