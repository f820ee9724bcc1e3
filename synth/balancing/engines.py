"""Engines of several cylinders: slider-cranks on one crankshaft, in line or in V, and their shaking by orders.

The crankshaft lies along z. Angles in the transverse plane are measured from the vertical (+y) in the crank's
direction of rotation, so a direction alpha is the unit vector (sin alpha, cos alpha) and, written as the complex
number y + i·x, it is exp(i·alpha): a vector turning with the crank is a forward (co-rotating) term exp(+i·k·phi),
one turning against it a backward term exp(-i·k·phi).

Cylinder j has its throw ``crank_phase`` behind the first (throw at phi - gamma_j), its axis at ``bank_angle``
(alpha = beta_j) and its plane at z_j. Its piston sits at s(theta) = r·cos(theta) + sqrt(l² - r²·sin²(theta))
from the crank axis, theta = phi - gamma_j - beta_j, and at constant speed its inertia force is
-m_rec·w²·s''(theta) along its axis (exact, every order); the rotating mass at the crank pin adds m_rot·r·w²
along the throw. The shaking force is the sum, the shaking moment about the transverse axes the sum of z_j times
each (M_x = -C_y, M_y = C_x with C = sum z_j·F_j, about z = ``reference_z``). Every crank order k of both comes
from one FFT over a revolution: each order's vector traces an ellipse, the sum of a forward and a backward circle;
a mass on a shaft turning at +k·w cancels the forward circle, one on a shaft turning at -k·w the backward one
(two counter-rotating shafts at k·w for a reciprocating order, seed 003 (6.32)-(6.33); the crank's own
counterweight for the forward first order), and the same as couples (a pair of masses a distance apart along the
shaft) for the moment.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import InvalidInput, TooLarge
from ..model import FloatArray

#: Largest cylinder count and order count accepted.
MAX_CYLINDERS = 64
MAX_ORDERS = 24
# Samples per revolution of the FFT: a power of two well above twice the highest order, so that orders beyond
# the reported ones (the exact acceleration's series falls as (r/l)^k) cannot alias into them.
SAMPLES = 512


@dataclass(frozen=True, slots=True)
class Cylinder:
    """One cylinder: its throw's phase behind the first [rad], its axis' bank angle from the vertical [rad] and
    its plane's position along the crankshaft [m]."""

    crank_phase: float
    bank_angle: float = 0.0
    axial_position: float = 0.0


@dataclass(frozen=True, slots=True)
class EngineSpec:
    """Crank radius r and rod length l [m], reciprocating mass (piston, pin, rod's share) and rotating mass at the
    crank pin (rod's share, pin) per cylinder [kg], crank speed [rad/s] and the cylinders."""

    crank_radius: float
    rod_length: float
    reciprocating_mass: float
    rotating_mass: float
    speed: float
    cylinders: tuple[Cylinder, ...]
    orders: int = 6
    reference_z: float | None = None

    def validate(self) -> None:
        """InvalidInput naming the field for a geometry that does not assemble or counts out of range."""
        if not (0 < self.crank_radius < self.rod_length):
            raise InvalidInput("the crank radius must be positive and shorter than the rod", field="crank_radius_m")
        if self.reciprocating_mass < 0 or self.rotating_mass < 0:
            raise InvalidInput("masses must not be negative", field="reciprocating_mass_kg")
        if not self.speed > 0:
            raise InvalidInput("the crank speed must be positive", field="speed_rpm")
        if not self.speed**2 >= sys.float_info.min:
            # the inertia forces go as speed²: below this they underflow and the orders' mass·radius is 0/0
            raise InvalidInput(f"the crank speed {self.speed:g} rad/s is too small to compute with (its square "
                               "underflows): give it in rpm as turning", field="speed_rpm")
        if not self.cylinders:
            raise InvalidInput("an engine needs at least one cylinder", field="cylinders")
        if len(self.cylinders) > MAX_CYLINDERS:
            raise TooLarge("cylinders", MAX_CYLINDERS, len(self.cylinders))
        if not 1 <= self.orders <= MAX_ORDERS:
            raise InvalidInput(f"orders must lie in 1..{MAX_ORDERS}", field="orders")


