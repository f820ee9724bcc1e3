"""Standard motion laws of a cam follower and the follower's program over one turn of the cam.

A law is a normalised rise f(u) from f(0) = 0 to f(1) = 1 over u in [0, 1] with its first three derivatives. A rise
of lift h over cam angle beta gives s = h f(theta/beta), ds/dtheta = h f'/beta, d2s/dtheta2 = h f''/beta**2 and
d3s/dtheta3 = h f'''/beta**3; a return is h (1 - f). Every law starts and ends at rest (f'(0) = f'(1) = 0); all but
the simple harmonic law also start and end with zero acceleration, so they join dwells without a jump in
acceleration.

The laws built from sine ramps and constant pieces (modified trapezoid, modified sine) are integrated in closed form
piece by piece (:class:`_SinePieces`), and their amplitude is the one that makes f(1) = 1; their peak acceleration
coefficients (4.888 and 5.528) come out of that normalisation rather than being typed in.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from ..errors import InvalidInput
from ..model import FloatArray

LawName = Literal["cycloidal", "simple_harmonic", "polynomial_345", "polynomial_4567", "modified_trapezoid",
                  "modified_sine", "optimised"]
STANDARD_LAWS: tuple[LawName, ...] = ("cycloidal", "simple_harmonic", "polynomial_345", "polynomial_4567",
                                      "modified_trapezoid", "modified_sine")
SegmentKind = Literal["dwell", "rise", "return"]
#: f, f', f'', f''' at normalised angles u, each shaped like u.
Derivatives = tuple[FloatArray, FloatArray, FloatArray, FloatArray]
NormalisedLaw = Callable[[FloatArray], Derivatives]

_TWO_PI = 2.0 * math.pi


def _cycloidal(u: FloatArray) -> Derivatives:
    w = _TWO_PI * u
    return (u - np.sin(w) / _TWO_PI, 1.0 - np.cos(w), _TWO_PI * np.sin(w), _TWO_PI**2 * np.cos(w))


def _simple_harmonic(u: FloatArray) -> Derivatives:
    w = math.pi * u
    return (0.5 * (1.0 - np.cos(w)), 0.5 * math.pi * np.sin(w), 0.5 * math.pi**2 * np.cos(w),
            -0.5 * math.pi**3 * np.sin(w))


def _polynomial(coefficients: dict[int, float]) -> NormalisedLaw:
    """f(u) = sum c_k u**k with its derivatives."""
    def law(u: FloatArray) -> Derivatives:
        out = [np.zeros_like(u) for _ in range(4)]
        for k, c in coefficients.items():
            for d in range(4):
                if k - d >= 0:
                    out[d] = out[d] + c * math.perm(k, d) * u ** (k - d)
        return out[0], out[1], out[2], out[3]
    return law


@dataclass(frozen=True)
class _SinePieces:
    """An acceleration made of pieces a(t) = A + B sin(w t) + C cos(w t), t measured from each piece's start,
    integrated in closed form and scaled so that f(1) = 1."""

    breaks: tuple[float, ...]                        # piece starts, then 1.0
    pieces: tuple[tuple[float, float, float, float], ...]   # (A, B, C, w) per piece, amplitude 1
    start: FloatArray = field(init=False)            # f and f' at each piece's start, amplitude 1
    scale: float = field(init=False)

    def __post_init__(self) -> None:
        f, v = 0.0, 0.0
        starts = []
        for (t0, t1), piece in zip(zip(self.breaks[:-1], self.breaks[1:]), self.pieces):
            starts.append((f, v))
            fe, ve, _, _ = self._integrate(piece, np.array([t1 - t0]), f, v)
            f, v = float(fe[0]), float(ve[0])
        object.__setattr__(self, "start", np.array(starts))
        object.__setattr__(self, "scale", 1.0 / f)

    @staticmethod
    def _integrate(piece: tuple[float, float, float, float], t: FloatArray, f0: float, v0: float) -> Derivatives:
        A, B, C, w = piece
        s, c = np.sin(w * t), np.cos(w * t)
        a = A + B * s + C * c
        j = B * w * c - C * w * s
        v = v0 + A * t + B * (1.0 - c) / w + C * s / w
        f = f0 + v0 * t + 0.5 * A * t**2 + B * (t / w - s / w**2) + C * (1.0 - c) / w**2
        return f, v, a, j

    def __call__(self, u: FloatArray) -> Derivatives:
        edges = np.asarray(self.breaks)
        k = np.clip(np.searchsorted(edges, u, side="right") - 1, 0, len(self.pieces) - 1)
        out = [np.empty_like(u) for _ in range(4)]
        for i, piece in enumerate(self.pieces):
            mask = k == i
            if mask.any():
                parts = self._integrate(piece, u[mask] - edges[i], float(self.start[i, 0]), float(self.start[i, 1]))
                for d in range(4):
                    out[d][mask] = parts[d] * self.scale
        return out[0], out[1], out[2], out[3]


_FOUR_PI = 4.0 * math.pi
# Modified trapezoid: sine ramps over the first, fourth, fifth and eighth eighths, constant acceleration between.
_MODIFIED_TRAPEZOID = _SinePieces(
    (0.0, 0.125, 0.375, 0.625, 0.875, 1.0),
    ((0.0, 1.0, 0.0, _FOUR_PI), (1.0, 0.0, 0.0, 1.0), (0.0, 0.0, 1.0, _FOUR_PI), (-1.0, 0.0, 0.0, 1.0),
     (0.0, 0.0, -1.0, _FOUR_PI)))
# Modified sine: a quarter-wave of period 1/2 up to the peak, a sine of period 3/2 through the middle, and a
# quarter-wave of period 1/2 back to zero.
_MODIFIED_SINE = _SinePieces(
    (0.0, 0.125, 0.875, 1.0),
    ((0.0, 1.0, 0.0, _FOUR_PI), (0.0, 0.0, 1.0, _FOUR_PI / 3.0), (0.0, 0.0, -1.0, _FOUR_PI)))

LAWS: dict[str, NormalisedLaw] = {
    "cycloidal": _cycloidal,
    "simple_harmonic": _simple_harmonic,
    "polynomial_345": _polynomial({3: 10.0, 4: -15.0, 5: 6.0}),
    "polynomial_4567": _polynomial({4: 35.0, 5: -84.0, 6: 70.0, 7: -20.0}),
    "modified_trapezoid": _MODIFIED_TRAPEZOID,
    "modified_sine": _MODIFIED_SINE,
}


@dataclass(frozen=True, slots=True)
class LawCoefficients:
    """Peak values of a normalised law: |f'|, |f''|, |f'''| at their largest over u in [0, 1]; a rise of lift h
    over beta [rad] has peak velocity C_v h/beta, acceleration C_a h/beta**2 and jerk C_j h/beta**3."""

    name: str
    velocity: float
    acceleration: float
    jerk: float


def law_coefficients(name: str, samples: int = 20001) -> LawCoefficients:
    """The peak velocity, acceleration and jerk coefficients of a standard law, from a dense sampling of its
    closed form (exact to the sampling: every peak of these laws lies on a sample of a grid of 8k+1 points)."""
    u = np.linspace(0.0, 1.0, samples)
    _, v, a, j = LAWS[name](u)
    return LawCoefficients(name, float(np.max(np.abs(v))), float(np.max(np.abs(a))), float(np.max(np.abs(j))))


@dataclass(frozen=True, slots=True)
class Segment:
    """One part of the follower's program: a dwell, or a rise or return of ``lift`` (m, or rad for an
    oscillating follower) over ``angle`` [rad] of cam turn by law ``law``; ``shape`` is the normalised law an
    optimised segment was given."""

    kind: SegmentKind
    angle: float
    lift: float = 0.0
    law: LawName = "cycloidal"
    shape: NormalisedLaw | None = None

    def normalised(self) -> NormalisedLaw:
        """The normalised law of a rise or return."""
        if self.shape is not None:
            return self.shape
        if self.law == "optimised":
            raise InvalidInput("an optimised law needs its solved shape", field="law")
        return LAWS[self.law]


@dataclass(frozen=True, slots=True)
class FollowerMotion:
    """The follower's displacement s over one turn and its derivatives per radian of cam angle, at N angles."""

    theta: FloatArray   # cam angle [rad], (N,)
    s: FloatArray       # displacement [m] or [rad], (N,)
    v: FloatArray       # ds/dtheta
    a: FloatArray       # d2s/dtheta2
    j: FloatArray       # d3s/dtheta3
    segment: np.ndarray  # index of the segment each angle lies in, (N,)
    bounds: FloatArray  # start angle of each segment, then 2 pi [rad]


