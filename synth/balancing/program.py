"""Counterweight realisability and the cone programs of balancing, assembled directly for Clarabel.

A counterweight on a link adds (m, h_x, h_y, J) to that link's inertial parameters (mass, first moments in the
link frame, inertia about the link's first joint). It is physically realisable iff |h|² <= m·J (a rotated cone),
m >= 0 and |h| <= r_max·m; a fixed angle is a linear restriction of h.

The programs are small (a few variables per counterweight, one cone each, a handful of compressed objective
cones), so they are written straight into Clarabel's standard form min qᵀx s.t. A x + s = b, s in K with
numpy and scipy.sparse: no modelling layer to canonicalise on every request. The rows that depend only on the
counterweight layout are built once per layout and kept in a small per-process cache; a weight sweep changes
only q and re-solves one solver object.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import clarabel
import numpy as np
import scipy.sparse as sp

from ..errors import Infeasible, InvalidInput, SolverFailed, SolverTimeout
from ..model import Counterweight, FloatArray, Linkage
from ..warnings import link_lengths

#: Links that carry counterweights when none are named, per mechanism family: the four-bar's and the shaper's
#: crank and rocker, the slider-crank's crank (its rod may carry one when named).
DEFAULT_LINKS: Mapping[str, tuple[str, ...]] = {
    "fourbar": ("crank", "rocker"), "slider_crank": ("crank",), "slotted_lever": ("crank", "rocker"),
}


def _default_links(linkage: Linkage) -> tuple[str, ...]:
    """The family's default counterweight links; for a general linkage, every link turning about a frame pivot."""
    mech = linkage.mechanism
    if mech.family in DEFAULT_LINKS:
        return DEFAULT_LINKS[mech.family]
    bars = link_lengths(mech)
    pivoted = [j.bodies[1] for j in mech.topology.joints if j.kind == "revolute" and j.bodies[0] is None]
    return tuple(link for link in mech.topology.links if link in pivoted and link in bars) or (mech.topology.crank,)


@dataclass(frozen=True, slots=True)
class CounterweightSpec:
    """Where counterweights may go: links (none named: the family's :data:`DEFAULT_LINKS`, or a general linkage's
    links that turn about frame pivots), each link's largest
    radius [m], optional fixed radius [m] and fixed angle [rad] (in the link frame)."""

    links: tuple[str, ...] = ()
    max_radius: Mapping[str, float] | None = None
    angle: Mapping[str, float] | None = None
    radius: Mapping[str, float] | None = None

    def resolve(self, linkage: Linkage) -> CounterweightSpec:
        """This spec with the family's default links when it names none, validated against ``linkage``."""
        spec = self if self.links else replace(self, links=_default_links(linkage))
        spec.validate(linkage)
        return spec

    def validate(self, linkage: Linkage) -> None:
        """InvalidInput naming the field for unknown links, links that slide, or radii that are not positive."""
        names = linkage.mechanism.topology.links
        bars = link_lengths(linkage.mechanism)
        if not self.links:
            raise InvalidInput("at least one counterweight link is needed", field="counterweight_links")
        for link in self.links:
            if link not in names:
                raise InvalidInput(f"unknown link {link!r}; this mechanism has {list(names)}", field="counterweight_links")
            if link not in bars:
                # A slider, ram or block moves along its guide or slot, so whatever it carries moves along too:
                # more reciprocating mass, never a force against it.
                raise InvalidInput(
                    f"{link!r} slides on a guide or in a slot instead of turning about a pivot: a counterweight on "
                    f"it would slide with it and only add reciprocating mass; counterweights go on {list(bars)}",
                    field="counterweight_links")
        for link, r in (self.max_radius or {}).items():
            if link not in self.links:
                raise InvalidInput(f"max_radius_m given for {link!r}, which carries no counterweight",
                                   field=f"max_radius_m.{link}")
            if not (math.isfinite(r) and r > 0):
                raise InvalidInput(f"max_radius_m.{link} must be positive, got {r}", field=f"max_radius_m.{link}")
        for link in (self.angle or {}):
            if link not in self.links:
                raise InvalidInput(f"angle given for {link!r}, which carries no counterweight", field=f"angle_deg.{link}")
        for link, r in (self.radius or {}).items():
            if link not in self.links:
                raise InvalidInput(f"radius_m given for {link!r}, which carries no counterweight",
                                   field=f"radius_m.{link}")
            if not (math.isfinite(r) and r > 0):
                raise InvalidInput(f"radius_m.{link} must be positive, got {r}", field=f"radius_m.{link}")

    def limit(self, linkage: Linkage, link: str) -> float:
        """Largest counterweight radius on ``link`` [m]: its fixed radius, its maximum, or the link's length
        (crank, coupler, rocker or rod; the shaper's lever O1-B)."""
        if self.radius and link in self.radius:
            return float(self.radius[link])
        if self.max_radius and link in self.max_radius:
            return float(self.max_radius[link])
        return link_lengths(linkage.mechanism)[link]


