"""What closed forms do not cover: Assur groups of class III and above placed numerically, and passive links.

A group of more than two links (a triad of an eight-bar press: a ternary link with three binary links, each on a
known point) has no closed form. Its loop equations, one complex equation per revolute pair,

    sum over the pair's sides of  sign · (o_l + exp(i·theta_l)·p_l)   (a group link l: origin o_l, angle theta_l)
                                  sign · K(phi)                        (a known point K, already placed)  = 0,

are solved by Newton's method in the links' coordinates q = (x_o, y_o, theta) per link, from the solution at
the previous crank angle moved on by its velocity (continuation keeps the assembly branch), starting at crank
angle 0 from the positions as drawn. On a path of many samples the continuation runs on samples about 30° apart
and every sample is then solved at once from the nearer of them; the result is kept when neighbouring samples
join up as their velocities say, else the continuation runs again on every sample. Differentiating the loop once and twice in the crank angle gives the
analogues from linear systems with the same Jacobian: J·q' = -sum sign·K', J·q'' = -sum sign·K'' + sum over
the group's sides sign·theta_l'²·exp(i·theta_l)·p_l (seed 001:1160-1190 on groups of higher class; the digest's
section 1).

A passive link is a binary link whose two pairs repeat constraints the other links impose already (the third
crank of a double parallelogram): the structural formula counts them, the geometry does not. It is placed after
the others on its two pins, and the distance between them, which its length must equal, is the residual that
says the constraint is indeed redundant. The mobility from the geometry is W = 3n - rank of the constraint
Jacobian (all pairs, all moving links) at sampled crank angles; the rows its left null space touches are the
pairs whose constraints depend on each other.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Collection, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..errors import InvalidInput, NotAssemblable
from ..mechanism import FloatArray
from ..structure import PassiveLink, Redundancy
from .jets import Jet

IndexArray = NDArray[np.intp]

#: Largest step [rad] of the continuation between two placements of a numerical group.
MAX_STEP = math.radians(2.0)
#: Largest loop-closure residual [m] accepted at any crank angle (numerical groups and passive links).
CLOSURE_TOLERANCE = 1e-9
#: Beyond this many samples on the path the group is continued on samples about MAX_STEP/2 apart and the rest
#: solved all at once from them.
DENSE = 400
#: Spacing [rad] of a first, coarse continuation on paths of more than COARSE_MIN samples: the samples between
#: are solved all at once from it and kept when they join up sample to sample as their velocities say (a change
#: of assembly would not); otherwise the group is continued again at MAX_STEP.
COARSE_STEP = math.radians(30.0)
COARSE_MIN = 24
#: Largest miss [m or rad] of the trapezoidal rule between two neighbouring samples' positions and velocities
#: that still counts as one assembly: the rule's own error is far smaller at a few degrees a sample, and a
#: change of assembly moves a link by a finite distance.
JOIN_TOLERANCE = 1e-3
#: Newton iterations per crank angle before the group is declared not assemblable there.
MAX_NEWTON = 25
#: Singular values below this fraction of the largest count as zero in the rank of the constraint Jacobian.
RANK_TOLERANCE = 1e-8


@dataclass(frozen=True, slots=True)
class NumericGroup:
    """An Assur group of more than two links, placed numerically: its links, its pairs (inner, then outer) and
    its class."""

    links: tuple[str, ...]
    joints: tuple[str, ...]
    group_class: int


@dataclass(frozen=True, slots=True)
class Side:
    """One side of a revolute pair in a group's loop equation: +1 or -1, and either a group link (its index and
    the pin in its frame, complex) or a known point (its jet)."""

    sign: float
    index: int
    local: complex
    known: Jet | None


@dataclass(frozen=True, slots=True)
class _Loops:
    """A group's loop equations as arrays, built once per placement: per side on a group link (U of them) the
    column of its link's x in q, its sign and its pin in the link's frame; the one-hot maps that add each side into
    its pair's equation and its lever into the Jacobian; the known points' sum per pair with its analogues."""

    pairs: int
    width: int
    col: IndexArray
    sign: FloatArray
    local: NDArray[np.complex128]
    scatter: FloatArray             # (U, pairs)
    base: FloatArray                # (2·pairs·width,) the origins' constant entries of the Jacobian
    lever_re: FloatArray            # (U, 2·pairs·width) where each side's i·exp(i·theta)·p lands, real part
    lever_im: FloatArray            # the same, imaginary part
    known: NDArray[np.complex128]   # (N, pairs) sum of sign·K over the pair's known sides
    known_d1: NDArray[np.complex128]
    known_d2: NDArray[np.complex128]
    reach: float                    # largest over the links of half the sum of their pins' distances from the origin
    known_points: NDArray[np.complex128]   # every known side's point at the first sample
    split: _Split | None            # the Jacobian's constant origin columns factored once (None: not of full rank)

    @staticmethod
    def of(sides: Sequence[tuple[Side, Side]], m: int, n: int) -> _Loops:
        unknown = [(j, s) for j, pair in enumerate(sides) for s in pair if s.known is None]
        pairs, width = len(sides), 3 * m
        col = np.array([3 * s.index for _, s in unknown], dtype=np.intp)
        scatter = np.zeros((len(unknown), pairs))
        base = np.zeros((2 * pairs, width))
        lever_re = np.zeros((len(unknown), 2 * pairs, width))
        lever_im = np.zeros_like(lever_re)
        half = np.zeros(m)
        for u, (j, s) in enumerate(unknown):
            scatter[u, j] = 1.0
            base[2 * j, 3 * s.index] += s.sign
            base[2 * j + 1, 3 * s.index + 1] += s.sign
            lever_re[u, 2 * j, 3 * s.index + 2] = 1.0
            lever_im[u, 2 * j + 1, 3 * s.index + 2] = 1.0
            half[s.index] += abs(s.local) / 2
        known, known_d1, known_d2 = (np.zeros((n, pairs), dtype=complex) for _ in range(3))
        for j, pair in enumerate(sides):
            for s in pair:
                if s.known is not None:
                    known[:, j] += s.sign * s.known.v
                    known_d1[:, j] += s.sign * s.known.d1
                    known_d2[:, j] += s.sign * s.known.d2
        return _Loops(pairs, width, col, np.array([s.sign for _, s in unknown]),
                      np.array([s.local for _, s in unknown], dtype=complex), scatter, base.reshape(-1),
                      lever_re.reshape(len(unknown), -1), lever_im.reshape(len(unknown), -1), known, known_d1,
                      known_d2,
                      float(np.max(half)) if m else 0.0,
                      np.array([s.known.v[0] for pair in sides for s in pair if s.known is not None], dtype=complex),
                      _Split.of(base, lever_re, lever_im, m))


@dataclass(frozen=True, slots=True)
class _Split:
    """The loop Jacobian J = [B | Theta(q)] (origin columns, angle columns) of a group with as many equations as
    unknowns, solved through B's QR factors computed once: with Q^T·B = [R; 0], J·d = f becomes the m×m system
    (Q^T·Theta)_lower · d_theta = (Q^T·f)_lower, then R·d_xy = (Q^T·f)_upper - (Q^T·Theta)_upper · d_theta. Only
    the small system changes with q, and det J = ±det R·det(lower) keeps the lower block's sign."""

    xy: IndexArray                  # the origin columns of q, (2m,)
    theta: IndexArray               # the angle columns of q, (m,)
    qt: FloatArray                  # Q^T, (2·pairs, 2·pairs)
    r_inv: FloatArray               # R^-1, (2m, 2m)
    theta_re: FloatArray            # (U, 2·pairs·m): where each side's lever lands among the angle columns
    theta_im: FloatArray

    @staticmethod
    def of(base: FloatArray, lever_re: FloatArray, lever_im: FloatArray, m: int) -> _Split | None:
        rows = base.shape[0]
        if rows != 3 * m or m == 0:
            return None
        xy = np.array([3 * i + c for i in range(m) for c in (0, 1)], dtype=np.intp)
        theta = np.arange(2, 3 * m, 3, dtype=np.intp)
        q, r = np.linalg.qr(base[:, xy], mode="complete")
        diag = np.abs(np.diag(r[:2 * m]))
        if not diag.min() > 1e-9 * diag.max():
            return None
        u = lever_re.shape[0]
        return _Split(xy, theta, np.ascontiguousarray(q.T), np.linalg.inv(r[:2 * m]),
                      lever_re.reshape(u, rows, 3 * m)[:, :, theta].reshape(u, -1),
                      lever_im.reshape(u, rows, 3 * m)[:, :, theta].reshape(u, -1))