TURN_TOLERANCE = 1e-6


def check_segments(segments: Sequence[Segment]) -> None:
    """The program closes the turn: angles sum to 2 pi, rises and returns have an angle and a lift, and the
    follower ends where it started."""
    if not segments:
        raise InvalidInput("the program needs at least one segment", field="segments")
    for i, seg in enumerate(segments):
        if not seg.angle > 0.0:
            raise InvalidInput(f"segment {i} ({seg.kind}) has no angle", field=f"segments.{i}.angle_deg")
        if seg.kind != "dwell" and not seg.lift > 0.0:
            raise InvalidInput(f"segment {i} ({seg.kind}) has no lift", field=f"segments.{i}")
    total = sum(seg.angle for seg in segments)
    if abs(total - _TWO_PI) > TURN_TOLERANCE:
        raise InvalidInput(f"the segments cover {math.degrees(total):.6g} deg of cam turn, not 360 deg",
                           field="segments", code="turn_not_closed")
    height = 0.0
    for seg in segments:
        height += seg.lift if seg.kind == "rise" else -seg.lift if seg.kind == "return" else 0.0
        if height < -1e-12 * max(1.0, max(s.lift for s in segments)):
            raise InvalidInput("a return takes the follower below its lowest position", field="segments")
    if abs(height) > 1e-9 * max(s.lift for s in segments) + 1e-15:
        raise InvalidInput(f"rises and returns do not bring the follower back: it ends {height:.6g} above its "
                           "start", field="segments", code="lift_not_closed")


def follower_motion(segments: Sequence[Segment], theta: FloatArray) -> FollowerMotion:
    """The follower's program evaluated at cam angles ``theta`` [rad] in [0, 2 pi), vectorised per segment."""
    check_segments(segments)
    bounds = np.concatenate([[0.0], np.cumsum([seg.angle for seg in segments])])
    bounds[-1] = _TWO_PI
    index = np.clip(np.searchsorted(bounds, np.mod(theta, _TWO_PI), side="right") - 1, 0, len(segments) - 1)
    s, v, a, j = (np.zeros_like(theta) for _ in range(4))
    base = 0.0
    for i, seg in enumerate(segments):
        mask = index == i
        if seg.kind == "dwell":
            s[mask] = base
            continue
        u = (np.mod(theta[mask], _TWO_PI) - bounds[i]) / seg.angle
        f, f1, f2, f3 = seg.normalised()(np.clip(u, 0.0, 1.0))
        sign = 1.0 if seg.kind == "rise" else -1.0
        h, b = seg.lift, seg.angle
        s[mask] = base + sign * h * f
        v[mask] = sign * h * f1 / b
        a[mask] = sign * h * f2 / b**2
        j[mask] = sign * h * f3 / b**3
        base += sign * h
    return FollowerMotion(theta, s, v, a, j, index, bounds)
