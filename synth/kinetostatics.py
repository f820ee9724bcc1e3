"""Generic d'Alembert kinetostatics: every moving link in equilibrium, one linear system per crank angle.

Unknowns: for each joint two reaction components (revolute: Rx, Ry; prismatic: the force normal to the slide
axis and the couple), plus the driving torque on the crank; 3 equations per moving link (forces, and moments
about the link's first joint). A one-degree-of-freedom linkage has as many unknowns as equations; the
systems of all crank angles are stacked and solved at once.

The systems are not solved as dense 3n x 3n matrices. A revolute joint's reaction enters the force equations of
its two links with constant coefficients (plus or minus one), so for a choice of n revolute joints (made once
per topology) the force rows restricted to their 2n reactions are a constant, invertible matrix F. Eliminating
those reactions leaves the n moment equations in the other n unknowns: the reduced matrix S (n x n, n the
number of moving links) carries all of the geometry, and det A = ±det S. A dead position of the linkage is where
S is singular, found on this reduced, kinematic system rather than by factorising A: the Hadamard ratio
|det A| / prod(row norms of A), which lies in [0, 1], is taken with det A = det F · det S.

Two paths share only the geometry (the system matrix):
``solve_direct`` builds the right-hand side from the links' actual loads, and ``linear_map`` builds it per
inertial parameter (m, m·x, m·y, J about the first joint), so every output is ``Y @ p + y0``. Balancing
optimises over that map; the direct path re-analyses its answers.
"""

from __future__ import annotations

import functools
import math
import itertools
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from .errors import NotAssemblable, angle_ranges_deg
from .kinematics.motion import Motion, complex_of, cross, dot, perp, unit, xy
from .model import FloatArray, Linkage
from .topology import Topology

PARAMS_PER_LINK = 4
IndexArray = npt.NDArray[np.intp]
# Below this Hadamard ratio a system is treated as singular (a dead position of the linkage).
SINGULAR_RATIO = 1e-10


@dataclass(frozen=True, slots=True)
class LinkArrays:
    """Every link's mass properties and the kinematics of its frame and centre of mass, stacked once per motion.

    Links on axis 0 in topology order (counterweights included in the mass properties), crank angle on axis 1.
    The direct kinetostatics, the linear map, the virtual-power check and the reduced model all read these arrays
    instead of asking the linkage and the motion link by link.

    ``params`` (L, 4): m [kg], m·x, m·y [kg·m] in the link frame, J about the first joint [kg·m²];
    ``mass`` (L,) [kg], ``com`` (L, 2) [m] in the link frame, ``inertia`` (L,) about the centre of mass [kg·m²];
    ``origin_pos`` / ``origin_acc`` (L, N, 2) of each frame origin [m, m/s²]; ``angle``, ``omega``, ``alpha``
    (L, N) [rad, rad/s, rad/s²]; ``com_pos``, ``com_vel``, ``com_acc`` (L, N, 2) [m, m/s, m/s²].
    From :func:`link_arrays_per_sample` the mass properties vary per sample: ``params`` (L, N, 4), ``mass`` and
    ``inertia`` (L, N), ``com`` (L, N, 2).
    """

    links: tuple[str, ...]
    params: FloatArray
    mass: FloatArray
    com: FloatArray
    inertia: FloatArray
    origin_pos: FloatArray
    origin_acc: FloatArray
    angle: FloatArray
    omega: FloatArray
    alpha: FloatArray
    com_pos: FloatArray
    com_vel: FloatArray
    com_acc: FloatArray

    def index(self, link: str) -> int:
        """Position of ``link`` on axis 0."""
        return self.links.index(link)


def link_arrays(motion: Motion, linkage: Linkage) -> LinkArrays:
    """Stack every link's inertial parameters and frame and centre-of-mass kinematics once for ``motion``.

    The centre of mass of a massless link is its frame origin, as :meth:`synth.MassProps.from_params` has it.
    """
    links = linkage.mechanism.topology.links
    return _link_arrays(motion, links, linkage.params().reshape(len(links), PARAMS_PER_LINK))


def link_arrays_per_sample(motion: Motion, linkage: Linkage, params: FloatArray) -> LinkArrays:
    """:func:`link_arrays` with every link's inertial parameters given per sample, ``params`` (L, N, 4).

    For a stack of variants of one topology laid end to end along the sample axis (each variant its own
    masses over its own block of samples): ``params`` (L, N, 4), ``mass`` and ``inertia`` (L, N), ``com``
    (L, N, 2). The direct kinetostatics, the virtual-power check and the reduced model take these arrays as they
    take :func:`link_arrays`'s.
    """
    links = linkage.mechanism.topology.links
    params = np.asarray(params, dtype=float)
    if params.shape != (len(links), motion.samples, PARAMS_PER_LINK):
        raise ValueError(f"params must be (links, samples, {PARAMS_PER_LINK}), got {params.shape}")
    return _link_arrays(motion, links, params)


def _link_arrays(motion: Motion, links: tuple[str, ...], params: FloatArray) -> LinkArrays:
    """:class:`LinkArrays` of ``motion`` for inertial parameters (L, 4), or per sample (L, N, 4)."""
    mass = params[..., 0]
    heavy = mass > 0.0
    safe = np.where(heavy, mass, 1.0)
    com = np.where(heavy[..., None], params[..., 1:3] / safe[..., None], 0.0)
    inertia = np.where(heavy, params[..., 3] - mass * (com[..., 0] * com[..., 0] + com[..., 1] * com[..., 1]),
                       params[..., 3])
    origins = [motion.link_origin[link] for link in links]
    # np.array of equal-shaped arrays stacks them in one call (np.stack is several Python calls)
    origin_pos = np.array([motion.point_pos[o] for o in origins], dtype=float)
    origin_vel = np.array([motion.point_vel[o] for o in origins], dtype=float)
    origin_acc = np.array([motion.point_acc[o] for o in origins], dtype=float)
    angle = np.array([motion.link_angle[link] for link in links], dtype=float)
    omega = np.array([motion.link_omega[link] for link in links], dtype=float)
    alpha = np.array([motion.link_alpha[link] for link in links], dtype=float)
    # Motion.point_on's arithmetic for all links at once, the plane vectors as complex numbers: the centre of mass
    # at r = e^(i·angle)·(x + i·y) from the frame origin moves with i·omega·r and accelerates with
    # (i·alpha - omega²)·r relative to it.
    known = motion.link_unit
    e = (np.array([known[link] for link in links], dtype=complex) if all(link in known for link in links)
         else unit(angle))
    local = com[..., 0] + 1j * com[..., 1]
    r = e * (local[:, None] if local.ndim == 1 else local)
    com_pos = origin_pos + xy(r)
    com_vel = origin_vel + xy((1j * omega) * r)
    com_acc = origin_acc + xy((1j * alpha - omega * omega) * r)
    for arr in (com_pos, com_vel, com_acc):
        arr.flags.writeable = False
    return LinkArrays(links, params, mass, com, inertia, origin_pos, origin_acc, angle, omega, alpha,
                      com_pos, com_vel, com_acc)


