"""Splitting a total ratio between the stages of a drive.

The objectives are geometric programs, so the answer is the global optimum of the stated model. Each is
solved in log space directly: with y = log u a posynomial sum_i c_i prod u^a_i becomes the convex
log-sum-exp of a_i·y + log c_i, written as one exponential cone per monomial straight into Clarabel's form
(the exponents depend only on the stage count and objective, and are built once per pair);
``build_split_program`` states the same program in cvxpy's DGP form for cross-checks.

- ``min_inertia``: inertia reduced to the motor shaft; pinions of one size J_p, each gear J_p * u_k^4 (shared face
  width and module), optional shaft inertias, the load reduced by the total ratio squared. For two stages
  without shaft terms the optimum satisfies u1^6 - u1^2 - 2 U^2 = 0.
- ``min_volume``: pinion plus gear volume of every stage sized for contact stress,
  V_k = c_k * T_k * (u_k + 1)(u_k^2 + 1)/u_k with T_k the torque on the stage's pinion (``stage_types.json``).
- ``handbook``: the two-stage rule for a developed reducer, slow stage = 0.88 * sqrt(U) (or a given factor);
  with one stage ratio fixed, the remainder goes to the other (seed 004:790-800). For comparison; not a GP.

Fixed stage ratios (a standard bevel stage, say) enter every objective as equalities. Snapping to the R20
preferred numbers keeps the total within 2.5 % up to U = 4.5 and 4 % above (or a given tolerance).
"""

from __future__ import annotations

import functools
import itertools
import math
import operator
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import clarabel
import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from ..errors import Infeasible, InvalidInput, SolverFailed, SolverTimeout
from ..model import FloatArray
from ..warnings import DesignWarning
from .stages import Stage, stage_name
from .teeth import ToothRules, grid_pairs

Objective = Literal["min_inertia", "min_volume", "handbook"]
OBJECTIVES: tuple[str, ...] = ("min_inertia", "min_volume", "handbook")

R20_BASE = (1.00, 1.12, 1.25, 1.40, 1.60, 1.80, 2.00, 2.24, 2.50, 2.80,
            3.15, 3.55, 4.00, 4.50, 5.00, 5.60, 6.30, 7.10, 8.00, 9.00)
HANDBOOK_FACTOR = 0.88
_SNAP_STEPS = 3
# The objectives are flat at the optimum: Clarabel's default gap (1e-8) leaves the ratios only ~1e-5 accurate.
_CLARABEL_TOLERANCES = {"tol_gap_abs": 1e-10, "tol_gap_rel": 1e-10, "tol_feas": 1e-10}


@dataclass(frozen=True, slots=True)
class InertiaModel:
    """Data of the reduced-inertia model.

    ``pinion_inertia`` J_p of every pinion [kg·m²]; ``load_inertia`` on the output shaft [kg·m²];
    ``shaft_inertias`` extra inertia on shafts 0 (motor) .. n (output), or empty [kg·m²];
    ``motor_inertia`` rotor inertia [kg·m²].
    """

    pinion_inertia: float = 1e-3
    load_inertia: float = 0.0
    shaft_inertias: tuple[float, ...] = ()
    motor_inertia: float = 0.0


@dataclass(frozen=True, slots=True)
class SplitChecks:
    """Independent check figures of a split.

    ``objective_model``: the objective re-evaluated with the plain NumPy model at the answer;
    ``ratio_product_error``: |prod(u)/U - 1| [-]; ``kkt_residual``: largest violation of the first-order
    conditions in log-ratios (finite differences of the plain model, relative to the objective), None for
    the handbook rule or after snapping.
    """

    objective_model: float
    ratio_product_error: float
    kkt_residual: float | None