@dataclass(frozen=True, slots=True)
class OrderShaking:
    """One crank order k of the shaking force [N] or moment [N·m].

    ``forward`` and ``backward`` the complex amplitudes of the circles turning with and against the crank (as
    y + i·x); ``largest`` and ``smallest`` the ellipse's half axes |P| + |Q| and ||P| - |Q||; ``forward_mr`` and
    ``backward_mr`` the mass·radius [kg·m] (for a moment mass·radius·spacing [kg·m²]) a shaft at ±k·w must carry
    to cancel each, at the angle ``forward_angle`` / ``backward_angle`` [rad] (from the vertical, in the sense
    of rotation, at phi = 0).
    """

    order: int
    forward: complex
    backward: complex
    largest: float
    smallest: float
    forward_mr: float
    backward_mr: float
    forward_angle: float
    backward_angle: float


@dataclass(frozen=True, slots=True)
class EngineShaking:
    """Shaking force and moment of an engine over one revolution and by orders, with the checks.

    ``phi`` (N,) crank angles [rad]; ``force`` (N, 2) x, y [N]; ``moment`` (N, 2) M_x, M_y [N·m]; ``force_orders``
    and ``moment_orders`` orders 1..``orders``; ``reconstruction_error`` the largest difference [N] between the
    sampled force and its orders' sum through the highest order resolved (the FFT's check); ``residual_force``
    and ``residual_moment`` the largest force [N] and moment [N·m] left over the revolution once every reported
    order is cancelled by the masses named, evaluated in the time domain from the masses themselves;
    ``balanced_tolerance`` [N] below which an order counts as cancelled.
    """

    spec: EngineSpec
    phi: FloatArray
    force: FloatArray
    moment: FloatArray
    force_orders: tuple[OrderShaking, ...]
    moment_orders: tuple[OrderShaking, ...]
    reconstruction_error: float
    residual_force: float
    residual_moment: float
    remaining_force: float
    remaining_moment: float
    balanced_tolerance: float
    reference_z: float


def piston_acceleration_ratio(theta: FloatArray, lam: float) -> FloatArray:
    """s''(theta)/r of the slider-crank, exact: the piston's acceleration along its axis over r·w² [-]."""
    sin, cos = np.sin(theta), np.cos(theta)
    root = np.sqrt(1 - (lam * sin) ** 2)
    out: FloatArray = -cos - lam * (cos**2 - sin**2) / root - lam**3 * sin**2 * cos**2 / root**3
    return out


def _direction(alpha: FloatArray) -> FloatArray:
    return np.stack([np.sin(alpha), np.cos(alpha)], axis=-1)


def _order(k: int, value: complex, back: complex, w: float) -> OrderShaking:
    scale = (k * w) ** 2
    # a mass·radius mr on a shaft at ±k·w pointing at angle psi pulls with mr·(k·w)² along it: opposite the term
    return OrderShaking(
        order=k, forward=value, backward=back, largest=abs(value) + abs(back), smallest=abs(abs(value) - abs(back)),
        forward_mr=abs(value) / scale, backward_mr=abs(back) / scale,
        forward_angle=float(np.mod(np.angle(-value), 2 * math.pi)),
        backward_angle=float(np.mod(np.angle(-back), 2 * math.pi)),
    )


def _orders(series: FloatArray, count: int, w: float) -> tuple[tuple[OrderShaking, ...], FloatArray]:
    """Forward and backward circles of orders 1..count of an (N, 2) x, y series, and the series rebuilt from
    every order the samples resolve."""
    n = series.shape[0]
    z = series[:, 1] + 1j * series[:, 0]
    spectrum = np.fft.fft(z) / n
    out = tuple(_order(k, complex(spectrum[k]), complex(spectrum[n - k]), w) for k in range(1, count + 1))
    rebuilt = np.fft.ifft(spectrum * n)
    return out, np.stack([rebuilt.imag, rebuilt.real], axis=-1)


