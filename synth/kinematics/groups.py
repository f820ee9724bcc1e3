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
from collections.abc import Callable, Mapping, Sequence
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


def place_group(group: NumericGroup, sides: Sequence[tuple[Side, Side]], phi: FloatArray,
                start: Mapping[str, tuple[float, float]], link_points: Mapping[str, Mapping[str, complex]]
                ) -> tuple[list[tuple[Jet, Jet]], FloatArray]:
    """Place a numerical group at every crank angle of ``phi`` [rad] (a path starting at 0, in small steps).

    ``sides`` per pair of the group; ``start`` positions of points as drawn at crank angle 0 [m] (those of the
    group's links that are given); ``link_points`` each group link's named points in its frame. Returns per
    group link (origin jet, angle jet) and the loop-closure residual [m] at every angle. Raises NotAssemblable
    at the first angle where Newton's method does not close the loop.
    """
    m, n = len(group.links), len(phi)
    q0 = _first(group, sides, start, link_points)
    q = _coarse(group, sides, phi, q0) if n > COARSE_MIN else None
    if q is None and n > DENSE:
        q = _dense(group, sides, phi, q0)
    if q is None:
        q = _continue(group, sides, phi, q0, np.arange(n))
    residual = np.max(np.abs(_residuals(sides, q, np.arange(n))), axis=1)
    jac = _jacobians(sides, q, m)
    # the determinant keeps its sign within one assembly; it changes where the path passes a position at which
    # two assemblies meet, and beyond it the group may have gone over to the other one
    sign = np.sign(np.linalg.det(jac))
    flips = np.flatnonzero(sign[1:] != sign[:-1])
    if flips.size:
        k = int(flips[0])
        a, b = (math.degrees(float(phi[i])) % 360 for i in (k, k + 1))
        raise NotAssemblable(
            f"the class-{group.group_class} group of links {list(group.links)} passes a position where two of its "
            f"assemblies meet between crank angles {a:.3f}° and {b:.3f}°: beyond it the motion is not determined "
            "by the drawing (the group may go over to the other assembly); change a length to keep it away",
            phi=phi[k:k + 2], ranges_deg=[(a, b)])
    qd = np.asarray(np.linalg.solve(jac, _rhs1_all(sides, n)[..., None])[..., 0], dtype=float)
    qdd = np.asarray(np.linalg.solve(jac, _rhs2_all(sides, q, qd)[..., None])[..., 0], dtype=float)
    out = []
    for i in range(m):
        x, y, th = (slice(3 * i + c, 3 * i + c + 1) for c in range(3))
        origin = Jet(q[:, x][:, 0] + 1j * q[:, y][:, 0], qd[:, x][:, 0] + 1j * qd[:, y][:, 0],
                     qdd[:, x][:, 0] + 1j * qdd[:, y][:, 0])
        out.append((origin, Jet(q[:, th][:, 0].copy(), qd[:, th][:, 0].copy(), qdd[:, th][:, 0].copy())))
    return out, residual


def _continue(group: NumericGroup, sides: Sequence[tuple[Side, Side]], phi: FloatArray, q0: FloatArray,
              at: IndexArray) -> FloatArray:
    """Newton's method angle after angle along the samples ``at`` of the path ``phi``, each started from the last
    solution moved on by its velocity; NotAssemblable at the first angle where the loop does not close."""
    m = len(group.links)
    q = np.empty((len(at), 3 * m))
    rate: FloatArray = np.zeros(3 * m)
    for i, k in enumerate(at):
        q[i] = q0 if i == 0 else q[i - 1] + rate * (phi[k] - phi[at[i - 1]])
        for _ in range(MAX_NEWTON):
            f = _residual(sides, q[i], k)
            if np.max(np.abs(f)) <= 1e-14:
                break
            try:
                q[i] -= np.linalg.solve(_jacobian(sides, q[i], m), f)
            except np.linalg.LinAlgError:
                break
        miss = float(np.max(np.abs(_residual(sides, q[i], k))))
        if not miss <= CLOSURE_TOLERANCE:
            at_deg = math.degrees(phi[k]) % 360
            raise NotAssemblable(
                f"the class-{group.group_class} group of links {list(group.links)} does not close at crank angle "
                f"{at_deg:.3f}° (loop residual {miss:.2e} m; it meets a dead or unreachable position there)",
                phi=phi[k:k + 1], ranges_deg=[(at_deg, at_deg)])
        rate = np.asarray(np.linalg.solve(_jacobian(sides, q[i], m), _rhs1(sides, k)), dtype=float)
    return q