@dataclass(frozen=True, slots=True)
class SplitResult:
    """A ratio split, motor side first.

    ``stage_ratios`` [-]; ``continuous_ratios`` before R20 snapping [-]; ``objective_value`` in the objective's
    unit (kg·m² or m³); ``reduced_inertia`` [kg·m²] and ``gear_volume`` [m³] of the answer under both models
    (None where a stage type has no sizing rule); ``solve_time`` [s].
    """

    total_ratio: float
    objective: str
    stage_ratios: tuple[float, ...]
    continuous_ratios: tuple[float, ...]
    objective_value: float
    reduced_inertia: float
    gear_volume: float | None
    solver: str
    solver_status: str
    solve_time: float
    snapped: bool
    snap_tolerance: float | None
    checks: SplitChecks
    warnings: tuple[DesignWarning, ...] = field(default=())


def total_ratio(motor_speed: float, output_speed: float) -> float:
    """Total ratio U = motor speed / output speed [-] (any one unit for both speeds)."""
    for name, v in (("motor_speed", motor_speed), ("output_speed", output_speed)):
        if not (math.isfinite(v) and v > 0):
            raise InvalidInput(f"{name} must be positive, got {v}", field=name)
    return motor_speed / output_speed


def default_snap_tolerance(total: float) -> float:
    """Admissible relative deviation of the total ratio after snapping: 2.5 % up to 4.5, 4 % above [-]."""
    return 0.025 if total <= 4.5 else 0.04


def r20_values(lo: float, hi: float) -> FloatArray:
    """R20 preferred numbers in [lo, hi], ascending [-]."""
    decades = range(math.floor(math.log10(lo)) - 1, math.ceil(math.log10(hi)) + 1)
    vals = np.array([b * 10.0**d for d in decades for b in R20_BASE])
    vals = np.round(vals, 10)
    return vals[(vals >= lo * (1 - 1e-12)) & (vals <= hi * (1 + 1e-12))]


def reduced_train_inertia(ratios: Sequence[float] | FloatArray, model: InertiaModel) -> float:
    """Inertia reduced to the motor shaft [kg·m²] of the one-size-pinion model, plain NumPy.

    Shaft 0 carries the motor rotor and pinion 1; shaft k carries gear k (J_p u_k^4) and, but for the last,
    pinion k+1; the load sits on shaft n. Each shaft's inertia is divided by the square of the ratio from the motor.
    """
    u = np.asarray(ratios, dtype=float)
    n = len(u)
    jp = model.pinion_inertia
    shaft = np.zeros(n + 1)
    shaft[0] = jp + model.motor_inertia
    shaft[1:] = jp * u**4
    shaft[1:n] += jp
    shaft[n] += model.load_inertia
    if model.shaft_inertias:
        shaft += np.asarray(model.shaft_inertias, dtype=float)
    to_motor = np.concatenate([[1.0], np.cumprod(u)])
    return float(np.sum(shaft / to_motor**2))


def gear_volume(ratios: Sequence[float] | FloatArray, stages: Sequence[Stage], input_torque: float = 1.0) -> float | None:
    """Pinion plus gear volume of all stages sized for contact stress [m³]; None if a stage has no sizing rule.

    ``input_torque`` on the motor shaft [N·m]; stage k's pinion carries it times the ratios and efficiencies
    of the stages before it.
    """
    if any(s.volume_coefficient is None for s in stages):
        return None
    u = np.asarray(ratios, dtype=float)
    eta = np.array([s.efficiency for s in stages])
    coeff = np.array([s.volume_coefficient or 0.0 for s in stages])
    torque = input_torque * np.concatenate([[1.0], np.cumprod(u * eta)[:-1]])
    return float(np.sum(coeff * torque * (u + 1) * (u**2 + 1) / u))


def _objective_value(objective: str, ratios: FloatArray, stages: Sequence[Stage], model: InertiaModel,
                     input_torque: float) -> float:
    if objective == "min_volume":
        vol = gear_volume(ratios, stages, input_torque)
        assert vol is not None
        return vol
    return reduced_train_inertia(ratios, model)