PARAMS = 4  # per counterweight: m [kg], h_x, h_y [kg·m], J about the link's first joint [kg·m²]
# The radius cone carries a margin so that the solver's tolerance never carries a counterweight past its limit
# (the reported mass is also floored at |h|/r_max).
_RADIUS_MARGIN = 1e-7
# Tighter than Clarabel's defaults: the counterweights themselves (the argmin), not only the objective, are the
# answer, and flat optima leave them loose at the default gap.
_TOLERANCES = {"tol_gap_abs": 1e-10, "tol_gap_rel": 1e-10, "tol_feas": 1e-10}


@dataclass(frozen=True, slots=True)
class CounterweightLayout:
    """Where the counterweights go, as the programs take it: per link its radius limit [m], and the fixed
    radius [m] and fixed angle [rad] or NaN. Variables are ordered per link (m, h_x, h_y, J)."""

    links: tuple[str, ...]
    r_max: tuple[float, ...]
    radius: tuple[float, ...]
    angle: tuple[float, ...]

    @property
    def size(self) -> int:
        """Number of counterweight variables."""
        return PARAMS * len(self.links)

    def mass_columns(self) -> FloatArray:
        """Indicator of the mass variables, (size,)."""
        out = np.zeros(self.size)
        out[0::PARAMS] = 1.0
        return out

    def inertia_columns(self) -> FloatArray:
        """Indicator of the inertia variables, (size,)."""
        out = np.zeros(self.size)
        out[3::PARAMS] = 1.0
        return out


def counterweight_layout(spec: CounterweightSpec, linkage: Linkage) -> CounterweightLayout:
    """The layout of ``spec`` on ``linkage``: radius limits resolved, fixed radii and angles aligned per link."""
    radius, angle = spec.radius or {}, spec.angle or {}
    return CounterweightLayout(
        spec.links,
        tuple(spec.limit(linkage, link) for link in spec.links),
        tuple(float(radius.get(link, math.nan)) for link in spec.links),
        tuple(float(angle.get(link, math.nan)) for link in spec.links),
    )


@dataclass(frozen=True, slots=True)
class CounterweightSolution:
    """Solved counterweight variables: per link m [kg], h [kg·m] and J about the link's first joint [kg·m²]."""

    layout: CounterweightLayout
    x: FloatArray

    def counterweights(self, point_masses: bool = False) -> list[Counterweight]:
        """Counterweights from the solution: mass at least |h|/r_max (the solver meets the radius limit only to
        its tolerance), own inertia J - m·|r|² clipped at zero (zero for ``point_masses``)."""
        out = []
        v = self.x[: self.layout.size].reshape(-1, PARAMS)
        for i, link in enumerate(self.layout.links):
            mass = max(float(v[i, 0]), float(np.hypot(v[i, 1], v[i, 2])) / self.layout.r_max[i], 0.0)
            if mass <= 1e-12:
                continue
            pos = (float(v[i, 1] / mass), float(v[i, 2] / mass))
            own = 0.0 if point_masses else max(float(v[i, 3]) - mass * (pos[0] ** 2 + pos[1] ** 2), 0.0)
            out.append(Counterweight(link, mass, pos, own))
        return out


