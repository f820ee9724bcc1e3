"""Counterweight variables over the linear-in-parameters map, and the translation of solver outcomes.

A counterweight on a link adds (m, h_x, h_y, J) to that link's inertial parameters (mass, first moments in the
link frame, inertia about the link's first joint). It is physically realisable iff |h|² <= m·J (a rotated cone),
m >= 0 and |h| <= r_max·m; a fixed angle is a linear restriction of h.
"""

from __future__ import annotations

from typing import Any

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import cvxpy as _cvxpy
import numpy as np

from ..errors import Infeasible, InvalidInput, SolverFailed, SolverTimeout
from ..model import Counterweight, FloatArray, Linkage

# cvxpy builds its atoms (norm, sum, quad_over_lin...) lazily, so a type checker cannot see them.
cp: Any = _cvxpy


@dataclass(frozen=True, slots=True)
class CounterweightSpec:
    """Where counterweights may go: links, each link's largest radius [m], optional fixed radius [m] and fixed
    angle [rad] (in the link frame)."""

    links: tuple[str, ...] = ("crank", "rocker")
    max_radius: Mapping[str, float] | None = None
    angle: Mapping[str, float] | None = None
    radius: Mapping[str, float] | None = None

    def validate(self, linkage: Linkage) -> None:
        """InvalidInput naming the field for unknown links or radii that are not positive."""
        names = linkage.mechanism.topology.links
        if not self.links:
            raise InvalidInput("at least one counterweight link is needed", field="counterweight_links")
        for link in self.links:
            if link not in names:
                raise InvalidInput(f"unknown link {link!r}; this mechanism has {list(names)}", field="counterweight_links")
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
        """Largest counterweight radius on ``link`` [m]: its fixed radius, its maximum, or the link's length."""
        if self.radius and link in self.radius:
            return float(self.radius[link])
        if self.max_radius and link in self.max_radius:
            return float(self.max_radius[link])
        lengths = _link_lengths(linkage)
        return lengths.get(link, 0.1)


def _link_lengths(linkage: Linkage) -> dict[str, float]:
    mech = linkage.mechanism
    out: dict[str, float] = {}
    for name in ("crank", "coupler", "rocker", "rod"):
        if hasattr(mech, name):
            out[name] = float(getattr(mech, name))
    return out


@dataclass(frozen=True, slots=True)
class CounterweightVars:
    """cvxpy variables of the counterweights: per link m, h (2), J about the link's first joint."""

    links: tuple[str, ...]
    r_max: FloatArray
    m: cp.Variable
    h: cp.Variable
    j: cp.Variable
    constraints: list[cp.Constraint]

    def counterweights(self) -> list[Counterweight]:
        """Counterweights from the solved variables: mass at least |h|/r_max (the solver meets the radius limit
        only to its tolerance), own inertia J - m·|r|² clipped at zero."""
        out = []
        m = np.asarray(self.m.value, dtype=float)
        h = np.asarray(self.h.value, dtype=float)
        j = np.asarray(self.j.value, dtype=float)
        for i, link in enumerate(self.links):
            mass = max(float(m[i]), float(np.hypot(*h[i])) / float(self.r_max[i]), 0.0)
            if mass <= 1e-12:
                continue
            pos = (float(h[i, 0] / mass), float(h[i, 1] / mass))
            own = max(float(j[i]) - mass * (pos[0] ** 2 + pos[1] ** 2), 0.0)
            out.append(Counterweight(link, mass, pos, own))
        return out