def _check_reachable(total: float, stages: Sequence[Stage]) -> None:
    lo = math.prod(s.ratio if s.ratio is not None else s.ratio_min for s in stages)
    hi = math.prod(s.ratio if s.ratio is not None else s.ratio_max for s in stages)
    if total < lo * (1 - 1e-9):
        raise Infeasible(
            f"total ratio {total:g} is below the smallest the stages reach ({lo:g}, every stage at its minimum "
            "or fixed ratio)", constraint="stage_ratio_min", total_ratio=total, reachable_min=lo, reachable_max=hi)
    if total > hi * (1 + 1e-9):
        raise Infeasible(
            f"total ratio {total:g} exceeds the largest the stages reach ({hi:g}, every stage at its maximum "
            "or fixed ratio)", constraint="stage_ratio_max", total_ratio=total, reachable_min=lo, reachable_max=hi)


@dataclass(frozen=True, slots=True)
class TeethLimit:
    """A toothed stage's ratio range narrowed to what its tooth pairs make under the tooth rules.

    ``stage`` index, motor side first; ``ratio_min``/``ratio_max`` the range after narrowing [-];
    ``smallest``/``largest`` the (pinion, gear) pairs that make them.
    """

    stage: int
    ratio_min: float
    ratio_max: float
    smallest: tuple[int, int]
    largest: tuple[int, int]


def teeth_limited(stages: Sequence[Stage], rules: ToothRules) -> tuple[tuple[Stage, ...], tuple[TeethLimit, ...]]:
    """The stages with every free toothed stage's range narrowed to the ratios its tooth pairs make [-].

    A split within a stage's nominal range may ask for a ratio no pair within the tooth bounds and the
    interference limit makes (6.3 needs a 107-tooth wheel on a 17-tooth pinion): splitting within the narrowed
    ranges gives ratios the tooth search can meet. A stage with no admissible pair at all is left as it is (the
    tooth search names it). Returns the stages and the narrowings made.
    """
    out: list[Stage] = []
    limits: list[TeethLimit] = []
    for k, s in enumerate(stages):
        narrowed, limit = _teeth_narrowed(s, rules)
        if limit is not None:
            limits.append(TeethLimit(k, *limit))
        out.append(narrowed)
    return tuple(out), tuple(limits)


@functools.lru_cache(maxsize=256)
def _teeth_narrowed(s: Stage, rules: ToothRules) -> tuple[Stage, tuple[float, float, tuple[int, int],
                                                                     tuple[int, int]] | None]:
    """One stage narrowed as :func:`teeth_limited` narrows it, and the narrowing made (range and the pairs that
    make it) or None: a family's members share their stages and rules, so each is narrowed once."""
    if not s.toothed or s.ratio is not None:
        return s, None
    zp, zg = grid_pairs(s, rules)
    if not zp.size:
        return s, None
    ratio = zg / zp
    i_lo, i_hi = int(np.argmin(ratio)), int(np.argmax(ratio))
    lo, hi = float(ratio[i_lo]), float(ratio[i_hi])
    if lo > s.ratio_min * (1 + 1e-12) or hi < s.ratio_max * (1 - 1e-12):
        limit = (lo, hi, (int(zp[i_lo]), int(zg[i_lo])), (int(zp[i_hi]), int(zg[i_hi])))
        return Stage(s.type, max(lo, s.ratio_min), min(hi, s.ratio_max), s.efficiency, s.volume_coefficient,
                     s.toothed, None), limit
    return s, None


