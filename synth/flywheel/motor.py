"""A motor's static characteristic reduced to the crank, and the least flywheel for it as a collocation NLP."""

from __future__ import annotations

import functools
import math
import threading
import warnings
from dataclasses import dataclass
from typing import Protocol

import casadi as ca
import numpy as np
import numpy.typing as npt
from scipy.sparse import csc_array
from scipy.sparse.linalg import MatrixRankWarning, spsolve

from ..compiled import compiled
from ..errors import Infeasible, InvalidInput, SolverFailed, SolverTimeout
from ..model import FloatArray
from .cycle import ReducedCycle
from .sizing import speed_band


class RatedMotor(Protocol):
    """What the flywheel reads of a catalogue motor (:class:`synth.gearing.CatalogueMotor` is one): speeds
    [rad/s], torques [N·m] (the starting torque at standstill), rotor inertia [kg·m²] or None when the catalogue
    does not give it."""

    @property
    def synchronous_speed(self) -> float: ...
    @property
    def rated_speed(self) -> float: ...
    @property
    def rated_torque(self) -> float: ...
    @property
    def breakdown_torque(self) -> float: ...
    @property
    def starting_torque(self) -> float: ...
    @property
    def rotor_inertia(self) -> float | None: ...


@dataclass(frozen=True, slots=True)
class ReducedMotor:
    """Motor torque on the crank, M_d(w) = slope·(no_load_speed - w) [N·m], valid up to ``max_torque`` [N·m].

    ``no_load_speed`` crank speed at synchronous motor speed [rad/s]; ``slope`` [N·m·s/rad]; ``inertia`` the
    rotor's inertia reduced to the crank [kg·m²].
    """

    no_load_speed: float
    slope: float
    max_torque: float
    inertia: float

    def torque(self, omega: FloatArray | float) -> FloatArray:
        """Driving torque on the crank at crank speed ``omega`` [rad/s] -> [N·m]."""
        return np.asarray(self.slope * (self.no_load_speed - np.asarray(omega, dtype=float)), dtype=float)

    def mean_speed(self, cycle: ReducedCycle) -> float:
        """Crank speed averaged over the angle in steady motion [rad/s].

        The characteristic is linear, so zero net work over the cycle fixes the angle-average speed whatever
        the inertia: slope·(w0 - mean w)·period + A_load = 0.
        """
        return self.no_load_speed + cycle.cycle_work / (self.slope * cycle.period)


