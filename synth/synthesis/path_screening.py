"""Every start of a path synthesis screened by Levenberg-Marquardt over its stacked residuals, compiled.

The unknowns of one start are the design (crank pivot x, y, ground angle, crank, coupler, rocker, ground,
coupler point x, y) and the crank angles at the targets (one angle when they are prescribed up to a common shift),
all in units of the targets' extent. Its residuals are the coupler point's miss at every target, x then y, and
the constraints as penalty rows: ``weight * min(0, c)`` for every Grashof margin, transmission-angle limit and
crank-angle order within one turn, so the least squares slides along a constraint instead of stopping at it;
each step is clipped to the bounds. The Jacobian is analytic (the coupler point's closed form differentiated by
hand, in complex numbers) and each start keeps its own damping (Nielsen's update), so a start's path does not
depend on which others share the batch.

A start's forty steps on a 19-unknown system are a few thousand flops each: stacked over the starts in numpy, every
step was some seventy array calls whose overhead was most of the time, so each start's iteration is one compiled
loop (:mod:`synth.compiled`) that skips the Jacobian's zeros (a target's row touches the nine design coordinates
and its own crank angle; a penalty row is zero unless its constraint is broken).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..compiled import compiled
from ..errors import SolverTimeout
from ..model import FloatArray

_DESIGN = 9
_Complex = NDArray[np.complex128]
PENALTY_WEIGHT = 100.0
# Grashof crank-rocker margins as rows over (crank, coupler, rocker, ground): each row @ lengths >= margin.
_GRASHOF = np.array([[-1, 1, 0, 0], [-1, 0, 1, 0], [-1, 0, 0, 1], [-1, -1, 1, 1], [-1, 1, -1, 1], [-1, 1, 1, -1]],
                    dtype=float)


@dataclass(frozen=True, slots=True)
class Screened:
    """Where each start's screening ended: unknowns (k, m) in the working frame, the sum of squared target
    residuals (k,) [extent²], the largest constraint violation (k,) [extent or rad] and the iterations run."""

    unknowns: FloatArray
    objectives: FloatArray
    violations: FloatArray
    iterations: int


@compiled
def _coupler(z: FloatArray, phi: FloatArray, branch: float, point: _Complex, jac: _Complex,
             jac_phi: _Complex) -> None:  # pragma: no cover - compiled; run through coupler_jacobian and screen
    """Coupler point as complex x + iy at crank angles ``phi`` (n,) [rad] of design ``z`` (9,) into ``point``
    (n,), its derivatives with respect to the design into ``jac`` (n, 9) and to each angle into ``jac_phi`` (n,).

    The point is P = A + w·c·E with A the crank pin, E = Q - A, w the coupler point as a complex number and
    c = (x + i·branch·h) / (b·L) fixed by the triangle A B Q (L = |E|, x and h the foot and height of B over AQ),
    so each derivative is dA + w·(dc·E + c·dE) with dc through L, b and c only. Where the loop cannot close
    (b² < x²) the height is clamped as :func:`synth.synthesis.path._coupler_points` clamps it, and its derivative
    is zero there.
    """
    xo, yo, th, a, b, c, d, px, py = z[0], z[1], z[2], z[3], z[4], z[5], z[6], z[7], z[8]
    ground = complex(math.cos(th), math.sin(th))
    w = complex(px, py)
    for i in range(phi.shape[0]):
        crank = complex(math.cos(th + phi[i]), math.sin(th + phi[i]))
        pin = complex(xo, yo) + a * crank
        e = d * ground - a * crank
        l2 = e.real * e.real + e.imag * e.imag
        length = math.sqrt(l2)
        foot = (b * b - c * c + l2) / (2 * length)
        h2 = b * b - foot * foot
        closes = h2 > 1e-18
        height = math.sqrt(h2 if closes else 1e-18)
        shape = complex(foot, branch * height) / (b * length)
        point[i] = pin + w * shape * e
        foot_l = 0.5 - (b * b - c * c) / (2 * l2)
        inv_h = 1.0 / height if closes else 0.0
        height_l = -foot * foot_l * inv_h
        height_b = (b - foot * b / length) * inv_h
        height_c = foot * c / length * inv_h
        shape_l = complex(foot_l, branch * height_l) / (b * length) - shape / length
        shape_b = complex(b / length, branch * height_b) / (b * length) - shape / b
        shape_c = complex(-c / length, branch * height_c) / (b * length)
        # d(point) = dA + w·(c_L·dL·E + c·dE), dL = Re(conj(E)·dE) / L, for each (dA, dE) below.
        e_conj = e.conjugate()
        de = 1j * e
        jac[i, 0] = 1.0
        jac[i, 1] = 1j
        jac[i, 2] = 1j * a * crank + w * (shape_l * ((e_conj * de).real / length) * e + shape * de)
        de = -crank
        jac[i, 3] = crank + w * (shape_l * ((e_conj * de).real / length) * e + shape * de)
        jac[i, 4] = w * shape_b * e
        jac[i, 5] = w * shape_c * e
        de = ground
        jac[i, 6] = w * (shape_l * ((e_conj * de).real / length) * e + shape * de)
        jac[i, 7] = shape * e
        jac[i, 8] = 1j * shape * e
        de = -1j * a * crank
        jac_phi[i] = 1j * a * crank + w * (shape_l * ((e_conj * de).real / length) * e + shape * de)


def coupler_jacobian(z: FloatArray, phi: FloatArray,
                     branch: FloatArray) -> tuple[_Complex, _Complex, _Complex]:
    """Coupler point as complex x + iy (k, n), its derivatives with respect to the nine design coordinates
    (k, n, 9) and to each target's own crank angle (k, n), for designs ``z`` (k, 9), crank angles ``phi`` (k, n)
    [rad] and branches (k,): the screening's own kernel, one design at a time."""
    k, n = phi.shape
    point = np.empty((k, n), dtype=complex)
    jac = np.empty((k, n, _DESIGN), dtype=complex)
    jac_phi = np.empty((k, n), dtype=complex)
    for j in range(k):
        _coupler(np.ascontiguousarray(z[j], dtype=float), np.ascontiguousarray(phi[j], dtype=float),
                 float(branch[j]), point[j], jac[j], jac_phi[j])
    return point, jac, jac_phi