class _Linear:
    """The loop Jacobian at every row of q, ready to solve J·d = f for one right-hand side after another."""

    def __init__(self, loops: _Loops, q: FloatArray) -> None:
        self.loops, self.split = loops, loops.split
        if self.split is None:
            self.jac = _jacobians(loops, q)
            return
        sp, m = self.split, len(self.split.theta)
        lever = loops.sign * (np.exp(1j * q[:, loops.col + 2]) * loops.local * 1j)
        theta = (lever.real @ sp.theta_re + lever.imag @ sp.theta_im).reshape(q.shape[0], 3 * m, m)
        t = sp.qt @ theta
        self.upper, self.lower = t[:, :2 * m], t[:, 2 * m:]

    def solve(self, f: FloatArray) -> FloatArray:
        """d with J·d = f, one row per row of q, (K, 3m)."""
        if self.split is None:
            return np.asarray(np.linalg.solve(self.jac, f[..., None])[..., 0], dtype=float)
        sp = self.split
        g = f @ sp.qt.T
        m = len(sp.theta)
        d_theta = np.linalg.solve(self.lower, g[:, 2 * m:, None])
        d = np.empty((f.shape[0], 3 * m))
        d[:, sp.theta] = d_theta[..., 0]
        d[:, sp.xy] = (g[:, :2 * m] - (self.upper @ d_theta)[..., 0]) @ sp.r_inv.T
        return d

    def det_sign(self) -> FloatArray:
        """The sign of det J at every row, up to one factor the same for all rows."""
        return np.asarray(np.sign(np.linalg.det(self.jac if self.split is None else self.lower)), dtype=float)