@dataclass(slots=True)
class ConeProgram:
    """A linear objective over cones in Clarabel's form: min qᵀx s.t. A x + s = b, s in the listed cones.

    Rows are appended block by block with ``equal`` (G x = g), ``at_most`` (G x <= g) and ``cone``
    (G x + g in a second-order cone, first entry the bound). The blocks are kept dense: a program has a few
    dozen columns, and scipy.sparse's per-block bookkeeping cost more than the solve; one sparse matrix is made
    for Clarabel at the end.
    """

    size: int
    q: FloatArray = field(init=False)
    _a: list[FloatArray] = field(default_factory=list)
    _b: list[FloatArray] = field(default_factory=list)
    _cones: list[object] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.q = np.zeros(self.size)

    def _rows(self, g: FloatArray | sp.spmatrix) -> FloatArray:
        m = np.atleast_2d(sp.csr_matrix.toarray(g) if sp.issparse(g) else np.asarray(g, dtype=float))
        if m.shape[1] < self.size:
            m = np.pad(m, ((0, 0), (0, self.size - m.shape[1])))
        return m

    def equal(self, g: FloatArray | sp.spmatrix, rhs: FloatArray) -> None:
        """Rows G x = rhs (G may cover only the first columns)."""
        if g.shape[0]:
            self._a.append(self._rows(g))
            self._b.append(np.asarray(rhs, dtype=float).reshape(-1))
            self._cones.append(clarabel.ZeroConeT(g.shape[0]))

    def at_most(self, g: FloatArray | sp.spmatrix, rhs: FloatArray) -> None:
        """Rows G x <= rhs."""
        if g.shape[0]:
            self._a.append(self._rows(g))
            self._b.append(np.asarray(rhs, dtype=float).reshape(-1))
            self._cones.append(clarabel.NonnegativeConeT(g.shape[0]))

    def cone(self, g: FloatArray | sp.spmatrix, offset: FloatArray, dim: int | None = None) -> None:
        """G x + offset in the second-order cone {(t, v): |v| <= t}; with ``dim``, consecutive cones of that
        size (one per angle, say)."""
        self._a.append(-self._rows(g))
        self._b.append(np.asarray(offset, dtype=float).reshape(-1))
        size = dim or g.shape[0]
        self._cones.extend(clarabel.SecondOrderConeT(size) for _ in range(g.shape[0] // size))

    def add(self, block: tuple[FloatArray, FloatArray, list[object]]) -> None:
        """Append a prebuilt block (rows, right-hand side, cones)."""
        a, b, cones = block
        self._a.append(self._rows(a))
        self._b.append(b)
        self._cones.extend(cones)

    def solver(self, time_limit_s: float) -> clarabel.DefaultSolver:
        """A Clarabel solver on this program; ``update(q=...)`` on it re-solves with new costs."""
        settings = clarabel.DefaultSettings()
        settings.verbose = False
        settings.time_limit = float(time_limit_s)
        for key, value in _TOLERANCES.items():
            setattr(settings, key, value)
        return clarabel.DefaultSolver(_zero_square(self.size), self.q, _csc(np.vstack(self._a)),
                                      np.concatenate(self._b), self._cones, settings)


def _csc(dense: FloatArray) -> sp.csc_matrix:
    """``scipy.sparse.csc_matrix(dense)`` (the same nonzeros in the same order) built from its index arrays: the
    generic conversion goes through a COO matrix and costs more than the solve of these small programs."""
    nonzero = dense.T != 0
    # 32-bit indices, as scipy would choose for a matrix this small, spare its constructor a conversion.
    rows = np.nonzero(nonzero)[1].astype(np.int32)
    indptr = np.concatenate([[0], np.cumsum(nonzero.sum(axis=1))]).astype(np.int32)
    return sp.csc_matrix((dense.T[nonzero], rows, indptr), shape=dense.shape)


@functools.lru_cache(maxsize=16)
def _zero_square(size: int) -> sp.csc_matrix:
    """The zero quadratic cost of a linear program (Clarabel copies it, so one per size serves every solver)."""
    return sp.csc_matrix((size, size))


@functools.lru_cache(maxsize=16)
def realisability_block(layout: CounterweightLayout) -> tuple[FloatArray, FloatArray, list[object]]:
    """Rows of the realisability cones of a layout (built once per layout per process).

    Per counterweight: m >= 0, J >= 0; |h| <= r_max·m; |h|² <= m·J as the cone |(2h, m - J)| <= m + J;
    a fixed radius r as J = r²·m (all of the mass at r); a fixed angle a as h parallel to (cos a, sin a).
    """
    n = layout.size
    blocks: list[tuple[FloatArray, str]] = []
    for i in range(len(layout.links)):
        m, hx, hy, j = (PARAMS * i + c for c in range(PARAMS))

        def row(*pairs: tuple[int, float]) -> FloatArray:
            out = np.zeros(n)
            for col, val in pairs:
                out[col] += val
            return out

        blocks.append((np.stack([row((m, -1.0)), row((j, -1.0))]), "nonneg"))
        blocks.append((np.stack([row((m, layout.r_max[i] * (1 - _RADIUS_MARGIN))), row((hx, 1.0)),
                                 row((hy, 1.0))]), "soc"))
        blocks.append((np.stack([row((m, 1.0), (j, 1.0)), row((m, 1.0), (j, -1.0)), row((hx, 2.0)),
                                 row((hy, 2.0))]), "soc"))
        if math.isfinite(layout.radius[i]):
            blocks.append((row((j, 1.0), (m, -layout.radius[i] ** 2))[None, :], "zero"))
        if math.isfinite(layout.angle[i]):
            c, s = math.cos(layout.angle[i]), math.sin(layout.angle[i])
            blocks.append((row((hx, -s), (hy, c))[None, :], "zero"))
            blocks.append((row((hx, -c), (hy, -s))[None, :], "nonneg"))
    rows, cones = [], []
    for g, kind in blocks:
        # Clarabel's rows are b - A x in the cone: equalities and inequalities G x <= 0 keep G, cones G x take -G.
        rows.append(-g if kind == "soc" else g)
        size = g.shape[0]
        cones.append(clarabel.SecondOrderConeT(size) if kind == "soc"
                     else clarabel.ZeroConeT(size) if kind == "zero" else clarabel.NonnegativeConeT(size))
    a = np.concatenate(rows)
    a.flags.writeable = False  # shared by every program of the layout in this process
    return a, np.zeros(a.shape[0]), cones


def row_space(a: FloatArray, b: FloatArray, what: str, constraint: str) -> tuple[FloatArray, FloatArray]:
    """Reduce the stacked equalities a @ x = b (thousands of rows, few independent) to their row space.

    Raises Infeasible when b has a part outside the column space of a: no choice of x can meet them.
    """
    u, s, _ = np.linalg.svd(a, full_matrices=False)
    return _reduced(a, b, u, s, what, constraint)


def row_spaces(a: FloatArray, b: FloatArray, what: str, constraint: str
               ) -> list[tuple[FloatArray, FloatArray] | Infeasible]:
    """:func:`row_space` of each system a[k] @ x = b[k] of a stack (K, M, n) and (K, M), with one SVD call for
    the whole stack (LAPACK runs on each matrix as it would alone): per system its reduced rows, or the
    Infeasible that :func:`row_space` raises."""
    u, s, _ = np.linalg.svd(a, full_matrices=False)
    out: list[tuple[FloatArray, FloatArray] | Infeasible] = []
    for k in range(a.shape[0]):
        try:
            out.append(_reduced(a[k], b[k], u[k], s[k], what, constraint))
        except Infeasible as exc:
            out.append(exc.as_answer())
    return out


def _reduced(a: FloatArray, b: FloatArray, u: FloatArray, s: FloatArray, what: str, constraint: str
             ) -> tuple[FloatArray, FloatArray]:
    """The row space of a @ x = b from the SVD of a (left vectors ``u``, singular values ``s``)."""
    tol = max(a.shape) * np.finfo(float).eps * (s[0] if s.size else 0.0) * 1e3
    r = int(np.sum(s > tol))
    ur = u[:, :r]
    residual = b - ur @ (ur.T @ b)
    scale = max(float(np.linalg.norm(b)), 1e-300)
    if float(np.linalg.norm(residual)) > 1e-8 * scale and float(np.linalg.norm(b)) > 1e-12:
        raise Infeasible(f"{what} cannot be made identically zero with counterweights on these links",
                         constraint=constraint, unreachable_fraction=float(np.linalg.norm(residual) / scale))
    return ur.T @ a, ur.T @ b


def solve(program: ConeProgram | clarabel.DefaultSolver, time_limit_s: float, what: str,
          binding: Sequence[str] = ()) -> FloatArray:
    """Solve with Clarabel (globally: the programs are convex) and translate every non-optimal status.

    Takes a program, or a solver already built from one (a sweep updates its costs and solves again).
    Returns the primal solution. Raises Infeasible naming the first of ``binding``, SolverTimeout when
    Clarabel's time limit stops it, SolverFailed for an iteration limit or a numerical failure.
    """
    solver = program.solver(time_limit_s) if isinstance(program, ConeProgram) else program
    solution = solver.solve()
    status = solution.status
    if status in (clarabel.SolverStatus.Solved, clarabel.SolverStatus.AlmostSolved):
        return np.asarray(solution.x, dtype=float)
    if status in (clarabel.SolverStatus.PrimalInfeasible, clarabel.SolverStatus.AlmostPrimalInfeasible):
        limits = ", ".join(binding) or "the counterweight limits"
        raise Infeasible(f"{what}: no counterweights satisfy {limits}", constraint=binding[0] if binding else None)
    if status == clarabel.SolverStatus.MaxTime:
        raise SolverTimeout(time_limit_s, solve_time_s=float(solution.solve_time))
    if status == clarabel.SolverStatus.MaxIterations:
        raise SolverFailed("iteration_limit", f"{what}: the solver reached its iteration limit")
    raise SolverFailed(str(status).rsplit(".", 1)[-1].lower(), f"{what}: Clarabel stopped with status {status}")