@dataclass(frozen=True, slots=True)
class Motor:
    """Induction motor: torque linear from zero at synchronous speed to ``rated_torque`` at ``rated_speed``.

    Speeds on the motor shaft [rad/s], torques [N·m], ``gear_ratio`` motor speed over crank speed [-],
    ``efficiency`` of the gearing [-], ``rotor_inertia`` [kg·m²], ``breakdown_torque`` the largest torque of the
    linear branch [N·m] (None: unbounded), ``starting_torque`` the locked-rotor torque at standstill [N·m] (None:
    the linear branch holds down to standstill). Between standstill and the breakdown speed the torque runs
    linearly from the starting torque to the breakdown torque; only a start passes there.
    """

    synchronous_speed: float
    rated_speed: float
    rated_torque: float
    gear_ratio: float = 1.0
    efficiency: float = 1.0
    rotor_inertia: float = 0.0
    breakdown_torque: float | None = None
    starting_torque: float | None = None

    def __post_init__(self) -> None:
        if not 0 < self.rated_speed < self.synchronous_speed:
            raise InvalidInput("the rated speed must lie below the synchronous speed", field="motor.rated_speed_rpm")
        if not self.rated_torque > 0:
            raise InvalidInput("the rated torque must be positive", field="motor.rated_torque_Nm")
        if not self.gear_ratio > 0:
            raise InvalidInput("the gear ratio must be positive", field="motor.gear_ratio")
        if not 0 < self.efficiency <= 1:
            raise InvalidInput("the efficiency must lie in (0, 1]", field="motor.efficiency")
        if self.rotor_inertia < 0:
            raise InvalidInput("the rotor inertia must not be negative", field="motor.rotor_inertia_kgm2")
        if self.breakdown_torque is not None and not self.breakdown_torque > self.rated_torque:
            raise InvalidInput("the breakdown torque must exceed the rated torque", field="motor.breakdown_torque_Nm")
        if self.starting_torque is not None:
            if not (math.isfinite(self.starting_torque) and self.starting_torque > 0):
                raise InvalidInput("the starting torque must be positive", field="motor.starting_torque_Nm")
            if self.breakdown_torque is None or self.starting_torque > self.breakdown_torque:
                raise InvalidInput("a starting torque needs a breakdown torque at least as large",
                                   field="motor.starting_torque_Nm")

    @staticmethod
    def from_catalogue(motor: RatedMotor, gear_ratio: float = 1.0, efficiency: float = 1.0) -> Motor:
        """The static characteristic of a catalogue motor, driving through ``gear_ratio`` (motor over crank speed
        [-]) at ``efficiency`` [-]: rated torque P/w_rated, breakdown torque its ratio times that, the rotor's
        inertia (zero when the catalogue does not give it), the starting torque its ratio times the rated."""
        return Motor(motor.synchronous_speed, motor.rated_speed, motor.rated_torque, gear_ratio, efficiency,
                     motor.rotor_inertia or 0.0, motor.breakdown_torque,
                     min(motor.starting_torque, motor.breakdown_torque))

    def torque_at(self, speed: FloatArray | float) -> FloatArray:
        """Torque on the motor shaft at motor speed ``speed`` [rad/s] -> [N·m] (the linear branch)."""
        slope = self.rated_torque / (self.synchronous_speed - self.rated_speed)
        return np.asarray(slope * (self.synchronous_speed - np.asarray(speed, dtype=float)), dtype=float)

    @property
    def breakdown_speed(self) -> float:
        """Motor speed where the linear branch reaches the breakdown torque [rad/s]; 0 without one."""
        if self.breakdown_torque is None:
            return 0.0
        slope = self.rated_torque / (self.synchronous_speed - self.rated_speed)
        return max(self.synchronous_speed - self.breakdown_torque / slope, 0.0)

    def start_torque_at(self, speed: FloatArray | float) -> FloatArray:
        """Torque on the motor shaft [N·m] over the whole speed range from standstill, at motor speed ``speed``
        [rad/s]: the linear branch above the breakdown speed, below it the line from the starting torque at
        standstill to the breakdown torque (the linear branch alone without a starting torque)."""
        n = np.asarray(speed, dtype=float)
        branch = self.torque_at(n)
        if self.starting_torque is None or self.breakdown_torque is None:
            return branch
        n_b = self.breakdown_speed
        low = self.starting_torque + (self.breakdown_torque - self.starting_torque) * n / max(n_b, 1e-300)
        return np.asarray(np.where(n >= n_b, branch, low), dtype=float)

    def reduced(self) -> ReducedMotor:
        """The characteristic reduced to the crank: torque i·eta·T(i·w), rotor inertia i²·J_rotor."""
        i, eta = self.gear_ratio, self.efficiency
        slope = i * i * eta * self.rated_torque / (self.synchronous_speed - self.rated_speed)
        top = math.inf if self.breakdown_torque is None else i * eta * self.breakdown_torque
        return ReducedMotor(self.synchronous_speed / i, slope, top, i * i * self.rotor_inertia)


@dataclass(frozen=True, slots=True)
class MotorSizing:
    """Least constant inertia [kg·m²] keeping the steady motion in the speed band, and the NLP's speeds [rad/s]."""

    constant_inertia: float
    omega: FloatArray
    solver_status: str