def place_group(group: NumericGroup, sides: Sequence[tuple[Side, Side]], phi: FloatArray,
                start: Mapping[str, tuple[float, float]], link_points: Mapping[str, Mapping[str, complex]],
                fixed: Collection[str] = ()) -> tuple[list[tuple[Jet, Jet]], FloatArray]:
    """Place a numerical group at every crank angle of ``phi`` [rad] (a path starting at 0, in small steps).

    ``sides`` per pair of the group; ``start`` positions of points as drawn at crank angle 0 [m] (those of the
    group's links that are given), of which those named in ``fixed`` are the known points' own positions, the same
    in every assembly; ``link_points`` each group link's named points in its frame. Returns per
    group link (origin jet, angle jet) and the loop-closure residual [m] at every angle. Raises NotAssemblable
    at the first angle where Newton's method does not close the loop.
    """
    m, n = len(group.links), len(phi)
    loops = _Loops.of(sides, m, n)
    q0 = _first(group, loops, start, link_points, fixed)
    q = _coarse(group, loops, phi, q0) if n > COARSE_MIN else None
    if q is None and n > DENSE:
        q = _dense(group, loops, phi, q0)
    if q is None:
        q = _continue(group, loops, phi, q0, np.arange(n))
    every = np.arange(n)
    residual = np.max(np.abs(_residuals(loops, q, every)), axis=1)
    linear = _Linear(loops, q)
    # the determinant keeps its sign within one assembly; it changes where the path passes a position at which
    # two assemblies meet, and beyond it the group may have gone over to the other one
    sign = linear.det_sign()
    flips = np.flatnonzero(sign[1:] != sign[:-1])
    if flips.size:
        k = int(flips[0])
        a, b = (math.degrees(float(phi[i])) % 360 for i in (k, k + 1))
        raise NotAssemblable(
            f"the class-{group.group_class} group of links {list(group.links)} passes a position where two of its "
            f"assemblies meet between crank angles {a:.3f}° and {b:.3f}°: beyond it the motion is not determined "
            "by the drawing (the group may go over to the other assembly); change a length to keep it away",
            phi=phi[k:k + 2], ranges_deg=[(a, b)])
    qd = linear.solve(_rhs1(loops, every))
    qdd = linear.solve(_rhs2(loops, q, qd))
    out = []
    for i in range(m):
        x, y, th = (slice(3 * i + c, 3 * i + c + 1) for c in range(3))
        origin = Jet(q[:, x][:, 0] + 1j * q[:, y][:, 0], qd[:, x][:, 0] + 1j * qd[:, y][:, 0],
                     qdd[:, x][:, 0] + 1j * qdd[:, y][:, 0])
        out.append((origin, Jet(q[:, th][:, 0].copy(), qd[:, th][:, 0].copy(), qdd[:, th][:, 0].copy())))
    return out, residual


