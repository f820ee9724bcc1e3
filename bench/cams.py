"""Disc cams: the least-cam search against dense brute-force searches, and the analysis against a per-angle loop.

Run: ``.venv/bin/python -m bench.cams``. Prints medians and ratios, each against a baseline run here:

* least base radius, offset fixed (a roller follower, cycloidal rise, 3-4-5 return, 30°/45° limits): the
  engine's scan and bisection against a dense search over radii every 1e-5 m of the range, both on the same 720
  cam angles; the answers' difference is printed with the times (the engine also refines each limit's peak
  between the samples, so its radius is the continuous one, a fraction of a micrometre above the sampled one);
* least base radius with a free offset: the engine (offset scan and Brent refinement) against a dense grid of 41
  offsets by 401 radii;
* the analysis of one cam (720 angles: motion, geometry, the point-table check, forces) against the same geometry
  computed one cam angle at a time in a Python loop.
"""

from __future__ import annotations

import math
import time

import numpy as np

import synth.cams as cams
from synth.cams.profile import limit_figures
from bench._timing import median_of

r = math.radians
SEGMENTS = (cams.Segment("rise", r(120), 0.02, "cycloidal"), cams.Segment("dwell", r(60)),
            cams.Segment("return", r(120), 0.02, "polynomial_345"), cams.Segment("dwell", r(60)))
FOLLOWER = cams.Follower("translating", "roller", 0.01)
BOUNDS = (0.005, 0.2)
LIMITS = cams.CamLimits(r(30), r(45), 0.0, BOUNDS)
THETA = np.linspace(0.0, 2 * math.pi, 720, endpoint=False)
MOTION = cams.follower_motion(SEGMENTS, THETA)
RISE = np.array([s.kind for s in SEGMENTS])[MOTION.segment] == "rise"
RETURN = np.array([s.kind for s in SEGMENTS])[MOTION.segment] == "return"


def _feasible(base: float, offset: float) -> bool:
    follower = cams.Follower("translating", "roller", 0.01, offset)
    try:
        alpha = np.abs(limit_figures(follower, base, MOTION)[0])
    except cams.InvalidInput:
        return False
    return bool(alpha[RISE].max() <= LIMITS.max_pressure_rise and alpha[RETURN].max() <= LIMITS.max_pressure_return)


def brute_radius(offset: float, step: float) -> float:
    """The least radius on a grid of ``step`` [m] over the bounds."""
    for base in np.arange(BOUNDS[0], BOUNDS[1], step):
        if _feasible(float(base), offset):
            return float(base)
    return math.inf


def brute_free(offsets: int, radii: int) -> tuple[float, float]:
    """The least radius and its offset on a grid of offsets by radii."""
    best = (math.inf, 0.0)
    for e in np.linspace(-0.02, 0.02, offsets):
        for base in np.geomspace(BOUNDS[0], BOUNDS[1], radii):
            if _feasible(float(base), float(e)):
                best = min(best, (float(base), float(e)))
                break
    return best


def per_angle_geometry(spec: cams.CamSpec) -> list[float]:
    """The pressure angle one cam angle at a time, the way a loop over angles would compute it."""
    out = []
    for k in range(len(THETA)):
        m = cams.follower_motion(spec.segments, THETA[k:k + 1])
        out.append(float(cams.cam_geometry(spec.follower, spec.base_radius, m).pressure_angle[0]))
    return out


def main() -> None:
    least = cams.least_cam(SEGMENTS, FOLLOWER, LIMITS)
    t_engine = median_of(lambda: cams.least_cam(SEGMENTS, FOLLOWER, LIMITS), 5)
    t0 = time.perf_counter()
    brute = brute_radius(0.0, 1e-5)
    t_brute = time.perf_counter() - t0
    print(f"least base radius, fixed offset: engine {least.base_radius * 1e3:.6f} mm in {t_engine * 1e3:.1f} ms "
          f"({least.evaluations} cams); dense search every 0.01 mm {brute * 1e3:.3f} mm in {t_brute * 1e3:.0f} ms; "
          f"ratio {t_brute / t_engine:.1f}x, engine - brute = {(least.base_radius - brute) * 1e6:+.2f} um")

    free_limits = cams.CamLimits(r(30), r(45), 0.0, BOUNDS, (-0.02, 0.02))
    t0 = time.perf_counter()
    free = cams.least_cam(SEGMENTS, FOLLOWER, free_limits)
    t_free = time.perf_counter() - t0
    t0 = time.perf_counter()
    grid_radius, grid_offset = brute_free(41, 401)
    t_grid = time.perf_counter() - t0
    print(f"least base radius, free offset: engine {free.base_radius * 1e3:.5f} mm at e = {free.offset * 1e3:.4f} "
          f"mm in {t_free:.2f} s; grid 41 x 401 {grid_radius * 1e3:.4f} mm at e = {grid_offset * 1e3:.3f} mm in "
          f"{t_grid:.2f} s; ratio {t_grid / t_free:.1f}x, the grid's answer is "
          f"{(grid_radius / free.base_radius - 1) * 100:.2f} % larger")

    spec = cams.CamSpec(SEGMENTS, cams.Follower("translating", "roller", 0.01, 0.005), 10 * math.pi, 0.04,
                        loads=cams.PairLoads(2.0, 10 * math.pi))
    t_an = median_of(lambda: cams.analyse_cam(spec), 5)
    t_loop = median_of(lambda: per_angle_geometry(spec), 2)
    an = cams.analyse_cam(spec)
    diff = float(np.max(np.abs(np.array(per_angle_geometry(spec)) - an.geometry.pressure_angle)))
    print(f"analysis of one cam, 720 angles with checks and forces: {t_an * 1e3:.1f} ms; the geometry alone one "
          f"angle at a time {t_loop * 1e3:.0f} ms; ratio {t_loop / t_an:.1f}x (max difference {diff:.1e} rad)")


if __name__ == "__main__":
    main()