def motor_speed_limits(cycle: ReducedCycle, motor: ReducedMotor, mean_speed: float, delta: float) -> tuple[float, float]:
    """The band the steady speed must stay in [rad/s]; Infeasible naming the limit when no flywheel can do it."""
    w_min, w_max = speed_band(mean_speed, delta)
    load = -cycle.cycle_work / cycle.period
    if load >= motor.max_torque:
        raise Infeasible(
            "the motor is too weak: the mean load torque exceeds its breakdown torque reduced to the crank",
            constraint="motor.breakdown_torque_Nm",
            mean_load_torque_Nm=load,
            max_motor_torque_Nm=motor.max_torque,
        )
    lower = max(w_min, motor.no_load_speed - motor.max_torque / motor.slope)
    steady = motor.mean_speed(cycle)
    if not lower < steady < w_max:
        raise Infeasible(
            "no periodic motion at the requested mean speed: the motor's steady speed lies outside the band "
            "w_m(1 ± delta/2), and a flywheel only narrows the fluctuation around that steady speed",
            constraint="mean_speed",
            motor_mean_speed_rad_s=steady,
            omega_min_rad_s=lower,
            omega_max_rad_s=w_max,
        )
    return lower, w_max


def motor_constant_inertia(
    cycle: ReducedCycle,
    motor: ReducedMotor,
    mean_speed: float,
    delta: float,
    *,
    guess: float,
    start: FloatArray | None = None,
    time_limit_s: float = 20.0,
) -> MotorSizing:
    """Least constant inertia for a speed-dependent driving torque, as an NLP solved with IPOPT.

    Unknowns: the speed at every sample, its extremes w_min and w_max, and the constant inertia J_c.
    Trapezoidal collocation of the energy form of the equation of motion, d[(J(phi) + J_c)·w²/2]/dphi =
    M_load(phi) + M_d(w), closes the cycle on itself (periodicity). The motor sets its own mean speed, so the
    band is not centred on ``mean_speed``: the true coefficient is constrained, w_max - w_min <=
    delta·(w_max + w_min)/2, with w_min and w_max results; the speed stays above the breakdown point of the
    characteristic; minimise J_c. ``mean_speed`` [rad/s] only scales the problem and is checked against the
    motor's steady speed by :func:`motor_speed_limits`. ``cycle.torque`` holds the load torque alone; ``guess``
    [kg·m²] and ``start`` (speeds at the samples [rad/s]) start IPOPT.
    """
    lower, upper = motor_speed_limits(cycle, motor, mean_speed, delta)
    floor = max(motor.no_load_speed - motor.max_torque / motor.slope, 0.0)
    n = cycle.samples
    initial = np.clip(start, lower, upper) if start is not None else np.full(n, mean_speed)
    least_speed = max(floor, 1e-6 * mean_speed)
    least_inertia = 1e-9 * max(guess, 1.0) - float(cycle.inertia.min())
    newton = _periodic_newton(cycle, motor, delta, guess, initial, least_speed, least_inertia)
    if newton is not None:
        return MotorSizing(newton[1], newton[0], "newton")
    phi, _, _ = cycle.closed()
    # in units of the kinetic energy, so IPOPT sees residuals of order one whatever the machine's size
    e_scale = 0.5 * (guess + cycle.mean_inertia) * mean_speed**2
    scale = max(guess, 1e-9)
    params = np.concatenate([cycle.inertia, cycle.torque, np.diff(phi),
                             [motor.slope, motor.no_load_speed, delta, e_scale, mean_speed, scale]])
    x0 = np.concatenate([initial, [initial.min(), initial.max(), guess]])
    lbx = np.full(n + 3, -np.inf)
    lbx[n] = least_speed
    lbx[n + 2] = least_inertia
    lbg = np.concatenate([np.zeros(n), np.zeros(2 * n), [-np.inf]])
    ubg = np.concatenate([np.zeros(n), np.full(2 * n, np.inf), [0.0]])
    solver = _motor_nlp(n, float(time_limit_s))
    sol = solver(x0=x0, p=params, lbx=lbx, ubx=np.inf, lbg=lbg, ubg=ubg)
    stats = solver.stats()
    status = str(stats.get("return_status", "unknown"))
    x = np.asarray(sol["x"], dtype=float).reshape(-1)
    if not stats.get("success", False):
        if status == "Maximum_WallTime_Exceeded":
            raise SolverTimeout(time_limit_s, reached_inertia_kgm2=float(x[n + 2]))
        raise SolverFailed(status)
    return MotorSizing(float(x[n + 2]), x[:n], status)