def _continue(group: NumericGroup, loops: _Loops, phi: FloatArray, q0: FloatArray, at: IndexArray) -> FloatArray:
    """Newton's method angle after angle along the samples ``at`` of the path ``phi``, each started from the last
    solution moved on by its velocity; NotAssemblable at the first angle where the loop does not close."""
    q = np.empty((len(at), loops.width))
    rate: FloatArray = np.zeros(loops.width)
    bend: FloatArray = np.zeros(loops.width)
    for i, k in enumerate(at):
        here = at[i:i + 1]
        h = 0.0 if i == 0 else float(phi[k] - phi[at[i - 1]])
        # the start moved on by the velocity and by the change of velocity over the last step
        qi = (q0 if i == 0 else q[i - 1] + (rate + 0.5 * h * bend) * h)[None, :]
        linear = None
        for _ in range(MAX_NEWTON):
            f = _residuals(loops, qi, here)
            if np.max(np.abs(f)) <= 1e-14:
                break
            try:
                linear = _Linear(loops, qi)
                qi = qi - linear.solve(f)
            except np.linalg.LinAlgError:
                break
        else:
            f = _residuals(loops, qi, here)
        miss = float(np.max(np.abs(f)))
        if not miss <= CLOSURE_TOLERANCE:
            at_deg = math.degrees(phi[k]) % 360
            raise NotAssemblable(
                f"the class-{group.group_class} group of links {list(group.links)} does not close at crank angle "
                f"{at_deg:.3f}° (loop residual {miss:.2e} m; it meets a dead or unreachable position there)",
                phi=phi[k:k + 1], ranges_deg=[(at_deg, at_deg)])
        q[i] = qi[0]
        # the velocity only predicts the next start: the Jacobian of the last Newton step serves
        new_rate = (linear or _Linear(loops, qi)).solve(_rhs1(loops, here))[0]
        bend = (new_rate - rate) / h if i > 0 and h != 0.0 else np.zeros(loops.width)
        rate = new_rate
    return q


def _coarse(group: NumericGroup, loops: _Loops, phi: FloatArray, q0: FloatArray) -> FloatArray | None:
    """Every sample at once from a continuation on samples about COARSE_STEP apart, or None when that
    continuation does not close or the samples do not join up into one assembly (see JOIN_TOLERANCE)."""
    try:
        q = _dense(group, loops, phi, q0, COARSE_STEP)
    except NotAssemblable:
        return None
    if q is None:
        return None
    qd = _Linear(loops, q).solve(_rhs1(loops, np.arange(len(phi))))
    step = np.diff(phi)[:, None]
    miss = q[1:] - q[:-1] - 0.5 * (qd[1:] + qd[:-1]) * step
    return q if np.max(np.abs(miss)) <= JOIN_TOLERANCE else None


def _dense(group: NumericGroup, loops: _Loops, phi: FloatArray, q0: FloatArray, spacing: float = MAX_STEP / 2
           ) -> FloatArray | None:
    """A long path: continuation on samples about ``spacing`` [rad] apart, then every sample at once by batched
    Newton steps from the nearest earlier one moved on by its velocity. None when a sample does not close that way
    (the caller then continues sample by sample, which names the first angle that fails)."""
    travel = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(phi)))])
    coarse = np.unique(np.concatenate([[0], np.searchsorted(travel, np.arange(0.0, travel[-1], spacing)),
                                       [len(phi) - 1]]))
    qc = _continue(group, loops, phi, q0, coarse)
    rates = _Linear(loops, qc).solve(_rhs1(loops, coarse))
    # Each sample starts from the nearer of the coarse samples on either side, moved on by its velocity.
    before = np.searchsorted(coarse, np.arange(len(phi)), side="right") - 1
    after = np.minimum(before + 1, len(coarse) - 1)
    near = np.where(travel[coarse[after]] - travel < travel - travel[coarse[before]], after, before)
    q = qc[near] + rates[near] * (phi - phi[coarse[near]])[:, None]
    every = np.arange(len(phi))
    for _ in range(MAX_NEWTON):
        f = _residuals(loops, q, every)
        if np.max(np.abs(f)) <= 1e-14:
            break
        q -= _Linear(loops, q).solve(f)
    else:
        f = _residuals(loops, q, every)
    if not np.max(np.abs(f)) <= CLOSURE_TOLERANCE:
        return None
    return np.asarray(q, dtype=float)


def _split(z: NDArray[np.complex128]) -> FloatArray:
    """(K, pairs) complex loop values as (K, 2·pairs) real ones, x and y of each pair side by side."""
    return np.ascontiguousarray(z).view(np.float64)


def _residuals(loops: _Loops, q: FloatArray, at: IndexArray) -> FloatArray:
    """The loop equations at the samples ``at`` for the coordinates ``q`` (one row each), (K, 2·pairs)."""
    c = loops.col
    terms = loops.sign * (q[:, c] + 1j * q[:, c + 1] + np.exp(1j * q[:, c + 2]) * loops.local)
    return _split(loops.known[at] + terms @ loops.scatter)