def per_sample(values: FloatArray) -> FloatArray:
    """A link property of :class:`LinkArrays` (``mass``, ``inertia``), (L,) or per sample (L, N), as an array
    that broadcasts against (L, N): (L, 1) or (L, N)."""
    return values if values.ndim == 2 else values[:, None]


def link_sum(values: FloatArray, per_link: FloatArray) -> FloatArray:
    """Σ over the links of a link property of :class:`LinkArrays` (``mass``, ``inertia``: (L,), or per sample
    (L, N)) times a per-link quantity (L, N): (N,)."""
    return np.asarray(values @ per_link if values.ndim == 1 else np.einsum("ln,ln->n", values, per_link))


def _axis_normal(motion: Motion, topo: Topology, joint_index: int) -> FloatArray:
    """Unit normal to a prismatic joint's slide axis at every sample, (N, 2)."""
    joint = topo.joints[joint_index]
    if joint.axis_link is None:  # fixed in the frame: one normal, read-only, for every sample
        normal = np.array([-np.sin(joint.axis_angle), np.cos(joint.axis_angle)])
        return np.broadcast_to(normal, (motion.samples, 2))
    angle = joint.axis_angle + motion.link_angle[joint.axis_link]
    return np.stack([-np.sin(angle), np.cos(angle)], axis=-1)


def system_matrix(motion: Motion, topo: Topology) -> FloatArray:
    """Equilibrium matrix A of shape (N, 3n, 3n): A @ unknowns + known loads = 0 for every link."""
    natural = tuple(range(3 * len(topo.links)))
    return np.moveaxis(_assemble(motion, topo, natural, natural), -1, 0)


def _assemble(motion: Motion, topo: Topology, row_pos: tuple[int, ...], col_pos: tuple[int, ...]) -> FloatArray:
    """The equilibrium matrix, crank angle last (3n, 3n, N), with equation i in row ``row_pos[i]`` and unknown k
    in column ``col_pos[k]``.

    The angle is the last axis so that each coefficient is one contiguous run over the cycle: filling and
    combining the small matrices then streams memory instead of striding across it.
    """
    a = np.zeros((len(row_pos), len(col_pos), motion.samples))
    for j, joint in enumerate(topo.joints):
        cx, cy = col_pos[2 * j], col_pos[2 * j + 1]
        p = motion.point_pos[joint.point]
        giver, receiver = joint.bodies
        for body, sign in ((receiver, 1.0), (giver, -1.0)):
            if body is None:
                continue
            i = 3 * topo.links.index(body)
            fx, fy, mz = row_pos[i], row_pos[i + 1], row_pos[i + 2]
            lever = p - motion.point_pos[motion.link_origin[body]]
            if joint.kind == "revolute":
                a[fx, cx] += sign
                a[fy, cy] += sign
                a[mz, cx] -= sign * lever[:, 1]
                a[mz, cy] += sign * lever[:, 0]
            else:
                normal = _axis_normal(motion, topo, j)
                a[fx, cx] += sign * normal[:, 0]
                a[fy, cx] += sign * normal[:, 1]
                a[mz, cx] += sign * cross(lever, normal)
                a[mz, cy] += sign
    a[row_pos[3 * topo.links.index(topo.crank) + 2], col_pos[-1]] = 1.0
    return a


@dataclass(frozen=True, slots=True)
class _MomentPlan:
    """Where each revolute lever enters the moment rows, fixed per topology and column order: the lever of
    joint point ``joint_points[p]`` about the frame origin ``origin_points[p]`` of link ``link[p]``, with
    ``sign`` (+1 on the receiving link, -1 on the giving one), in columns ``col_x[p]`` and ``col_y[p]``. A joint at
    its link's own origin has no lever there and no entry."""

    points: tuple[str, ...]
    joint_points: IndexArray
    origin_points: IndexArray
    link: IndexArray
    col_x: IndexArray
    col_y: IndexArray
    sign: FloatArray
    incidence: FloatArray                                     # (links, levers): 1 where a lever is in a link's row
    heads: IndexArray                                         # the signed lever is points[heads] - points[tails]
    tails: IndexArray
    prismatic: tuple[tuple[int, int, int, int, float], ...]   # (joint, link, cx, cy, sign)
    torque: tuple[int, int]


@functools.lru_cache(maxsize=64)
def _moment_plan(topo: Topology, col_pos: tuple[int, ...], origins: tuple[str, ...]) -> _MomentPlan:
    links = topo.links
    points: list[str] = []

    def index(point: str) -> int:
        if point not in points:
            points.append(point)
        return points.index(point)

    rev: list[tuple[int, int, int, int, int, float]] = []
    prismatic: list[tuple[int, int, int, int, float]] = []
    for j, joint in enumerate(topo.joints):
        cx, cy = col_pos[2 * j], col_pos[2 * j + 1]
        giver, receiver = joint.bodies
        for body, sign in ((receiver, 1.0), (giver, -1.0)):
            if body is None:
                continue
            i = links.index(body)
            if joint.kind == "revolute":
                if joint.point != origins[i]:   # a joint at its link's origin has no lever: no entry to make
                    rev.append((index(joint.point), index(origins[i]), i, cx, cy, sign))
            else:
                prismatic.append((j, i, cx, cy, sign))
    cols = np.array(rev, dtype=float).reshape(-1, 6)
    as_int = cols[:, :5].astype(np.intp)
    incidence = np.zeros((len(links), len(rev)))
    incidence[as_int[:, 2], np.arange(len(rev))] = 1.0
    receiving = cols[:, 5] > 0
    heads = np.where(receiving, as_int[:, 0], as_int[:, 1])
    tails = np.where(receiving, as_int[:, 1], as_int[:, 0])
    return _MomentPlan(tuple(points), as_int[:, 0], as_int[:, 1], as_int[:, 2], as_int[:, 3], as_int[:, 4],
                       cols[:, 5], incidence, heads, tails, tuple(prismatic), (links.index(topo.crank), col_pos[-1]))


@dataclass(frozen=True, slots=True)
class _MomentTerms:
    """The reduced system of :func:`_solve_constant_forces` written from the moment rows' nonzero entries alone.

    The varying entries are, in order, every revolute lever's x column (-Im lever), its y column (Re lever) and
    each slide's lever term; ``s_map`` takes them to S = M_kept - M_elim·G, (n·n_kept, entries), and
    ``s_const`` holds the constant entries' part (a slide's unit column, the driving torque), (n, n_kept).
    The eliminated columns hold revolute levers only: ``r_entries`` picks those entries, ``r_columns`` their
    eliminated unknowns and ``r_rows`` the moment rows they sit in, for R = B_kept - M_elim·H.
    """

    plan: _MomentPlan
    s_map: FloatArray
    s_const: FloatArray
    r_entries: IndexArray
    r_columns: IndexArray
    r_rows: IndexArray
    r_incidence: FloatArray        # (n, entries picked): 1 where a picked entry sits in a link's moment row
    # The reduction's orders as index arrays, made once: force rows, moment rows, eliminated and kept unknowns.
    force_rows: IndexArray
    moment_rows: IndexArray
    eliminated: IndexArray
    kept: IndexArray