#: Newton iterations on the collocation's optimality system before IPOPT is asked instead.
NEWTON_ITERATIONS = 40

# What one compiled Newton iteration reports: its step is taken; there is no step (the band's row is
# degenerate or the solve is not finite), so the root is not found; the recurrence cannot solve this system,
# so the caller solves it by sparse LU and takes the step itself.
_STEPPED, _NO_STEP, _NEEDS_LU = 0, 1, 2


def _periodic_newton(cycle: ReducedCycle, motor: ReducedMotor, delta: float, guess: float, start: FloatArray,
                     least_speed: float, least_inertia: float) -> tuple[FloatArray, float] | None:
    """The NLP's optimum as the root of its optimality system, by Newton's method; None when the root is not
    the NLP's optimum (then IPOPT solves the program itself).

    Least J_c holds the speed band exactly: its optimum has the n periodic collocation equations and the
    coefficient at its limit, w_max·(1 - delta/2) = w_min·(1 + delta/2), with w_max and w_min the largest and
    least speeds at the samples; n + 1 equations in the n speeds and J_c. The Jacobian is cyclic bidiagonal in
    the speeds with one column for J_c and one row for the band, solved in O(n) (:func:`_border`): a step costs
    far less than an IPOPT iteration, at 3 600 samples too, and the root does not depend on where the
    iterations start. It is the optimum when the coefficient falls as J_c grows there (a larger J_c only narrows
    the band) and the speed and inertia bounds of the program do not bind. Each iteration is one compiled call
    (:func:`_newton_iteration`); the few systems its recurrence cannot solve go to a sparse LU here.
    """
    phi, _, _ = cycle.closed()
    h = np.diff(phi)
    # contiguous float tables, the one layout the compiled iteration is built for
    inertia, torque = (np.ascontiguousarray(v, dtype=float) for v in (cycle.inertia, cycle.torque))
    n = inertia.size
    s, w_free = motor.slope, motor.no_load_speed
    up, down = 1.0 - 0.5 * delta, 1.0 + 0.5 * delta
    w, jc = np.array(start, dtype=float), float(guess)
    if not np.all(w > 0):
        return None
    scale = float(np.mean(w))
    # the iteration's Jacobian (row i: diag[i] at speed i, sup[i] at speed i + 1, the last row's at speed 0, col[i]
    # at J_c), its right-hand sides (-g, col) and its step, filled in place
    diag, sup, col = np.empty(n), np.empty(n), np.empty(n)
    rhs, step = np.empty((n, 2)), np.empty(n + 1)
    lo = hi = 0
    # J_c held at its guess until the speeds are periodic: from a flat start the band's row means nothing
    free = False
    for _ in range(NEWTON_ITERATIONS):
        status, lo, hi, band, shrink, jc_next, moved = _newton_iteration(
            inertia, torque, h, s, w_free, up, down, w, jc, free, least_inertia, diag, sup, col, rhs, step)
        if status == _NEEDS_LU:
            z = _sparse_cyclic_solve(diag, sup, rhs if free else rhs[:, :1])
            # in the layout the compiled iteration hands it, so no other variant of it is compiled
            if z is None or not _border(np.ascontiguousarray(z), band, hi, lo, up, down, free, step):
                return None
            shrink, jc_next, moved = _advance(w, jc, step, least_inertia)
        elif status == _NO_STEP:
            return None
        jc = jc_next
        if not free:
            free = shrink == 1.0 and moved <= 1e-6 * scale
            continue
        if shrink == 1.0 and moved <= 1e-13 * scale and abs(step[n]) <= 1e-13 * max(abs(jc), guess):
            break
    else:
        return None
    if int(np.argmin(w)) != lo or int(np.argmax(w)) != hi or w[lo] <= least_speed or jc <= least_inertia:
        return None
    # dw/dJ_c from the periodic equations alone: the band must narrow as J_c grows
    sens = _cyclic_solve(diag, sup, -col[:, None])
    if sens is None or not up * sens[hi, 0] - down * sens[lo, 0] < 0:
        return None
    # numpy's scalar, as the reports have always carried this inertia
    return w, np.float64(jc)