def _coarse(group: NumericGroup, sides: Sequence[tuple[Side, Side]], phi: FloatArray, q0: FloatArray
            ) -> FloatArray | None:
    """Every sample at once from a continuation on samples about COARSE_STEP apart, or None when that
    continuation does not close or the samples do not join up into one assembly (see JOIN_TOLERANCE)."""
    try:
        q = _dense(group, sides, phi, q0, COARSE_STEP)
    except NotAssemblable:
        return None
    if q is None:
        return None
    m = len(group.links)
    qd = np.linalg.solve(_jacobians(sides, q, m), _rhs1_all(sides, len(phi))[..., None])[..., 0]
    step = np.diff(phi)[:, None]
    miss = q[1:] - q[:-1] - 0.5 * (qd[1:] + qd[:-1]) * step
    return q if np.max(np.abs(miss)) <= JOIN_TOLERANCE else None


def _dense(group: NumericGroup, sides: Sequence[tuple[Side, Side]], phi: FloatArray, q0: FloatArray,
           spacing: float = MAX_STEP / 2) -> FloatArray | None:
    """A long path: continuation on samples about ``spacing`` [rad] apart, then every sample at once by batched
    Newton steps from the nearest earlier one moved on by its velocity. None when a sample does not close that way
    (the caller then continues sample by sample, which names the first angle that fails)."""
    travel = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(phi)))])
    coarse = np.unique(np.concatenate([[0], np.searchsorted(travel, np.arange(0.0, travel[-1], spacing)),
                                       [len(phi) - 1]]))
    m = len(group.links)
    qc = _continue(group, sides, phi, q0, coarse)
    rates = np.linalg.solve(_jacobians(sides, qc, m), _rhs1_all(sides, len(phi))[coarse][..., None])[..., 0]
    # Each sample starts from the nearer of the coarse samples on either side, moved on by its velocity.
    before = np.searchsorted(coarse, np.arange(len(phi)), side="right") - 1
    after = np.minimum(before + 1, len(coarse) - 1)
    near = np.where(travel[coarse[after]] - travel < travel - travel[coarse[before]], after, before)
    q = qc[near] + rates[near] * (phi - phi[coarse[near]])[:, None]
    every = np.arange(len(phi))
    for _ in range(MAX_NEWTON):
        f = _residuals(sides, q, every)
        if np.max(np.abs(f)) <= 1e-14:
            break
        q -= np.linalg.solve(_jacobians(sides, q, m), f[..., None])[..., 0]
    if not np.max(np.abs(_residuals(sides, q, every))) <= CLOSURE_TOLERANCE:
        return None
    return np.asarray(q, dtype=float)


def _unknown_sides(sides: Sequence[tuple[Side, Side]]
                   ) -> tuple[IndexArray, IndexArray, FloatArray, NDArray[np.complex128]]:
    """The group links' sides of every pair as arrays: their pair, the column of their link's x in q, their
    sign and their pin in the link's frame, so that the loop equations are evaluated side by side."""
    unknown = [(j, s) for j, pair in enumerate(sides) for s in pair if s.known is None]
    return (np.array([j for j, _ in unknown], dtype=np.intp),
            np.array([3 * s.index for _, s in unknown], dtype=np.intp),
            np.array([s.sign for _, s in unknown]), np.array([s.local for _, s in unknown], dtype=complex))


