"""The one Motion object every analysis shares, and the builder that turns position analogues into it."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from ..errors import InvalidInput
from ..mechanism import AngleAnalogues as AngleAnalogues
from ..mechanism import FloatArray
from ..mechanism import PointAnalogues as PointAnalogues


class PointState(NamedTuple):
    """Position [m], velocity [m/s] and acceleration [m/s²] of a point, each (N, 2)."""

    pos: FloatArray
    vel: FloatArray
    acc: FloatArray


def perp(v: FloatArray) -> FloatArray:
    """Vectors turned 90 degrees counter-clockwise (k × v), shape (..., 2)."""
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


_ONES2 = np.ones(2)


def unit(angle: FloatArray) -> np.ndarray:
    """Unit vectors at ``angle`` [rad] as complex numbers cos + i·sin, contiguous so that :func:`xy` views them
    as plane vectors (..., 2) without a copy."""
    e = np.empty(np.shape(angle) + (2,))
    np.cos(angle, out=e[..., 0])
    np.sin(angle, out=e[..., 1])
    return e.view(np.complex128)[..., 0]


def xy(z: np.ndarray) -> FloatArray:
    """Complex plane vectors as real ones (..., 2), a view of the same memory (a copy if ``z`` is strided)."""
    z = np.ascontiguousarray(z)
    return z.view(np.float64).reshape(z.shape + (2,))


def complex_of(v: FloatArray) -> np.ndarray:
    """Plane vectors (..., 2) as complex numbers x + i·y (a view when ``v`` is contiguous)."""
    v = np.ascontiguousarray(v, dtype=np.float64)
    return v.view(np.complex128)[..., 0]


def cross_c(a: np.ndarray, b: np.ndarray) -> FloatArray:
    """z-component of a × b for complex plane vectors: Im(conj(a)·b)."""
    return np.asarray((a.conj() * b).imag)


def dot_c(a: np.ndarray, b: np.ndarray) -> FloatArray:
    """Scalar product of complex plane vectors: Re(conj(a)·b)."""
    return np.asarray((a.conj() * b).real)


def dot(a: FloatArray, b: FloatArray) -> FloatArray:
    """Scalar products of stacked plane vectors, shape (...,): one product and one matrix-vector sum, where a
    generic contraction (einsum) would walk the small last axis element by element."""
    return np.asarray((a * b) @ _ONES2)


def magnitude(v: FloatArray) -> FloatArray:
    """Lengths of stacked plane vectors (...,): √(x² + y²), several times faster than ``np.hypot``; where a square
    overflows (lengths beyond 1e154) ``np.hypot`` answers instead."""
    out = np.sqrt(dot(v, v))
    if not np.isfinite(out).all():
        out = np.asarray(np.hypot(v[..., 0], v[..., 1]))
    return out


def cross(a: FloatArray, b: FloatArray) -> FloatArray:
    """z-component of a × b for stacked plane vectors, shape (...,)."""
    return np.asarray(a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0])


@dataclass(frozen=True, slots=True)
class Motion:
    """Kinematics of one linkage over one cycle at N crank angles; SI units; crank angle is axis 0.

    Every link has a frame: origin at its first joint (``link_origin`` names that point), x-axis at
    ``link_angle``. Velocities and accelerations are for crank speed ``omega_crank`` [rad/s] and crank angular
    acceleration ``alpha_crank`` [rad/s²], the same at every sample.
    """

    phi: FloatArray
    omega_crank: float
    alpha_crank: float
    point_pos: Mapping[str, FloatArray]
    point_vel: Mapping[str, FloatArray]
    point_acc: Mapping[str, FloatArray]
    link_angle: Mapping[str, FloatArray]
    link_omega: Mapping[str, FloatArray]
    link_alpha: Mapping[str, FloatArray]
    link_origin: Mapping[str, str]
    # Unit vectors along the links' x-axes (complex, cos + i·sin) where the position solve had them.
    link_unit: Mapping[str, np.ndarray] = field(default_factory=dict)
    # Kinetostatics, the virtual-power check and the reduced model all ask for the same centres of mass; each
    # point is resolved once per motion and handed out read-only so no caller can change another's view of it.
    _states: dict[tuple[str, float, float], PointState] = field(
        default_factory=dict, init=False, repr=False, compare=False
    )

    def __post_init__(self) -> None:
        n = len(self.phi)
        for label, points in (("point_pos", self.point_pos), ("point_vel", self.point_vel), ("point_acc", self.point_acc)):
            if bad := [k for k, a in points.items() if a.shape != (n, 2)]:
                raise InvalidInput(f"{label}: points with wrong shape, expected ({n}, 2): {bad}")
        for label, angles in (("link_angle", self.link_angle), ("link_omega", self.link_omega), ("link_alpha", self.link_alpha)):
            if bad := [k for k, a in angles.items() if a.shape != (n,)]:
                raise InvalidInput(f"{label}: links with wrong shape, expected ({n},): {bad}")
        if missing := [k for k, p in self.link_origin.items() if p not in self.point_pos or k not in self.link_angle]:
            raise InvalidInput(f"links without a frame: {missing}")

    @classmethod
    def derived(cls, phi: FloatArray, omega_crank: float, alpha_crank: float, point_pos: Mapping[str, FloatArray],
                point_vel: Mapping[str, FloatArray], point_acc: Mapping[str, FloatArray],
                link_angle: Mapping[str, FloatArray], link_omega: Mapping[str, FloatArray],
                link_alpha: Mapping[str, FloatArray], link_origin: Mapping[str, str],
                link_unit: Mapping[str, np.ndarray]) -> Motion:
        """A motion made from the arrays of motions already checked (more points on the same links, a block of
        samples): the constructor's shape checks are not repeated (an analysis makes two motions, a batched
        study three per variant)."""
        motion = object.__new__(cls)
        for name, value in (("phi", phi), ("omega_crank", omega_crank), ("alpha_crank", alpha_crank),
                            ("point_pos", point_pos), ("point_vel", point_vel), ("point_acc", point_acc),
                            ("link_angle", link_angle), ("link_omega", link_omega), ("link_alpha", link_alpha),
                            ("link_origin", link_origin), ("link_unit", link_unit), ("_states", {})):
            object.__setattr__(motion, name, value)
        return motion

    @property
    def samples(self) -> int:
        """Number of crank angles N."""
        return len(self.phi)

    def point_on(self, link: str, local: tuple[float, float] | FloatArray) -> PointState:
        """Position, velocity and acceleration of a point fixed in ``link`` at ``local`` (link frame) [m]."""
        x, y = float(local[0]), float(local[1])
        key = (link, x, y)
        if (state := self._states.get(key)) is not None:
            return state
        origin = self.link_origin[link]
        th, w, a = self.link_angle[link], self.link_omega[link], self.link_alpha[link]
        e = self.link_unit.get(link)
        r = (unit(th) if e is None else e) * complex(x, y)
        pos = self.point_pos[origin] + xy(r)
        vel = self.point_vel[origin] + xy((1j * w) * r)
        acc = self.point_acc[origin] + xy((1j * a - w * w) * r)
        for arr in (pos, vel, acc):
            arr.flags.writeable = False
        state = PointState(pos, vel, acc)
        self._states[key] = state
        return state

    def with_points(self, points: Mapping[str, tuple[str, tuple[float, float]]],
                    states: Mapping[str, PointState] | None = None, *, states_checked: bool = False) -> Motion:
        """A copy with named extra points (centres of mass, coupler points): name -> (link, local xy), and
        points whose kinematics the caller has already resolved (``states``: name -> position, velocity,
        acceleration; ``states_checked`` when the caller made them (N, 2) from this motion's own arrays)."""
        pos, vel, acc = dict(self.point_pos), dict(self.point_vel), dict(self.point_acc)
        shape = (self.samples, 2)
        if not states_checked and (
                bad := [k for k, s in (states or {}).items() if any(a.shape != shape for a in s)]):
            raise InvalidInput(f"points with wrong shape, expected {shape}: {bad}")
        for name, state in (states or {}).items():
            pos[name], vel[name], acc[name] = state
        for name, (link, local) in points.items():
            pos[name], vel[name], acc[name] = self.point_on(link, local)
        moved = Motion.derived(
            self.phi, self.omega_crank, self.alpha_crank, pos, vel, acc,
            self.link_angle, self.link_omega, self.link_alpha, self.link_origin, self.link_unit,
        )
        moved._states.update(self._states)  # same links, same frames: every resolved point still holds
        return moved


def build_motion(
    phi: FloatArray,
    omega: float,
    alpha: float,
    points: Mapping[str, PointAnalogues],
    angles: Mapping[str, AngleAnalogues],
    origins: Mapping[str, str],
) -> Motion:
    """Motion from position analogues: v = w·dr/dphi, a = w²·d²r/dphi² + eps·dr/dphi (seed 001:966-1006)."""
    def acceleration(d1: FloatArray, d2: FloatArray) -> FloatArray:
        return omega**2 * d2 + alpha * d1 if alpha else omega**2 * d2

    # The mechanisms' own solvers made these arrays over ``phi``: the constructor's shape checks, meant for
    # motions made by hand, are not repeated on every analysis.
    return Motion.derived(
        phi, float(omega), float(alpha),
        {k: p.pos for k, p in points.items()},
        {k: omega * p.d1 for k, p in points.items()},
        {k: acceleration(p.d1, p.d2) for k, p in points.items()},
        {k: a.angle for k, a in angles.items()},
        {k: omega * a.d1 for k, a in angles.items()},
        {k: acceleration(a.d1, a.d2) for k, a in angles.items()},
        dict(origins),
        {k: a.unit for k, a in angles.items() if a.unit is not None},
    )


def crank_point(length: float, phi: FloatArray) -> PointAnalogues:
    """Crank pin at ``length`` [m] from the origin: position and analogues."""
    pin = length * unit(phi)
    return PointAnalogues(xy(pin), xy(1j * pin), xy(-pin))


def fixed_point(xy: tuple[float, float], n: int) -> PointAnalogues:
    """A frame point [m] repeated over N samples, with zero analogues."""
    # Read-only views of one row each: a point that stands still costs no memory per sample.
    zero = _repeated(np.zeros(2), n)
    return PointAnalogues(_repeated(np.array(xy, dtype=float), n), zero, zero)


def _repeated(row: FloatArray, n: int) -> FloatArray:
    """``row`` (2,) as a read-only (n, 2) view with stride 0 (np.broadcast_to's result in one call)."""
    view = np.ndarray((n, 2), dtype=float, buffer=row, strides=(0, row.itemsize))
    view.flags.writeable = False
    return view


def constant_angle(value: float, n: int) -> AngleAnalogues:
    """A link that does not turn (a slider, a ram)."""
    unit = np.full(n, complex(np.cos(value), np.sin(value)))
    return AngleAnalogues(np.full(n, float(value)), np.zeros(n), np.zeros(n), unit)