@compiled
def _newton_iteration(inertia: FloatArray, torque: FloatArray, h: FloatArray, s: float, w_free: float, up: float,
                      down: float, w: FloatArray, jc: float, free: bool, least_inertia: float, diag: FloatArray,
                      sup: FloatArray, col: FloatArray, rhs: FloatArray, step: FloatArray
                      ) -> tuple[int, int, int, float, float, float, float]:  # pragma: no cover - compiled
    """One Newton iteration of :func:`_periodic_newton` at speeds ``w`` and J_c ``jc``: the collocation residuals
    g (energy form, trapezoidal power), the band's residual and the Jacobian into ``diag``, ``sup``, ``col``, the
    right-hand sides (-g, col) into ``rhs``, the step into ``step`` and, when it is taken, ``w`` moved along it.

    Returns the status, the least and largest speeds' indices, the band's residual, the step's shrink factor,
    the new J_c and the largest speed step (NaN when a step is not finite); with ``_NEEDS_LU`` only the status,
    the indices and the band mean anything."""
    n = w.shape[0]
    lo, hi = _arg_extremes(w)
    band = up * w[hi] - down * w[lo]
    for i in range(n):
        k = i + 1 if i + 1 < n else 0
        total, total_k = inertia[i] + jc, inertia[k] + jc
        energy, energy_k = 0.5 * total * (w[i] * w[i]), 0.5 * total_k * (w[k] * w[k])
        power, power_k = torque[i] + s * (w_free - w[i]), torque[k] + s * (w_free - w[k])
        rhs[i, 0] = -(energy_k - energy - 0.5 * h[i] * (power + power_k))
        diag[i] = -total * w[i] + 0.5 * h[i] * s
        sup[i] = total_k * w[k] + 0.5 * h[i] * s
        col[i] = 0.5 * (w[k] * w[k] - w[i] * w[i])
        rhs[i, 1] = col[i]
    z = np.empty((n, 2 if free else 1))
    if not _recurrence(diag, sup, rhs[:, : z.shape[1]], z):
        return _NEEDS_LU, lo, hi, band, 0.0, jc, 0.0
    for i in range(n):
        for c in range(z.shape[1]):
            if not math.isfinite(z[i, c]):
                return _NO_STEP, lo, hi, band, 0.0, jc, 0.0
    if not _border(z, band, hi, lo, up, down, free, step):
        return _NO_STEP, lo, hi, band, 0.0, jc, 0.0
    shrink, jc_next, moved = _advance(w, jc, step, least_inertia)
    return _STEPPED, lo, hi, band, shrink, jc_next, moved


@compiled
def _arg_extremes(x: FloatArray) -> tuple[int, int]:  # pragma: no cover - compiled
    """numpy's (argmin, argmax) in one pass: the first least and first largest value's indices, or both the first
    NaN's."""
    lo = hi = 0
    for i in range(x.shape[0]):
        if x[i] != x[i]:
            return i, i
        if x[i] < x[lo]:
            lo = i
        if x[i] > x[hi]:
            hi = i
    return lo, hi