def _shaking(spec: EngineSpec, phi: FloatArray, ref: float) -> tuple[FloatArray, FloatArray]:
    r, w = spec.crank_radius, spec.speed
    lam = r / spec.rod_length
    force = np.zeros((phi.size, 2))
    couple = np.zeros((phi.size, 2))
    for c in spec.cylinders:
        throw = phi - c.crank_phase
        f = (-spec.reciprocating_mass * r * w**2 * piston_acceleration_ratio(throw - c.bank_angle, lam))[:, None] \
            * _direction(np.full(phi.size, c.bank_angle))
        f = f + spec.rotating_mass * r * w**2 * _direction(throw)
        force += f
        couple += (c.axial_position - ref) * f
    return force, np.stack([-couple[:, 1], couple[:, 0]], axis=-1)


def _cancel(orders: Sequence[OrderShaking], phi: FloatArray, w: float) -> FloatArray:
    """The x, y pull [N] (or couple [N·m]) of the named masses on shafts at ±k·w over ``phi``, (N, 2)."""
    out = np.zeros((phi.size, 2))
    for o in orders:
        scale = (o.order * w) ** 2
        out += o.forward_mr * scale * _direction(o.forward_angle + o.order * phi)
        out += o.backward_mr * scale * _direction(o.backward_angle - o.order * phi)
    return out


def engine_shaking(spec: EngineSpec) -> EngineShaking:
    """Shaking force and moment of ``spec`` over a revolution, every order to ``spec.orders`` and the masses on
    shafts at ±k·w (the crank's counterweight for the forward first order) that cancel each, with their check."""
    spec.validate()
    z = [c.axial_position for c in spec.cylinders]
    ref = float(np.mean(z)) if spec.reference_z is None else spec.reference_z
    phi = 2 * math.pi * np.arange(SAMPLES) / SAMPLES
    force, moment = _shaking(spec, phi, ref)
    force_orders, force_rebuilt = _orders(force, spec.orders, spec.speed)
    # the moment vector turned back to the couple C (C_x = M_y, C_y = -M_x) so its circles are the couples' own
    couple = np.stack([moment[:, 1], -moment[:, 0]], axis=-1)
    couple_orders, _ = _orders(couple, spec.orders, spec.speed)
    # the check: the named masses' pulls computed from the masses, added to the engine's own shaking, leave only
    # orders beyond the reported ones (and the force's constant part, which a rotating mass cannot make)
    left_force = force + _cancel(force_orders, phi, spec.speed)
    left_couple = couple + _cancel(couple_orders, phi, spec.speed)
    left_f, _ = _orders(left_force, spec.orders, spec.speed)
    left_c, _ = _orders(left_couple, spec.orders, spec.speed)
    scale = spec.reciprocating_mass * spec.crank_radius * spec.speed**2 * len(spec.cylinders) \
        + spec.rotating_mass * spec.crank_radius * spec.speed**2 * len(spec.cylinders)
    return EngineShaking(
        spec=spec, phi=phi, force=force, moment=moment, force_orders=force_orders,
        moment_orders=couple_orders,
        reconstruction_error=float(np.max(np.abs(force_rebuilt - force))),
        residual_force=max(o.largest for o in left_f),
        residual_moment=max(o.largest for o in left_c),
        remaining_force=float(np.max(np.hypot(*left_force.T))),
        remaining_moment=float(np.max(np.hypot(*left_couple.T))),
        balanced_tolerance=1e-9 * max(scale, 1e-300),
        reference_z=ref,
    )


def _inline(phases_deg: Sequence[float], pitch: float) -> tuple[Cylinder, ...]:
    return tuple(Cylinder(math.radians(p), 0.0, i * pitch) for i, p in enumerate(phases_deg))


#: The even firing order of each in-line arrangement as built (four-stroke), cylinders numbered from the first
#: along the shaft: cylinder k fires 720/n degrees of crank after the one before it, so its throw stands that
#: time (mod 360) behind the first's (:func:`firing_throws`).
FIRING_ORDERS: dict[str, tuple[int, ...]] = {
    "inline2_360": (1, 2),
    "inline3": (1, 2, 3),
    "inline4": (1, 3, 4, 2),
    "inline5": (1, 2, 4, 5, 3),
    "inline6": (1, 5, 3, 6, 2, 4),
}


