"""The pin of a revolute joint sized from the joint's reaction over the cycle: shear, bending and bearing pressure.

Inputs: the joint's reaction at every crank angle, shape (N, 2) [N] (the analysis gives it); the arrangement
(:class:`PinJoint`: single or double shear, the clevis fit, the thicknesses of the rod and of the fork's cheeks,
absolute [m] or as ratios of the diameter); the allowable stresses (:class:`PinLimits`, given, or from the
materials' tensile strengths and the kind of load by :func:`roloff_limits`). Output: :func:`size_pin` gives a
:class:`PinResult`: the least diameter every check allows, the standard diameter chosen (ISO 2340 clevis pins),
the stresses over the cycle at that diameter, shape (N,) [Pa], and each check's value and limit.

Models
------
- Shear: the mean shear stress over the shear planes, tau = F / (n pi d²/4), n = 1 (single) or 2 (double shear)
  (Beer, Johnston, DeWolf, Mazurek, *Mechanics of Materials*, §1.2, the boom-and-rod example).
- Bearing pressure: p = F / (d t_S) in the rod (the middle member), F / (2 d t_G) in each of the fork's cheeks;
  in single shear F / (d t) in each member (same source).
- Bending (Roloff/Matek, *Maschinenelemente*, ch. 9, pin joints): the pin as a short beam under the rod's load
  spread over t_S and the cheeks' over t_G. Pin loose in rod and fork: M = F (t_S + 2 t_G)/8; pin fixed (press fit)
  in the fork: M = F t_S/8; pin fixed in the rod: M = F t_G/4. A single-shear pin fixed in one member, the other
  member of thickness t_S on its overhang: M = F t_S/2 at the root. Stress sigma_b = 32 M/(pi d³).
- The kind of load decides the allowable stresses (Roloff/Matek): static (the reaction constant), pulsating (it
  varies but never turns against the pin by more than a right angle) or alternating. A pin fixed in a member sees
  the reaction's direction in that member's frame; a loose pin turns, so its load is taken as alternating.

Where it stops: the pin as a beam of the rigid-member model (no clearance, no fretting), the mean shear stress
(not the 4/3 peak of a solid section); the lugs' tear-out and net section are the links' checks, not the pin's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from ..errors import Infeasible, InvalidInput
from ..model import FloatArray
from .checks import PartCheck

ClevisFit = Literal["loose", "fixed_in_fork", "fixed_in_rod"]
LoadKind = Literal["static", "pulsating", "alternating"]

#: ISO 2340 clevis pins without head, nominal diameters [m]; beyond the series, steps of 10 mm.
STANDARD_PIN_DIAMETERS = tuple(d / 1000.0 for d in (
    3, 4, 5, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 25, 27, 28, 30, 32, 33, 36, 40, 45, 50, 55, 60, 70, 80, 90, 100,
    110, 120, 130, 140, 150, 160, 180, 200))

# Allowable stresses as fractions of the tensile strength R_m by the kind of load (Roloff/Matek, ch. 9, notes to
# the pin equations): bending, shear, and bearing pressure on surfaces that do not slide.
_ROLOFF_FRACTIONS: dict[str, tuple[float, float, float]] = {
    "static": (0.30, 0.20, 0.35),
    "pulsating": (0.20, 0.15, 0.25),
    "alternating": (0.15, 0.10, 0.25),
}
# A reaction whose magnitude stays within this fraction of its peak counts as static.
_STATIC_SPREAD = 0.05


@dataclass(frozen=True, slots=True)
class PinJoint:
    """How a joint's pin is held. ``shear_planes`` 1 (single shear, an overhung pin) or 2 (double shear, a clevis);
    ``fit`` for a clevis: ``loose`` in rod and fork, ``fixed_in_fork`` or ``fixed_in_rod`` (press fit);
    ``rod_thickness`` t_S of the middle member (single shear: of the member on the overhang) [m], or None to take
    ``rod_ratio`` t_S/d [-]; ``fork_thickness`` t_G of each cheek [m], or None to take ``fork_ratio`` t_G/d [-];
    ``application_factor`` K_A on the reaction for shocks [-]."""

    shear_planes: Literal[1, 2] = 2
    fit: ClevisFit = "loose"
    rod_thickness: float | None = None
    fork_thickness: float | None = None
    rod_ratio: float = 1.0
    fork_ratio: float = 0.5
    application_factor: float = 1.0


@dataclass(frozen=True, slots=True)
class PinLimits:
    """Allowable stresses of the pin joint: ``bending`` sigma_b [Pa], ``shear`` tau [Pa] and ``pressure`` p on the
    bearing surfaces [Pa] (of the weaker of pin and member)."""

    bending: float
    shear: float
    pressure: float


@dataclass(frozen=True, slots=True)
class PinResult:
    """A joint's pin: ``diameter_required`` the least diameter every check allows [m], ``diameter`` the standard
    one chosen [m], ``force_max`` the largest reaction times K_A [N], ``load_kind`` of the cycle, ``governing`` the
    check that set the least diameter; at ``diameter`` over the cycle, shape (N,) [Pa]: ``shear_stress``,
    ``bending_stress``, ``rod_pressure``, ``fork_pressure`` (single shear: the other member's); ``checks`` each
    stress's peak against its limit."""

    joint: str
    diameter_required: float
    diameter: float
    force_max: float
    load_kind: LoadKind
    governing: str
    limits: PinLimits
    shear_stress: FloatArray
    bending_stress: FloatArray
    rod_pressure: FloatArray
    fork_pressure: FloatArray
    checks: tuple[PartCheck, ...]


def load_kind(reaction: ArrayLike, member_angle: ArrayLike | None = None) -> LoadKind:
    """The kind of load the reaction puts on a pin over the cycle: ``static``, ``pulsating`` or ``alternating``.

    ``reaction`` (N, 2) [N] in the frame of the page; ``member_angle`` (N,) [rad] of the member the pin is fixed
    in, or None for a pin that turns in both members (then alternating unless the reaction is constant in size and
    direction). Alternating when the reaction's directions in the member's frame spread over more than a right
    angle; static when, besides, its size stays within 5 % of its peak; pulsating otherwise.
    """
    r = np.asarray(reaction, dtype=float)
    mag = np.hypot(r[:, 0], r[:, 1])
    peak = float(mag.max(initial=0.0))
    if peak == 0.0:
        return "static"
    steady = float(mag.max() - mag.min()) <= _STATIC_SPREAD * peak
    if member_angle is None:
        return "static" if steady and _direction_spread(r) <= math.radians(5.0) else "alternating"
    th = np.asarray(member_angle, dtype=float)
    c, s = np.cos(th), np.sin(th)
    local = np.stack([c * r[:, 0] + s * r[:, 1], -s * r[:, 0] + c * r[:, 1]], axis=1)
    if _direction_spread(local) > math.pi / 2.0:
        return "alternating"
    return "static" if steady else "pulsating"


def _direction_spread(r: FloatArray) -> float:
    """Angle between the extreme directions of the non-zero reactions about their mean direction [rad]."""
    mag = np.hypot(r[:, 0], r[:, 1])
    keep = mag > 1e-9 * float(mag.max(initial=0.0))
    if int(keep.sum()) < 2:
        return 0.0
    u = r[keep] / mag[keep, None]
    mean = u.sum(axis=0)
    if float(np.hypot(mean[0], mean[1])) < 1e-9 * len(u):
        return math.pi   # directions all round: no mean direction
    rel = np.angle(np.exp(1j * (np.arctan2(u[:, 1], u[:, 0]) - math.atan2(float(mean[1]), float(mean[0])))))
    return float(rel.max() - rel.min())


def roloff_limits(pin_strength: float, member_strength: float, kind: LoadKind) -> PinLimits:
    """Allowable stresses from the tensile strengths R_m of the pin and of the weaker member [Pa] and the kind
    of load, as fractions of R_m after Roloff/Matek (bending 0.30/0.20/0.15, shear 0.20/0.15/0.10, pressure
    0.35/0.25/0.25 of R_m for static/pulsating/alternating load; the pressure on the weaker of pin and member)."""
    for name, v in (("pin_strength", pin_strength), ("member_strength", member_strength)):
        if not (math.isfinite(v) and v > 0.0):
            raise InvalidInput(f"a pin's limits need a positive tensile strength, got {name}={v!r}", field=name)
    fb, fs, fp = _ROLOFF_FRACTIONS[kind]
    return PinLimits(fb * pin_strength, fs * pin_strength, fp * min(pin_strength, member_strength))


def _thickness(absolute: float | None, ratio: float, d: float) -> float:
    return absolute if absolute is not None else ratio * d


def _stresses_per_newton(joint: PinJoint, d: float) -> tuple[float, float, float, float]:
    """Shear, bending, rod and fork pressure per newton of reaction at diameter d [Pa/N]."""
    t_s = _thickness(joint.rod_thickness, joint.rod_ratio, d)
    t_g = _thickness(joint.fork_thickness, joint.fork_ratio, d)
    area = math.pi * d * d / 4.0
    shear = 1.0 / (joint.shear_planes * area)
    if joint.shear_planes == 1:
        arm = t_s / 2.0
        return shear, 32.0 * arm / (math.pi * d**3), 1.0 / (d * t_s), 1.0 / (d * t_g)
    arm = {"loose": (t_s + 2.0 * t_g) / 8.0, "fixed_in_fork": t_s / 8.0, "fixed_in_rod": t_g / 4.0}[joint.fit]
    return shear, 32.0 * arm / (math.pi * d**3), 1.0 / (d * t_s), 1.0 / (2.0 * d * t_g)


_CHECKS = (("shear", "shear", "mean shear stress over the shear planes"),
           ("bending", "bending", "bending stress of the pin as a beam in its clevis"),
           ("rod_pressure", "pressure", "bearing pressure between the pin and the rod (middle member)"),
           ("fork_pressure", "pressure", "bearing pressure between the pin and each fork cheek (other member)"))


def _least_diameter(joint: PinJoint, force: float, limits: PinLimits) -> tuple[float, str]:
    """The least diameter where every stress at ``force`` is within its limit, and the check that sets it."""
    allow = {"shear": limits.shear, "bending": limits.bending, "pressure": limits.pressure}
    best, which = 0.0, "shear"
    for k, (name, kind, _) in enumerate(_CHECKS):
        def excess(d: float, k: int = k, kind: str = kind) -> float:
            return force * _stresses_per_newton(joint, d)[k] - allow[kind]
        # Every stress falls as the diameter grows: bisect on log d between 0.1 mm and 10 m.
        lo, hi = 1e-4, 10.0
        if excess(hi) > 0.0:
            raise Infeasible(f"no pin diameter up to {hi:g} m carries {force:g} N in {name}", constraint=name)
        if excess(lo) <= 0.0:
            continue
        for _ in range(100):
            mid = math.sqrt(lo * hi)
            lo, hi = (mid, hi) if excess(mid) > 0.0 else (lo, mid)
        if hi > best:
            best, which = hi, name
    return best, which


def standard_pin_diameter(required: float) -> float | None:
    """The smallest standard pin diameter (ISO 2340, then 10 mm steps to 200 mm) at least ``required`` [m]."""
    for d in STANDARD_PIN_DIAMETERS:
        if d >= required * (1.0 - 1e-12):
            return d
    return None


def pin_stresses(reaction: ArrayLike, joint: PinJoint, diameter: float) -> dict[str, FloatArray]:
    """Shear, bending, rod and fork pressure over the cycle at ``diameter`` [m], each shape (N,) [Pa]."""
    r = np.asarray(reaction, dtype=float)
    force = joint.application_factor * np.hypot(r[:, 0], r[:, 1])
    per = _stresses_per_newton(joint, diameter)
    return {name: force * per[k] for k, (name, _, _) in enumerate(_CHECKS)}


def size_pin(
    joint_name: str,
    reaction: ArrayLike,
    joint: PinJoint,
    limits: PinLimits,
    *,
    member_angle: ArrayLike | None = None,
    max_diameter: float = 0.2,
    diameter: float | None = None,
) -> PinResult:
    """Size the pin of ``joint_name`` from its reaction over the cycle.

    Parameters
    ----------
    joint_name : The joint's name, carried into errors and checks.
    reaction : The joint's reaction at every crank angle, shape (N, 2) [N].
    joint : How the pin is held (shear planes, fit, thicknesses) and the application factor.
    limits : Allowable stresses [Pa] (see :func:`roloff_limits`).
    member_angle : Angle of the member the pin is fixed in, shape (N,) [rad], to tell the kind of load (reported).
    max_diameter : Largest pin accepted [m]; beyond it :class:`Infeasible` names the joint and the check.
    diameter : A given diameter [m] (a rolling bearing's bore, say): checked at it, not chosen; the least
        diameter is still reported.
    """
    r = np.asarray(reaction, dtype=float)
    if r.ndim != 2 or r.shape[1] != 2 or r.shape[0] == 0 or not np.all(np.isfinite(r)):
        raise InvalidInput(f"joint {joint_name}: the reaction must be finite, shape (N, 2), got {r.shape}",
                           field=f"{joint_name}.reaction")
    _validate(joint_name, joint, limits)
    force_max = joint.application_factor * float(np.hypot(r[:, 0], r[:, 1]).max())
    try:
        required, governing = _least_diameter(joint, force_max, limits)
    except Infeasible as exc:
        raise Infeasible(f"joint {joint_name}: {exc.reason}", constraint=exc.constraint, joint=joint_name) from exc
    required = max(required, 1e-4)
    if diameter is not None and not (math.isfinite(diameter) and diameter > 0.0):
        raise InvalidInput(f"joint {joint_name}: the pin diameter must be positive, got {diameter!r}",
                           field=f"{joint_name}.diameter")
    chosen = standard_pin_diameter(required) if diameter is None else diameter
    if chosen is None or (diameter is None and chosen > max_diameter * (1.0 + 1e-12)):
        raise Infeasible(f"joint {joint_name}: the pin needs {required * 1e3:.1f} mm for {governing}, beyond the "
                         f"largest pin of {max_diameter * 1e3:.0f} mm", constraint=governing, joint=joint_name,
                         diameter_required_m=required)
    s = pin_stresses(r, joint, chosen)
    allow = {"shear": limits.shear, "bending": limits.bending, "pressure": limits.pressure}
    checks = tuple(PartCheck(joint_name, f"pin_{name}", float(s[name].max()), allow[kind], "Pa", meaning)
                   for name, kind, meaning in _CHECKS)
    return PinResult(joint_name, required, chosen, force_max, load_kind(r, member_angle), governing, limits,
                     s["shear"], s["bending"], s["rod_pressure"], s["fork_pressure"], checks)


def _validate(joint_name: str, joint: PinJoint, limits: PinLimits) -> None:
    if joint.shear_planes not in (1, 2):
        raise InvalidInput(f"joint {joint_name}: a pin has 1 or 2 shear planes, got {joint.shear_planes!r}",
                           field=f"{joint_name}.shear_planes")
    if joint.fit not in ("loose", "fixed_in_fork", "fixed_in_rod"):
        raise InvalidInput(f"joint {joint_name}: unknown clevis fit {joint.fit!r}", field=f"{joint_name}.fit")
    for name in ("rod_thickness", "fork_thickness"):
        v = getattr(joint, name)
        if v is not None and not (math.isfinite(v) and v > 0.0):
            raise InvalidInput(f"joint {joint_name}: {name} must be positive, got {v!r}", field=f"{joint_name}.{name}")
    for name in ("rod_ratio", "fork_ratio", "application_factor"):
        v = getattr(joint, name)
        if not (math.isfinite(v) and v > 0.0):
            raise InvalidInput(f"joint {joint_name}: {name} must be positive, got {v!r}", field=f"{joint_name}.{name}")
    for name in ("bending", "shear", "pressure"):
        v = getattr(limits, name)
        if not (math.isfinite(v) and v > 0.0):
            raise InvalidInput(f"joint {joint_name}: the pin material has no {name} limit (got {v!r})",
                               field=f"{joint_name}.limits.{name}")