@compiled
def _recurrence(diag: FloatArray, sup: FloatArray, rhs: FloatArray, z: FloatArray) -> bool:  # pragma: no cover
    """z with diag[i]·z[i] + sup[i]·z[i+1] = rhs[i] (z[n] is z[0]) for each column of ``rhs`` (n, k) into ``z``,
    in O(n): z[i+1] = rho[i]·z[i] + rhs[i]/sup[i] from z[0], closed on itself. False, ``z`` untouched, where the
    recurrence's products grow too small to divide by or the cycle's gain is one (see :func:`_cyclic_solve`)."""
    n, k = rhs.shape
    beta = np.empty(n + 1)
    beta[0] = 1.0
    for i in range(n):
        beta[i + 1] = beta[i] * (-diag[i] / sup[i])
    for i in range(n + 1):
        if not (math.isfinite(beta[i]) and abs(beta[i]) > 1e-6):
            return False
    if not abs(1.0 - beta[n]) > 1e-9:
        return False
    for c in range(k):
        # z[i] = beta[i]·(z[0] + sum of rhs[j]/(sup[j]·beta[j+1]) for j < i), the sums accumulated in order
        total = rhs[0, c] / (sup[0] * beta[1])
        z[0, c] = total
        for i in range(1, n):
            z[i, c] = total
            total = total + rhs[i, c] / (sup[i] * beta[i + 1])
        start = beta[n] * total / (1.0 - beta[n])
        z[0, c] = beta[0] * (start + 0.0)
        for i in range(1, n):
            z[i, c] = beta[i] * (start + z[i, c])
    return True


@compiled
def _border(z: FloatArray, band: float, hi: int, lo: int, up: float, down: float, free: bool,
            step: FloatArray) -> bool:  # pragma: no cover - compiled
    """Newton's step (speeds, J_c) into ``step`` from the periodic system's solutions ``z`` (n, 1 or 2): held J_c,
    the speeds' step is z[:, 0] and J_c's zero; free, it is p - y·q with p, q the solutions for -g and col and y
    (J_c's step) what the band's equation up·w[hi] - down·w[lo] = ``band`` asks. False when the band's row is
    degenerate."""
    n = z.shape[0]
    if not free:
        for i in range(n):
            step[i] = z[i, 0]
        step[n] = 0.0
        return True
    across = up * z[hi, 1] - down * z[lo, 1]
    if across == 0.0:
        return False
    y = (up * z[hi, 0] - down * z[lo, 0] + band) / across
    for i in range(n):
        step[i] = z[i, 0] - y * z[i, 1]
    step[n] = y
    return True


@compiled
def _advance(w: FloatArray, jc: float, step: FloatArray,
             least_inertia: float) -> tuple[float, float, float]:  # pragma: no cover - compiled
    """``w`` moved in place along the speeds' ``step``: the shrink factor, J_c moved along its step and the
    largest speed step (NaN when one is not finite). The speeds must stay positive and J_c above its bound: a
    step that would stop the machine or take more than half of J_c's room is halved until it does not."""
    n = w.shape[0]
    room = 0.5 * (jc + least_inertia)
    lift = float(step[n])
    shrink = 1.0
    while shrink > 1e-6:
        stops = jc + shrink * lift <= room
        for i in range(n):
            if w[i] + shrink * step[i] <= 0.0:
                stops = True
                break
        if not stops:
            break
        shrink *= 0.5
    moved = abs(float(step[0]))
    for i in range(n):
        w[i] = w[i] + shrink * step[i]
        a = abs(float(step[i]))
        if a != a or moved != moved:
            moved = math.nan
        elif a > moved:
            moved = a
    return shrink, jc + shrink * lift, moved


def _cyclic_solve(diag: FloatArray, sup: FloatArray, rhs: FloatArray) -> FloatArray | None:
    """z with diag[i]·z[i] + sup[i]·z[i+1] = rhs[i] (z[n] is z[0]) for each column of ``rhs`` (n, k), in O(n) by
    :func:`_recurrence`. The motor's damping keeps |rho| = |diag/sup| below one, so the recurrence is stable;
    where its products grow too small to divide by, a sparse LU solves it. None when the answer is not finite."""
    z = np.empty(rhs.shape)
    if not _recurrence(diag, sup, np.ascontiguousarray(rhs), z):
        return _sparse_cyclic_solve(diag, sup, rhs)
    return z if np.all(np.isfinite(z)) else None


