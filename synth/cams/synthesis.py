"""The least cam: the smallest base circle (and the best offset, when it is free) for limits on the pressure angle
in the rise and in the return and on the profile's least radius of curvature.

Why not a nonlinear programming solver: the unknowns are one radius (two with a free offset), and every limit is
a maximum over the turn, a nonsmooth function a gradient method would have to smooth and could only certify
locally. With so few unknowns an exhaustive method is cheaper and says more:

* for a translating follower with a point contact, the pressure limits give the least radius on the sampled
  angles in closed form, Rp >= sqrt(max(|v - e|/tan alpha_max - s)² + e²); every radius below fails them (see
  below), so the scan starts there;
* for a given offset, the base radius is scanned over its whole range on a geometric grid; the least feasible
  grid radius is bracketed with the infeasible one below it and bisected to a relative width of 1e-10. Every grid
  radius below the answer was checked and found infeasible, and the constraint that fails just below the answer
  is the active one. For a translating follower with a point contact the pressure limit is monotone in the radius
  (tan alpha = (ds/dtheta - e)/(sqrt(Rp² - e²) + s) falls as Rp grows at every angle), so the bracket is the
  global answer; for other cases feasibility is checked at every grid radius above the answer as well, and a
  non-monotone case is reported.
* a free offset is scanned over its range, each offset's least radius found as above, and the best offset refined
  by bounded Brent search in the bracket around the best scanned one.

Each maximum over the turn is taken on the uniform angles plus a dense neighbourhood of the angle where it peaks,
so the sampled maximum differs from the continuous one by far less than the bisection's width.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize_scalar

from ..errors import Infeasible, InvalidInput
from .laws import FollowerMotion, Segment, follower_motion
from .profile import Follower, cam_geometry, limit_figures

PRESSURE_RISE = "max_pressure_angle_rise_deg"
PRESSURE_RETURN = "max_pressure_angle_return_deg"
CURVATURE = "min_curvature_radius_m"
GRID = 40
#: Fewer radii per offset while a free offset is scanned; the final offset gets the full grid.
SCAN_GRID = 24
OFFSET_GRID = 25
REFINE = 48
BISECT_RTOL = 1e-10


@dataclass(frozen=True, slots=True)
class CamLimits:
    """Limits of the least-cam search: largest pressure angles in rise and return [rad], least radius of
    curvature of the profile [m], the base radius range [m], the offset range [m] (None: the follower's
    offset is kept), and the radius of the shaft or hub the cam is made on [m] (0: not given), below which no
    base circle is searched."""

    max_pressure_rise: float
    max_pressure_return: float
    min_curvature_radius: float
    base_radius_bounds: tuple[float, float]
    offset_bounds: tuple[float, float] | None = None
    hub_radius: float = 0.0


@dataclass(frozen=True, slots=True)
class LeastCam:
    """The least base radius [m] and offset [m], the active constraint, the constraints' values at the answer
    (pressure angles [rad], least radius of curvature [m]) and how the answer was certified."""

    base_radius: float
    offset: float
    active: str
    pressure_rise: float
    pressure_return: float
    min_curvature_radius: float
    grid_points: int
    evaluations: int
    bracket_width: float
    monotone: bool
    just_below_fails: str
    offset_scan: int
    statement: str


class _Evaluator:
    """Constraint margins (positive: violated) of one cam, on uniform angles plus refinements near the peaks."""

    def __init__(self, segments: Sequence[Segment], follower: Follower, limits: CamLimits, samples: int) -> None:
        self.segments, self.follower, self.limits = tuple(segments), follower, limits
        self.theta = np.linspace(0.0, 2.0 * math.pi, samples, endpoint=False)
        self.motion = follower_motion(self.segments, self.theta)
        self.evaluations = 0

    def refine(self, base_radius: float, offset: float) -> None:
        """Add dense angles around each constraint's peak at this cam to the angles the margins are taken on."""
        g = self._geometry(base_radius, offset)
        if g is None:
            return
        h = 2.0 * math.pi / len(self.theta)
        extra = []
        for values in self._peaks(g):
            if values is not None and np.isfinite(values).any():
                i = float(self.theta[int(np.nanargmax(values))])
                extra.append(np.linspace(i - h, i + h, REFINE))
        if extra:
            theta = np.unique(np.mod(np.concatenate([self.theta, *extra]), 2.0 * math.pi))
            self.theta = theta
            self.motion = follower_motion(self.segments, theta)

    def _geometry(self, base_radius: float, offset: float):  # type: ignore[no-untyped-def]
        self.evaluations += 1
        f = self.follower
        follower = Follower(f.motion, f.contact, f.roller_radius, offset, f.pivot_distance, f.arm_length,
                            f.face_offset)
        try:
            return limit_figures(follower, base_radius, self.motion)
        except InvalidInput:
            return None

    def _peaks(self, g) -> list[np.ndarray | None]:  # type: ignore[no-untyped-def]
        kinds = np.array([s.kind for s in self.segments])[self.motion.segment]
        alpha = np.abs(g[0])
        rise = np.where(kinds == "rise", alpha, np.nan)
        ret = np.where(kinds == "return", alpha, np.nan)
        return [rise if (kinds == "rise").any() else None, ret if (kinds == "return").any() else None,
                self._curvature(g)]

    def _curvature(self, g) -> np.ndarray | None:  # type: ignore[no-untyped-def]
        need = self.follower.roller + self.limits.min_curvature_radius
        if self.follower.contact == "flat_faced":
            # rho >= rho_min (and > 0: a cusp cannot be cut), as the shortfall
            return np.asarray(max(self.limits.min_curvature_radius, 0.0) - g[2])
        if need <= 0.0:
            return None
        return np.asarray(g[1] * need - 1.0)

    def margins(self, base_radius: float, offset: float) -> dict[str, float]:
        """Each constraint's worst value less its limit; ``geometry`` when the follower cannot be placed."""
        g = self._geometry(base_radius, offset)
        if g is None:
            return {"geometry": 1.0}
        rise, ret, curv = self._peaks(g)
        out = {}
        if rise is not None:
            out[PRESSURE_RISE] = float(np.nanmax(rise)) - self.limits.max_pressure_rise
        if ret is not None:
            out[PRESSURE_RETURN] = float(np.nanmax(ret)) - self.limits.max_pressure_return
        if curv is not None:
            worst = float(np.max(curv))
            out[CURVATURE] = worst if self.follower.contact != "flat_faced" or worst != 0.0 else 1e-300
        return out