def _residuals(sides: Sequence[tuple[Side, Side]], q: FloatArray, at: IndexArray) -> FloatArray:
    """The loop equations at the samples ``at`` for the coordinates ``q`` (one row each), (N, 2·pairs)."""
    pair, col, sign, local = _unknown_sides(sides)
    terms = sign * (q[:, col] + 1j * q[:, col + 1] + np.exp(1j * q[:, col + 2]) * local)
    z = np.zeros((len(at), len(sides)), dtype=complex)
    for j, two in enumerate(sides):
        for s in two:
            if s.known is not None:
                z[:, j] += s.sign * s.known.v[at]
    for u, j in enumerate(pair):
        z[:, j] += terms[:, u]
    out = np.empty((len(at), 2 * len(sides)))
    out[:, 0::2], out[:, 1::2] = z.real, z.imag
    return out


def _term(side: Side, q: FloatArray, k: int) -> complex:
    if side.known is not None:
        return complex(side.known.v[k])
    x, y, th = q[3 * side.index: 3 * side.index + 3]
    return complex(x, y) + complex(math.cos(th), math.sin(th)) * side.local


def _residual(sides: Sequence[tuple[Side, Side]], q: FloatArray, k: int) -> FloatArray:
    out = np.empty(2 * len(sides))
    for j, pair in enumerate(sides):
        z = sum((s.sign * _term(s, q, k) for s in pair), 0j)
        out[2 * j], out[2 * j + 1] = z.real, z.imag
    return out


def _jacobian(sides: Sequence[tuple[Side, Side]], q: FloatArray, m: int) -> FloatArray:
    """d(loop)/dq at one angle: scalar arithmetic, as the matrix is small and built at every Newton step."""
    jac = np.zeros((2 * len(sides), 3 * m))
    for j, pair in enumerate(sides):
        for s in pair:
            if s.known is not None:
                continue
            c = 3 * s.index
            th = float(q[c + 2])
            lever = complex(math.cos(th), math.sin(th)) * s.local * 1j
            jac[2 * j, c] += s.sign
            jac[2 * j + 1, c + 1] += s.sign
            jac[2 * j, c + 2] += s.sign * lever.real
            jac[2 * j + 1, c + 2] += s.sign * lever.imag
    return jac


def _jacobians(sides: Sequence[tuple[Side, Side]], q: FloatArray, m: int) -> FloatArray:
    """d(loop)/dq at every angle, (N, 2·pairs, 3m): per group side, the identity on its origin and
    i·exp(i·theta)·p on its angle (every side's entries added at once, in the sides' order)."""
    pair, col, sign, local = _unknown_sides(sides)
    jac = np.zeros((q.shape[0], 2 * len(sides), 3 * m))
    lever = sign * (np.exp(1j * q[:, col + 2]) * local * 1j)
    every = np.arange(q.shape[0])[:, None]
    np.add.at(jac, (every, 2 * pair, col), np.broadcast_to(sign, lever.shape))
    np.add.at(jac, (every, 2 * pair + 1, col + 1), np.broadcast_to(sign, lever.shape))
    np.add.at(jac, (every, 2 * pair, col + 2), lever.real)
    np.add.at(jac, (every, 2 * pair + 1, col + 2), lever.imag)
    return jac


def _rhs1(sides: Sequence[tuple[Side, Side]], k: int) -> FloatArray:
    out = np.zeros(2 * len(sides))
    for j, pair in enumerate(sides):
        z = -sum((s.sign * complex(s.known.d1[k]) for s in pair if s.known is not None), 0j)
        out[2 * j], out[2 * j + 1] = z.real, z.imag
    return out