def build_split_program(total: float, stages: Sequence[Stage], objective: str, model: InertiaModel,
                        input_torque: float = 1.0) -> tuple[cp.Problem, cp.Variable]:
    """The geometric program of a split: stage ratios u > 0 with prod(u) = U, per-stage bounds and fixed ratios.

    Returns the problem (``problem.is_dgp()`` holds) and the ratio variable, motor side first. The service
    solves the same program in log space (``solve_split_log``); this statement is its cross-check.
    """
    n = len(stages)
    u = cp.Variable(n, pos=True)
    cons = [functools.reduce(operator.mul, [u[k] for k in range(n)]) == total]
    for k, s in enumerate(stages):
        if s.ratio is not None:
            cons.append(u[k] == s.ratio)
        else:
            cons += [u[k] >= s.ratio_min, u[k] <= s.ratio_max]
    terms: list[Any] = []
    if objective == "min_inertia":
        # Shaft k's inertia over the square of the ratio from the motor: posynomial terms only.
        jp = model.pinion_inertia
        extra = list(model.shaft_inertias) or [0.0] * (n + 1)
        const0 = jp + model.motor_inertia + extra[0]
        terms.append(cp.Constant(const0))
        to_motor: cp.Expression = cp.Constant(1.0)
        for k in range(n):
            before = to_motor
            to_motor = to_motor * u[k]
            terms.append(jp * u[k] ** 2 / before**2)
            rest = extra[k + 1] + (jp if k < n - 1 else model.load_inertia)
            if rest > 0:
                terms.append(rest / to_motor**2)
    elif objective == "min_volume":
        torque: cp.Expression = cp.Constant(input_torque)
        for k, s in enumerate(stages):
            if s.volume_coefficient is None:
                raise InvalidInput(
                    f"stage type {s.type!r} has no contact-stress sizing rule; use min_inertia or handbook",
                    field=f"stages[{k}].type")
            c = s.volume_coefficient
            terms.append(c * torque * (u[k] ** 2 + u[k] + 1 + u[k] ** -1))
            torque = torque * u[k] * s.efficiency
    else:
        raise InvalidInput(f"objective {objective!r} is not a geometric program; known: {OBJECTIVES}",
                           field="objective")
    return cp.Problem(cp.Minimize(functools.reduce(operator.add, terms)), cons), u


@functools.lru_cache(maxsize=32)
def _exponents(n: int, objective: str) -> tuple[FloatArray, tuple[tuple[str, int], ...]]:
    """Exponents of the objective's monomials in the stage ratios, (terms, n), and what each coefficient is.

    min_inertia: the motor shaft ("shaft", 0); per stage k the gear J_p u_k^4 over (u_1..u_k)^2, i.e.
    J_p u_k^2 over (u_1..u_(k-1))^2 ("gear", k), and the rest of shaft k over (u_1..u_k)^2 ("shaft", k + 1).
    min_volume: per stage k the pinion torque carries prod_(j<k) u_j, times u_k^2 + u_k + 1 + 1/u_k
    ("volume", k) four times.
    """
    rows: list[FloatArray] = []
    kinds: list[tuple[str, int]] = []
    if objective == "min_inertia":
        rows.append(np.zeros(n))
        kinds.append(("shaft", 0))
        for k in range(n):
            gear = np.zeros(n)
            gear[:k] = -2.0
            gear[k] = 2.0
            shaft = np.zeros(n)
            shaft[: k + 1] = -2.0
            rows += [gear, shaft]
            kinds += [("gear", k), ("shaft", k + 1)]
    else:
        for k in range(n):
            for power in (2.0, 1.0, 0.0, -1.0):
                row = np.zeros(n)
                row[:k] = 1.0
                row[k] = power
                rows.append(row)
                kinds.append(("volume", k))
    return np.array(rows), tuple(kinds)


def _coefficients(objective: str, stages: Sequence[Stage], model: InertiaModel, input_torque: float) -> FloatArray:
    """Coefficients of the monomials of ``_exponents`` (kg·m² or m³); zero where a term is absent."""
    n = len(stages)
    _, kinds = _exponents(n, objective)
    if objective == "min_inertia":
        jp = model.pinion_inertia
        extra = list(model.shaft_inertias) or [0.0] * (n + 1)
        shaft = [jp + model.motor_inertia + extra[0]]
        shaft += [extra[k] + (jp if k < n else model.load_inertia) for k in range(1, n + 1)]
        return np.array([jp if kind == "gear" else shaft[k] for kind, k in kinds])
    torque = input_torque * np.concatenate([[1.0], np.cumprod([s.efficiency for s in stages])[:-1]])
    for k, s in enumerate(stages):
        if s.volume_coefficient is None:
            raise InvalidInput(f"stage type {s.type!r} has no contact-stress sizing rule; use min_inertia or handbook",
                               field=f"stages[{k}].type")
    return np.array([(stages[k].volume_coefficient or 0.0) * torque[k] for _, k in kinds])