def _sparse_cyclic_solve(diag: FloatArray, sup: FloatArray, rhs: FloatArray) -> FloatArray | None:
    """The same system by sparse LU (O(n) for this pattern, where a dense one costs O(n³): seconds at 3 600
    samples); None when it is singular."""
    n = diag.size
    indices, indptr = _cyclic_pattern(n)
    data = np.empty(2 * n)
    data[0], data[1], data[2::2], data[3::2] = diag[0], sup[-1], sup[:-1], diag[1:]
    a = csc_array((data, indices, indptr), shape=(n, n))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MatrixRankWarning)
        try:
            z = np.asarray(spsolve(a, rhs), dtype=float).reshape(rhs.shape)
        except RuntimeError:  # SuperLU: "Factor is exactly singular"
            return None
    return z if np.all(np.isfinite(z)) else None


@functools.lru_cache(maxsize=8)
def _cyclic_pattern(n: int) -> tuple[npt.NDArray[np.intc], npt.NDArray[np.intc]]:
    """Row indices and column pointers of the cyclic bidiagonal (n, n) matrix in canonical CSC form (rows sorted
    in each column, SuperLU's index type): column j holds row j - 1 (sup) above row j (diag), column 0 row 0
    (diag) above row n - 1 (sup). They depend on n alone, so they are built once per sample count (read-only)."""
    rows = np.arange(n, dtype=np.intc)
    indices = np.empty(2 * n, dtype=np.intc)
    indices[0], indices[1], indices[2::2], indices[3::2] = 0, n - 1, rows[:-1], rows[1:]
    indptr = np.arange(0, 2 * n + 1, 2, dtype=np.intc)
    indices.flags.writeable = False
    indptr.flags.writeable = False
    return indices, indptr


_MOTOR_NLPS = threading.local()


def _motor_nlp(samples: int, time_limit_s: float) -> ca.Function:
    """The collocation NLP of :func:`motor_constant_inertia` for ``samples`` speeds, built once per thread.

    Everything that changes between machines (the cycle, the motor, delta, the scales) is a parameter, so a
    request pays only for IPOPT's iterations; building the program and its derivatives cost several times
    more. IPOPT instances are not shared between threads, so each thread keeps its own.
    """
    cache: dict[tuple[int, float], ca.Function] = _MOTOR_NLPS.__dict__.setdefault("solvers", {})
    key = (samples, time_limit_s)
    if key not in cache:
        n = samples
        x = ca.SX.sym("x", n + 3)
        p = ca.SX.sym("p", 3 * n + 6)
        w, w_lo, w_hi, jc = x[:n], x[n], x[n + 1], x[n + 2]
        inertia, torque, h = p[:n], p[n : 2 * n], p[2 * n : 3 * n]
        slope, no_load, delta, e_scale, mean_speed, scale = (p[3 * n + k] for k in range(6))
        energy = 0.5 * (inertia + jc) * w**2
        power = torque + slope * (no_load - w)
        # the sample after the last is the first: periodicity without an extra unknown
        e_next = ca.vertcat(energy[1:], energy[0])
        p_next = ca.vertcat(power[1:], power[0])
        g = ca.vertcat(
            (e_next - energy - 0.5 * h * (power + p_next)) / e_scale,
            (w - w_lo) / mean_speed,
            (w_hi - w) / mean_speed,
            (w_hi - w_lo - 0.5 * delta * (w_hi + w_lo)) / mean_speed,
        )
        cache[key] = ca.nlpsol("motor_flywheel", "ipopt", {"x": x, "p": p, "f": jc / scale, "g": g}, {
            "print_time": False, "error_on_fail": False,
            # The adaptive barrier update halves IPOPT's iterations on these programs (11 instead of 21, the same
            # inertia to 1e-11); each iteration's factorisation is most of the solve.
            "ipopt": {"print_level": 0, "sb": "yes", "max_wall_time": time_limit_s, "tol": 1e-9, "max_iter": 1000,
                      "mu_strategy": "adaptive"},
        })
    return cache[key]
