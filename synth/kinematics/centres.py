"""Instant centres, centrodes and the curvature of point paths, computed on request from a motion.

A link's plane motion at an instant is its twist (w, v_O): its angular velocity and the velocity of its point at
the frame's origin, v_O = v_A - w·k×A for any point A of it. Its instant centre relative to the frame is where
v_O + w·k×P = 0, P = k×v_O / w; kept in homogeneous coordinates (k×v_O, w) normalised to unit length, so a link
that translates (w = 0) has its centre at infinity (third coordinate zero) and nothing is ever infinite. The
centre of link j relative to link i comes from the twist difference, and Kennedy's theorem (the three relative
centres of any three links lie on one line) is the check: the determinant of the three unit homogeneous vectors.
A point's path has curvature (v × a)/|v|³ (signed, counter-clockwise positive), its radius the inverse.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations

import numpy as np

from ..model import FloatArray
from .motion import Motion, cross, perp

#: Below this speed, relative to the largest speed of the motion, a point counts as stopped: no curvature.
STOPPED = 1e-9


@dataclass(frozen=True, slots=True)
class Centres:
    """Instant centres over the cycle, (N, 3) unit homogeneous (x·w, y·w, w) each.

    ``absolute`` every moving link's centre relative to the frame; ``relative`` every pair of links (frame
    included as ``frame``), keyed ``"a/b"``, only when asked; ``kennedy`` the largest |det| of three relative
    centres over every triple of bodies and every sample (zero to rounding: they are collinear);
    ``fixed_centrode`` and ``moving_centrode`` of the coupler (the link named), the moving one in the
    coupler's own frame (origin at its first joint, x-axis along it).
    """

    absolute: dict[str, FloatArray]
    relative: dict[str, FloatArray]
    kennedy: float
    coupler: str | None
    fixed_centrode: FloatArray | None
    moving_centrode: FloatArray | None


def _twists(motion: Motion) -> dict[str, tuple[FloatArray, FloatArray]]:
    out: dict[str, tuple[FloatArray, FloatArray]] = {"frame": (np.zeros(motion.samples), np.zeros((motion.samples, 2)))}
    for link, origin in motion.link_origin.items():
        w = np.asarray(motion.link_omega[link], dtype=float)
        a = np.asarray(motion.point_pos[origin], dtype=float)
        out[link] = (w, np.asarray(motion.point_vel[origin], dtype=float) - w[:, None] * perp(a))
    return out


def _homogeneous(w: FloatArray, v: FloatArray) -> FloatArray:
    h = np.column_stack([perp(v), w])
    norm = np.linalg.norm(h, axis=1, keepdims=True)
    # two bodies that move alike have no relative centre: any point; kept as the origin's direction, zero
    return np.where(norm > 0, h / np.where(norm > 0, norm, 1.0), 0.0)


def instant_centres(motion: Motion, relative: bool = False, coupler: str | None = None) -> Centres:
    """Every link's instant centre relative to the frame, the relative ones on request (Kennedy's check over
    every triple), and the centrodes of ``coupler`` (a link name) when given."""
    twists = _twists(motion)

    def centre(i: str, j: str) -> FloatArray:
        (wi, vi), (wj, vj) = twists[i], twists[j]
        return _homogeneous(wj - wi, vj - vi)

    absolute = {link: centre("frame", link) for link in motion.link_origin}
    pairs = {f"{i}/{j}": centre(i, j) for i, j in combinations(twists, 2)}
    kennedy = 0.0
    for i, j, k in combinations(twists, 3):
        det = np.linalg.det(np.stack([pairs[f"{i}/{j}"], pairs[f"{j}/{k}"], pairs[f"{i}/{k}"]], axis=1))
        kennedy = max(kennedy, float(np.max(np.abs(det))))
    fixed = moving = None
    if coupler is not None:
        fixed = absolute[coupler]
        origin = np.asarray(motion.point_pos[motion.link_origin[coupler]], dtype=float)
        theta = np.asarray(motion.link_angle[coupler], dtype=float)
        # the same homogeneous points seen from the coupler: translate by -origin, turn by -theta
        x = fixed[:, 0] - fixed[:, 2] * origin[:, 0]
        y = fixed[:, 1] - fixed[:, 2] * origin[:, 1]
        c, s = np.cos(theta), np.sin(theta)
        moving = _homogeneous_rows(np.column_stack([c * x + s * y, -s * x + c * y, fixed[:, 2]]))
    return Centres(absolute, pairs if relative else {}, kennedy, coupler, fixed, moving)


def _homogeneous_rows(h: FloatArray) -> FloatArray:
    norm = np.linalg.norm(h, axis=1, keepdims=True)
    return np.where(norm > 0, h / np.where(norm > 0, norm, 1.0), 0.0)


def path_curvature(motion: Motion) -> tuple[dict[str, FloatArray], dict[str, FloatArray]]:
    """Signed curvature (v × a)/|v|³ [1/m] of every point's path, (N,) each, zero where the point stops, and
    the mask of those samples (where the radius of curvature is undefined)."""
    top = max((float(np.max(np.linalg.norm(v, axis=1))) for v in motion.point_vel.values()), default=0.0)
    curvature: dict[str, FloatArray] = {}
    stopped: dict[str, FloatArray] = {}
    for name, v in motion.point_vel.items():
        speed = np.linalg.norm(v, axis=1)
        still = speed <= STOPPED * max(top, 1e-300)
        k = cross(v, motion.point_acc[name]) / np.where(still, 1.0, speed) ** 3
        curvature[name] = np.where(still, 0.0, k)
        stopped[name] = still
    return curvature, stopped