@dataclass(frozen=True, slots=True)
class _LogProgram:
    """The parts of a split's log-space program that depend only on its layout: the stage count, the objective,
    which stages are fixed and which monomials are present. ``cone_b`` holds the exponential cones' constant
    rows (their coefficient rows are zero, to be filled)."""

    a: sp.csc_matrix
    p: sp.csc_matrix
    q: FloatArray
    cones: tuple[Any, ...]
    cone_b: FloatArray


@functools.lru_cache(maxsize=64)
def _log_program(n: int, objective: str, fixed: tuple[bool, ...], keep: tuple[bool, ...]) -> _LogProgram:
    """The layout's constraint matrix and cones, built once: a split asks the same program of every member of
    a family but for its right-hand side (the total ratio, the bounds and the coefficients)."""
    exps, _ = _exponents(n, objective)
    exps = exps[np.array(keep, dtype=bool)]
    terms = len(exps)
    size = n + 1 + terms
    eq_a = [np.concatenate([np.ones(n), np.zeros(1 + terms)])]
    le_a = []
    for k in range(n):
        e = np.zeros(size)
        e[k] = 1.0
        if fixed[k]:
            eq_a.append(e)
        else:
            le_a += [e, -e]
    le_a.append(np.concatenate([np.zeros(n + 1), np.ones(terms)]))
    # Clarabel's rows are b - A x in the cone; per monomial (a·y + log c - t, 1, w).
    cone_a = np.zeros((3 * terms, size))
    cone_a[0::3, :n] = -exps
    cone_a[0::3, n] = 1.0
    cone_a[2::3, n + 1 :] = -np.eye(terms)
    cone_b = np.zeros(3 * terms)
    cone_b[1::3] = 1.0
    a = sp.csc_matrix(np.vstack([np.array(eq_a), np.array(le_a), cone_a]))
    cones = [clarabel.ZeroConeT(len(eq_a)), clarabel.NonnegativeConeT(len(le_a))]
    cones += [clarabel.ExponentialConeT() for _ in range(terms)]
    q = np.zeros(size)
    q[n] = 1.0
    for arr in (a.data, a.indices, a.indptr, q, cone_b):
        arr.setflags(write=False)
    return _LogProgram(a, sp.csc_matrix((size, size)), q, tuple(cones), cone_b)


def _log_program_of(total: float, stages: Sequence[Stage], objective: str, model: InertiaModel,
                    input_torque: float) -> tuple[_LogProgram, FloatArray]:
    """A split's log-space program: the layout's part (built once) and this split's right-hand side b."""
    coeff = _coefficients(objective, stages, model, input_torque)
    keep = coeff > 0
    program = _log_program(len(stages), objective, tuple(s.ratio is not None for s in stages),
                           tuple(keep.tolist()))
    eq_b = [math.log(total)]
    le_b = []
    for s in stages:
        if s.ratio is not None:
            eq_b.append(math.log(s.ratio))
        else:
            le_b += [math.log(s.ratio_max), -math.log(s.ratio_min)]
    le_b.append(1.0)
    cone_b = program.cone_b.copy()
    cone_b[0::3] = np.log(coeff[keep])
    return program, np.concatenate([eq_b, le_b, cone_b])