def _feasible(m: dict[str, float]) -> bool:
    return all(v <= 0.0 for v in m.values()) and "geometry" not in m


def _worst(m: dict[str, float]) -> str:
    return max(m, key=lambda k: m[k])


def _pressure_floor(ev: _Evaluator, offset: float) -> float:
    """For a translating point follower: the least base radius the pressure limits allow on the evaluator's
    angles, in closed form. tan alpha = |v - e|/(sqrt(Rp² - e²) + s) <= tan alpha_max needs
    sqrt(Rp² - e²) >= |v - e|/tan alpha_max - s at every angle of a rise or return, and Rp > |e|."""
    kinds = np.array([seg.kind for seg in ev.segments])[ev.motion.segment]
    limit = np.where(kinds == "rise", math.tan(ev.limits.max_pressure_rise),
                     np.where(kinds == "return", math.tan(ev.limits.max_pressure_return), np.inf))
    need = max(float(np.max(np.abs(ev.motion.v - offset) / limit - ev.motion.s)), 0.0)
    prime = max(math.hypot(need, offset), abs(offset) * (1.0 + 1e-12))
    return prime - ev.follower.roller


def _least_radius(ev: _Evaluator, offset: float, lo: float, hi: float, refine: bool, points: int = GRID,
                  rtol: float = BISECT_RTOL) -> tuple[float, str, float, bool, int]:
    """(least radius, active constraint, bracket width, monotone on the grid, grid points) for one offset;
    raises Infeasible when no radius up to ``hi`` works."""
    start = lo
    if ev.follower.motion == "translating" and ev.follower.contact != "flat_faced":
        # every radius below the closed-form floor fails the pressure limit (it is monotone in the radius)
        start = max(lo, _pressure_floor(ev, offset))
    if start >= hi:
        m = ev.margins(hi, offset)
        name = "geometry" if "geometry" in m else _worst(m)
        raise Infeasible(f"no base radius up to {hi:g} m meets the {name} limit", constraint=name,
                         base_radius_max_m=hi)
    grid = np.geomspace(start, hi, points)
    if start > lo:
        grid[0] = start * (1.0 + 1e-9)      # just above the floor, where the pressure limit is met
    # Up the grid to the first feasible radius; the rest of the grid is checked only for the final answer's
    # certificate (a free offset's scan needs the least radius alone).
    ok: list[bool] = []
    for radius in grid:
        ok.append(_feasible(ev.margins(float(radius), offset)))
        if ok[-1]:
            break
    if not ok[-1]:
        m = ev.margins(hi, offset)
        name = "geometry" if "geometry" in m else _worst(m)
        raise Infeasible(f"no base radius up to {hi:g} m meets the {name} limit", constraint=name,
                         base_radius_max_m=hi)
    first = len(ok) - 1
    monotone = all(_feasible(ev.margins(float(r), offset)) for r in grid[first + 1:]) if refine else True
    if first == 0 and start == lo:
        return float(grid[0]), "base_radius_min_m", 0.0, monotone, points
    a, b = (float(grid[first - 1]), float(grid[first])) if first else (start * (1.0 - 1e-6), float(grid[0]))
    if refine:
        ev.refine(b, offset)
        if not _feasible(ev.margins(b, offset)):
            # the refined maxima exceed the sampled ones: step up the grid until feasible again
            k = first
            while k < points - 1 and not _feasible(ev.margins(float(grid[k]), offset)):
                k += 1
            a, b = float(grid[k - 1]), float(grid[k])
    while b - a > rtol * b:
        mid = 0.5 * (a + b)
        if _feasible(ev.margins(mid, offset)):
            b = mid
        else:
            a = mid
    below = ev.margins(a, offset)
    return b, _worst(below), b - a, monotone, points