@compiled
def _evaluate(u: FloatArray, branch: float, targets: _Complex, offsets: FloatArray, timed: bool, cos_mu: float,
              lin: FloatArray, lin0: FloatArray, phi: FloatArray, point: _Complex, jac_z: _Complex,
              jac_phi: _Complex, r: FloatArray, jac: FloatArray) -> float:  # pragma: no cover - compiled
    """Residuals ``r`` (rows,) and Jacobian ``jac`` (rows, m) at unknowns ``u`` (m,), written in place; half
    the sum of squared residuals. ``targets`` (n,) complex; ``lin``, ``lin0``: the constraints linear in the
    unknowns (Grashof margins, crank angles in order), each row @ u + lin0 >= 0; the rest are work arrays."""
    n = targets.shape[0]
    m = u.shape[0]
    jac[:, :] = 0.0
    for i in range(n):
        phi[i] = u[_DESIGN] + offsets[i] if timed else u[_DESIGN + i]
    _coupler(u[:_DESIGN], phi, branch, point, jac_z, jac_phi)
    for i in range(n):
        miss = point[i] - targets[i]
        r[i], r[n + i] = miss.real, miss.imag
        for q in range(_DESIGN):
            jac[i, q], jac[n + i, q] = jac_z[i, q].real, jac_z[i, q].imag
        col = _DESIGN if timed else _DESIGN + i
        jac[i, col], jac[n + i, col] = jac_phi[i].real, jac_phi[i].imag
    # Transmission angle within its limits at both crank positions along the ground line:
    # |b² + c² - far²| <= 2·b·c·cos(mu_min), far = d - a and d + a.
    a, b, c, d = u[3], u[4], u[5], u[6]
    limit = 2 * b * c * cos_mu
    for j in range(2):
        far, sign = (d - a, -1.0) if j == 0 else (d + a, 1.0)
        cosine = b * b + c * c - far * far
        for side in range(2):
            turn = -1.0 if side == 0 else 1.0
            row = 2 * n + 2 * j + side
            con = limit + turn * cosine
            if con < 0:
                r[row] = PENALTY_WEIGHT * con
                jac[row, 3] = PENALTY_WEIGHT * (turn * -2 * far * sign)
                jac[row, 4] = PENALTY_WEIGHT * (2 * c * cos_mu + turn * 2 * b)
                jac[row, 5] = PENALTY_WEIGHT * (2 * b * cos_mu + turn * 2 * c)
                jac[row, 6] = PENALTY_WEIGHT * (turn * -2 * far)
            else:
                r[row] = 0.0
    for q in range(lin.shape[0]):
        row = 2 * n + 4 + q
        con = lin0[q]
        for p in range(m):
            con += lin[q, p] * u[p]
        if con < 0:
            r[row] = PENALTY_WEIGHT * con
            for p in range(m):
                jac[row, p] = PENALTY_WEIGHT * lin[q, p]
        else:
            r[row] = 0.0
    total = 0.0
    for i in range(r.shape[0]):
        total += r[i] * r[i]
    return 0.5 * total


