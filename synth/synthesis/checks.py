"""Independent checks of a synthesised linkage by the kinematics engine: dead centres, travel, time ratio and
transmission angles found on the engine's own position solution, not on the synthesis formulas."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import cast

import numpy as np

from ..errors import SolverFailed
from ..kinematics import FourBar, Mechanism, SliderCrank, motion, transmission_angle
from ..model import FloatArray
from ..warnings import DesignWarning, link_ratio_warning, transmission_angle_warning

_GRID = 720
_NEWTON_STEPS = 60  # bisection alone halves a grid interval to 1e-14 rad in about 40


@dataclass(frozen=True, slots=True)
class LinkageCheck:
    """What the kinematics engine finds the linkage does.

    ``travel``: rocker swing [rad] or slider stroke [m] between the dead centres; ``time_ratio``: crank angle of
    the slow stroke over that of the fast one; ``slow_stroke``: crank angles [rad] at which the slow stroke starts
    and ends (the fast one runs from its end back to its start); ``output_extremes``: rocker angle [rad] or slide
    position [m] at those two crank angles; ``min_/max_transmission_angle`` [rad] with the crank angles [rad]
    where they occur; ``warnings`` the analysis' own notes on the answer (a transmission angle under 40°, a
    link ratio beyond what a drawing office builds).
    """

    travel: float
    time_ratio: float
    slow_stroke: tuple[float, float]
    output_extremes: tuple[float, float]
    min_transmission_angle: float
    min_transmission_crank_angle: float
    max_transmission_angle: float
    max_transmission_crank_angle: float
    warnings: tuple[DesignWarning, ...] = field(default=())

    def stroke_times(self, speed: float) -> tuple[float, float]:
        """Durations [s] of the slow and the fast stroke at crank speed ``speed`` [rad/s]."""
        slow = (self.slow_stroke[1] - self.slow_stroke[0]) % (2 * math.pi)
        return slow / speed, (2 * math.pi - slow) / speed


def _dead_centres(rate: FloatArray, phi: FloatArray, fn: Callable[[FloatArray], tuple[FloatArray, FloatArray]]
                  ) -> list[float]:
    """Crank angles where the output's rate (sampled on ``phi``) changes sign, refined together by Newton's
    method on ``fn`` (the rate and its derivative at an array of crank angles), kept within each sign change's
    grid interval by bisection, to a step of 1e-14 rad."""
    nxt = np.roll(rate, -1)
    idx = np.flatnonzero((rate > 0) != (nxt > 0))  # a zero counts with the negatives: one root each
    if idx.size != 2:
        raise SolverFailed("dead_centres", f"expected two dead centres of the output, found {idx.size}")
    lo = phi[idx]
    hi = lo + 2 * math.pi / phi.size
    rising = rate[idx] > 0
    x = 0.5 * (lo + hi)
    for _ in range(_NEWTON_STEPS):
        value, slope = fn(x)
        same = (value > 0) == rising
        lo, hi = np.where(same, x, lo), np.where(same, hi, x)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = value / slope
        # Newton's step where it stays within the bracket, else bisection.
        inside = np.isfinite(step) & (x - step >= lo) & (x - step <= hi)
        new = np.where(inside, x - step, 0.5 * (lo + hi))
        moved = np.abs(new - x)
        x = new
        if np.all(moved <= 1e-14):
            break
    else:
        raise SolverFailed("dead_centres", "the dead centres did not converge")
    return [float(v) % (2 * math.pi) for v in x]


def _strokes(roots: list[float]) -> tuple[float, tuple[float, float]]:
    span = (roots[1] - roots[0]) % (2 * math.pi)
    if span >= math.pi:
        return span / (2 * math.pi - span), (roots[0], roots[1])
    return (2 * math.pi - span) / span, (roots[1], roots[0])


def _extremes(mu: FloatArray, phi: FloatArray) -> tuple[float, float, float, float]:
    i, j = int(np.argmin(mu)), int(np.argmax(mu))
    return float(mu[i]), float(phi[i] % (2 * math.pi)), float(mu[j]), float(phi[j] % (2 * math.pi))


def _grid() -> FloatArray:
    # The exact extreme angles of both families (crank along or across the guide line) are on this grid.
    return np.linspace(0.0, 2 * math.pi, _GRID, endpoint=False)


def check_fourbar(fb: FourBar) -> LinkageCheck:
    """Rocker swing, time ratio and transmission angle extremes of ``fb`` from the engine's position solution."""
    phi = _grid()
    mot = motion(cast(Mechanism, fb), phi, 1.0)

    def rate(x: FloatArray) -> tuple[FloatArray, FloatArray]:
        rocker = fb.solve(x)[1]["rocker"]
        return rocker.d1, rocker.d2

    roots = _dead_centres(mot.link_omega["rocker"], phi, rate)
    q, slow = _strokes(roots)
    out = fb.solve(np.array(slow))[1]["rocker"].angle
    swing = abs(math.remainder(float(out[1] - out[0]), 2 * math.pi))
    mu = transmission_angle(mot.link_angle["coupler"], mot.link_angle["rocker"])
    notes = (*transmission_angle_warning(phi, mu), *link_ratio_warning(fb))
    return LinkageCheck(swing, q, slow, (float(out[0]), float(out[1])), *_extremes(mu, phi), notes)


def check_slider_crank(sc: SliderCrank) -> LinkageCheck:
    """Stroke, time ratio and transmission angle extremes of ``sc`` from the engine's position solution.

    The transmission angle is the angle between the rod and the normal to the guide: 90° less the rod's
    inclination to the guide.
    """
    phi = _grid()
    mot = motion(cast(Mechanism, sc), phi, 1.0)

    def rate(x: FloatArray) -> tuple[FloatArray, FloatArray]:
        slide = sc.solve(x)[0]["B"]
        return slide.d1[:, 0], slide.d2[:, 0]

    roots = _dead_centres(mot.point_vel["B"][:, 0], phi, rate)
    q, slow = _strokes(roots)
    xb = sc.solve(np.array(slow))[0]["B"].pos[:, 0]
    mu = 0.5 * math.pi - np.arcsin(np.abs(np.sin(mot.link_angle["rod"])))
    notes = (*transmission_angle_warning(phi, mu), *link_ratio_warning(sc))
    return LinkageCheck(abs(float(xb[1] - xb[0])), q, slow, (float(xb[0]), float(xb[1])), *_extremes(mu, phi),
                        notes)
