"""Path generation: a crank-rocker four-bar whose coupler point passes through (or nearest to) target points.

A nonconvex least-squares problem over the crank pivot (x, y), the ground angle, the four lengths, the coupler
point in the coupler frame and the crank angle at each target (or one starting angle when the angles are
prescribed up to a common shift). The coupler position is the closed-form assembly of the requested branch; the
Grashof crank-rocker conditions (crank shortest, shortest + longest <= sum of the other two) hold at the answer,
so the linkage assembles at every crank angle and never changes branch. Everything is worked in units of the
targets' extent about their centre, where every length and angle is of order one.

The problem has many local minima, so it is started from scrambled-Sobol points (scipy.stats.qmc, seeded), and
every start is screened by a compiled Levenberg-Marquardt iteration over its stacked residuals with the coupler
point's analytic Jacobian, each start with its own damping, the constraints (Grashof margins, transmission angle,
crank angles in order within one turn, the bounds) as penalty rows of the same least squares.
The best distinct designs it reaches are then polished by IPOPT on the exact constrained problem (residuals
lifted into variables, r = P - T as equalities, so IPOPT meets a Gauss-Newton-like Hessian near a fit), warm
started at the screened point; IPOPT's status is the certificate of each. Every distinct fit is answered with how
many starts reached it, and the residual at every target is recomputed by the kinematics engine. The
Roberts-Chebyshev cognates of the answer trace the same curve and are given in closed form.
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, cast

import casadi as ca
import numpy as np
from scipy.stats import qmc

from ..analysis import analyse
from ..errors import Infeasible, InvalidInput, SolverFailed, SolverTimeout, TooLarge
from ..kinematics import FourBar, Mechanism, motion
from ..model import FloatArray, Linkage
from .checks import LinkageCheck, check_fourbar
from .cognates import cognates
from .path_screening import first_shifts, screen

MAX_POINTS = 40
MAX_STARTS = 256
GRASHOF_MARGIN = 1e-3  # least slack of each Grashof inequality, in units of the targets' extent
_LENGTHS = ("crank", "coupler", "rocker", "ground")
_DESIGN = 9  # crank pivot x, y, ground angle, crank, coupler, rocker, ground, coupler point x, y
# How fits equally near the targets are ordered: least residual (where their residuals differ by round-off only,
# most starts reaching it), largest least transmission angle (its least deviation from 90° taken both ways), least
# ratio of the longest link to the shortest, most starts reaching it.
RANKINGS = ("residual", "transmission_angle", "link_ratio", "starts")
SCREEN_ITERATIONS = 40
MAX_POLISHED = 4
# Screened starts within this distance of each other (design coordinates in units of the targets' extent, the
# ground angle in radians) are taken for one design; polished designs closer than _SAME_FIT are one fit.
_SAME_BASIN = 0.05
_SAME_FIT = 1e-6


@dataclass(frozen=True, slots=True)
class PathSpec:
    """Target points and the limits of the four-bar that should trace them.

    targets: (N, 2) points [m] in the order the coupler point should pass them while the crank turns
    counter-clockwise; crank_angles: (N,) crank angles [rad] at the targets, fixed up to a common shift, or None
    (free, increasing, within one turn); bounds: link -> (min, max) length [m] for every one of crank, coupler,
    rocker, ground; pivot_box: (x_min, x_max, y_min, y_max) for both ground pivots [m]; coupler_point_max: bound on
    each coordinate of the coupler point in the coupler frame [m]; branch: +1, -1, or 0 to try both (half the
    starts each); starts: number of multistart points; seed: Sobol scrambling seed; time_limit: wall-clock budget
    for all starts [s]; min_transmission_angle: lowest admissible transmission angle over the cycle [rad];
    rank_by: how fits equally near the targets are ordered, one of :data:`RANKINGS`.
    """

    targets: FloatArray
    crank_angles: FloatArray | None
    bounds: dict[str, tuple[float, float]]
    pivot_box: tuple[float, float, float, float]
    coupler_point_max: float
    branch: int = 0
    starts: int = 32
    seed: int = 0
    time_limit: float = 20.0
    min_transmission_angle: float = 0.0
    rank_by: str = "residual"

    def validate(self) -> None:
        """Raise InvalidInput or TooLarge naming the field that cannot be used."""
        t = np.asarray(self.targets, dtype=float)
        if t.ndim != 2 or t.shape[1] != 2 or t.shape[0] < 3:
            raise InvalidInput("give at least three target points as [x, y] pairs", field="points_m")
        if t.shape[0] > MAX_POINTS:
            raise TooLarge("target points", MAX_POINTS, t.shape[0], field="points_m")
        if not np.all(np.isfinite(t)):
            raise InvalidInput("target points must be finite", field="points_m")
        if self.crank_angles is not None and np.asarray(self.crank_angles).shape != (t.shape[0],):
            raise InvalidInput("give one crank angle per target point", field="crank_angle_deg")
        if not 1 <= self.starts <= MAX_STARTS:
            raise TooLarge("starts", MAX_STARTS, self.starts) if self.starts > MAX_STARTS else InvalidInput(
                "at least one start is needed", field="starts")
        for name in _LENGTHS:
            lo, hi = self.bounds.get(name, (math.nan, math.nan))
            if not (0.0 < lo < hi and math.isfinite(hi)):
                raise InvalidInput(f"bounds of {name}: need 0 < min < max", field=f"bounds.{name}")
        x0, x1, y0, y1 = self.pivot_box
        if not (x0 < x1 and y0 < y1):
            raise InvalidInput("pivot box: need x_min < x_max and y_min < y_max", field="pivot_box_m")
        if not self.coupler_point_max > 0:
            raise InvalidInput("coupler_point_max must be positive", field="coupler_point_max_m")
        if self.branch not in (-1, 0, 1):
            raise InvalidInput("branch must be -1, 0 or +1", field="branch")
        if not self.time_limit > 0:
            raise InvalidInput("the time limit must be positive", field="time_limit_s")
        if not 0.0 <= self.min_transmission_angle < 0.5 * math.pi:
            raise InvalidInput("the least transmission angle must lie in [0°, 90°)", field="min_transmission_angle_deg")
        if self.rank_by not in RANKINGS:
            raise InvalidInput(f"rank_by must be one of {', '.join(RANKINGS)}", field="rank_by")


@dataclass(frozen=True, slots=True)
class PathFit:
    """One four-bar through (or near) the targets, placed in the targets' frame, with the engine's residuals.

    ``linkage``: the four-bar in its own frame (crank pivot at the origin, rocker pivot on +x);
    ``coupler_point``: in the coupler frame [m]; ``crank_pivot`` [m] and ``ground_angle`` [rad]: where that frame
    sits among the targets; ``crank_angles``: its driver's angle at each target [rad]; ``residuals``: distance
    from each target to the coupler point recomputed by the analysis engine [m]; ``starts``: starts whose
    screening ended in this design's basin (0 for a cognate no start reached); ``status``: IPOPT's status of its
    polish (``cognate`` for one built in closed form); ``check``: swing, time ratio and transmission angles from
    the engine, for a crank-rocker (None otherwise: a cognate driven by a rocker).
    """

    linkage: Linkage
    coupler_point: tuple[float, float]
    crank_pivot: tuple[float, float]
    ground_angle: float
    crank_angles: FloatArray
    residuals: FloatArray
    starts: int
    status: str
    check: LinkageCheck | None

    @property
    def fourbar(self) -> FourBar:
        """The four-bar."""
        mech = self.linkage.mechanism
        assert isinstance(mech, FourBar)
        return mech

    @property
    def rms_residual(self) -> float:
        """RMS of the residuals [m]."""
        return float(np.sqrt(np.mean(self.residuals**2)))


@dataclass(frozen=True, slots=True)
class PathResult:
    """The best four-bar, every distinct fit the starts reached and the answer's cognates.

    The answer's fields are those of :class:`PathFit` (it is ``fits[0]``); ``start_objectives``: sum of squared
    residuals [m²] where each start's screening ended (NaN where it broke down); ``starts_at_best``: starts whose
    screening ended in the answer's basin; ``fits``: the distinct designs polished, ranked by ``spec.rank_by``
    among those as near the targets as the best, then by residual; ``cognates``: the answer's two
    Roberts-Chebyshev cognates, which trace the same curve.
    """

    linkage: Linkage
    coupler_point: tuple[float, float]
    crank_pivot: tuple[float, float]
    ground_angle: float
    crank_angles: FloatArray
    residuals: FloatArray
    start_objectives: FloatArray
    starts_at_best: int
    status: str
    check: LinkageCheck
    fits: tuple[PathFit, ...] = ()
    cognates: tuple[PathFit, ...] = ()

    @property
    def fourbar(self) -> FourBar:
        """The synthesised four-bar."""
        mech = self.linkage.mechanism
        assert isinstance(mech, FourBar)
        return mech


def default_path_limits(
    targets: FloatArray,
) -> tuple[dict[str, tuple[float, float]], tuple[float, float, float, float], float]:
    """Limits that suit targets of extent D (their bounding box's larger side) [m]: every link between D/50 and
    4·D, both pivots within 2·D of the targets' bounding box, coupler point coordinates within 4·D."""
    t = np.asarray(targets, dtype=float)
    lo, hi = t.min(axis=0), t.max(axis=0)
    size = float(max(hi - lo)) or 1.0
    bounds = {name: (0.02 * size, 4.0 * size) for name in _LENGTHS}
    box = (float(lo[0] - 2 * size), float(hi[0] + 2 * size), float(lo[1] - 2 * size), float(hi[1] + 2 * size))
    return bounds, box, 4.0 * size


def _coupler_points(z: Any, phi: Any, branch: Any) -> tuple[Any, Any]:
    """World x and y of the coupler point at crank angles ``phi`` for design ``z`` (CasADi or NumPy)."""
    lib = ca if isinstance(z, (ca.MX, ca.SX)) else np
    xo, yo, th, a, b, c, d, px, py = (z[i] for i in range(_DESIGN))
    ax, ay = xo + a * lib.cos(th + phi), yo + a * lib.sin(th + phi)
    qx, qy = xo + d * lib.cos(th), yo + d * lib.sin(th)
    ex, ey = qx - ax, qy - ay
    dist = lib.sqrt(ex * ex + ey * ey)
    ux, uy = ex / dist, ey / dist
    x = (b * b - c * c + dist * dist) / (2 * dist)
    # The clamp only acts away from a solution: the Grashof constraints keep b² - x² positive there.
    h = lib.sqrt(lib.fmax(b * b - x * x, 1e-18))
    bx, by = ax + x * ux - branch * h * uy, ay + x * uy + branch * h * ux
    e2x, e2y = (bx - ax) / b, (by - ay) / b
    return ax + px * e2x - py * e2y, ay + px * e2y + py * e2x


@functools.lru_cache(maxsize=32)
def _program(n: int, timed: bool, branch: int) -> Any:
    """The NLP for ``n`` targets, built once per worker and reused with new data through its parameters.

    Lengths are in units of the targets' extent and positions are taken from the targets' centre (see
    :class:`_Frame`), so the objective is the sum of squared residuals over the extent squared.
    """
    z = ca.SX.sym("z", _DESIGN)
    phi = ca.SX.sym("phi", 1 if timed else n)
    targets = ca.SX.sym("targets", n, 2)
    offsets = ca.SX.sym("offsets", n)
    cos_mu = ca.SX.sym("cos_mu")
    angles = phi[0] + offsets if timed else phi
    px, py = _coupler_points(z, angles, float(branch))
    # Lifted residuals: with r as variables and r = P - T as equalities, the Lagrangian's Hessian tends to the
    # Gauss-Newton one as the residual vanishes, which IPOPT converges on far faster than on the plain sum.
    r = ca.SX.sym("r", 2 * n)
    f = ca.sumsqr(r)
    a, b, c, d = z[3], z[4], z[5], z[6]
    g = [b - a, c - a, d - a, c + d - a - b, b + d - a - c, b + c - a - d]
    # The transmission angle's extremes are at crank angles 0 and 180° (crank along the ground line):
    # |b² + c² - (d -+ a)²| <= 2·b·c·cos(mu_min).
    for far in (d - a, d + a):
        cosine = b * b + c * c - far * far
        g += [2 * b * c * cos_mu - cosine, 2 * b * c * cos_mu + cosine]
    if not timed:
        g += [phi[i + 1] - phi[i] for i in range(n - 1)] + [phi[0] + 2 * math.pi - phi[n - 1]]
    g += [ca.vertcat(px - targets[:, 0], py - targets[:, 1]) - r]
    nlp = {"x": ca.vertcat(z, phi, r), "p": ca.vertcat(ca.vec(targets), offsets, cos_mu), "f": f, "g": ca.vertcat(*g)}
    # IPOPT backs off from a trial point where the assembly is undefined; that is routine, not worth a log line.
    # A KKT system of about a hundred rows is solved to round-off by one factorisation, so IPOPT's residual check
    # and iterative refinement of each step (fast_step_computation off) only cost time. It starts at the screened
    # point, near a minimum: a small barrier parameter and bound push keep it there instead of pushing it back
    # into the interior and walking the way again.
    opts: dict[str, Any] = {"print_time": False, "show_eval_warnings": False, "ipopt.print_level": 0, "ipopt.sb": "yes",
                            "ipopt.tol": 1e-12, "ipopt.acceptable_tol": 1e-9, "ipopt.max_iter": 120,
                            "ipopt.fast_step_computation": "yes", "ipopt.mu_init": 1e-9,
                            "ipopt.warm_start_init_point": "yes", "ipopt.warm_start_bound_push": 1e-12,
                            "ipopt.warm_start_mult_bound_push": 1e-12, "ipopt.warm_start_slack_bound_push": 1e-12}
    return ca.nlpsol("path", "ipopt", nlp, opts)


@dataclass(frozen=True, slots=True)
class _Frame:
    """Where IPOPT works: positions from ``centre`` [m] and lengths in units of ``scale`` [m], the targets'
    centre and extent. The design vector is (pivot x, y, ground angle, four lengths, coupler point x, y)."""

    centre: FloatArray
    scale: float

    def to_unit(self, z: FloatArray) -> FloatArray:
        """Designs (..., 9) from metres to the working frame."""
        u = np.array(z, dtype=float)
        u[..., 0:2] = (u[..., 0:2] - self.centre) / self.scale
        u[..., 3:_DESIGN] /= self.scale
        return u

    def to_metres(self, u: FloatArray) -> FloatArray:
        """Designs (..., 9) from the working frame to metres."""
        z = np.array(u, dtype=float)
        z[..., 0:2] = z[..., 0:2] * self.scale + self.centre
        z[..., 3:_DESIGN] *= self.scale
        return z


@functools.lru_cache(maxsize=16)
def _sobol(seed: int, starts: int) -> FloatArray:
    """The first ``starts`` scrambled-Sobol points in the unit cube of the design and the first crank angle, read
    only: most requests ask for the default seed and number of starts, and scipy's generator costs about as much
    to set up as a quarter of the screening."""
    unit = qmc.Sobol(_DESIGN + 1, scramble=True, seed=seed).random(starts)
    unit.setflags(write=False)
    return np.asarray(unit)


def _starts(spec: PathSpec) -> FloatArray:
    """Scrambled-Sobol designs over the bounds: pivot, ground angle, lengths, coupler point; the first crank
    angle is then fitted to the targets."""
    lo, hi = _box(spec)
    unit = _sobol(spec.seed, spec.starts)
    x = lo + unit * (hi - lo)
    # The crank's coordinate becomes a fraction of the longest crank that keeps the start a Grashof crank-rocker
    # with the sampled coupler, rocker and ground, so every start assembles at every angle.
    # First the longest of the three is shortened until the other two outreach it by twice the least crank.
    rest = x[:, 4:7]
    j = np.argmax(rest, axis=1)
    rows = np.arange(len(x))
    others = rest.sum(axis=1) - rest[rows, j]
    rest[rows, j] = np.clip(np.minimum(rest[rows, j], others - 2 * lo[3]), lo[4 + j], hi[4 + j])
    b, c, d = x[:, 4], x[:, 5], x[:, 6]
    a_max = np.minimum.reduce([b, c, d, c + d - b, b + d - c, b + c - d, np.full_like(b, hi[3])])
    room = a_max > lo[3]
    x[room, 3] = lo[3] + unit[room, 3] * (a_max[room] - lo[3])
    return np.asarray(x)


def _first_angles(starts: FloatArray, targets: FloatArray, offsets: FloatArray, timed: bool,
                  branches: FloatArray) -> FloatArray:
    """Crank angles to start from, one row per start design (k, 9) with its branch (k,): evenly spread (or the
    prescribed offsets), turned by whichever of 72 shifts puts that design's coupler point nearest the targets.
    Rows of (k, 1) first angles when ``timed``, else (k, n)."""
    n = targets.shape[0]
    steps = offsets if timed else 2 * math.pi * np.arange(n) / n
    shifts = np.linspace(0.0, 2 * math.pi, 72, endpoint=False)
    phi = shifts[:, None] + steps[None, :]
    nearest = first_shifts(np.ascontiguousarray(starts[:, :_DESIGN], dtype=float),
                           np.ascontiguousarray(branches, dtype=float), np.ascontiguousarray(targets, dtype=float), phi)
    first = shifts[nearest.astype(np.intp)][:, None]
    return np.asarray(first if timed else first + steps[None, :])


def _box(spec: PathSpec) -> tuple[FloatArray, FloatArray]:
    x0, x1, y0, y1 = spec.pivot_box
    cp = spec.coupler_point_max
    lo = [x0, y0, -math.pi] + [spec.bounds[n][0] for n in _LENGTHS] + [-cp, -cp, 0.0]
    hi = [x1, y1, math.pi] + [spec.bounds[n][1] for n in _LENGTHS] + [cp, cp, 2 * math.pi]
    return np.array(lo), np.array(hi)


@dataclass(frozen=True, slots=True)
class PathStarts:
    """Where one chunk of the multistart's screening ended, start by start: the indices run, the sum of squared
    residuals of each [over the targets' extent squared] (NaN where the screening broke down), its unknowns in
    the working frame (design, crank angles) and branch, and the screening's iterations."""

    indices: tuple[int, ...]
    objectives: FloatArray
    unknowns: FloatArray
    branches: FloatArray
    iterations: int = 0


def start_chunks(spec: PathSpec, chunks: int) -> list[tuple[int, ...]]:
    """The starts dealt into at most ``chunks`` groups to run side by side, in pairs (starts 2j and 2j + 1, one
    on each assembly branch, to group j mod chunks): each group mixes both branches and early and late Sobol
    points, so the groups take about equally long."""
    count = max(1, min(chunks, spec.starts))
    groups = [tuple(k for k in range(spec.starts) if (k // 2) % count == i) for i in range(count)]
    return [g for g in groups if g]


def _problem(spec: PathSpec) -> tuple[FloatArray, FloatArray, bool, _Frame, FloatArray, dict[str, FloatArray]]:
    """Targets [m], crank-angle offsets, whether the angles are prescribed, the working frame, the NLP's
    parameters and its bounds (both in the working frame); Infeasible when the crank cannot be the shortest link."""
    spec.validate()
    crank_lo = spec.bounds["crank"][0]
    if crank_lo >= min(spec.bounds[n][1] for n in ("coupler", "rocker", "ground")):
        raise Infeasible("the crank's least length reaches another link's greatest: it cannot be the shortest link",
                         constraint="crank_shortest")
    targets = np.asarray(spec.targets, dtype=float)
    n = targets.shape[0]
    timed = spec.crank_angles is not None
    offsets = np.zeros(n) if spec.crank_angles is None else np.asarray(spec.crank_angles) - spec.crank_angles[0]
    frame = _Frame(0.5 * (targets.min(axis=0) + targets.max(axis=0)), float(np.ptp(targets, axis=0).max()) or 1.0)
    unit_targets = (targets - frame.centre) / frame.scale
    params = np.concatenate([unit_targets.T.reshape(-1), offsets, [math.cos(spec.min_transmission_angle)]])
    lo, hi = (frame.to_unit(v[:_DESIGN]) for v in _box(spec))
    # The ground angle is periodic: a wider box than one turn lets a start slide past +-pi.
    lo[2], hi[2] = -3 * math.pi, 3 * math.pi
    n_phi = 1 if timed else n
    n_g = 10 + (0 if timed else n)
    # A margin keeps the answer off the Grashof limit, where the coupler and rocker would fold flat.
    bounds = {
        "lbx": np.concatenate([lo, np.full(n_phi, -4 * math.pi), np.full(2 * n, -np.inf)]),
        "ubx": np.concatenate([hi, np.full(n_phi, 4 * math.pi), np.full(2 * n, np.inf)]),
        "lbg": np.concatenate([np.full(6, GRASHOF_MARGIN), np.zeros(n_g - 6), np.zeros(2 * n)]),
        "ubg": np.concatenate([np.full(n_g, np.inf), np.zeros(2 * n)]),
    }
    return targets, offsets, timed, frame, params, bounds


def _initial_points(spec: PathSpec, indices: Sequence[int], frame: _Frame, targets: FloatArray, offsets: FloatArray,
                    timed: bool) -> tuple[FloatArray, FloatArray]:
    """The starts ``indices`` as IPOPT's initial points in the working frame, one row each (design, crank
    angles, residuals at those angles), and their assembly branches."""
    branches = np.array([spec.branch or (1 if k % 2 == 0 else -1) for k in indices], dtype=float)
    designs = frame.to_unit(_starts(spec)[list(indices), :_DESIGN])
    unit_targets = (targets - frame.centre) / frame.scale
    angles = _first_angles(designs, unit_targets, offsets, timed, branches)
    with np.errstate(all="ignore"):
        px, py = _coupler_points(designs.T[:, :, None], angles + offsets if timed else angles, branches[:, None])
    residuals = np.nan_to_num(np.concatenate([px - unit_targets[:, 0], py - unit_targets[:, 1]], axis=1))
    return np.concatenate([designs, angles, residuals], axis=1), branches


def path_starts(spec: PathSpec, indices: Sequence[int]) -> PathStarts:
    """Screen the starts ``indices`` of the multistart (a chunk of :func:`start_chunks`), each from its own
    Sobol point and on its own path: a plain function of plain data, so chunks run in separate workers
    and give what one run of all starts gives. SolverTimeout past ``spec.time_limit`` counted from this call."""
    targets, offsets, timed, frame, params, bounds = _problem(spec)
    n = targets.shape[0]
    deadline = time.monotonic() + spec.time_limit
    x0, branches = _initial_points(spec, indices, frame, targets, offsets, timed)
    m = x0.shape[1] - 2 * n
    unit_targets = (targets - frame.centre) / frame.scale
    out = screen(x0[:, :m], branches, unit_targets, offsets, timed, bounds["lbx"][:m], bounds["ubx"][:m],
                 math.cos(spec.min_transmission_angle), GRASHOF_MARGIN, SCREEN_ITERATIONS, deadline, spec.time_limit)
    return PathStarts(tuple(indices), out.objectives, out.unknowns, branches, out.iterations)


def _gap(u: FloatArray, v: FloatArray) -> FloatArray:
    """Largest difference between designs (..., 9) in the working frame, the ground angle taken modulo a turn."""
    d = np.abs(u[..., :_DESIGN] - v[..., :_DESIGN])
    d[..., 2] = np.abs(np.remainder(d[..., 2] + math.pi, 2 * math.pi) - math.pi)
    return np.asarray(d.max(axis=-1))


def _polish(spec: PathSpec, u: FloatArray, branch: int) -> tuple[float, FloatArray, str] | None:
    """IPOPT on the exact problem from the screened unknowns ``u``: objective, solution and status, None when it
    does not converge."""
    targets, offsets, timed, frame, params, bounds = _problem(spec)
    n = targets.shape[0]
    unit_targets = (targets - frame.centre) / frame.scale
    with np.errstate(all="ignore"):
        px, py = _coupler_points(u[:_DESIGN], u[_DESIGN] + offsets if timed else u[_DESIGN:], float(branch))
    x0 = np.concatenate([u, np.nan_to_num(px - unit_targets[:, 0]), np.nan_to_num(py - unit_targets[:, 1])])
    solver = _program(n, timed, branch)
    sol = solver(x0=x0, p=params, **bounds)
    status = str(solver.stats()["return_status"])
    if status not in ("Solve_Succeeded", "Solved_To_Acceptable_Level"):
        return None
    return float(sol["f"]), np.asarray(sol["x"]).reshape(-1), status


def _fit(spec: PathSpec, x: FloatArray, branch: int, starts: int, status: str) -> PathFit:
    """A polished solution (working frame) placed in the targets' frame with the engine's residuals."""
    targets, offsets, timed, frame, _, _ = _problem(spec)
    n = targets.shape[0]
    z = frame.to_metres(x[:_DESIGN])
    phi = x[_DESIGN] + offsets if timed else x[_DESIGN:_DESIGN + n]
    fb = FourBar(float(z[6]), float(z[3]), float(z[4]), float(z[5]), branch)
    return PathFit(Linkage(cast(Mechanism, fb)), (float(z[7]), float(z[8])), (float(z[0]), float(z[1])),
                   float(math.remainder(z[2], 2 * math.pi)), np.mod(phi, 2 * math.pi),
                   _engine_residuals(fb, z, phi, targets), starts, status, check_fourbar(fb))


def _cognate_fits(answer: PathFit, targets: FloatArray, tolerance: float) -> tuple[PathFit, ...]:
    """The answer's cognates that pass every target on one assembly, with the engine's residuals (their
    independent check). The crank-driven cognate of a crank-rocker is a crank-rocker and always does; the
    coupler-driven one is a double-rocker whose driver reverses and whose assembly flips between the targets, so
    it is kept only where the engine finds it within ``tolerance`` [m] of them all."""
    out = []
    for cog in cognates(answer.fourbar, answer.crank_pivot, answer.ground_angle, answer.coupler_point,
                        answer.crank_angles):
        z = np.array([*cog.crank_pivot, cog.ground_angle, 0.0, 0.0, 0.0, 0.0, *cog.coupler_point])
        fb = cog.fourbar
        residuals = _engine_residuals(fb, z, cog.crank_angles, targets)
        if residuals.max() > tolerance:
            continue
        check = check_fourbar(fb) if fb.grashof == "crank-rocker" else None
        out.append(PathFit(Linkage(cast(Mechanism, fb)), cog.coupler_point, cog.crank_pivot,
                           float(math.remainder(cog.ground_angle, 2 * math.pi)), cog.crank_angles, residuals, 0,
                           "cognate", check))
    return tuple(out)


def _rank_key(rank_by: str) -> Any:
    def key(fit: PathFit) -> float:
        if rank_by == "transmission_angle" and fit.check is not None:
            return -min(fit.check.min_transmission_angle, math.pi - fit.check.max_transmission_angle)
        if rank_by == "link_ratio":
            lengths = [fit.fourbar.ground, fit.fourbar.crank, fit.fourbar.coupler, fit.fourbar.rocker]
            return max(lengths) / min(lengths)
        if rank_by == "starts":
            return -fit.starts
        return fit.rms_residual
    return key


def best_path(spec: PathSpec, parts: Sequence[PathStarts]) -> PathResult:
    """The answer from every chunk's screened starts: the distinct designs nearest the targets (at most
    :data:`MAX_POLISHED`, the best and those within ten times its objective) polished by IPOPT, each counted with
    the starts that ended in its basin, ranked, placed in the targets' frame with the engine's residuals, and the
    best one's cognates. The same whichever way the starts were dealt into chunks."""
    targets, _, _, frame, _, _ = _problem(spec)
    scale = frame.scale
    m = parts[0].unknowns.shape[1] if parts else 0
    objectives = np.full(spec.starts, np.nan)
    unknowns = np.full((spec.starts, m), np.nan)
    branches = np.zeros(spec.starts)
    for part in parts:
        rows = list(part.indices)
        objectives[rows], unknowns[rows], branches[rows] = part.objectives, part.unknowns, part.branches
    finite = np.flatnonzero(np.isfinite(objectives))
    if finite.size == 0:
        raise SolverFailed("no_start_converged", f"none of the {spec.starts} starts converged")
    order = finite[np.lexsort((finite, objectives[finite]))]
    f_best = objectives[order[0]]
    picked: list[int] = []
    for k in order:
        if len(picked) == MAX_POLISHED or objectives[k] > 10.0 * f_best + 1e-12:
            break
        if all(branches[j] != branches[k] or _gap(unknowns[j], unknowns[k]) > _SAME_BASIN for j in picked):
            picked.append(int(k))
    solved: list[tuple[float, FloatArray, int, str]] = []
    seeds: list[list[int]] = []
    for k in picked:
        polished = _polish(spec, unknowns[k], int(branches[k]))
        if polished is None:
            continue
        same = [i for i, (_, x, b, _) in enumerate(solved) if b == branches[k] and _gap(x, polished[1]) <= _SAME_FIT]
        if same:
            seeds[same[0]].append(k)
        else:
            solved.append((polished[0], polished[1], int(branches[k]), polished[2]))
            seeds.append([k])
    if not solved:
        raise SolverFailed("no_start_converged", f"IPOPT converged from none of the {len(picked)} best screened "
                           "starts")
    # A start counts for the fit nearest where its screening ended (the fit itself or a start polished into it),
    # when that is within one basin.
    counts = [0] * len(solved)
    for k in finite:
        gaps = [min([float(_gap(x, unknowns[k]))] + [float(_gap(unknowns[j], unknowns[k])) for j in seeds[i]])
                if b == branches[k] else math.inf for i, (_, x, b, _) in enumerate(solved)]
        i = int(np.argmin(gaps))
        if gaps[i] <= _SAME_BASIN:
            counts[i] += 1
    fits = [_fit(spec, x, b, counts[i], status) for i, (_, x, b, status) in enumerate(solved)]
    f_min = min(f for f, _, _, _ in solved)
    level = f_min + 1e-9 / scale**2 + 1e-6 * f_min
    at_best = [fit for fit, (f, _, _, _) in zip(fits, solved) if f <= level]
    rest = sorted((fit for fit, (f, _, _, _) in zip(fits, solved) if f > level), key=_rank_key("residual"))
    # Fits as near the targets as the best (a fit and its cognate, say) differ in residual by round-off only:
    # ordered by it they would be ordered by chance, so there "residual" ranks them by the starts reaching them.
    ranked = sorted(at_best, key=_rank_key("starts" if spec.rank_by == "residual" else spec.rank_by)) + rest
    best = ranked[0]
    assert best.check is not None
    return PathResult(
        linkage=best.linkage, coupler_point=best.coupler_point, crank_pivot=best.crank_pivot,
        ground_angle=best.ground_angle, crank_angles=best.crank_angles, residuals=best.residuals,
        start_objectives=objectives * scale**2, starts_at_best=best.starts, status=best.status, check=best.check,
        fits=tuple(ranked),
        cognates=_cognate_fits(best, targets, 10.0 * float(best.residuals.max()) + 1e-9 * scale),
    )


def synthesise_path(spec: PathSpec) -> PathResult:
    """The crank-rocker whose coupler point passes nearest to ``spec.targets``, every distinct fit the starts
    reached and the answer's cognates.

    Raises InvalidInput/TooLarge for unusable requests, SolverFailed when no start converges and SolverTimeout
    when the screening outruns ``spec.time_limit``. The same as :func:`best_path` of :func:`path_starts` over the
    chunks of :func:`start_chunks`, whichever the number of chunks.
    """
    return best_path(spec, [path_starts(spec, range(spec.starts))])


def _engine_residuals(fb: FourBar, z: FloatArray, phi: FloatArray, targets: FloatArray) -> FloatArray:
    """Distances [m] from the targets to the coupler point as the kinematics engine places it."""
    mot = motion(cast(Mechanism, fb), np.mod(phi, 2 * math.pi), 1.0)
    local = mot.point_on("coupler", (float(z[7]), float(z[8])))[0]
    rot = np.array([[math.cos(z[2]), -math.sin(z[2])], [math.sin(z[2]), math.cos(z[2])]])
    world = local @ rot.T + z[:2]
    return np.asarray(np.hypot(*(world - targets).T))


def coupler_curve(result: PathResult, samples: int = 360) -> FloatArray:
    """The coupler point's path over one crank turn in the targets' frame, (samples, 2) [m]."""
    phi = np.linspace(0.0, 2 * math.pi, samples, endpoint=False)
    an = analyse(result.linkage, 1.0, phi=phi, points={"P": ("coupler", result.coupler_point)})
    g = result.ground_angle
    rot = np.array([[math.cos(g), -math.sin(g)], [math.sin(g), math.cos(g)]])
    return np.asarray(an.motion.point_pos["P"] @ rot.T + np.asarray(result.crank_pivot))