def firing_throws(order: Sequence[int], strokes: int = 4) -> tuple[float, ...]:
    """The throws [rad] behind the first of the cylinders 1..n fired in ``order`` at even intervals of 720/n
    (four-stroke) or 360/n (two-stroke) degrees of crank; InvalidInput unless ``order`` is a permutation of
    1..n."""
    n = len(order)
    if sorted(order) != list(range(1, n + 1)):
        raise InvalidInput(f"a firing order names every cylinder 1..{n} once", field="firing_order")
    if strokes not in (2, 4):
        raise InvalidInput("an engine has two or four strokes", field="strokes")
    interval = (360.0 if strokes == 4 else 180.0) * 2 / n
    start = {cyl: k * interval for k, cyl in enumerate(order)}
    return tuple(math.radians(start[c] % 360.0) for c in range(1, n + 1))


def inline_from_firing_order(order: Sequence[int], pitch: float, strokes: int = 4) -> tuple[Cylinder, ...]:
    """An in-line engine of cylinders ``pitch`` [m] apart with the throws of its even firing ``order``."""
    return tuple(Cylinder(t, 0.0, i * pitch) for i, t in enumerate(firing_throws(order, strokes)))


def engine_layout(name: str, pitch: float = 0.1) -> tuple[Cylinder, ...]:
    """The classic arrangements as built, cylinders ``pitch`` [m] apart along the crankshaft (a V's pair shares
    a throw and a plane), the throws in degrees behind the first (the in-line engines' even firing orders in
    :data:`FIRING_ORDERS`): inline2_360 (0-0, 1-2), inline2_180 (0-180, uneven firing), inline3 (0-240-120,
    1-2-3), inline4 (0-180-180-0, 1-3-4-2), inline5 (0-144-216-288-72, 1-2-4-5-3), inline6 (0-120-240-240-120-0,
    1-5-3-6-2-4), v2_90 (one throw, banks ∓45), v8_crossplane (throws 0-90-270-180, banks ∓45), boxer2 (0-180,
    banks ∓90), flat4 (0-180-180-0, banks alternating ∓90)."""
    layouts: dict[str, tuple[Cylinder, ...]] = {
        "inline2_360": _inline([0, 0], pitch),
        "inline2_180": _inline([0, 180], pitch),
        "inline3": _inline([0, 240, 120], pitch),
        "inline4": _inline([0, 180, 180, 0], pitch),
        "inline5": _inline([0, 144, 216, 288, 72], pitch),
        "inline6": _inline([0, 120, 240, 240, 120, 0], pitch),
        "v2_90": (Cylinder(0.0, math.radians(-45), 0.0), Cylinder(0.0, math.radians(45), 0.0)),
        "v8_crossplane": tuple(
            Cylinder(math.radians(p), math.radians(b), (i // 2) * pitch)
            for i, (p, b) in enumerate([(0, -45), (0, 45), (90, -45), (90, 45), (270, -45), (270, 45),
                                        (180, -45), (180, 45)])),
        "boxer2": (Cylinder(0.0, math.radians(-90), 0.0), Cylinder(math.pi, math.radians(90), pitch)),
        "flat4": (Cylinder(0.0, math.radians(-90), 0.0), Cylinder(math.pi, math.radians(90), pitch),
                  Cylinder(math.pi, math.radians(-90), 2 * pitch), Cylinder(0.0, math.radians(90), 3 * pitch)),
    }
    if name not in layouts:
        raise InvalidInput(f"unknown arrangement {name!r}; known: {sorted(layouts)}", field="arrangement")
    return layouts[name]


ARRANGEMENTS = ("inline2_360", "inline2_180", "inline3", "inline4", "inline5", "inline6", "v2_90",
                "v8_crossplane", "boxer2", "flat4")