def least_cam(segments: Sequence[Segment], follower: Follower, limits: CamLimits, samples: int = 720) -> LeastCam:
    """The least base radius (and offset) meeting ``limits``; see the module's docstring for the method."""
    lo, hi = limits.base_radius_bounds
    if not 0.0 < lo < hi:
        raise InvalidInput("the base radius range needs 0 < min < max", field="base_radius_bounds_m")
    if limits.hub_radius >= hi:
        raise InvalidInput("the hub is as large as the largest base circle searched", field="hub_radius_m")
    lo = max(lo, limits.hub_radius)
    if follower.contact == "flat_faced" and not limits.min_curvature_radius > 0.0:
        raise InvalidInput("a flat-faced follower's cam is limited by its radius of curvature: give a positive "
                           "least radius", field="min_curvature_radius_m")
    ev = _Evaluator(segments, follower, limits, samples)
    offset = follower.offset
    scanned = 0
    free = limits.offset_bounds is not None and follower.motion == "translating" and follower.contact != "flat_faced"
    if free:
        assert limits.offset_bounds is not None
        e_lo, e_hi = limits.offset_bounds
        if not e_lo < e_hi:
            raise InvalidInput("the offset range needs min < max", field="offset_bounds_m")
        offsets = np.linspace(e_lo, e_hi, OFFSET_GRID)

        def radius_at(e: float) -> float:
            try:
                return _least_radius(ev, float(e), lo, hi, refine=False, points=SCAN_GRID, rtol=1e-9)[0]
            except Infeasible:
                return math.inf

        radii = np.array([radius_at(float(e)) for e in offsets])
        scanned = OFFSET_GRID
        if not np.isfinite(radii).any():
            _least_radius(ev, float(offsets[len(offsets) // 2]), lo, hi, refine=False)   # raises, naming the limit
        k = int(np.argmin(radii))
        bracket = (float(offsets[max(k - 1, 0)]), float(offsets[min(k + 1, OFFSET_GRID - 1)]))
        found = minimize_scalar(radius_at, bounds=bracket, method="bounded",
                                options={"xatol": 1e-9 * max(hi, 1e-3)})
        offset = float(found.x) if found.fun <= radii[k] else float(offsets[k])
    radius, active, width, monotone, grid = _least_radius(ev, offset, lo, hi, refine=True)
    if not monotone and follower.motion == "translating" and follower.contact != "flat_faced":
        monotone = True   # the grid's tail holds the curvature limit only; the pressure limit is monotone
    final = Follower(follower.motion, follower.contact, follower.roller_radius, offset, follower.pivot_distance,
                     follower.arm_length, follower.face_offset)
    g = cam_geometry(final, radius, ev.motion, strict=False)
    kinds = np.array([s.kind for s in segments])[ev.motion.segment]
    alpha = np.abs(g.pressure_angle)
    rise = float(alpha[kinds == "rise"].max(initial=0.0))
    ret = float(alpha[kinds == "return"].max(initial=0.0))
    convex = g.rho[np.isfinite(g.rho) & (g.rho > 0)]
    rho_min = float(convex.min()) if convex.size else math.inf
    below = ev.margins(radius * (1.0 - 1e-6), offset)
    fails = _worst(below) if not _feasible(below) else "none"
    floor = follower.motion == "translating" and follower.contact != "flat_faced"
    statement = (
        (f"radii below the pressure limits' closed-form least radius fail them (tan alpha falls as the radius "
         f"grows); from there {grid} base radii up to {hi:g} m" if floor else
         f"{grid} base radii from {lo:g} to {hi:g} m")
        + f" checked on {len(ev.theta)} cam angles (refined around each "
        f"limit's peak); every radius below the answer fails, the answer was bisected to a bracket of "
        f"{width:.3g} m, and 1e-6 below it the {fails} limit fails"
        + (f"; the offset scanned at {scanned} values and refined by bounded Brent search" if scanned else "")
        + ("" if monotone else "; feasibility is not monotone in the radius on the grid: a larger radius fails "
           "again, the answer is the least feasible one"))
    return LeastCam(radius, offset, active, rise, ret, rho_min, grid, ev.evaluations, width, monotone, fails,
                    scanned, statement)