def solve_split_log(total: float, stages: Sequence[Stage], objective: str, model: InertiaModel,
                    input_torque: float = 1.0, time_limit_s: float = 20.0) -> tuple[FloatArray, float, str, float]:
    """Solve a split's geometric program in log space with Clarabel.

    Variables y = log u (n), the log-objective t and one w_i per monomial: minimise t subject to
    sum y = log U, the stage bounds (or fixed ratios) on y, sum w <= 1 and (a_i·y + log c_i - t, 1, w_i) in
    the exponential cone, i.e. w_i >= exp(a_i·y + log c_i - t).

    Returns the ratios [-], the objective's value (kg·m² or m³), the solver status and the wall time [s].
    Raises Infeasible, SolverTimeout or SolverFailed.
    """
    if objective not in ("min_inertia", "min_volume"):
        raise InvalidInput(f"objective {objective!r} is not a geometric program; known: {OBJECTIVES}",
                           field="objective")
    n = len(stages)
    program, b = _log_program_of(total, stages, objective, model, input_torque)
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.time_limit = float(time_limit_s)
    for key, value in _CLARABEL_TOLERANCES.items():
        setattr(settings, key, value)
    t0 = time.perf_counter()
    solution = clarabel.DefaultSolver(program.p, program.q, program.a, b, list(program.cones), settings).solve()
    elapsed = time.perf_counter() - t0
    status = solution.status
    if status in (clarabel.SolverStatus.PrimalInfeasible, clarabel.SolverStatus.AlmostPrimalInfeasible):
        raise Infeasible("the stage ratio bounds and fixed ratios admit no split of the total ratio",
                         constraint="stage_ratio_bounds", solver_status="infeasible")
    if status == clarabel.SolverStatus.MaxTime:
        raise SolverTimeout(time_limit_s, solver_status="user_limit")
    if status not in (clarabel.SolverStatus.Solved, clarabel.SolverStatus.AlmostSolved):
        raise SolverFailed(str(status).rsplit(".", 1)[-1].lower(), f"Clarabel stopped with status {status}")
    x = np.asarray(solution.x, dtype=float)
    label = "optimal" if status == clarabel.SolverStatus.Solved else "optimal_inaccurate"
    return np.exp(x[:n]), math.exp(x[n]), label, elapsed


def _objective_rows(objective: str, ratios: FloatArray, stages: Sequence[Stage], model: InertiaModel,
                    input_torque: float) -> FloatArray:
    """The plain model's objective at every row of ``ratios`` (points x stages), each row computed by the same
    operations, in the same order, as :func:`reduced_train_inertia` or :func:`gear_volume` compute one point."""
    m, n = ratios.shape
    u = ratios
    if objective == "min_volume":
        assert all(s.volume_coefficient is not None for s in stages)
        eta = np.array([s.efficiency for s in stages])
        coeff = np.array([s.volume_coefficient or 0.0 for s in stages])
        torque = input_torque * np.concatenate([np.ones((m, 1)), np.cumprod(u * eta, axis=1)[:, :-1]], axis=1)
        volumes: FloatArray = np.sum(coeff * torque * (u + 1) * (u**2 + 1) / u, axis=1)
        return volumes
    jp = model.pinion_inertia
    shaft = np.zeros((m, n + 1))
    shaft[:, 0] = jp + model.motor_inertia
    shaft[:, 1:] = jp * u**4
    shaft[:, 1:n] += jp
    shaft[:, n] += model.load_inertia
    if model.shaft_inertias:
        shaft += np.asarray(model.shaft_inertias, dtype=float)
    to_motor = np.concatenate([np.ones((m, 1)), np.cumprod(u, axis=1)], axis=1)
    inertias: FloatArray = np.sum(shaft / to_motor**2, axis=1)
    return inertias


def _kkt_residual(objective: str, ratios: FloatArray, stages: Sequence[Stage], model: InertiaModel,
                  input_torque: float) -> float:
    """First-order conditions of min f(exp x) s.t. sum x = log U, bounds: interior slopes equal, signs at bounds.

    The slopes are central differences of the plain model, all points evaluated at once."""
    x = np.log(ratios)
    h = 1e-6
    step = h * np.eye(len(x))
    points = np.concatenate([ratios[None, :], np.exp(np.concatenate([x + step, x - step]))])
    values = _objective_rows(objective, points, stages, model, input_torque)
    f0 = float(values[0])
    grad = (values[1 : len(x) + 1] - values[len(x) + 1 :]) / (2 * h)
    free = np.array([s.ratio is None for s in stages])
    lo = np.array([math.log(s.ratio_min) for s in stages])
    hi = np.array([math.log(s.ratio_max) for s in stages])
    tol = 1e-5
    at_lo, at_hi = free & (x <= lo + tol), free & (x >= hi - tol)
    interior = free & ~at_lo & ~at_hi
    if not free.any():
        return 0.0
    lam = float(np.mean(grad[interior])) if interior.any() else float(np.median(grad[free]))
    viol = np.zeros(len(x))
    viol[interior] = np.abs(grad[interior] - lam)
    viol[at_hi] = np.maximum(grad[at_hi] - lam, 0.0)   # raising a ratio at its maximum must not pay
    viol[at_lo] = np.maximum(lam - grad[at_lo], 0.0)
    return float(np.max(viol) / abs(f0))


