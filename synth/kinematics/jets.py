"""Closed-form expressions carried with their first and second derivatives in the crank angle.

A jet is a value with its two analogues, ``(value, d/dphi, d²/dphi²)``, over all crank angles at once: a scalar
jet holds arrays of shape (N,), a vector jet (N, 2). Writing a dyad's closed-form position with these operations
gives its velocity and acceleration analogues exactly (the chain rule applied term by term), with no per-angle loop
and no numerical differencing. :class:`~synth.mechanism.PointAnalogues` and
:class:`~synth.mechanism.AngleAnalogues` are jets of this shape.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..mechanism import FloatArray


class Jet(NamedTuple):
    """A value and its first and second derivatives in the crank angle; (N,) for a scalar, (N, 2) for a vector."""

    v: FloatArray
    d1: FloatArray
    d2: FloatArray


def _col(s: FloatArray, like: FloatArray) -> FloatArray:
    """A scalar array shaped to multiply ``like`` (a column for vectors)."""
    return s[:, None] if like.ndim == 2 and s.ndim == 1 else s


def constant(value: FloatArray) -> Jet:
    """A value that does not change with the crank angle."""
    value = np.asarray(value, dtype=float)
    return Jet(value, np.zeros_like(value), np.zeros_like(value))


def add(a: Jet, b: Jet) -> Jet:
    """a + b."""
    return Jet(a.v + b.v, a.d1 + b.d1, a.d2 + b.d2)


def sub(a: Jet, b: Jet) -> Jet:
    """a - b."""
    return Jet(a.v - b.v, a.d1 - b.d1, a.d2 - b.d2)


def scale(c: float, a: Jet) -> Jet:
    """c·a for a constant c."""
    return Jet(c * a.v, c * a.d1, c * a.d2)


def shift(a: Jet, c: float) -> Jet:
    """a + c for a constant scalar c."""
    return Jet(a.v + c, a.d1, a.d2)


def mul(s: Jet, x: Jet) -> Jet:
    """s·x for a scalar jet s and a scalar or vector jet x (product rule)."""
    sv, s1, s2 = _col(s.v, x.v), _col(s.d1, x.v), _col(s.d2, x.v)
    return Jet(sv * x.v, s1 * x.v + sv * x.d1, s2 * x.v + 2 * s1 * x.d1 + sv * x.d2)


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
    def d(x: FloatArray, y: FloatArray) -> FloatArray:
        return np.asarray(x[:, 0] * y[:, 0] + x[:, 1] * y[:, 1])
    return Jet(d(a.v, b.v), d(a.d1, b.v) + d(a.v, b.d1), d(a.d2, b.v) + 2 * d(a.d1, b.d1) + d(a.v, b.d2))


def cross(a: Jet, b: Jet) -> Jet:
    """z-component of a × b of vector jets."""
    def c(x: FloatArray, y: FloatArray) -> FloatArray:
        return np.asarray(x[:, 0] * y[:, 1] - x[:, 1] * y[:, 0])
    return Jet(c(a.v, b.v), c(a.d1, b.v) + c(a.v, b.d1), c(a.d2, b.v) + 2 * c(a.d1, b.d1) + c(a.v, b.d2))


def _perp(x: FloatArray) -> FloatArray:
    out = np.empty_like(x)
    np.negative(x[:, 1], out=out[:, 0])
    out[:, 1] = x[:, 0]
    return out


def perp(a: Jet) -> Jet:
    """The vector jet turned 90 degrees counter-clockwise."""
    return Jet(_perp(a.v), _perp(a.d1), _perp(a.d2))


def angle(a: Jet) -> Jet:
    """Direction angle atan2(y, x) of a vector jet [rad]: psi' = (v × v')/|v|², differentiated once more."""
    v, v1, v2 = a
    q = v[:, 0] ** 2 + v[:, 1] ** 2
    c1 = v[:, 0] * v1[:, 1] - v[:, 1] * v1[:, 0]
    c2 = v[:, 0] * v2[:, 1] - v[:, 1] * v2[:, 0]
    d1 = v[:, 0] * v1[:, 0] + v[:, 1] * v1[:, 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        return Jet(np.arctan2(v[:, 1], v[:, 0]), c1 / q, c2 / q - 2 * c1 * d1 / q**2)


def turn(a: Jet, angle: float) -> Jet:
    """A vector jet turned by a constant ``angle`` [rad] counter-clockwise."""
    if angle == 0.0:
        return a
    c, s = math.cos(angle), math.sin(angle)

    def t(x: FloatArray) -> FloatArray:
        out = np.empty_like(x)
        np.subtract(c * x[:, 0], s * x[:, 1], out=out[:, 0])
        np.add(s * x[:, 0], c * x[:, 1], out=out[:, 1])
        return out
    return Jet(t(a.v), t(a.d1), t(a.d2))


def unit(theta: Jet) -> Jet:
    """The unit vector at angle ``theta``: u' = theta'·perp(u), u'' = theta''·perp(u) - theta'²·u."""
    if not theta.d1.any() and not theta.d2.any() and theta.v.min() == theta.v.max():
        # A direction fixed in the frame: one cosine and one sine for all the samples.
        n = len(theta.v)
        fixed = np.broadcast_to([math.cos(theta.v[0]), math.sin(theta.v[0])], (n, 2)).copy()
        return Jet(fixed, np.zeros((n, 2)), np.zeros((n, 2)))
    u = np.empty((len(theta.v), 2))
    np.cos(theta.v, out=u[:, 0])
    np.sin(theta.v, out=u[:, 1])
    k = _perp(u)
    t1, t2 = theta.d1[:, None], theta.d2[:, None]
    return Jet(u, t1 * k, t2 * k - t1 * t1 * u)


def rotate(theta: Jet, local: tuple[float, float] | FloatArray, u: Jet | None = None) -> Jet:
    """A constant vector given in a frame at angle ``theta``, seen in the fixed frame; ``u`` is ``unit(theta)``
    when the caller has it already."""
    x, y = float(local[0]), float(local[1])
    u = unit(theta) if u is None else u
    k = perp(u)
    return Jet(x * u.v + y * k.v, x * u.d1 + y * k.d1, x * u.d2 + y * k.d2)