def _jacobians(loops: _Loops, q: FloatArray) -> FloatArray:
    """d(loop)/dq at every row of ``q``, (K, 2·pairs, 3m): per group side, the identity on its origin and
    i·exp(i·theta)·p on its angle."""
    lever = loops.sign * (np.exp(1j * q[:, loops.col + 2]) * loops.local * 1j)
    flat: FloatArray = loops.base + lever.real @ loops.lever_re + lever.imag @ loops.lever_im
    return flat.reshape(q.shape[0], 2 * loops.pairs, loops.width)


def _rhs1(loops: _Loops, at: IndexArray) -> FloatArray:
    """J·q' at the samples ``at``: minus the known points' velocity analogues, per pair."""
    return _split(-loops.known_d1[at])


def _rhs2(loops: _Loops, q: FloatArray, qd: FloatArray) -> FloatArray:
    """J·q'' at every sample: minus the known points' acceleration analogues, plus each group side's
    sign·theta'²·exp(i·theta)·p."""
    c = loops.col
    turn = loops.sign * qd[:, c + 2] ** 2 * np.exp(1j * q[:, c + 2]) * loops.local
    return _split(-loops.known_d2 + turn @ loops.scatter)


def _first(group: NumericGroup, loops: _Loops, start: Mapping[str, tuple[float, float]],
           link_points: Mapping[str, Mapping[str, complex]], fixed: Collection[str]) -> FloatArray:
    """The group's coordinates at the path's first angle.

    With points drawn, the links are first placed on them (:func:`_drawn`) and closed; that placement is kept
    when :func:`_only_near` proves no other assembly lies as near the drawing. Otherwise deterministic starts
    spread over the known points are closed at once by least squares with the analytic Jacobian, and the one
    nearest the drawing is kept (:func:`_nearest`; without a drawing, the first that closes).
    """
    m = len(group.links)
    drawn = [(i, link_points[link][p], complex(*start[p])) for i, link in enumerate(group.links)
             for p in link_points[link] if p in start]
    guess = _drawn(group.links, link_points, start, fixed) if drawn else None
    if guess is not None:
        solved, miss = _close_all(loops, guess[0][None, :], m)
        if miss[0] <= CLOSURE_TOLERANCE:
            gap = float(np.sqrt(np.sum(np.abs(_points(solved[0], drawn) - np.array([w for _, _, w in drawn])) ** 2)))
            if _only_near(loops, solved[0], guess[1], gap * (1 + 1 / ASSEMBLY_MARGIN)):
                return np.asarray(solved[0], dtype=float)
    guesses: list[FloatArray] = []
    fitted = [_fit(link_points[link], start) for link in group.links]
    if all(f is not None for f in fitted):
        guesses.append(np.concatenate([f for f in fitted if f is not None]))
    known = loops.known_points
    centre = complex(known.mean()) if known.size else 0j
    spread = float(np.max(np.abs(known - centre))) if known.size else 1.0
    rng = np.random.default_rng(0)
    for _ in range(24):
        z = centre + spread * (rng.uniform(-1, 1, m) + 1j * rng.uniform(-1, 1, m))
        guesses.append(np.column_stack([z.real, z.imag, rng.uniform(-math.pi, math.pi, m)]).reshape(-1))
    solved, miss = _close_all(loops, np.array(guesses), m)
    closed = [solved[k] for k in range(len(guesses)) if miss[k] <= CLOSURE_TOLERANCE]
    if closed and not drawn:
        return np.asarray(closed[0], dtype=float)
    if closed:
        return _nearest(group, closed, drawn)
    raise NotAssemblable(f"the class-{group.group_class} group of links {list(group.links)} cannot be assembled at "
                         "crank angle 0° from the drawn positions (assembly_m) or any start tried",
                         phi=[0.0], ranges_deg=[(0.0, 0.0)])