def _handbook(total: float, stages: Sequence[Stage], factor: float) -> tuple[FloatArray, list[DesignWarning]]:
    if len(stages) != 2:
        raise InvalidInput(f"the handbook rule splits two-stage reducers; this layout has {len(stages)} stages",
                           field="objective")
    fixed = [s.ratio for s in stages]
    if fixed[0] is not None and fixed[1] is not None:
        u = np.array([fixed[0], fixed[1]], dtype=float)
    elif fixed[0] is not None:
        u = np.array([fixed[0], total / fixed[0]])
    elif fixed[1] is not None:
        u = np.array([total / fixed[1], fixed[1]])
    else:
        slow = factor * math.sqrt(total)
        u = np.array([total / slow, slow])
    warnings = [
        DesignWarning("stage_ratio_out_of_range", f"stages[{k}]", float(u[k]),
                      f"{stage_name(k)}: ratio {u[k]:.4g} lies outside the {s.type} range [{s.ratio_min:g}, {s.ratio_max:g}]")
        for k, s in enumerate(stages) if not s.ratio_min * (1 - 1e-9) <= u[k] <= s.ratio_max * (1 + 1e-9)
    ]
    return u, warnings


def _at_limit(ratios: FloatArray, stages: Sequence[Stage], objective: str) -> list[DesignWarning]:
    """Free stages whose ratio sits on a bound of their range: the objective would move them further, so the
    split is the range's, not the objective's."""
    out = []
    for k, (u, s) in enumerate(zip(ratios, stages, strict=True)):
        if s.ratio is not None:
            continue
        for bound, side in ((s.ratio_max, "upper"), (s.ratio_min, "lower")):
            if abs(u / bound - 1) <= 1e-7:
                out.append(DesignWarning(
                    "stage_ratio_at_limit", f"stages[{k}]", float(u),
                    f"{stage_name(k)} ({s.type}): ratio {u:.5g} sits at its {side} limit {bound:g}: the {objective} "
                    "split is held there by the range, not by its objective; widen the range, change the stage "
                    "count or the stage type"))
                break
    return out


def _snap(total: float, ratios: FloatArray, stages: Sequence[Stage], objective: str, model: InertiaModel,
          input_torque: float, tolerance: float) -> FloatArray:
    """Best R20 combination within a few steps of each optimal ratio that keeps the total within ``tolerance``."""
    choices = []
    for u, s in zip(ratios, stages, strict=True):
        if s.ratio is not None:
            choices.append(np.array([s.ratio]))
            continue
        vals = r20_values(s.ratio_min, s.ratio_max)
        if vals.size == 0:
            raise Infeasible(f"no R20 ratio lies in the {s.type} range [{s.ratio_min:g}, {s.ratio_max:g}]",
                             constraint="snap_r20")
        i = int(np.searchsorted(vals, u))
        choices.append(vals[max(0, i - _SNAP_STEPS): i + _SNAP_STEPS])
    grid = np.array(list(itertools.product(*choices)))
    err = np.abs(np.prod(grid, axis=1) / total - 1)
    ok = err <= tolerance * (1 + 1e-12)
    if not ok.any():
        raise Infeasible(
            f"no combination of R20 ratios near the optimum keeps the total within {tolerance:.3%} of {total:g}; "
            "widen the tolerance or leave the ratios unsnapped",
            constraint="snap_tolerance", tolerance=tolerance, closest_error=float(err.min()))
    grid, err = grid[ok], err[ok]
    if objective == "handbook":
        score = np.sum(np.log(grid / ratios) ** 2, axis=1)
    else:
        score = np.array([_objective_value(objective, g, stages, model, input_torque) for g in grid])
    best = np.lexsort((err, score))[0]
    return np.asarray(grid[best], dtype=float)