@functools.lru_cache(maxsize=64)
def _moment_terms(topo: Topology, col_pos: tuple[int, ...], origins: tuple[str, ...]) -> _MomentTerms:
    plan = _moment_plan(topo, col_pos, origins)
    red = _reduction(topo)
    assert red is not None and red.g is not None
    n, k = len(topo.links), 2 * len(topo.links)
    g = red.g
    n_kept = g.shape[1]
    links = list(plan.link) * 2 + [i for _, i, _, _, _ in plan.prismatic]
    columns = list(plan.col_x) + list(plan.col_y) + [cx for _, _, cx, _, _ in plan.prismatic]

    def coefficients(column: int) -> FloatArray:
        """Row of the map from an entry in ``column`` to S's n_kept columns."""
        return np.asarray(np.eye(n_kept)[column - k] if column >= k else -g[column], dtype=float)

    s_map = np.zeros((n, n_kept, len(links)))
    for e, (link, column) in enumerate(zip(links, columns, strict=True)):
        s_map[link, :, e] += coefficients(column)
    s_const = np.zeros((n, n_kept))
    for _, i, _, cy, sign in plan.prismatic:
        s_const[i] += sign * coefficients(cy)
    s_const[plan.torque[0]] += coefficients(plan.torque[1])
    r_entries = np.array([e for e, c in enumerate(columns) if c < k], dtype=np.intp)
    rows = np.asarray(red.rows, dtype=np.intp)
    r_rows = np.asarray(links, dtype=np.intp)[r_entries]
    r_incidence = np.zeros((n, len(r_entries)))
    r_incidence[r_rows, np.arange(len(r_entries))] = 1.0
    return _MomentTerms(plan, s_map.reshape(n * n_kept, -1), s_const, r_entries,
                        np.asarray(columns, dtype=np.intp)[r_entries], r_rows, r_incidence,
                        rows[:k], rows[k:], np.asarray(red.eliminated, dtype=np.intp),
                        np.asarray(red.kept, dtype=np.intp))


def _batched_matmul(a: FloatArray, b: FloatArray) -> FloatArray:
    """Products of stacked small matrices, crank angle last: (i, j, N) @ (j, k, N) -> (i, k, N)."""
    out = a[:, 0, None, :] * b[None, 0]
    for j in range(1, a.shape[1]):
        out += a[:, j, None, :] * b[None, j]
    return out


@dataclass(frozen=True, slots=True)
class _Reduction:
    """Which unknowns the constant force rows eliminate: ``eliminated`` (2n columns, revolute reactions whose
    force-row block is the constant ``f_inv``⁻¹) and ``kept`` (the other n unknowns).

    ``g`` is F⁻¹ times the force rows of the kept unknowns when those rows are constant too (revolute joints,
    slides fixed in the frame, the driving torque): the eliminated reactions are then ``h - g @ kept`` with a
    constant ``g`` and no per-angle product is needed to form it. None when a slide axis turns with a link.
    """

    eliminated: tuple[int, ...]
    kept: tuple[int, ...]
    f_inv: FloatArray
    f_det: float
    g: FloatArray | None
    force_rows_norm: float | None = None   # product of the constant force rows' norms, when g is not None

    @property
    def rows(self) -> tuple[int, ...]:
        """Equations in solving order: every link's two force rows, then every link's moment row."""
        n = len(self.kept)
        return tuple(3 * i + c for i in range(n) for c in (0, 1)) + tuple(3 * i + 2 for i in range(n))

    @property
    def columns(self) -> tuple[int, ...]:
        """Unknowns in solving order: the eliminated reactions, then the kept unknowns."""
        return self.eliminated + self.kept

    @staticmethod
    def positions(order: tuple[int, ...]) -> tuple[int, ...]:
        """Inverse of a permutation: where each natural index sits in ``order``."""
        out = [0] * len(order)
        for pos, i in enumerate(order):
            out[i] = pos
        return tuple(out)


@functools.lru_cache(maxsize=32)
def _reduction(topo: Topology) -> _Reduction | None:
    """Choose n revolute joints whose reactions the force equations determine (built once per topology).

    Returns None when no such choice exists (too few revolute joints); the full system is solved then.
    """
    n = len(topo.links)
    row = {name: 2 * i for i, name in enumerate(topo.links)}
    revolute = [j for j, joint in enumerate(topo.joints) if joint.kind == "revolute"]
    for chosen in itertools.combinations(revolute, n):
        f = np.zeros((2 * n, 2 * n))
        for c, j in enumerate(chosen):
            giver, receiver = topo.joints[j].bodies
            for body, sign in ((receiver, 1.0), (giver, -1.0)):
                if body is not None:
                    f[row[body], 2 * c] += sign
                    f[row[body] + 1, 2 * c + 1] += sign
        if abs(np.linalg.det(f)) > 0.5:  # integer matrix: its determinant is 0 or at least 1 in magnitude
            eliminated = tuple(col for j in chosen for col in (2 * j, 2 * j + 1))
            kept = tuple(col for col in range(3 * n) if col not in eliminated)
            f_inv = np.asarray(np.linalg.inv(f), dtype=float)
            kept_rows = _constant_force_rows(topo, kept)
            g = None if kept_rows is None else f_inv @ kept_rows
            all_rows = _constant_force_rows(topo, tuple(range(3 * n)))
            norm = None if all_rows is None else float(np.prod(np.sqrt((all_rows * all_rows).sum(axis=1))))
            return _Reduction(eliminated, kept, f_inv, float(np.linalg.det(f)), g, norm)
    return None


