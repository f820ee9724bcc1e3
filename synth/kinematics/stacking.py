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
from .motion import AngleAnalogues, Motion, PointAnalogues, build_motion, cross_c, dot_c, unit, xy


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
        _joined([m.link_unit for m in motions]) if all(m.link_unit.keys() == first.link_unit.keys()
                                                       for m in motions) else {},
    )


def motion_block(motion: Motion, start: int, stop: int) -> Motion:
    """Samples ``start`` to ``stop`` of ``motion`` (one variant of a stack) as a motion of its own (views)."""
    s = slice(start, stop)
    return Motion.derived(
        motion.phi[s], motion.omega_crank, motion.alpha_crank,
        {k: v[s] for k, v in motion.point_pos.items()}, {k: v[s] for k, v in motion.point_vel.items()},
        {k: v[s] for k, v in motion.point_acc.items()}, {k: v[s] for k, v in motion.link_angle.items()},
        {k: v[s] for k, v in motion.link_omega.items()}, {k: v[s] for k, v in motion.link_alpha.items()},
        motion.link_origin, {k: v[s] for k, v in motion.link_unit.items()},
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

    a = per_sample([m.crank for m in mechanisms])
    ground = per_sample([m.ground for m in mechanisms])
    b = per_sample([m.coupler for m in mechanisms])
    c = per_sample([m.rocker for m in mechanisms])
    branch = per_sample([m.branch for m in mechanisms])
    angles = np.tile(np.asarray(phi, dtype=float), k)
    pin = a * unit(angles)
    to_q = ground - pin
    dist = np.abs(to_q)
    bad = (dist > b + c + 1e-12) | (dist < abs(b - c) - 1e-12) | (dist == 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = (b * b - c * c + dist * dist) / (2 * dist)
        h = np.sqrt(np.clip(b * b - x * x, 0.0, None))
        bpos = pin + (to_q / dist) * (x + (1j * branch) * h)
        e2 = (bpos - pin) / b
        e3 = (bpos - ground) / c
        det = -b * c * cross_c(e2, e3)
        pin_d1 = 1j * pin
        t2d1 = c * dot_c(pin_d1, e3) / det
        t3d1 = b * dot_c(e2, pin_d1) / det
        rhs2 = pin + b * (t2d1 * t2d1) * e2 - c * (t3d1 * t3d1) * e3
        t2d2 = -c * dot_c(rhs2, e3) / det
        t3d2 = -b * dot_c(e2, rhs2) / det
    k3 = 1j * e3
    size = k * n
    points = {
        "O": PointAnalogues(np.zeros((size, 2)), np.zeros((size, 2)), np.zeros((size, 2))),
        "A": PointAnalogues(xy(pin), xy(pin_d1), xy(-pin)),
        "B": PointAnalogues(xy(bpos), xy((c * t3d1) * k3), xy(c * (t3d2 * k3 - (t3d1 * t3d1) * e3))),
        "Q": PointAnalogues(np.stack([ground, np.zeros(size)], axis=-1), np.zeros((size, 2)), np.zeros((size, 2))),
    }
    links = {
        "crank": AngleAnalogues(angles, np.ones(size), np.zeros(size), pin / a),
        "coupler": AngleAnalogues(np.angle(e2), t2d1, t2d2, e2),
        "rocker": AngleAnalogues(np.angle(e3), t3d1, t3d2, e3),
    }
    return build_motion(angles, omega, alpha, points, links, FourBar.origins), bad.reshape(k, n).any(axis=1)