def _drawn(links: Sequence[str], link_points: Mapping[str, Mapping[str, complex]],
           start: Mapping[str, tuple[float, float]], fixed: Collection[str]
           ) -> tuple[FloatArray, Callable[[float, float], float]] | None:
    """The group's links placed on the drawing: each on the two of its points farthest apart whose positions are
    drawn (or known) or follow from a link placed before, until every link is placed (None if one cannot be).

    Also the map from a distance eps [m] and a length ``scale`` [m] to a bound on how far (in the coordinates
    origins and scale·angles, Euclidean) the same construction moves between two exact placements whose drawn
    points differ by at most eps (the ``fixed`` ones not at all):
    two pins at distance s each moved by at most e_a and e_b turn the link by at most 2·asin((e_a + e_b)/(2s)),
    its origin and other points then move by at most e_a plus their distance from the first pin times that turn.
    The bound places each link on the pair of its pins available that turns it least.
    """
    world = {p: complex(*xy) for p, xy in start.items()}
    order: list[tuple[int, list[str]]] = []
    q = np.zeros(3 * len(links))
    pending = list(range(len(links)))
    while pending:
        placed = []
        for i in pending:
            points = link_points[links[i]]
            names = [p for p in points if p in world]
            pins = [(a, b) for k, a in enumerate(names) for b in names[k + 1:] if points[a] != points[b]]
            if not pins:
                continue
            a, b = max(pins, key=lambda ab: abs(points[ab[1]] - points[ab[0]]))
            turn = (world[b] - world[a]) / (points[b] - points[a])
            e = turn / abs(turn) if turn else 1.0 + 0j
            origin = world[a] - e * points[a]
            q[3 * i: 3 * i + 3] = origin.real, origin.imag, math.atan2(e.imag, e.real)
            for p, local in points.items():
                world.setdefault(p, origin + e * local)
            order.append((i, names))
            placed.append(i)
        if not placed:
            return None
        pending = [i for i in pending if i not in placed]

    def bound(eps: float, scale: float) -> float:
        err = {p: 0.0 if p in fixed else eps for p in start}
        total = 0.0
        for i, names in order:
            points = link_points[links[i]]
            a, b = min(((a, b) for k, a in enumerate(names) for b in names[k + 1:] if points[a] != points[b]),
                       key=lambda ab: (err[ab[0]] + err[ab[1]]) / abs(points[ab[1]] - points[ab[0]]))
            if err[b] < err[a]:
                a, b = b, a
            span = abs(points[b] - points[a])
            if err[a] + err[b] >= 2 * span:
                return math.inf
            turn = 2 * math.asin((err[a] + err[b]) / (2 * span))
            total += (err[a] + abs(points[a]) * turn) ** 2 + (scale * turn) ** 2
            for p, local in points.items():
                err.setdefault(p, err[a] + abs(local - points[a]) * turn)
        return math.sqrt(total)

    return q, bound


def _only_near(loops: _Loops, q: FloatArray, bound: Callable[[float, float], float], eps: float) -> bool:
    """True when the placement ``q`` (closed at the first angle) is the only assembly whose drawn points lie
    within ``eps`` [m] of its own: by :func:`_drawn`'s bound such an assembly lies within bound(eps) of ``q``, and
    none but ``q`` itself does within Newton's uniqueness radius.

    In the coordinates d = (origins [m], scale·angles [m]), for two placements q and q + d of the loops F,
    F(q + d) = F(q) + J'·d + R(d) with |R(d)| at most the sum over the group's sides of |p|·dtheta²/2
    (|exp(i·t) - 1 - i·t| <= t²/2), so at most (reach/scale²)·|d|²; a second root then has
    sigma·|d| <= |F(q)| + (reach/scale²)·|d|², sigma the least singular value of J', J with its angle columns
    divided by scale: |d| is either within rounding of 0 or at least the larger root of that quadratic. Any
    scale gives a proof; a few around the links' size are tried.
    """
    jac = _jacobians(loops, q[None, :])[0]
    if jac.shape[0] < jac.shape[1] or loops.reach <= 0:
        return False
    rho = float(np.linalg.norm(_residuals(loops, q[None, :], np.zeros(1, dtype=np.intp))))
    for scale in loops.reach * np.array([1.0, 2.0, 4.0, 8.0]):
        scaled = jac.copy()
        scaled[:, 2::3] /= scale
        sigma = float(np.linalg.svd(scaled, compute_uv=False)[-1])
        curve = loops.reach / scale**2
        if sigma * sigma > 4 * curve * rho and \
                bound(eps, scale) < (sigma + math.sqrt(sigma * sigma - 4 * curve * rho)) / (2 * curve):
            return True
    return False