@compiled
def _solve(a: FloatArray, rhs: FloatArray) -> None:  # pragma: no cover - compiled; run through screen
    """``rhs`` overwritten with the solution of ``a`` x = ``rhs`` for a symmetric positive definite ``a`` (its
    lower triangle overwritten with its Cholesky factor): the damped normal equations are, their damping adds a
    positive multiple of each diagonal entry. A pivot that is not positive (the damping lost to round-off) gives
    NaN, which the step's trial then rejects."""
    m = rhs.shape[0]
    for k in range(m):
        d = a[k, k]
        for j in range(k):
            d -= a[k, j] * a[k, j]
        if not d > 0.0:
            rhs[:] = np.nan
            return
        d = math.sqrt(d)
        a[k, k] = d
        for i in range(k + 1, m):
            s = a[i, k]
            for j in range(k):
                s -= a[i, j] * a[k, j]
            a[i, k] = s / d
    for k in range(m):
        s = rhs[k]
        for j in range(k):
            s -= a[k, j] * rhs[j]
        rhs[k] = s / a[k, k]
    for k in range(m - 1, -1, -1):
        s = rhs[k]
        for j in range(k + 1, m):
            s -= a[j, k] * rhs[j]
        rhs[k] = s / a[k, k]


@compiled
def _march(u: FloatArray, branch: float, targets: _Complex, offsets: FloatArray, timed: bool, lower: FloatArray,
           upper: FloatArray, cos_mu: float, lin: FloatArray, lin0: FloatArray,
           iterations: int) -> tuple[float, float, int]:  # pragma: no cover - compiled; run through screen
    """Levenberg-Marquardt from ``u`` (m,), overwritten with where it ends: the sum of squared target residuals
    there, the largest penalty residual and the iterations it took (one more than its steps when it stopped
    early, as a batch run counts them). A step is kept when it achieves at least 1e-4 of the decrease its
    linear model predicts; the damping then shrinks by Nielsen's factor, else grows by a doubling factor. The
    start stops when its objective no longer falls (relative 1e-14), vanishes, or the damping reaches 1e15."""
    n = targets.shape[0]
    m = u.shape[0]
    rows = 2 * n + 4 + lin.shape[0]
    phi = np.empty(n)
    point = np.empty(n, dtype=np.complex128)
    jac_z = np.empty((n, _DESIGN), dtype=np.complex128)
    jac_phi = np.empty(n, dtype=np.complex128)
    r, r_t = np.empty(rows), np.empty(rows)
    jac, jac_t = np.empty((rows, m)), np.empty((rows, m))
    normal, system = np.empty((m, m)), np.empty((m, m))
    grad, step, trial = np.empty(m), np.empty(m), np.empty(m)
    f = _evaluate(u, branch, targets, offsets, timed, cos_mu, lin, lin0, phi, point, jac_z, jac_phi, r, jac)
    damping, growth = 1e-3, 2.0
    run = iterations if math.isfinite(f) else 1
    for it in range(1, iterations + 1 if math.isfinite(f) else 1):
        normal[:, :] = 0.0
        grad[:] = 0.0
        for i in range(rows):
            for p in range(m):
                jp = jac[i, p]
                if jp != 0.0:
                    grad[p] += jp * r[i]
                    for q in range(m):
                        normal[p, q] += jp * jac[i, q]
        for p in range(m):
            for q in range(m):
                system[p, q] = normal[p, q]
            system[p, p] += damping * max(normal[p, p], 1e-12)
            step[p] = -grad[p]
        _solve(system, step)
        for p in range(m):
            t = u[p] + step[p]
            if t < lower[p]:
                t = lower[p]
            elif t > upper[p]:
                t = upper[p]
            trial[p] = t
            step[p] = t - u[p]
        f_t = _evaluate(trial, branch, targets, offsets, timed, cos_mu, lin, lin0, phi, point, jac_z, jac_phi, r_t,
                        jac_t)
        predicted = 0.0
        for p in range(m):
            s = 0.0
            for q in range(m):
                s += normal[p, q] * step[q]
            predicted -= grad[p] * step[p] + 0.5 * step[p] * s
        gain = (f - f_t) / (predicted if predicted > 1e-300 or predicted != predicted else 1e-300)
        stalled = False
        if math.isfinite(f_t) and gain > 1e-4:
            stalled = f - f_t <= 1e-14 * f
            u[:] = trial
            r, r_t = r_t, r
            jac, jac_t = jac_t, jac
            f = f_t
            ratio = min(gain, 1.0)
            damping *= max(1.0 / 3.0, 1.0 - (2.0 * ratio - 1.0) ** 3)
            growth = 2.0
        else:
            damping *= growth
            growth = min(2.0 * growth, 1e6)
        damping = min(max(damping, 1e-15), 1e15)
        if stalled or f < 1e-30 or damping >= 1e15:
            run = min(it + 1, iterations)
            break
    data = 0.0
    for i in range(2 * n):
        data += r[i] * r[i]
    violation = 0.0
    for i in range(2 * n, rows):
        violation = max(violation, abs(r[i]))
    return data, violation / PENALTY_WEIGHT, run