def split_ratio(
    total: float,
    stages: Sequence[Stage],
    objective: str = "min_inertia",
    *,
    inertia: InertiaModel | None = None,
    input_torque: float = 1.0,
    handbook_factor: float = HANDBOOK_FACTOR,
    snap_r20: bool = False,
    snap_tolerance: float | None = None,
    time_limit_s: float = 20.0,
) -> SplitResult:
    """Split the total ratio ``total`` [-] between ``stages`` (motor side first) for ``objective``.

    Parameters
    ----------
    total : total ratio U = motor speed / output speed [-].
    stages : the layout's stages with their ranges, efficiencies and fixed ratios.
    objective : ``min_inertia``, ``min_volume`` (geometric programs, Clarabel) or ``handbook``.
    inertia : data of the reduced-inertia model (pinion, load, shaft and rotor inertias [kg·m²]).
    input_torque : torque on the motor shaft for the volume model [N·m]; the split does not depend on it.
    handbook_factor : slow stage = factor * sqrt(U) in the handbook rule [-].
    snap_r20 : snap the stage ratios to R20 preferred numbers within ``snap_tolerance`` of the total [-].
    time_limit_s : Clarabel's own time limit [s].

    Raises Infeasible (a total outside what the stages reach, naming the bound; no R20 combination within the
    tolerance), InvalidInput, SolverFailed, SolverTimeout.
    """
    if not (math.isfinite(total) and total > 0):
        raise InvalidInput(f"total_ratio must be positive, got {total}", field="total_ratio")
    if objective not in OBJECTIVES:
        raise InvalidInput(f"unknown objective {objective!r}; known: {', '.join(OBJECTIVES)}", field="objective")
    model = inertia or InertiaModel()
    if model.shaft_inertias and len(model.shaft_inertias) != len(stages) + 1:
        raise InvalidInput(f"shaft_inertias needs {len(stages) + 1} values (motor shaft to output shaft), "
                           f"got {len(model.shaft_inertias)}", field="shaft_inertias_kgm2")
    _check_reachable(total, stages)
    warnings: list[DesignWarning] = []
    kkt: float | None = None
    solver_value: float | None = None
    if objective == "handbook":
        ratios, warnings = _handbook(total, stages, handbook_factor)
        solver, status, elapsed = "closed form", "optimal", 0.0
    else:
        raw, solver_value, status, elapsed = solve_split_log(total, stages, objective, model, input_torque,
                                                             time_limit_s)
        # Clarabel meets the bounds to its tolerance; pull the answer onto them so reported ratios are admissible.
        lo, hi = np.array([s.ratio_min for s in stages]), np.array([s.ratio_max for s in stages])
        ratios = np.clip(raw, lo, hi)
        ratios = np.where(np.abs(ratios / hi - 1) < 1e-7, hi, np.where(np.abs(ratios / lo - 1) < 1e-7, lo, ratios))
        # Fixed stages are equalities the solver meets to its tolerance; report them exactly.
        ratios = np.array([s.ratio if s.ratio is not None else r for s, r in zip(stages, ratios, strict=True)])
        solver = "clarabel"
        kkt = _kkt_residual(objective, ratios, stages, model, input_torque)
    continuous = ratios.copy()
    tol = None
    if snap_r20:
        tol = default_snap_tolerance(total) if snap_tolerance is None else snap_tolerance
        ratios = _snap(total, ratios, stages, objective, model, input_torque, tol)
        kkt, solver_value = None, None
    if objective != "handbook":
        warnings += _at_limit(ratios, stages, objective)
    inertia_value = reduced_train_inertia(ratios, model)
    volume = gear_volume(ratios, stages, input_torque)
    model_value = volume if objective == "min_volume" and volume is not None else inertia_value
    checks = SplitChecks(model_value, abs(float(np.prod(ratios)) / total - 1), kkt)
    value = model_value if solver_value is None else solver_value
    return SplitResult(total, objective, tuple(map(float, ratios)), tuple(map(float, continuous)), value,
                       inertia_value, volume, solver, status, elapsed, snap_r20, tol, checks, tuple(warnings))
