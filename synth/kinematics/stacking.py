"""Motions of several variants of one mechanism laid end to end along the sample axis, and the blocks back.

A batch of variants (a design study's) is analysed as one long motion: every array operation of the
kinetostatics then runs once over all the variants' samples instead of once per variant, and each variant's
answer is its block of samples.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ..mechanism import FloatArray
from .fourbar import FourBar
from .motion import AngleAnalogues, Motion, PointAnalogues, build_motion, cross, perp


def _joined(parts: Sequence[Mapping[str, FloatArray]]) -> dict[str, FloatArray]:
    return {key: np.concatenate([p[key] for p in parts]) for key in parts[0]}


def stack_motions(motions: Sequence[Motion]) -> Motion:
    """One motion whose samples are those of ``motions`` in order (variant k's at k·N to (k+1)·N for N each).

    The motions must share their crank speed and acceleration, points, links and link frames (one mechanism
    family and topology); ValueError otherwise.
    """
    first = motions[0]
    for m in motions[1:]:
        if (m.omega_crank != first.omega_crank or m.alpha_crank != first.alpha_crank
                or m.point_pos.keys() != first.point_pos.keys() or m.link_angle.keys() != first.link_angle.keys()
                or dict(m.link_origin) != dict(first.link_origin)):
            raise ValueError("only motions of one topology at one crank speed and acceleration stack")
    return Motion(
        np.concatenate([m.phi for m in motions]), first.omega_crank, first.alpha_crank,
        _joined([m.point_pos for m in motions]), _joined([m.point_vel for m in motions]),
        _joined([m.point_acc for m in motions]), _joined([m.link_angle for m in motions]),
        _joined([m.link_omega for m in motions]), _joined([m.link_alpha for m in motions]),
        dict(first.link_origin),
    )


def motion_block(motion: Motion, start: int, stop: int) -> Motion:
    """Samples ``start`` to ``stop`` of ``motion`` (one variant of a stack) as a motion of its own (views)."""
    s = slice(start, stop)
    return Motion(
        motion.phi[s], motion.omega_crank, motion.alpha_crank,
        {k: v[s] for k, v in motion.point_pos.items()}, {k: v[s] for k, v in motion.point_vel.items()},
        {k: v[s] for k, v in motion.point_acc.items()}, {k: v[s] for k, v in motion.link_angle.items()},
        {k: v[s] for k, v in motion.link_omega.items()}, {k: v[s] for k, v in motion.link_alpha.items()},
        motion.link_origin,
    )


def stacked_fourbar_motion(mechanisms: Sequence[FourBar], phi: FloatArray, omega: float, alpha: float = 0.0
                           ) -> tuple[Motion, FloatArray]:
    """The motions of many four-bars at the same crank angles ``phi`` [rad], speed ``omega`` [rad/s] and
    acceleration ``alpha`` [rad/s²], stacked as :func:`stack_motions` stacks them, in one pass of
    :meth:`FourBar.solve`'s closed form with each sample's own lengths; and per four-bar whether its loop fails
    to close at some angle (its block is then meaningless: :func:`synth.kinematics.motion` of it alone raises
    the error with its gaps).

    The arithmetic is :meth:`FourBar.solve`'s, operation for operation, so each block is the single motion.
    """
    k, n = len(mechanisms), len(phi)

    def per_sample(values: Sequence[float]) -> FloatArray:
        return np.repeat(np.asarray(values, dtype=float), n)

    a = per_sample([m.crank for m in mechanisms])[:, None]
    d = per_sample([m.ground for m in mechanisms])
    b1 = per_sample([m.coupler for m in mechanisms])
    c1 = per_sample([m.rocker for m in mechanisms])
    branch = per_sample([m.branch for m in mechanisms])
    angles = np.tile(np.asarray(phi, dtype=float), k)
    e = np.stack([np.cos(angles), np.sin(angles)], axis=-1)
    a_pt = PointAnalogues(a * e, a * perp(e), -a * e)
    q = np.stack([d, np.zeros(k * n)], axis=-1)
    ev = q - a_pt.pos
    dist = np.hypot(ev[:, 0], ev[:, 1])
    bad = (dist > b1 + c1 + 1e-12) | (dist < abs(b1 - c1) - 1e-12) | (dist == 0)
    b, c = b1[:, None], c1[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        u = ev / dist[:, None]
        x = (b1 * b1 - c1 * c1 + dist * dist) / (2 * dist)
        h = np.sqrt(np.clip(b1 * b1 - x * x, 0.0, None))
        bpos = a_pt.pos + x[:, None] * u + (branch * h)[:, None] * perp(u)
        e2 = (bpos - a_pt.pos) / b
        e3 = (bpos - q) / c
        k2, k3 = perp(e2), perp(e3)
        det = cross(b * k2, -c * k3)
        rhs1 = -a_pt.d1
        t2d1 = cross(rhs1, -c * k3) / det
        t3d1 = cross(b * k2, rhs1) / det
        rhs2 = -a_pt.d2 + b * (t2d1**2)[:, None] * e2 - c * (t3d1**2)[:, None] * e3
        t2d2 = cross(rhs2, -c * k3) / det
        t3d2 = cross(b * k2, rhs2) / det
    b_d1 = c * t3d1[:, None] * k3
    b_d2 = c * t3d2[:, None] * k3 - c * (t3d1**2)[:, None] * e3
    zeros = np.zeros((k * n, 2))
    points = {
        "O": PointAnalogues(zeros.copy(), zeros.copy(), zeros.copy()),
        "A": a_pt,
        "B": PointAnalogues(bpos, b_d1, b_d2),
        "Q": PointAnalogues(q, zeros.copy(), zeros.copy()),
    }
    links = {
        "crank": AngleAnalogues(angles, np.ones(k * n), np.zeros(k * n)),
        "coupler": AngleAnalogues(np.arctan2(e2[:, 1], e2[:, 0]), t2d1, t2d2),
        "rocker": AngleAnalogues(np.arctan2(e3[:, 1], e3[:, 0]), t3d1, t3d2),
    }
    return build_motion(angles, omega, alpha, points, links, FourBar.origins), bad.reshape(k, n).any(axis=1)