@compiled
def first_shifts(designs: FloatArray, branches: FloatArray, targets: FloatArray, phi: FloatArray
                 ) -> FloatArray:  # pragma: no cover - compiled; run through synth.synthesis.path._first_angles
    """For each design (k, 9) on its branch (k,), the index of the row of crank angles ``phi`` (s, n) [rad] that
    puts its coupler point nearest the ``targets`` (n, 2) in the sum of squares (a row where the loop cannot
    close at some angle counts as infinitely far): the closed form of :func:`synth.synthesis.path._coupler_points`
    one design and angle at a time, without the (k, s, n) arrays numpy would make of it."""
    k, shifts, n = designs.shape[0], phi.shape[0], phi.shape[1]
    out = np.zeros(k)
    for j in range(k):
        xo, yo, th, a, b, c, d, px, py = (designs[j, 0], designs[j, 1], designs[j, 2], designs[j, 3], designs[j, 4],
                                          designs[j, 5], designs[j, 6], designs[j, 7], designs[j, 8])
        br = branches[j]
        qx, qy = xo + d * math.cos(th), yo + d * math.sin(th)
        best, at = math.inf, 0
        for s in range(shifts):
            total = 0.0
            for i in range(n):
                ax, ay = xo + a * math.cos(th + phi[s, i]), yo + a * math.sin(th + phi[s, i])
                ex, ey = qx - ax, qy - ay
                dist = math.sqrt(ex * ex + ey * ey)
                ux, uy = ex / dist, ey / dist
                x = (b * b - c * c + dist * dist) / (2 * dist)
                h2 = b * b - x * x
                h = math.sqrt(h2 if h2 > 1e-18 else 1e-18)
                bx, by = ax + x * ux - br * h * uy, ay + x * uy + br * h * ux
                e2x, e2y = (bx - ax) / b, (by - ay) / b
                mx = ax + px * e2x - py * e2y - targets[i, 0]
                my = ay + px * e2y + py * e2x - targets[i, 1]
                miss = mx * mx + my * my
                total += miss if math.isfinite(miss) else math.inf
            if total < best:
                best, at = total, s
        out[j] = at
    return out


def _linear_constraints(n: int, timed: bool, margin: float) -> tuple[FloatArray, FloatArray]:
    """The constraints linear in the unknowns, each row @ u + constant >= 0: Grashof margins, crank angles in
    order within one turn."""
    m = _DESIGN + (1 if timed else n)
    order = 0 if timed else n
    lin = np.zeros((6 + order, m))
    lin[:6, 3:7] = _GRASHOF
    if not timed:
        i = np.arange(n - 1)
        lin[6 + i, _DESIGN + i], lin[6 + i, _DESIGN + i + 1] = -1.0, 1.0
        lin[6 + n - 1, _DESIGN], lin[6 + n - 1, _DESIGN + n - 1] = 1.0, -1.0
    turn = np.zeros(order) if timed else np.r_[np.zeros(n - 1), 2 * math.pi]
    return lin, np.concatenate([np.full(6, -margin), turn])


def screen(u0: FloatArray, branches: FloatArray, targets: FloatArray, offsets: FloatArray, timed: bool,
           lower: FloatArray, upper: FloatArray, cos_mu: float, margin: float, iterations: int,
           deadline: float, time_limit: float) -> Screened:
    """Levenberg-Marquardt from every start ``u0`` (k, m) for at most ``iterations`` steps each.

    ``targets`` (n, 2) and bounds in the working frame; ``offsets`` (n,) the prescribed crank-angle steps when
    ``timed``; ``cos_mu`` the cosine of the least transmission angle; ``margin`` the Grashof margin. A start
    stops when its objective no longer falls (relative 1e-14) or vanishes. SolverTimeout past ``deadline``
    (``time.monotonic()``), naming ``time_limit`` [s] and the starts screened by then.
    """
    lin, lin0 = _linear_constraints(targets.shape[0], timed, margin)
    points = np.ascontiguousarray(targets[:, 0] + 1j * targets[:, 1])
    steps = np.ascontiguousarray(offsets, dtype=float)
    lo, hi = np.ascontiguousarray(lower, dtype=float), np.ascontiguousarray(upper, dtype=float)
    u = np.array(u0, dtype=float, order="C")
    k = len(u)
    data, violations = np.empty(k), np.empty(k)
    run = 0
    for j in range(k):
        if time.monotonic() > deadline:
            raise SolverTimeout(time_limit, starts_completed=j)
        data[j], violations[j], runs = _march(u[j], float(branches[j]), points, steps, timed, lo, hi, cos_mu, lin,
                                              lin0, iterations)
        run = max(run, runs)
    return Screened(u, np.where(np.isfinite(data), data, np.nan), violations, run)
