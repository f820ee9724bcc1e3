"""Geometry of a disc cam and its follower: pitch curve, profile, pressure angle and radius of curvature.

Frames: the cam centre O is the origin and the cam turns counter-clockwise by the cam angle theta. The *follower
frame* is fixed to the machine frame: a translating follower moves along +y on the line x = e (the offset); an
oscillating follower's pivot A is at (d, 0) with its arm reaching back toward the cam on the +y side, its angle
gamma = gamma0 + s measured from A->O. The *cam frame* turns with the cam; a point X of the follower frame is
R(-theta) X in the cam frame, so the profile is drawn once, in the cam frame.

Everything is written for a point or a line of the follower and its derivatives with respect to theta in the
follower frame; with J the quarter turn (x, y) -> (-y, x), a follower point P(theta) traces in the cam frame a
curve with tangent R(-theta)(P' - J P) and second derivative R(-theta)(P'' - 2 J P' - P). A flat face is a
family of lines n(tau) . x = p whose envelope (the profile) has radius of curvature p + d2p/dtau2.

Signs: the radius of curvature is positive where the profile is convex; the pressure angle is the angle from the
velocity of the follower's contact point to the common normal, positive counter-clockwise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from ..errors import InvalidInput
from ..model import FloatArray
from .laws import FollowerMotion

FollowerKind = Literal["translating", "oscillating"]
ContactKind = Literal["knife_edge", "roller", "flat_faced"]


@dataclass(frozen=True, slots=True)
class Follower:
    """A follower: translating (``offset`` e [m] of its axis from the cam centre) or oscillating (pivot at
    ``pivot_distance`` d [m], ``arm_length`` l [m] to the roller centre or knife edge; a flat face at
    ``face_offset`` f [m] from the pivot, on the cam's side); knife-edge, roller (``roller_radius`` [m]) or
    flat-faced (face perpendicular to a translating follower's axis)."""

    motion: FollowerKind
    contact: ContactKind
    roller_radius: float = 0.0
    offset: float = 0.0
    pivot_distance: float = 0.0
    arm_length: float = 0.0
    face_offset: float = 0.0

    @property
    def roller(self) -> float:
        """The roller radius, 0 for knife-edge and flat-faced followers [m]."""
        return self.roller_radius if self.contact == "roller" else 0.0


@dataclass(frozen=True, slots=True)
class CamGeometry:
    """The cam of base radius ``base_radius`` [m] with its follower at every cam angle of ``motion``.

    Arrays (N, 2) are points or unit vectors; (N,) scalars. ``pitch`` is the roller centre (the knife edge, or the
    face's reference point: the foot of the follower axis or of the perpendicular from the pivot) and
    ``profile`` the contact point, both in the cam frame [m]; ``contact`` the contact point and ``normal`` the
    common normal (out of the cam) in the follower frame. ``rho`` is the profile's radius of curvature and
    ``kappa`` its curvature 1/rho [1/m] (positive convex); ``rho_pitch`` the pitch curve's. ``lever`` maps the
    contact force N to the generalised force along the follower's coordinate (N·lever; lever is cos alpha for a
    translating follower, a length for an oscillating one); ``arm`` gives the cam's driving torque N·arm [m].
    ``face`` is the contact's position along a flat face from its reference point [m]; ``drive`` the velocity
    of the roller centre (knife edge, or the contact as a point of the arm) per unit of the follower's coordinate,
    in the follower frame [m per m or per rad].
    """

    follower: Follower
    base_radius: float
    motion: FollowerMotion
    pitch: FloatArray
    profile: FloatArray
    contact: FloatArray
    normal: FloatArray
    pressure_angle: FloatArray
    rho: FloatArray
    kappa: FloatArray
    rho_pitch: FloatArray
    lever: FloatArray
    arm: FloatArray
    face: FloatArray
    drive: FloatArray

    @property
    def prime_radius(self) -> float:
        """Base radius plus roller radius [m]."""
        return self.base_radius + self.follower.roller


def _J(x: FloatArray) -> FloatArray:
    return np.stack([-x[..., 1], x[..., 0]], axis=-1)


def _cross(a: FloatArray, b: FloatArray) -> FloatArray:
    return np.asarray(a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0])


def _dot(a: FloatArray, b: FloatArray) -> FloatArray:
    return np.asarray(np.sum(a * b, axis=-1))


def to_cam_frame(points: FloatArray, theta: FloatArray) -> FloatArray:
    """Follower-frame points (N, 2) at cam angles theta, in the cam frame: R(-theta) X."""
    c, s = np.cos(theta), np.sin(theta)
    return np.stack([c * points[:, 0] + s * points[:, 1], -s * points[:, 0] + c * points[:, 1]], axis=-1)


def to_follower_frame(points: FloatArray, theta: FloatArray) -> FloatArray:
    """Cam-frame vectors (N, 2) back in the follower frame: R(theta) X."""
    return to_cam_frame(points, -theta)


def oscillating_start(follower: Follower, prime_radius: float) -> float:
    """The arm angle gamma0 [rad] at which the roller centre (or knife edge) lies on the prime circle."""
    d, arm = follower.pivot_distance, follower.arm_length
    if not 2.0 * d * arm > 0:
        # lengths so small their product underflows (subnormal doubles): no angle can be computed from them
        short = "follower.arm_length_m" if arm <= d else "follower.pivot_distance_m"
        raise InvalidInput(f"an arm of {arm:g} m pivoted {d:g} m from the cam centre is too small to compute "
                           "with: give both in metres (their product underflows)", field=short)
    cos_g = (d * d + arm * arm - prime_radius**2) / (2.0 * d * arm)
    if not -1.0 < cos_g < 1.0:
        raise InvalidInput(f"an arm of {arm:g} m pivoted {d:g} m from the cam centre cannot reach the prime "
                           f"circle of radius {prime_radius:g} m", field="follower.arm_length_m",
                           code="arm_cannot_reach")
    return math.acos(cos_g)


def _point_follower(follower: Follower, base_radius: float, m: FollowerMotion
                    ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """The roller centre (knife edge) P, P', P'' in the follower frame and dP/ds, each (N, 2)."""
    rp = base_radius + follower.roller
    if follower.motion == "translating":
        e = follower.offset
        if not rp > abs(e):
            raise InvalidInput(f"an offset of {e:g} m does not fit inside the prime circle of radius {rp:g} m",
                               field="follower.offset_m", code="offset_too_large")
        y = math.sqrt(rp * rp - e * e) + m.s
        zero = np.zeros_like(m.s)
        P = np.stack([np.full_like(m.s, e), y], axis=-1)
        return P, np.stack([zero, m.v], axis=-1), np.stack([zero, m.a], axis=-1), np.stack([zero, zero + 1.0], -1)
    d, arm = follower.pivot_distance, follower.arm_length
    g = oscillating_start(follower, rp) + m.s
    cg, sg = np.cos(g), np.sin(g)
    P = np.stack([d - arm * cg, arm * sg], axis=-1)
    dP = arm * np.stack([sg, cg], axis=-1)
    ddP = dP * m.a[:, None] + arm * np.stack([cg, -sg], axis=-1) * (m.v**2)[:, None]
    return P, dP * m.v[:, None], ddP, dP


def _flat_face(follower: Follower, base_radius: float, m: FollowerMotion
               ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """Flat face as the line n . x = p in the follower frame: the contact point, the normal n, the face's
    reference point, the profile's radius of curvature p + d2p/dtau2 and the envelope's p_tau."""
    if follower.motion == "translating":
        p = base_radius + m.s
        # tau = pi/2 - theta: tau' = -1, so p_tau = -v and p_tautau = a
        p_tau, p_tautau = -m.v, m.a
        n = np.stack([np.zeros_like(p), np.ones_like(p)], axis=-1)
        along = np.stack([-np.ones_like(p), np.zeros_like(p)], axis=-1)
        ref = np.stack([np.full_like(p, follower.offset), p], axis=-1)
    else:
        d, f = follower.pivot_distance, follower.face_offset
        sin0 = (base_radius + f) / d
        if not 0.0 < sin0 < 1.0:
            raise InvalidInput(f"a flat face {f:g} m from a pivot {d:g} m away cannot touch a base circle of "
                               f"radius {base_radius:g} m", field="follower.pivot_distance_m",
                               code="face_cannot_reach")
        g = math.asin(sin0) + m.s
        cg, sg = np.cos(g), np.sin(g)
        p = d * sg - f
        dtau, ddtau = -(1.0 + m.v), -m.a
        if np.any(np.abs(dtau) < 1e-9):
            raise InvalidInput("the follower turns back as fast as the cam turns: the face has no envelope",
                               field="segments")
        dp = d * cg * m.v
        ddp = d * (cg * m.a - sg * m.v**2)
        p_tau = dp / dtau
        p_tautau = (ddp * dtau - dp * ddtau) / dtau**3
        n = np.stack([sg, cg], axis=-1)
        along = np.stack([-cg, sg], axis=-1)
        ref = np.stack([d - f * sg, -f * cg], axis=-1)
    contact = p[:, None] * n + p_tau[:, None] * along
    return contact, n, ref, p + p_tautau, np.asarray(_dot(contact - ref, along))


def cam_geometry(follower: Follower, base_radius: float, m: FollowerMotion, strict: bool = True) -> CamGeometry:
    """The cam's pitch curve, profile, pressure angle, curvature and force levers at every angle of ``m``.

    Raises InvalidInput when the follower cannot be placed (an offset or an arm that cannot reach the prime
    circle), or, when ``strict``, the profile cannot be cut (a roller larger than the pitch curve's least convex
    radius of curvature; a flat face whose envelope has a cusp), naming the field and the cam angles. The least-cam
    search passes ``strict=False`` and judges the curvature itself.
    """
    if not base_radius > 0.0:
        raise InvalidInput("the base circle needs a positive radius", field="base_radius_m")
    theta = m.theta
    if follower.contact == "flat_faced":
        C, n, ref, rho, face = _flat_face(follower, base_radius, m)
        if follower.motion == "translating":
            w = np.stack([np.zeros_like(m.s), np.ones_like(m.s)], axis=-1)
        else:
            A = np.array([follower.pivot_distance, 0.0])
            w = -_J(C - A)          # a point of the arm moves this way as gamma grows
        rho_pitch = rho
        pitch = ref
    else:
        P, dP, ddP, w = _point_follower(follower, base_radius, m)
        T1 = dP - _J(P)
        T2 = ddP - 2.0 * _J(dP) - P
        speed = np.hypot(T1[:, 0], T1[:, 1])
        cross = _cross(T1, T2)
        with np.errstate(divide="ignore"):
            rho_pitch = np.where(cross != 0.0, -speed**3 / np.where(cross != 0.0, cross, 1.0), np.inf)
        n = _J(T1) / speed[:, None]
        r = follower.roller
        if r > 0.0 and strict:
            convex = rho_pitch > 0.0
            bad = convex & (rho_pitch <= r)
            if bad.any():
                at = np.degrees(theta[bad])
                raise InvalidInput(
                    f"a roller of radius {r:g} m is larger than the pitch curve's least convex radius of curvature "
                    f"{float(rho_pitch[convex].min()):.6g} m (cam angles {at.min():.1f}..{at.max():.1f} deg): the "
                    "profile would be undercut; use a smaller roller or a larger base circle",
                    field="follower.roller_radius_m", code="undercut")
        rho = rho_pitch - r
        C = P - r * n
        pitch = P
        face = np.zeros_like(m.s)
    if strict and follower.contact == "flat_faced" and np.any(rho <= 0.0):
        at = np.degrees(theta[rho <= 0.0])
        raise InvalidInput(f"the flat face's profile has a cusp (radius of curvature {float(rho.min()):.6g} m at "
                           f"cam angles {at.min():.1f}..{at.max():.1f} deg); use a larger base circle",
                           field="base_radius_m", code="cusp")
    w_hat = w / np.hypot(w[:, 0], w[:, 1])[:, None]
    alpha = np.arctan2(_cross(w_hat, n), _dot(w_hat, n))
    lever = _dot(w, n)
    with np.errstate(divide="ignore"):
        kappa = np.where(np.isfinite(rho), 1.0 / np.where(rho != 0.0, rho, 1.0), 0.0)
    return CamGeometry(follower, base_radius, m, to_cam_frame(pitch, theta), to_cam_frame(C, theta), C, n,
                       alpha, rho, kappa, rho_pitch, lever, _cross(C, n), face, w)


@dataclass(frozen=True, slots=True)
class TableCheck:
    """The point table's own figures: pressure angle and curvature from fourth-order periodic finite differences
    of the profile points, compared with the analytic ones. Samples whose stencil straddles a segment boundary
    are left out (the law's acceleration, and with it the curvature, may jump there by design)."""

    max_pressure_angle_error: float      # [rad]
    max_curvature_error: float           # relative to the largest |curvature|
    samples_compared: int


def table_check(g: CamGeometry) -> TableCheck:
    """Recompute the pressure angle and the curvature from the profile's point table alone."""
    X, theta = g.profile, g.motion.theta
    N = len(theta)
    h = 2.0 * math.pi / N
    r = [np.roll(X, -k, axis=0) for k in (-2, -1, 1, 2)]
    d1 = (r[0] - 8.0 * r[1] + 8.0 * r[2] - r[3]) / (12.0 * h)
    d2 = (-r[0] + 16.0 * r[1] - 30.0 * X + 16.0 * r[2] - r[3]) / (12.0 * h * h)
    speed = np.hypot(d1[:, 0], d1[:, 1])
    kappa_fd = -_cross(d1, d2) / speed**3
    n_fd = to_follower_frame(_J(d1) / speed[:, None], theta)
    # The direction in which the follower's contact point moves as its coordinate grows, from the follower's
    # geometry and the table's points alone: along the axis, or square to the arm.
    if g.follower.motion == "translating":
        w = np.stack([np.zeros(N), np.ones(N)], axis=-1)
    else:
        on_arm = to_follower_frame(g.profile if g.follower.contact == "flat_faced" else g.pitch, theta)
        w = -_J(on_arm - np.array([g.follower.pivot_distance, 0.0]))
    w_hat = w / np.hypot(w[:, 0], w[:, 1])[:, None]
    alpha_fd = np.arctan2(_cross(w_hat, n_fd), _dot(w_hat, n_fd))
    idx = np.arange(N)
    seg = g.motion.segment
    smooth = np.ones(N, dtype=bool)
    for k in (-2, -1, 1, 2):
        smooth &= seg[(idx + k) % N] == seg
    use_alpha = smooth
    a_err = float(np.max(np.abs(np.angle(np.exp(1j * (alpha_fd - g.pressure_angle)))[use_alpha]), initial=0.0))
    k_err = float(np.max(np.abs(kappa_fd - g.kappa)[smooth], initial=0.0)) / max(float(np.max(np.abs(g.kappa))),
                                                                                  1e-300)
    return TableCheck(a_err, k_err, int(smooth.sum()))


def limit_figures(follower: Follower, base_radius: float, m: FollowerMotion) -> tuple[FloatArray, FloatArray,
                                                                                       FloatArray]:
    """Pressure angle [rad], pitch-curve curvature and profile radius of curvature [m] alone, as
    :func:`cam_geometry` computes them without the profile or the frames (the least-cam search asks for them
    thousands of times). Never refuses an undercut or a cusp."""
    if follower.contact == "flat_faced":
        g = cam_geometry(follower, base_radius, m, strict=False)
        return g.pressure_angle, g.kappa, g.rho
    P, dP, ddP, w = _point_follower(follower, base_radius, m)
    T1 = dP - _J(P)
    T2 = ddP - 2.0 * _J(dP) - P
    speed = np.hypot(T1[:, 0], T1[:, 1])
    kappa_pitch = -_cross(T1, T2) / speed**3
    n = _J(T1)
    alpha = np.arctan2(_cross(w, n), _dot(w, n))
    return alpha, kappa_pitch, np.zeros(0)