def _rhs1_all(sides: Sequence[tuple[Side, Side]], n: int) -> FloatArray:
    out = np.zeros((n, 2 * len(sides)))
    for j, pair in enumerate(sides):
        z = np.zeros(n, dtype=complex)
        for s in pair:
            if s.known is not None:
                z -= s.sign * s.known.d1
        out[:, 2 * j], out[:, 2 * j + 1] = z.real, z.imag
    return out


def _rhs2_all(sides: Sequence[tuple[Side, Side]], q: FloatArray, qd: FloatArray) -> FloatArray:
    out = np.zeros((q.shape[0], 2 * len(sides)))
    for j, pair in enumerate(sides):
        z = np.zeros(q.shape[0], dtype=complex)
        for s in pair:
            if s.known is not None:
                z -= s.sign * s.known.d2
            else:
                c = 3 * s.index
                z += s.sign * qd[:, c + 2] ** 2 * np.exp(1j * q[:, c + 2]) * s.local
        out[:, 2 * j], out[:, 2 * j + 1] = z.real, z.imag
    return out


def _first(group: NumericGroup, sides: Sequence[tuple[Side, Side]], start: Mapping[str, tuple[float, float]],
           link_points: Mapping[str, Mapping[str, complex]]) -> FloatArray:
    """The group's coordinates at the path's first angle: from the drawn positions where every link has two of
    its points drawn, else from deterministic starts spread over the known points; closed by least squares with
    the analytic Jacobian."""
    m = len(group.links)
    guesses: list[FloatArray] = []
    fitted = [_fit(link_points[link], start) for link in group.links]
    if all(f is not None for f in fitted):
        guesses.append(np.concatenate([f for f in fitted if f is not None]))
    known = np.array([s.known.v[0] for pair in sides for s in pair if s.known is not None])
    centre = complex(known.mean()) if known.size else 0j
    spread = float(np.max(np.abs(known - centre))) if known.size else 1.0
    rng = np.random.default_rng(0)
    for _ in range(24):
        z = centre + spread * (rng.uniform(-1, 1, m) + 1j * rng.uniform(-1, 1, m))
        guesses.append(np.column_stack([z.real, z.imag, rng.uniform(-math.pi, math.pi, m)]).reshape(-1))

    drawn = [(i, link_points[link][p], complex(*start[p])) for i, link in enumerate(group.links)
             for p in link_points[link] if p in start]
    solved, miss = _close_all(sides, np.array(guesses), m)
    closed = [solved[k] for k in range(len(guesses)) if miss[k] <= CLOSURE_TOLERANCE]
    if closed and not drawn:
        return np.asarray(closed[0], dtype=float)
    if closed:
        return _nearest(group, closed, drawn)
    raise NotAssemblable(f"the class-{group.group_class} group of links {list(group.links)} cannot be assembled at "
                         "crank angle 0° from the drawn positions (assembly_m) or any start tried",
                         phi=[0.0], ranges_deg=[(0.0, 0.0)])


def _close_all(sides: Sequence[tuple[Side, Side]], guesses: FloatArray, m: int, iterations: int = 50
               ) -> tuple[FloatArray, FloatArray]:
    """Every guess (K, 3m) closed at the first angle at once by Levenberg-Marquardt with the analytic Jacobian,
    each with its own damping (Nielsen's update); the solutions and their largest loop residual [m]."""
    q = np.array(guesses, dtype=float)
    k = len(q)
    at = np.zeros(k, dtype=np.intp)
    f = _residuals(sides, q, at)
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
        jac = _jacobians(sides, q[live], m)
        jt = jac.transpose(0, 2, 1)
        normal = jt @ jac
        grad = (jt @ f[live][..., None])[..., 0]
        scale = np.maximum(np.einsum("kjj->kj", normal), 1e-12)
        step = -np.linalg.solve(normal + (damping[live, None] * scale)[:, :, None] * eye, grad[..., None])[..., 0]
        trial = q[live] + step
        f_t = _residuals(sides, trial, at[live])
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