def counterweight_vars(spec: CounterweightSpec, linkage: Linkage) -> CounterweightVars:
    """Variables and realisability cones of the allowed counterweights (one cone each, never one per angle)."""
    k = len(spec.links)
    m, h, j = cp.Variable(k, nonneg=True), cp.Variable((k, 2)), cp.Variable(k, nonneg=True)
    r_max = np.array([spec.limit(linkage, link) for link in spec.links])
    # The cone is imposed with a margin of 1e-7 so that the solver's tolerance never carries a counterweight past
    # its radius limit (the reported mass is also floored at |h|/r_max).
    cons: list[cp.Constraint] = [cp.norm(h, 2, axis=1) <= cp.multiply(r_max * (1 - 1e-7), m)]
    cons += [cp.quad_over_lin(h[i], m[i]) <= j[i] for i in range(k)]
    for i, link in enumerate(spec.links):
        if spec.radius and link in spec.radius:
            # All of the mass at radius r: J = r²·m exactly; with |h| <= r·m, the optimum puts h on the circle.
            cons.append(j[i] == spec.radius[link] ** 2 * m[i])
        if spec.angle and link in spec.angle:
            a = spec.angle[link]
            cons += [h[i, 1] * math.cos(a) - h[i, 0] * math.sin(a) == 0, h[i, 0] * math.cos(a) + h[i, 1] * math.sin(a) >= 0]
    return CounterweightVars(spec.links, r_max, m, h, j, cons)


def row_space(a: FloatArray, b: FloatArray, what: str, constraint: str) -> tuple[FloatArray, FloatArray]:
    """Reduce the stacked equalities a @ x = b (thousands of rows, few independent) to their row space.

    Raises Infeasible when b has a part outside the column space of a: no choice of x can meet them.
    """
    u, s, _ = np.linalg.svd(a, full_matrices=False)
    tol = max(a.shape) * np.finfo(float).eps * (s[0] if s.size else 0.0) * 1e3
    r = int(np.sum(s > tol))
    ur = u[:, :r]
    residual = b - ur @ (ur.T @ b)
    scale = max(float(np.linalg.norm(b)), 1e-300)
    if float(np.linalg.norm(residual)) > 1e-8 * scale and float(np.linalg.norm(b)) > 1e-12:
        raise Infeasible(f"{what} cannot be made identically zero with counterweights on these links",
                         constraint=constraint, unreachable_fraction=float(np.linalg.norm(residual) / scale))
    return ur.T @ a, ur.T @ b


def solve(problem: cp.Problem, time_limit_s: float, what: str, binding: Sequence[str] = ()) -> None:
    """Solve with Clarabel (globally: the problems are convex) and translate every non-optimal status."""
    if not problem.is_dcp():
        raise SolverFailed("not_dcp", f"{what}: the program is not convex as posed")
    try:
        # Tighter than Clarabel's defaults: the counterweights themselves (the argmin), not only the objective,
        # are the answer, and flat optima leave them loose at the default gap.
        with warnings.catch_warnings():
            # cvxpy warns of inaccurate solutions; the status is translated below instead.
            warnings.filterwarnings("ignore", message="Solution may be inaccurate", category=UserWarning)
            problem.solve(solver=cp.CLARABEL, time_limit=time_limit_s, tol_gap_abs=1e-10, tol_gap_rel=1e-10,
                          tol_feas=1e-10)
    except cp.SolverError as exc:
        raise SolverFailed("solver_error", f"{what}: {exc}") from exc
    status = problem.status
    if status in (cp.INFEASIBLE, cp.INFEASIBLE_INACCURATE):
        limits = ", ".join(binding) or "the counterweight limits"
        raise Infeasible(f"{what}: no counterweights satisfy {limits}", constraint=binding[0] if binding else None)
    if status == cp.USER_LIMIT:
        # Clarabel's time limit and its iteration limit both arrive as user_limit; only the first is a timeout.
        spent = problem.solver_stats.solve_time if problem.solver_stats else None
        if spent is not None and spent >= 0.9 * time_limit_s:
            raise SolverTimeout(time_limit_s, solve_time_s=float(spent))
        raise SolverFailed("iteration_limit", f"{what}: the solver reached its iteration limit")
    if status not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE):
        raise SolverFailed(str(status))