def _close_all(loops: _Loops, guesses: FloatArray, m: int, iterations: int = 50) -> tuple[FloatArray, FloatArray]:
    """Every guess (K, 3m) closed at the first angle at once by Levenberg-Marquardt with the analytic Jacobian,
    each with its own damping (Nielsen's update); the solutions and their largest loop residual [m]."""
    q = np.array(guesses, dtype=float)
    k = len(q)
    at = np.zeros(k, dtype=np.intp)
    f = _residuals(loops, q, at)
    cost = np.einsum("ki,ki->k", f, f)
    damping, growth = np.full(k, 1e-3), np.full(k, 2.0)
    eye = np.eye(3 * m)
    stalled = np.zeros(k, dtype=bool)
    for _ in range(iterations):
        # a guess stops once its loops close, or when its residual no longer falls (a placement that does not
        # close from there)
        live = np.flatnonzero((np.max(np.abs(f), axis=1) > 1e-14) & (damping < 1e15) & ~stalled)
        if live.size == 0:
            break
        jac = _jacobians(loops, q[live])
        jt = jac.transpose(0, 2, 1)
        normal = jt @ jac
        grad = (jt @ f[live][..., None])[..., 0]
        scale = np.maximum(np.einsum("kjj->kj", normal), 1e-12)
        step = -np.linalg.solve(normal + (damping[live, None] * scale)[:, :, None] * eye, grad[..., None])[..., 0]
        trial = q[live] + step
        f_t = _residuals(loops, trial, at[live])
        cost_t = np.einsum("ki,ki->k", f_t, f_t)
        predicted = -2 * np.einsum("kj,kj->k", grad, step) - np.einsum("kj,kj->k", step,
                                                                        (normal @ step[..., None])[..., 0])
        gain = (cost[live] - cost_t) / np.maximum(predicted, 1e-300)
        taken = np.isfinite(cost_t) & (gain > 1e-4)
        went, back = live[taken], live[~taken]
        stalled[went] = cost_t[taken] > (1 - 1e-6) * cost[went]
        q[went], f[went], cost[went] = trial[taken], f_t[taken], cost_t[taken]
        damping[went] *= np.maximum(1.0 / 3.0, 1.0 - (2.0 * np.minimum(gain[taken], 1.0) - 1.0) ** 3)
        growth[went] = 2.0
        damping[back] *= growth[back]
        growth[back] = np.minimum(2.0 * growth[back], 1e6)
    return q, np.max(np.abs(f), axis=1)


#: The drawn points' distance from the assembly chosen must be at most this fraction of their distance from the
#: next one, or the drawing does not choose [-].
ASSEMBLY_MARGIN = 0.8


def _nearest(group: NumericGroup, closed: Sequence[FloatArray], drawn: Sequence[tuple[int, complex, complex]]
             ) -> FloatArray:
    """Of the placements that close the loops at the first angle, the one whose points lie nearest those drawn
    (root of the summed squared distances); InvalidInput when the drawing lies as near another assembly (its
    distance over the next assembly's more than :data:`ASSEMBLY_MARGIN`), naming both."""
    world = np.array([w for _, _, w in drawn])
    gaps = [float(np.sqrt(np.sum(np.abs(_points(q, drawn) - world) ** 2))) for q in closed]
    order = np.argsort(gaps)
    best = closed[int(order[0])]
    # another assembly: a placement whose points differ from the best's by more than rounding
    others = [int(j) for j in order[1:] if np.max(np.abs(_points(closed[int(j)], drawn) - _points(best, drawn)))
              > 1e-6 * max(1.0, float(np.max(np.abs(_points(best, drawn)))))]
    if others:
        near, far = gaps[int(order[0])], gaps[others[0]]
        if near > ASSEMBLY_MARGIN * far:
            raise InvalidInput(
                f"the points drawn in assembly_m do not tell the class-{group.group_class} group's assemblies "
                f"apart: the nearest lies {near:.4g} m from the drawing, another {far:.4g} m; draw the points of "
                "the assembly meant closer to it", field="mechanism.assembly_m")
    return best


def _points(q: FloatArray, drawn: Sequence[tuple[int, complex, complex]]) -> NDArray[np.complex128]:
    return np.array([complex(q[3 * i], q[3 * i + 1]) + complex(math.cos(q[3 * i + 2]), math.sin(q[3 * i + 2]))
                     * local for i, local, _ in drawn])


def _fit(points: Mapping[str, complex], start: Mapping[str, tuple[float, float]]) -> FloatArray | None:
    """Origin and angle of a link from two or more of its points as drawn (a rigid fit), None with fewer."""
    names = [p for p in points if p in start]
    if len(names) < 2:
        return None
    local = np.array([points[p] for p in names])
    world = np.array([complex(*start[p]) for p in names])
    lc, wc = local - local.mean(), world - world.mean()
    rot = np.sum(wc * np.conj(lc))
    if abs(rot) == 0:
        return None
    e = rot / abs(rot)
    origin = world.mean() - e * local.mean()
    return np.array([origin.real, origin.imag, math.atan2(e.imag, e.real)])


