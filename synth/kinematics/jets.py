"""Closed-form expressions carried with their first and second derivatives in the crank angle.

A jet is a value with its two analogues, ``(value, d/dphi, d²/dphi²)``, over all crank angles at once: a scalar
jet holds real arrays of shape (N,), a vector jet complex ones (N,), x + i·y, so that every vector operation is one
array operation over contiguous memory and a turn is a product. Writing a dyad's closed-form position with these
operations gives its velocity and acceleration analogues exactly (the chain rule applied term by term), with no
per-angle loop and no numerical differencing. :func:`analogues` turns a vector jet into the (N, 2) arrays of
:class:`~synth.mechanism.PointAnalogues` without a copy.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from ..mechanism import FloatArray, PointAnalogues
from .motion import cross_c as _cross
from .motion import dot_c as _dot

Values = NDArray[Any]   # real (scalar jets) or complex (vector jets)


class Jet(NamedTuple):
    """A value and its first and second derivatives in the crank angle; real (N,) for a scalar, complex (N,) for a
    plane vector."""

    v: Values
    d1: Values
    d2: Values


def point(xy: tuple[float, float], n: int) -> Jet:
    """A point fixed in the frame at ``xy`` [m], over N samples."""
    return Jet(np.full(n, complex(xy[0], xy[1])), np.zeros(n, dtype=complex), np.zeros(n, dtype=complex))


def analogues(a: Jet) -> PointAnalogues:
    """A vector jet as position analogues, each (N, 2): views of the complex arrays."""
    def real(z: FloatArray) -> FloatArray:
        z = np.ascontiguousarray(z, dtype=complex)
        return z.view(np.float64).reshape(-1, 2)
    return PointAnalogues(real(a.v), real(a.d1), real(a.d2))


def constant(value: FloatArray) -> Jet:
    """A value that does not change with the crank angle."""
    value = np.asarray(value)
    return Jet(value, np.zeros_like(value), np.zeros_like(value))


def add(a: Jet, b: Jet) -> Jet:
    """a + b."""
    return Jet(a.v + b.v, a.d1 + b.d1, a.d2 + b.d2)


def sub(a: Jet, b: Jet) -> Jet:
    """a - b."""
    return Jet(a.v - b.v, a.d1 - b.d1, a.d2 - b.d2)


def scale(c: float | complex, a: Jet) -> Jet:
    """c·a for a constant c (a complex c turns and stretches a vector jet)."""
    return Jet(c * a.v, c * a.d1, c * a.d2)


def shift(a: Jet, c: float) -> Jet:
    """a + c for a constant scalar c."""
    return Jet(a.v + c, a.d1, a.d2)


def mul(s: Jet, x: Jet) -> Jet:
    """s·x for a scalar jet s and a scalar or vector jet x (product rule)."""
    return Jet(s.v * x.v, s.d1 * x.v + s.v * x.d1, s.d2 * x.v + 2 * s.d1 * x.d1 + s.v * x.d2)


def div(a: Jet, b: Jet) -> Jet:
    """a / b for scalar jets (quotient rule)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        q = a.v / b.v
        q1 = (a.d1 - q * b.d1) / b.v
        q2 = (a.d2 - 2 * q1 * b.d1 - q * b.d2) / b.v
    return Jet(q, q1, q2)


def sqrt(a: Jet) -> Jet:
    """√a of a scalar jet; negative values (a loop that cannot close) are taken as zero, and flagged by callers."""
    r = np.sqrt(np.clip(a.v, 0.0, None))
    with np.errstate(divide="ignore", invalid="ignore"):
        r1 = a.d1 / (2 * r)
        r2 = (a.d2 - 2 * r1 * r1) / (2 * r)
    return Jet(r, r1, r2)


def dot(a: Jet, b: Jet) -> Jet:
    """a·b of vector jets."""
    return Jet(_dot(a.v, b.v), _dot(a.d1, b.v) + _dot(a.v, b.d1),
               _dot(a.d2, b.v) + 2 * _dot(a.d1, b.d1) + _dot(a.v, b.d2))


def cross(a: Jet, b: Jet) -> Jet:
    """z-component of a × b of vector jets."""
    return Jet(_cross(a.v, b.v), _cross(a.d1, b.v) + _cross(a.v, b.d1),
               _cross(a.d2, b.v) + 2 * _cross(a.d1, b.d1) + _cross(a.v, b.d2))


def perp(a: Jet) -> Jet:
    """The vector jet turned 90 degrees counter-clockwise."""
    return scale(1j, a)


def angle(a: Jet) -> Jet:
    """Direction angle atan2(y, x) of a vector jet [rad]: psi' = (v × v')/|v|², differentiated once more."""
    v, v1, v2 = a
    q = _dot(v, v)
    c1, c2, d1 = _cross(v, v1), _cross(v, v2), _dot(v, v1)
    with np.errstate(divide="ignore", invalid="ignore"):
        return Jet(np.angle(v), c1 / q, c2 / q - 2 * c1 * d1 / q**2)


def turn(a: Jet, angle: float) -> Jet:
    """A vector jet turned by a constant ``angle`` [rad] counter-clockwise."""
    if angle == 0.0:
        return a
    return scale(complex(math.cos(angle), math.sin(angle)), a)


def unit(theta: Jet) -> Jet:
    """The unit vector at angle ``theta``: u' = theta'·i·u, u'' = (theta''·i - theta'²)·u."""
    n = len(theta.v)
    if not theta.d1.any() and not theta.d2.any() and theta.v.min() == theta.v.max():
        # A direction fixed in the frame: one cosine and one sine for all the samples.
        return Jet(np.full(n, complex(math.cos(theta.v[0]), math.sin(theta.v[0]))), np.zeros(n, dtype=complex),
                   np.zeros(n, dtype=complex))
    u = np.empty((n, 2))
    np.cos(theta.v, out=u[:, 0])
    np.sin(theta.v, out=u[:, 1])
    e = u.view(np.complex128)[:, 0]
    return Jet(e, (1j * theta.d1) * e, (1j * theta.d2 - theta.d1 * theta.d1) * e)


def rotate(theta: Jet, local: tuple[float, float] | FloatArray, u: Jet | None = None) -> Jet:
    """A constant vector given in a frame at angle ``theta``, seen in the fixed frame; ``u`` is ``unit(theta)``
    when the caller has it already."""
    u = unit(theta) if u is None else u
    return scale(complex(float(local[0]), float(local[1])), u)