def _constant_force_rows(topo: Topology, columns: tuple[int, ...]) -> FloatArray | None:
    """The force rows (2n) of the unknowns ``columns`` when they do not depend on the crank angle, else None."""
    n = len(topo.links)
    row = {name: 2 * i for i, name in enumerate(topo.links)}
    out = np.zeros((2 * n, len(columns)))
    for c, col in enumerate(columns):
        if col == 3 * n - 1:  # the driving torque has no force
            continue
        joint = topo.joints[col // 2]
        if joint.kind == "revolute":
            direction = (1.0, 0.0) if col % 2 == 0 else (0.0, 1.0)
        elif col % 2 == 1:  # a slide's couple has no force
            continue
        elif joint.axis_link is None:
            direction = (-np.sin(joint.axis_angle), np.cos(joint.axis_angle))
        else:
            return None
        giver, receiver = joint.bodies
        for body, sign in ((receiver, 1.0), (giver, -1.0)):
            if body is not None:
                out[row[body], c] += sign * direction[0]
                out[row[body] + 1, c] += sign * direction[1]
    return out


def _constant_matmul(f: FloatArray, x: FloatArray) -> FloatArray:
    """F @ x for a constant matrix F and stacked x (j, ..., N), summing only F's nonzero entries: F⁻¹ of the
    plus-or-minus-one force rows is sparse, and a general product would spend most of its time on zeros."""
    out = np.zeros((f.shape[0],) + x.shape[1:])
    for i, j in zip(*np.nonzero(f), strict=True):
        out[i] += f[i, j] * x[j]
    return out


def _lu_det_and_solve(s: FloatArray, r: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Determinants and solutions of stacked k x k systems (k, k, N), (k, m, N) by Gaussian elimination with
    partial pivoting, each step one array operation over all crank angles (LAPACK's batched routines factorise
    the small matrices one at a time, and twice: once for the determinant, once for the solve)."""
    k, n = s.shape[0], s.shape[-1]
    s, r = s.copy(), r.copy()
    det = np.ones(n)
    for i in range(k):
        if i < k - 1:
            pivot = i + np.argmax(np.abs(s[i:, i]), axis=0)
            swap = np.flatnonzero(pivot != i)
            if swap.size:
                rows = pivot[swap]
                s[i, :, swap], s[rows, :, swap] = s[rows, :, swap], s[i, :, swap].copy()
                r[i, :, swap], r[rows, :, swap] = r[rows, :, swap], r[i, :, swap].copy()
                det[swap] = -det[swap]
        det *= s[i, i]
        if i < k - 1:
            factor = s[i + 1 :, i] / s[i, i]
            s[i + 1 :, i + 1 :] -= factor[:, None] * s[i, None, i + 1 :]
            r[i + 1 :] -= factor[:, None] * r[i, None]
    x = np.empty_like(r)
    for i in range(k - 1, -1, -1):
        rest = r[i].copy()
        for j in range(i + 1, k):
            rest -= s[i, j, None] * x[j]
        x[i] = rest / s[i, i]
    return det, x


@functools.lru_cache(maxsize=64)
def _block_order(k: int, pattern: bytes) -> tuple[tuple[tuple[int, ...], tuple[int, ...]], ...] | None:
    """Blocks (rows, columns) in which a k x k system of nonzero ``pattern`` (row-major booleans) can be solved one
    after another: a lower block-triangular form, found once per pattern.

    A linkage of dyads is solved dyad by dyad by hand; this finds the same order from the matrix alone: a
    matching of equations to unknowns (a zero-free diagonal), then the strongly connected components of
    "equation needs unknown", which Tarjan's algorithm emits dependencies first. None when no matching exists
    (the system is structurally singular).
    """
    mask = np.frombuffer(pattern, dtype=bool).reshape(k, k)
    match_col: dict[int, int] = {}                 # column -> its row

    def augment(row: int, seen: set[int]) -> bool:
        for col in np.flatnonzero(mask[row]):
            c = int(col)
            if c not in seen:
                seen.add(c)
                if c not in match_col or augment(match_col[c], seen):
                    match_col[c] = row
                    return True
        return False

    for row in range(k):
        if not augment(row, set()):
            return None
    row_of = [match_col[c] for c in range(k)]
    needs = [[int(c) for c in np.flatnonzero(mask[row_of[j]]) if c != j] for j in range(k)]
    index: dict[int, int] = {}
    low: dict[int, int] = {}
    stack: list[int] = []
    blocks: list[tuple[tuple[int, ...], tuple[int, ...]]] = []

    def connect(v: int) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in needs[v]:
            if w not in index:
                connect(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            cols: list[int] = []
            while True:
                w = stack.pop()
                cols.append(w)
                if w == v:
                    break
            cols.sort()
            blocks.append((tuple(row_of[c] for c in cols), tuple(cols)))

    for v in range(k):
        if v not in index:
            connect(v)
    return tuple(blocks)


def _permutation_sign(order: list[int]) -> float:
    """+1 or -1: the sign of a permutation given as the list of images."""
    sign, seen = 1.0, [False] * len(order)
    for start in range(len(order)):
        length, i = 0, start
        while not seen[i]:
            seen[i] = True
            i = order[i]
            length += 1
        if length and length % 2 == 0:
            sign = -sign
    return sign


@functools.lru_cache(maxsize=64)
def _block_plan(k: int, pattern: bytes) -> tuple[float, tuple[tuple[list[int], list[int], list[int]], ...]] | None:
    """The block order of :func:`_block_order` ready to run: the sign of its row and column permutations, and per
    block its rows, its columns and the earlier columns its rows need; None when there is no such order with
    blocks of at most 3 x 3."""
    blocks = _block_order(k, pattern)
    if blocks is None or max(len(cols) for _, cols in blocks) > 3:
        return None
    mask = np.frombuffer(pattern, dtype=bool).reshape(k, k)
    sign = (_permutation_sign([row for rows, _ in blocks for row in rows])
            * _permutation_sign([col for _, cols in blocks for col in cols]))
    plan: list[tuple[list[int], list[int], list[int]]] = []
    solved: list[int] = []
    for rows, cols in blocks:
        prior = [c for c in solved if mask[list(rows), c].any()]
        plan.append((list(rows), list(cols), prior))
        solved.extend(cols)
    return sign, tuple(plan)


def _block_det_and_solve(s: FloatArray, r: FloatArray) -> tuple[FloatArray, FloatArray] | None:
    """``_det_and_solve`` through the lower block-triangular form of ``s`` (k, k, N) when it has blocks of at most
    3 x 3 (each then solved in closed form), else None."""
    plan = _block_plan(s.shape[0], np.ascontiguousarray(np.any(s != 0, axis=-1)).tobytes())
    if plan is None:
        return None
    sign, blocks = plan
    x = np.empty(r.shape)
    det: FloatArray | float = sign
    for rows, cols, prior in blocks:
        rhs = r[rows]
        if prior:
            rhs = rhs - _batched_matmul(s[rows][:, prior], x[prior])
        block_det, block_x = _det_and_solve(s[rows][:, cols], rhs)
        det = det * block_det
        x[cols] = block_x
    return np.broadcast_to(det, s.shape[-1:]).copy() if np.ndim(det) == 0 else np.asarray(det), x


def _det_and_solve(s: FloatArray, r: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Determinants of the stacked small matrices ``s`` (k, k, N) and the solutions of s @ x = r (k, m, N).

    Up to 3 x 3 by the adjugate in closed form, larger by Gaussian elimination with partial pivoting; both
    vectorised over N, with no per-matrix LAPACK call.
    """
    k = s.shape[0]
    if k == 1:
        det = s[0, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            return det, r / det
    if k == 2:
        det = s[0, 0] * s[1, 1] - s[0, 1] * s[1, 0]
        adj = np.stack([np.stack([s[1, 1], -s[0, 1]]), np.stack([-s[1, 0], s[0, 0]])])
    elif k == 3:
        # Rows a, b, c: x = adj·r / det with the adjugate's columns b x c, c x a, a x b, and
        # r1·(c x a) + r2·(a x b) = a x (r2·b - r1·c): one cross product fewer than the adjugate.
        (a0, a1, a2), (b0, b1, b2), (c0, c1, c2) = s
        r0, r1, r2 = r
        u0, u1, u2 = b1 * c2 - b2 * c1, b2 * c0 - b0 * c2, b0 * c1 - b1 * c0
        det = a0 * u0 + a1 * u1 + a2 * u2
        t0, t1, t2 = r2 * b0 - r1 * c0, r2 * b1 - r1 * c1, r2 * b2 - r1 * c2
        x = np.empty(r.shape)
        x[0] = r0 * u0 + (a1 * t2 - a2 * t1)
        x[1] = r0 * u1 + (a2 * t0 - a0 * t2)
        x[2] = r0 * u2 + (a0 * t1 - a1 * t0)
        with np.errstate(divide="ignore", invalid="ignore"):
            x /= det
        return det, x
    else:
        with np.errstate(divide="ignore", invalid="ignore"):
            blocked = _block_det_and_solve(s, r)
            return _lu_det_and_solve(s, r) if blocked is None else blocked
    with np.errstate(divide="ignore", invalid="ignore"):
        return det, _batched_matmul(adj, r) / det


def _solve_stacked(motion: Motion, topo: Topology, b: FloatArray) -> FloatArray:
    """Solve A @ x = b at every angle, b of shape (N, 3n, m); a singular system is a dead point where the
    driving torque is undefined. Singularity is judged by the Hadamard ratio |det A| / prod(row norms of A),
    which lies in [0, 1]."""
    return _solve_angle_last(motion, topo, b.transpose(1, 2, 0))


def _solve_angle_last(motion: Motion, topo: Topology, b_last: FloatArray) -> FloatArray:
    """``_solve_stacked`` for right-hand sides with the crank angle last, (3n, M, N); unknowns (N, 3n, M).

    Every force row constant (revolute joints, slides fixed in the frame): :func:`_solve_constant_forces`.
    Otherwise the whole matrix is assembled, in the reduced system's solving order when the topology has one.
    """
    if topo.indeterminate:
        return _solve_least_norm(motion, topo, b_last)
    red = _reduction(topo)
    if red is not None and red.g is not None and red.force_rows_norm is not None:
        return _solve_constant_forces(motion, topo, red, red.g, red.force_rows_norm, b_last)
    return _solve_assembled(motion, topo, red, b_last.transpose(2, 0, 1))


def _solve_least_norm(motion: Motion, topo: Topology, b_last: FloatArray) -> FloatArray:
    """``_solve_stacked`` when redundant pairs leave more unknowns than equations (3n x (2p + 1), rank 3n): the
    least-norm solution, x = A⁺·b by the pseudo-inverse at every angle. The equations fix the driving torque (no
    self-balanced set of reactions moves the crank); among the reaction sets that balance every link this takes
    the one of least sum of squared components (forces [N], couples [N·m]). A dead position is where no
    solution balances every link."""
    rows = tuple(range(3 * len(topo.links)))
    cols = tuple(range(2 * len(topo.joints) + 1))
    a = np.moveaxis(_assemble(motion, topo, rows, cols), -1, 0)
    b = b_last.transpose(2, 0, 1)
    x = np.asarray(np.linalg.pinv(a, rcond=SINGULAR_RATIO) @ b)
    # Where A loses rank (a change point where all the links line up) the loads may still balance: refuse only
    # the angles where the least-norm solution leaves an equation unbalanced.
    miss = np.linalg.norm(a @ x - b, axis=(1, 2))
    scale = np.linalg.norm(a, axis=(1, 2)) * np.linalg.norm(x, axis=(1, 2)) + np.linalg.norm(b, axis=(1, 2))
    bad = ~(miss <= 1e-9 * scale)
    if bad.any():
        raise NotAssemblable(
            f"at {int(bad.sum())} of {motion.samples} crank angles (deg: {angle_ranges_deg(motion.phi, bad)}) the "
            "linkage with redundant pairs passes a change point (its links in line): the loads there have a part no "
            "reactions balance, and the rigid model's reactions grow without bound near it; analyse at other "
            "angles (crank_angle_deg) or move a passive link's pivot off the line",
            phi=motion.phi[bad], ranges_deg=angle_ranges_deg(motion.phi, bad))
    return x


def _solve_assembled(motion: Motion, topo: Topology, red: _Reduction | None, b: FloatArray) -> FloatArray:
    """``_solve_stacked`` on the assembled matrix A, b (N, 3n, m): through the reduced moment system when there is
    one (a slide turning with a link makes its force rows vary, so F⁻¹ times them is formed at every angle), else
    on the whole system; det A = det F · det S."""
    if red is None:
        natural = tuple(range(3 * len(topo.links)))
        a = _assemble(motion, topo, natural, natural)
        s, r, f_det = a, np.moveaxis(b, 0, -1), 1.0
    else:
        rows, cols = red.rows, red.columns
        a = _assemble(motion, topo, red.positions(rows), red.positions(cols))
        bp = np.moveaxis(b[:, list(rows)], 0, -1)
        k, f_det = len(red.eliminated), red.f_det
        m_elim = a[k:, :k]
        h = _constant_matmul(red.f_inv, bp[:k])              # eliminated = h - g @ kept
        g = _constant_matmul(red.f_inv, a[:k, k:])
        s = a[k:, k:] - _batched_matmul(m_elim, g)
        r = bp[k:] - _batched_matmul(m_elim, h)
    det, x_kept = _det_and_solve(s, r)
    rows_norm = np.prod(np.sqrt(np.einsum("ijn,ijn->in", a, a)), axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.abs(f_det * det) / rows_norm
    _refuse_dead_positions(motion, ratio)
    if red is None:
        return np.moveaxis(x_kept, -1, 0)
    x = np.empty(b.shape)
    x[:, list(cols)] = np.moveaxis(np.concatenate([h - _batched_matmul(g, x_kept), x_kept]), -1, 0)
    return x


def _refuse_dead_positions(motion: Motion, ratio: FloatArray) -> None:
    """NotAssemblable where the Hadamard ratio of the system says it is singular (or is not a number)."""
    bad = ~np.isfinite(ratio) | (ratio < SINGULAR_RATIO)
    if np.logical_or.reduce(bad):
        raise NotAssemblable(
            f"the linkage passes a dead (singular) position at {int(bad.sum())} of {motion.samples} crank angles; "
            "the crank cannot drive it there",
            phi=motion.phi[bad],
            ranges_deg=angle_ranges_deg(motion.phi, bad),
        )


def _solve_constant_forces(motion: Motion, topo: Topology, red: _Reduction, g: FloatArray, force_rows_norm: float,
                           b_last: FloatArray) -> FloatArray:
    """``_solve_stacked`` when every force row is constant (revolute joints and slides fixed in the frame): the
    force rows enter through F⁻¹, ``g`` and their norms, all constant, and the moment rows only through their
    nonzero entries (the levers), which constant maps made once per topology (:func:`_moment_terms`) take
    straight to the reduced system's matrix and right-hand side: no (n, 3n, N) matrix of mostly zeros is made."""
    k, n_kept = len(red.eliminated), len(red.kept)
    links = topo.links
    terms = _moment_terms(topo, red.positions(red.columns), tuple(motion.link_origin[link] for link in links))
    plan = terms.plan
    width, samples = b_last.shape[1], b_last.shape[2]
    # eliminated = h - g @ kept
    h = (red.f_inv @ b_last[terms.force_rows].reshape(k, -1)).reshape(k, width, samples)
    # The varying entries, (entries, N), written in place: at a few thousand angles each pass over memory costs
    # more than its arithmetic.
    levers = len(plan.sign)
    values = np.empty((terms.s_map.shape[1], samples))
    # every point the levers use, stacked in one call, (points, N) complex; all levers in one subtraction
    pos = np.array([motion.point_pos[p] for p in plan.points], dtype=float).view(np.complex128)[..., 0]
    lever = pos[plan.heads]
    lever -= pos[plan.tails]
    np.negative(lever.imag, out=values[:levers])
    values[levers:2 * levers] = lever.real
    squares = np.square(values[:2 * levers])
    row_sq = plan.incidence @ (squares[:levers] + squares[levers:])
    for e, (j, i, _, _, sign) in enumerate(plan.prismatic, start=2 * levers):
        joint = topo.joints[j]
        normal = complex(-np.sin(joint.axis_angle), np.cos(joint.axis_angle))
        lever_p = complex_of(motion.point_pos[joint.point]) - complex_of(motion.point_pos[motion.link_origin[links[i]]])
        term = values[e]
        np.multiply((lever_p.conj() * normal).imag, sign, out=term)
        row_sq[i] += term * term + 1.0
    row_sq[plan.torque[0]] += 1.0
    s = terms.s_map @ values
    s += terms.s_const.reshape(-1, 1)
    s = s.reshape(len(links), n_kept, samples)
    r = b_last[terms.moment_rows]                             # a copy, in solving order
    if len(terms.r_entries):
        # every lever times its eliminated reaction at once, summed into its link's row by a constant matrix
        picked = values[terms.r_entries][:, None, :] * h[terms.r_columns]
        r -= (terms.r_incidence @ picked.reshape(len(terms.r_entries), -1)).reshape(r.shape)
    det, x_kept = _det_and_solve(s, r)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.abs(red.f_det * det) / (force_rows_norm * np.sqrt(row_sq.prod(axis=0)))
    _refuse_dead_positions(motion, ratio)
    # Assembled with the angle last (each unknown one contiguous run) and handed out as an (N, 3n, M) view: a
    # scatter into the angle-first layout would stride across memory for every unknown.
    x = np.empty((b_last.shape[0], width, samples))
    np.subtract(h, (g @ x_kept.reshape(n_kept, -1)).reshape(k, width, samples), out=h)
    x[terms.eliminated] = h
    x[terms.kept] = x_kept
    return x.transpose(2, 0, 1)


@dataclass(frozen=True, slots=True)
class ExternalLoads:
    """Process forces and link torques resolved at every sample, in the frame's coordinates."""

    force: FloatArray  # on the output member [N], (N, 2)
    point: FloatArray  # where it acts [m], (N, 2)
    point_vel: FloatArray  # its velocity [m/s], (N, 2)
    torques: dict[str, FloatArray]  # link -> torque [N·m], (N,)
    has_force: bool = True  # False when ``force`` is zero throughout (no process force): its terms are skipped


def external_loads(motion: Motion, linkage: Linkage) -> ExternalLoads:
    """Process loads (against the output velocity, along the output or fixed in the frame), plus external torques,
    at every sample.

    A force of fixed direction on a turning output acts at its point on the output link; it is carried as the
    same force at the link's origin plus its moment about that origin, so that several such loads share one
    point of application.
    """
    topo = linkage.mechanism.topology
    n = motion.samples
    force = np.zeros((n, 2))
    origin_name = motion.link_origin[topo.output]
    point = motion.point_pos[origin_name].copy()
    point_vel = np.zeros((n, 2))
    torques: dict[str, FloatArray] = {t.link: np.zeros(n) for t in linkage.torques}
    for t in linkage.torques:
        torques[t.link] = torques[t.link] + t.torque
    if not linkage.loads:
        return ExternalLoads(force, point, point_vel, torques, has_force=False)
    sliding = topo.output_motion == "translation"
    if sliding:
        axis = np.array([np.cos(topo.output_axis_angle), np.sin(topo.output_axis_angle)])
        origin = motion.point_pos[origin_name]
        position = origin @ axis
        speed = motion.point_vel[origin_name] @ axis
    else:
        position = motion.link_angle[topo.output]
        speed = motion.link_omega[topo.output]
    direction = -np.sign(speed)
    has_force = sliding
    for load in linkage.loads:
        magnitude = load.magnitude_at(motion.phi, position)
        if load.stroke:
            magnitude = np.where(np.sign(speed) == load.stroke, magnitude, 0.0)
        signed = magnitude * direction if load.direction == "against_motion" else magnitude
        if load.direction == "frame":
            along = np.array([math.cos(load.angle), math.sin(load.angle)])
            state = motion.point_on(topo.output, load.point)
            if sliding:
                point, point_vel = state.pos, state.vel
                force = force + signed[:, None] * along
            else:
                # at the origin, with its moment about the origin: the rigid link takes it alike
                f = signed[:, None] * along
                force = force + f
                point, point_vel = motion.point_pos[origin_name], motion.point_vel[origin_name]
                torques[topo.output] = (torques.get(topo.output, np.zeros(n))
                                        + cross(state.pos - motion.point_pos[origin_name], f))
                has_force = True
        elif sliding:
            state = motion.point_on(topo.output, load.point)
            point, point_vel = state.pos, state.vel
            force = force + signed[:, None] * axis
        else:
            torques[topo.output] = torques.get(topo.output, np.zeros(n)) + signed
    return ExternalLoads(force, point, point_vel, torques, has_force=has_force)


def _known_loads_direct(linkage: Linkage, loads: ExternalLoads, arrays: LinkArrays) -> FloatArray:
    """Sum of gravity, inertia and external loads per link: force x, y and moment about its first joint, every
    link's three equations on axis 0 and the crank angle last, (3n, N)."""
    topo = linkage.mechanism.topology
    g = linkage.gravity.vector if linkage.gravity is not None else np.zeros(2)
    force = per_sample(arrays.mass) * (complex(g[0], g[1]) - complex_of(arrays.com_acc))   # (L, N), x + i·y
    lever = complex_of(arrays.com_pos) - complex_of(arrays.origin_pos)
    n_links, n = len(topo.links), arrays.angle.shape[1]
    out = np.empty((n_links, 3, n))
    out[:, 0] = force.real
    out[:, 1] = force.imag
    np.subtract((lever.conj() * force).imag, per_sample(arrays.inertia) * arrays.alpha, out=out[:, 2])
    if loads.has_force:
        i = topo.links.index(topo.output)
        out[i, :2] += loads.force.T
        out[i, 2] += cross(loads.point - arrays.origin_pos[i], loads.force)
    for link, torque in loads.torques.items():
        out[topo.links.index(link), 2] += torque
    return out.reshape(3 * n_links, n)


def _frame_action(motion: Motion, topo: Topology, x: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Force on the frame from its joints and the motor housing [N], and its moment about O [N·m].

    ``x`` has the unknowns on axis 1 and may carry extra trailing columns (one per parameter).
    """
    force = np.zeros((x.shape[0], 2) + x.shape[2:])
    moment = np.zeros((x.shape[0],) + x.shape[2:])
    extra = (slice(None),) + (None,) * (x.ndim - 2)
    for j, joint in enumerate(topo.joints):
        if joint.bodies[0] is not None:
            continue
        p = motion.point_pos[joint.point]
        if joint.kind == "revolute":
            fx, fy = -x[:, 2 * j], -x[:, 2 * j + 1]
            couple: FloatArray | float = 0.0
        else:
            normal = _axis_normal(motion, topo, j)
            fx = -x[:, 2 * j] * normal[:, 0][extra]
            fy = -x[:, 2 * j] * normal[:, 1][extra]
            couple = -x[:, 2 * j + 1]
        force[:, 0] += fx
        force[:, 1] += fy
        moment += p[:, 0][extra] * fy - p[:, 1][extra] * fx + couple
    moment -= x[:, -1]  # the motor housing takes the reaction of the driving torque
    return force, moment


@dataclass(frozen=True, slots=True)
class Kinetostatics:
    """Joint reactions, driving torque and the frame's shaking force and moment at every crank angle.

    ``reactions[j]`` is the force [N] that joint j's first body exerts on its second, (N, 2);
    ``couples[j]`` the couple [N·m] of a prismatic joint, (N,); ``shaking_force`` = -sum m·a_S [N], (N, 2);
    ``shaking_moment`` about the crank pivot O, including the motor housing reaction [N·m], (N,).
    """

    unknowns: FloatArray
    reactions: dict[str, FloatArray]
    couples: dict[str, FloatArray]
    driving_torque: FloatArray
    shaking_force: FloatArray
    shaking_moment: FloatArray


def unpack_unknowns(motion: Motion, topo: Topology, x: FloatArray
                    ) -> tuple[dict[str, FloatArray], dict[str, FloatArray]]:
    """The solved unknowns ``x`` (N, 2·joints) as each joint's reaction [N], (N, 2), and each slide's couple
    [N·m], (N,): a revolute joint's two components, a slide's force normal to its axis and its couple."""
    reactions: dict[str, FloatArray] = {}
    couples: dict[str, FloatArray] = {}
    for j, joint in enumerate(topo.joints):
        if joint.kind == "revolute":
            reactions[joint.name] = x[:, 2 * j : 2 * j + 2]
        else:
            reactions[joint.name] = x[:, 2 * j, None] * _axis_normal(motion, topo, j)
            couples[joint.name] = x[:, 2 * j + 1]
    return reactions, couples


def solve_direct(motion: Motion, linkage: Linkage, arrays: LinkArrays | None = None,
                 loads: ExternalLoads | None = None) -> Kinetostatics:
    """Kinetostatics from the links' actual loads (the plain model, independent of the linear map).

    ``arrays`` are :func:`link_arrays` and ``loads`` :func:`external_loads` of this motion and linkage when the
    caller has them already.
    """
    topo = linkage.mechanism.topology
    arrays = link_arrays(motion, linkage) if arrays is None else arrays
    loads = external_loads(motion, linkage) if loads is None else loads
    known = _known_loads_direct(linkage, loads, arrays)
    x = _solve_angle_last(motion, topo, -known[:, None, :])[..., 0]
    force, moment = _frame_action(motion, topo, x)
    # The process load's reaction lands on the frame (workpiece, cylinder head); weights are a static load.
    if loads.has_force:
        force = force - loads.force
        moment = moment - cross(loads.point, loads.force)
    for torque in loads.torques.values():
        moment = moment - torque
    if linkage.gravity is not None:  # the weights' resultant and its moment about O
        g = linkage.gravity.vector
        if arrays.mass.ndim == 1:
            force = force - np.add.reduce(arrays.mass) * g
            first = (arrays.mass @ arrays.com_pos.reshape(len(arrays.mass), -1)).reshape(-1, 2)
        else:   # masses per sample (link_arrays_per_sample)
            force = force - arrays.mass.sum(axis=0)[:, None] * g
            first = np.einsum("ln,lnk->nk", arrays.mass, arrays.com_pos)
        moment = moment - (first[:, 0] * g[1] - first[:, 1] * g[0])
    reactions, couples = unpack_unknowns(motion, topo, x)
    return Kinetostatics(x, reactions, couples, x[:, -1], force, moment)


@dataclass(frozen=True, slots=True)
class LinearMap:
    """Every kinetostatic output as ``Y @ p + y0`` for the stacked inertial parameters p of all links.

    Rows (axis 1) are the unknowns (joint reactions, then the driving torque), then shaking force x, y and the
    shaking moment. Columns (axis 2) are 4 per link in topology order: m [kg], m·x, m·y [kg·m] in the link
    frame, and J about the link's first joint [kg·m²]. A counterweight on a link adds to that link's columns.
    """

    links: tuple[str, ...]
    joints: tuple[str, ...]
    y: FloatArray  # (N, rows, 4 * links)
    y0: FloatArray  # (N, rows)

    @property
    def torque_row(self) -> int:
        """Row of the driving torque."""
        return 2 * len(self.joints)

    @property
    def force_rows(self) -> slice:
        """Rows of the shaking force (x, y)."""
        return slice(self.torque_row + 1, self.torque_row + 3)

    @property
    def moment_row(self) -> int:
        """Row of the shaking moment."""
        return self.torque_row + 3

    def reaction_rows(self, joint: str) -> slice:
        """Rows of a joint's two reaction unknowns."""
        j = self.joints.index(joint)
        return slice(2 * j, 2 * j + 2)

    def columns(self, link: str) -> slice:
        """Columns of one link's four inertial parameters."""
        i = self.links.index(link)
        return slice(PARAMS_PER_LINK * i, PARAMS_PER_LINK * (i + 1))

    def point_mass(self, link: str, position: tuple[float, float] | FloatArray) -> FloatArray:
        """Change of every output per kilogram of point mass at ``position`` [m] in ``link``'s frame, (N, rows).

        A point mass m at r adds m·(1, x, y, x² + y²) to its link's parameters.
        """
        x, y = float(position[0]), float(position[1])
        unit = np.array([1.0, x, y, x * x + y * y])
        return np.asarray(self.y[:, :, self.columns(link)] @ unit)

    def evaluate(self, p: FloatArray) -> FloatArray:
        """All outputs for parameters ``p``, shape (N, rows)."""
        return np.asarray(np.einsum("nrk,k->nr", self.y, p) + self.y0)


def linear_map(motion: Motion, linkage: Linkage, arrays: LinkArrays | None = None) -> LinearMap:
    """Build the linear-in-parameters map for a fixed motion (loads other than inertia and gravity in y0).

    ``arrays`` are :func:`link_arrays` of this motion and linkage when the caller has them already.
    """
    topo = linkage.mechanism.topology
    arrays = link_arrays(motion, linkage) if arrays is None else arrays
    n, n_links = motion.samples, len(topo.links)
    g = linkage.gravity.vector if linkage.gravity is not None else np.zeros(2)
    known = np.zeros((n, 3 * n_links, PARAMS_PER_LINK * n_links + 1))
    grav_force = np.zeros((n, 2, PARAMS_PER_LINK * n_links))
    grav_moment = np.zeros((n, PARAMS_PER_LINK * n_links))
    for i, link in enumerate(topo.links):
        r0, c0 = 3 * i, PARAMS_PER_LINK * i
        th, w, al = arrays.angle[i], arrays.omega[i], arrays.alpha[i]
        a_o, o = arrays.origin_acc[i], arrays.origin_pos[i]
        e1 = np.stack([np.cos(th), np.sin(th)], axis=-1)
        e2 = perp(e1)
        g_rel = g - a_o
        # m·a_S = m·a_O + h_x(al·e2 - w²·e1) + h_y(-al·e1 - w²·e2); moment about O_link = h × (g - a_O) - J_O·al.
        known[:, r0 : r0 + 2, c0] = g_rel
        known[:, r0 : r0 + 2, c0 + 1] = -(al[:, None] * e2 - (w * w)[:, None] * e1)
        known[:, r0 : r0 + 2, c0 + 2] = al[:, None] * e1 + (w * w)[:, None] * e2
        known[:, r0 + 2, c0 + 1] = cross(e1, g_rel)
        known[:, r0 + 2, c0 + 2] = cross(e2, g_rel)
        known[:, r0 + 2, c0 + 3] = -al
        gb = np.broadcast_to(g, (n, 2))
        grav_force[:, :, c0] = -gb
        grav_moment[:, c0] = -cross(o, gb)
        grav_moment[:, c0 + 1] = -cross(e1, gb)
        grav_moment[:, c0 + 2] = -cross(e2, gb)
    loads = external_loads(motion, linkage)
    for i, link in enumerate(topo.links):
        origin = arrays.origin_pos[i]
        if link == topo.output and loads.has_force:
            known[:, 3 * i : 3 * i + 2, -1] += loads.force
            known[:, 3 * i + 2, -1] += cross(loads.point - origin, loads.force)
        known[:, 3 * i + 2, -1] += loads.torques.get(link, 0.0)
    x = _solve_stacked(motion, topo, -known)
    force, moment = _frame_action(motion, topo, x)
    force[:, :, -1] -= loads.force
    moment[:, -1] -= cross(loads.point, loads.force) + sum(loads.torques.values(), np.zeros(n))
    force[:, :, :-1] += grav_force
    moment[:, :-1] += grav_moment
    full = np.concatenate([x, force, moment[:, None, :]], axis=1)
    return LinearMap(topo.links, tuple(j.name for j in topo.joints), full[:, :, :-1], full[:, :, -1])


def shaking_force_map(motion: Motion, linkage: Linkage, arrays: LinkArrays | None = None) -> FloatArray:
    """The shaking-force rows of :func:`linear_map`, (N, 2, 4·L), from their definition -Σ m·a_S, without the
    reaction solve: for a program that needs only these rows (static balancing).

    Per link, m·a_S = m·a_O + h_x(al·e2 - w²·e1) + h_y(-al·e1 - w²·e2) with J absent; the rows' constant part
    is zero (process loads and weights react on the frame, so they shake nothing). ``arrays`` are
    :func:`link_arrays` (or :func:`link_arrays_per_sample`) of this motion when the caller has them already.
    """
    topo = linkage.mechanism.topology
    arrays = link_arrays(motion, linkage) if arrays is None else arrays
    th, w2, al = arrays.angle, arrays.omega * arrays.omega, arrays.alpha
    c, s = np.cos(th), np.sin(th)
    y = np.zeros((motion.samples, 2, len(topo.links), PARAMS_PER_LINK))
    y[:, :, :, 0] = -np.moveaxis(arrays.origin_acc, 0, -1)
    # -(al·e2 - w²·e1) and -(-al·e1 - w²·e2) with e1 = (c, s), e2 = (-s, c)
    y[:, 0, :, 1] = (al * s + w2 * c).T
    y[:, 1, :, 1] = (w2 * s - al * c).T
    y[:, 0, :, 2] = (al * c - w2 * s).T
    y[:, 1, :, 2] = (al * s + w2 * c).T
    return y.reshape(motion.samples, 2, len(topo.links) * PARAMS_PER_LINK)


def virtual_power_torque(motion: Motion, linkage: Linkage, arrays: LinkArrays | None = None,
                         loads: ExternalLoads | None = None) -> FloatArray:
    """Driving torque [N·m] from virtual power: the powers of all loads and inertia forces sum to zero.

    Independent of the reaction solve (Zhukovsky's lever in analytic form, seed 000:138-192). ``arrays`` are
    :func:`link_arrays` and ``loads`` :func:`external_loads` of this motion and linkage when the caller has them.
    """
    topo = linkage.mechanism.topology
    arrays = link_arrays(motion, linkage) if arrays is None else arrays
    g = linkage.gravity.vector if linkage.gravity is not None else np.zeros(2)
    loads = external_loads(motion, linkage) if loads is None else loads
    power = dot(loads.force, loads.point_vel) if loads.has_force else np.zeros(motion.samples)
    for link, torque in loads.torques.items():
        power = power + torque * motion.link_omega[link]
    # all links at once: m_l (g - a_S)·v_S - J_S alpha omega, summed over the links
    power = power + link_sum(arrays.mass, dot(g - arrays.com_acc, arrays.com_vel))
    power = power - link_sum(arrays.inertia, arrays.alpha * arrays.omega)
    return np.asarray(-power / arrays.omega[arrays.index(topo.crank)])
