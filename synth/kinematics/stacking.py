"""Motions of several variants of one mechanism laid end to end along the sample axis, and the blocks back.

A batch of variants (a design study's) is analysed as one long motion: every array operation of the
kinetostatics then runs once over all the variants' samples instead of once per variant, and each variant's
answer is its block of samples.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import numpy.typing as npt

from ..mechanism import FloatArray
from .fourbar import FourBar, loop_closure
from .motion import Motion, PointAnalogues, build_motion


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
                           ) -> tuple[Motion, npt.NDArray[np.bool_]]:
    """The motions of many four-bars at the same crank angles ``phi`` [rad], speed ``omega`` [rad/s] and
    acceleration ``alpha`` [rad/s²], stacked as :func:`stack_motions` stacks them, in one pass of
    :meth:`FourBar.solve`'s closed form with each sample's own lengths; and per four-bar whether its loop fails
    to close at some angle (its block is then meaningless: :func:`synth.kinematics.motion` of it alone raises
    the error with its gaps).

    The arithmetic is :meth:`FourBar.solve`'s (:func:`~synth.kinematics.fourbar.loop_closure`), so each block is
    the single motion.
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
    moving, links, bad = loop_closure(a, ground, b, c, branch, angles)
    size = k * n
    points = {
        "O": PointAnalogues(np.zeros((size, 2)), np.zeros((size, 2)), np.zeros((size, 2))),
        **moving,
        "Q": PointAnalogues(np.stack([ground, np.zeros(size)], axis=-1), np.zeros((size, 2)), np.zeros((size, 2))),
    }
    failed: npt.NDArray[np.bool_] = np.asarray(bad.reshape(k, n).any(axis=1))
    return build_motion(angles, omega, alpha, points, links, FourBar.origins), failed