def continuation_path(phi: FloatArray) -> tuple[FloatArray, FloatArray]:
    """A path of crank angles from 0 through ``phi`` in order, in steps of at most MAX_STEP [rad], and the
    indices of ``phi`` on it."""
    stops = np.concatenate([[0.0], np.asarray(phi, dtype=float)])
    steps = np.maximum(1, np.ceil(np.abs(np.diff(stops)) / MAX_STEP).astype(int))
    idx = np.cumsum(steps)
    segment = np.repeat(np.arange(len(steps)), steps)
    within = np.arange(len(segment)) + 1 - np.repeat(idx - steps, steps)
    path = stops[segment] + (stops[segment + 1] - stops[segment]) * (within / steps[segment])
    # Each requested angle lands on the path exactly, as given.
    path[idx - 1] = stops[1:]
    return np.concatenate([[0.0], path]), idx


def constraint_jacobian(link_names: Sequence[str], origin: Mapping[str, FloatArray], angle: Mapping[str, FloatArray],
                        rows: Sequence[tuple[str, str, tuple[str, str], FloatArray | None, Callable[[str], FloatArray]]]
                        ) -> FloatArray:
    """The constraint Jacobian of a whole linkage at every angle, (N, 2·pairs, 3·links), in the coordinates
    (x, y, theta) of each moving link's origin and angle.

    ``rows`` per pair: (name, kind, (link a, link b), the point [m] (N, 2) for a revolute, and for a prismatic
    pair a function giving the axis direction's unit vector (N, 2) from the axis link's name). A prismatic
    pair's rows are its angle (theta_b - theta_a constant) and the slider point's distance from the axis.
    """
    n = next(iter(origin.values())).shape[0]
    col = {name: 3 * i for i, name in enumerate(link_names)}
    jac = np.zeros((n, 2 * len(rows), 3 * len(link_names)))
    for j, (_, kind, links, point, axis) in enumerate(rows):
        if kind == "revolute" and point is not None:
            for link, sign in zip(links, (1.0, -1.0)):
                if link not in col:
                    continue
                c = col[link]
                lever = point - origin[link]
                jac[:, 2 * j, c] = sign
                jac[:, 2 * j + 1, c + 1] = sign
                jac[:, 2 * j, c + 2] = -sign * lever[:, 1]
                jac[:, 2 * j + 1, c + 2] = sign * lever[:, 0]
            continue
        axis_link, other = links
        u = axis(axis_link)
        p = point if point is not None else np.zeros((n, 2))
        if other in col:
            c = col[other]
            jac[:, 2 * j, c + 2] = 1.0
            jac[:, 2 * j + 1, c] = -u[:, 1]
            jac[:, 2 * j + 1, c + 1] = u[:, 0]
            d = p - origin[other]
            jac[:, 2 * j + 1, c + 2] = u[:, 0] * d[:, 0] + u[:, 1] * d[:, 1]
        if axis_link in col:
            c = col[axis_link]
            jac[:, 2 * j, c + 2] = -1.0
            jac[:, 2 * j + 1, c] = u[:, 1]
            jac[:, 2 * j + 1, c + 1] = -u[:, 0]
            d = p - origin[axis_link]
            jac[:, 2 * j + 1, c + 2] = -(u[:, 0] * d[:, 0] + u[:, 1] * d[:, 1])
    return jac


def rank_and_dependent(jac: FloatArray, pair_names: Sequence[str]) -> tuple[int, tuple[str, ...]]:
    """Largest rank of the stacked Jacobians over the angles, and the pairs whose rows the left null space
    touches at the angle of that rank (rows linearly dependent on the others)."""
    u, s, _ = np.linalg.svd(jac)
    ranks = np.sum(s > RANK_TOLERANCE * s[:, :1], axis=1)
    rank = int(np.max(ranks))
    # The angle where that rank is best conditioned: at a change point a sub-loop's own rows depend on each other.
    k = int(np.argmax(np.where(ranks == rank, s[:, rank - 1] / s[:, 0], -1.0)))
    null = u[k][:, rank:]
    weight = np.sqrt(np.sum(null * null, axis=1))
    touched = {pair_names[r // 2] for r in range(len(weight)) if weight[r] > 1e-6}
    return rank, tuple(p for p in pair_names if p in touched)


__all__ = ["CLOSURE_TOLERANCE", "NumericGroup", "constraint_jacobian",
           "continuation_path", "place_group", "rank_and_dependent"]
