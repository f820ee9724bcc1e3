"""Path generation's screening as it was before it was compiled, kept as the benchmark's baseline: every start's
Levenberg-Marquardt step stacked over all starts in numpy (one batched normal-equation solve per step, the
Jacobian of all starts in array calls). The same residuals, penalties, damping and stopping rules as
:mod:`synth.synthesis.path_screening`, so both screen the same starts to the same points.
"""

from __future__ import annotations

import time

import numpy as np
from numpy.typing import NDArray

from synth.errors import SolverTimeout
from synth.model import FloatArray
from synth.synthesis.path_screening import _DESIGN, PENALTY_WEIGHT, Screened, _linear_constraints


def coupler_jacobian(z: FloatArray, phi: FloatArray,
                     branch: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Coupler point as complex x + iy (k, n), its derivatives with respect to the nine design coordinates
    (k, n, 9) and to each target's own crank angle (k, n), for designs ``z`` (k, 9), crank angles ``phi`` (k, n)
    [rad] and branches (k,).

    The point is P = A + w·c·E with A the crank pin, E = Q - A, w the coupler point as a complex number and
    c = (x + i·branch·h) / (b·L) fixed by the triangle A B Q (L = |E|, x and h the foot and height of B over AQ),
    so each derivative is dA + w·(dc·E + c·dE) with dc through L, b and c only. Where the loop cannot close
    (b² < x²) the height is clamped as :func:`synth.synthesis.path._coupler_points` clamps it, and its derivative
    is zero there.
    """
    xo, yo, th, a, b, c, d, px, py = (z[:, i, None] for i in range(_DESIGN))
    br = branch[:, None]
    ground = np.exp(1j * th)
    crank = np.exp(1j * (th + phi))
    pin = xo + 1j * yo + a * crank
    e = d * ground - a * crank
    l2 = e.real**2 + e.imag**2
    length = np.sqrt(l2)
    foot = (b * b - c * c + l2) / (2 * length)
    h2 = b * b - foot * foot
    closes = h2 > 1e-18
    height = np.sqrt(np.where(closes, h2, 1e-18))
    shape = (foot + 1j * br * height) / (b * length)
    w = px + 1j * py
    point = pin + w * shape * e
    foot_l = 0.5 - (b * b - c * c) / (2 * l2)
    inv_h = np.where(closes, 1.0 / height, 0.0)
    height_l = -foot * foot_l * inv_h
    height_b = (b - foot * b / length) * inv_h
    height_c = foot * c / length * inv_h
    shape_l = (foot_l + 1j * br * height_l) / (b * length) - shape / length
    shape_b = (b / length + 1j * br * height_b) / (b * length) - shape / b
    shape_c = (-c / length + 1j * br * height_c) / (b * length)
    e_conj = np.conj(e)

    def moved(d_pin: complex | FloatArray, d_e: complex | FloatArray) -> FloatArray:
        d_length = (e_conj * d_e).real / length
        return np.asarray(d_pin + w * (shape_l * d_length * e + shape * d_e))

    k, n = phi.shape
    jac = np.empty((k, n, _DESIGN), dtype=complex)
    jac[:, :, 0] = 1.0
    jac[:, :, 1] = 1j
    jac[:, :, 2] = moved(1j * a * crank, 1j * e)
    jac[:, :, 3] = moved(crank, -crank)
    jac[:, :, 4] = w * shape_b * e
    jac[:, :, 5] = w * shape_c * e
    jac[:, :, 6] = moved(0.0, ground)
    jac[:, :, 7] = shape * e
    jac[:, :, 8] = 1j * shape * e
    return point, jac, moved(1j * a * crank, -1j * a * crank)


class _Residuals:
    """Stacked residuals and Jacobians of the screening for one problem."""

    def __init__(self, targets: FloatArray, offsets: FloatArray, timed: bool, branches: FloatArray, cos_mu: float,
                 margin: float) -> None:
        n = targets.shape[0]
        m = _DESIGN + (1 if timed else n)
        self.n, self.m, self.timed = n, m, timed
        self.targets = targets[:, 0] + 1j * targets[:, 1]
        self.offsets, self.branches, self.cos_mu = offsets, branches, cos_mu
        # The constraints linear in the unknowns (Grashof margins, crank angles in order), as the engine has them.
        self.lin, self.lin0 = _linear_constraints(n, timed, margin)
        self.rows = 2 * n + 4 + len(self.lin)

    def __call__(self, u: FloatArray, rows: NDArray[np.intp]) -> tuple[FloatArray, FloatArray]:
        """Residuals (k, rows) and Jacobian (k, rows, m) at unknowns ``u`` (k, m) of the starts ``rows``."""
        n, m, k = self.n, self.m, len(u)
        z = u[:, :_DESIGN]
        phi = u[:, _DESIGN:_DESIGN + 1] + self.offsets if self.timed else u[:, _DESIGN:]
        point, jac_z, jac_phi = coupler_jacobian(z, phi, self.branches[rows])
        miss = point - self.targets
        r = np.empty((k, self.rows))
        jac = np.zeros((k, self.rows, m))
        r[:, :n], r[:, n:2 * n] = miss.real, miss.imag
        jac[:, :n, :_DESIGN], jac[:, n:2 * n, :_DESIGN] = jac_z.real, jac_z.imag
        if self.timed:
            jac[:, :n, _DESIGN], jac[:, n:2 * n, _DESIGN] = jac_phi.real, jac_phi.imag
        else:
            i = np.arange(n)
            jac[:, i, _DESIGN + i], jac[:, n + i, _DESIGN + i] = jac_phi.real, jac_phi.imag
        # Transmission angle within its limits at both crank positions along the ground line:
        # |b² + c² - far²| <= 2·b·c·cos(mu_min), far = d - a and d + a.
        a, b, c, d = z[:, 3], z[:, 4], z[:, 5], z[:, 6]
        cons = np.empty((k, 4 + len(self.lin)))
        grad = np.zeros((k, 4 + len(self.lin), m))
        limit = 2 * b * c * self.cos_mu
        for j, (far, sign) in enumerate(((d - a, -1.0), (d + a, 1.0))):
            cosine = b * b + c * c - far * far
            for row, turn in ((2 * j, -1.0), (2 * j + 1, 1.0)):
                # d(limit + turn·cosine) / d(a, b, c, d)
                cons[:, row] = limit + turn * cosine
                grad[:, row, 3] = turn * -2 * far * sign
                grad[:, row, 4] = 2 * c * self.cos_mu + turn * 2 * b
                grad[:, row, 5] = 2 * b * self.cos_mu + turn * 2 * c
                grad[:, row, 6] = turn * -2 * far
        cons[:, 4:] = u @ self.lin.T + self.lin0
        grad[:, 4:] = self.lin
        broken = cons < 0
        r[:, 2 * n:] = PENALTY_WEIGHT * np.where(broken, cons, 0.0)
        jac[:, 2 * n:] = PENALTY_WEIGHT * np.where(broken[..., None], grad, 0.0)
        return r, jac


def screen(u0: FloatArray, branches: FloatArray, targets: FloatArray, offsets: FloatArray, timed: bool,
           lower: FloatArray, upper: FloatArray, cos_mu: float, margin: float, iterations: int,
           deadline: float, time_limit: float) -> Screened:
    """Levenberg-Marquardt from every start ``u0`` (k, m) at once for at most ``iterations`` steps.

    ``targets`` (n, 2) and bounds in the working frame; ``offsets`` (n,) the prescribed crank-angle steps when
    ``timed``; ``cos_mu`` the cosine of the least transmission angle; ``margin`` the Grashof margin. A start
    stops when its objective no longer falls (relative 1e-14) or vanishes. SolverTimeout past ``deadline``
    (``time.monotonic()``), naming ``time_limit`` [s].
    """
    res = _Residuals(targets, offsets, timed, branches, cos_mu, margin)
    n, m = res.n, res.m
    k = len(u0)
    rows = np.arange(k)
    u = np.array(u0, dtype=float)
    with np.errstate(all="ignore"):
        r, jac = res(u, rows)
    f = 0.5 * np.einsum("ki,ki->k", r, r)
    damping, growth = np.full(k, 1e-3), np.full(k, 2.0)
    done = ~np.isfinite(f)
    eye = np.eye(m)
    run = 0
    for run in range(1, iterations + 1):
        if time.monotonic() > deadline:
            raise SolverTimeout(time_limit, starts_completed=int(done.sum()))
        live = np.flatnonzero(~done)
        if live.size == 0:
            break
        jl, rl = jac[live], r[live]
        jt = jl.transpose(0, 2, 1)
        normal = jt @ jl
        grad = (jt @ rl[..., None])[..., 0]
        scale = np.maximum(np.einsum("kjj->kj", normal), 1e-12)
        step = -np.linalg.solve(normal + (damping[live, None] * scale)[:, :, None] * eye, grad[..., None])[..., 0]
        trial = np.clip(u[live] + step, lower, upper)
        step = trial - u[live]
        with np.errstate(all="ignore"):
            r_t, jac_t = res(trial, live)
        f_t = 0.5 * np.einsum("ki,ki->k", r_t, r_t)
        predicted = -np.einsum("kj,kj->k", grad, step) - 0.5 * np.einsum("kj,kj->k", step,
                                                                           (normal @ step[..., None])[..., 0])
        gain = (f[live] - f_t) / np.maximum(predicted, 1e-300)
        taken = np.isfinite(f_t) & (gain > 1e-4)
        went = live[taken]
        stalled = f[went] - f_t[taken] <= 1e-14 * f[went]
        u[went], r[went], jac[went], f[went] = trial[taken], r_t[taken], jac_t[taken], f_t[taken]
        ratio = np.minimum(gain[taken], 1.0)
        damping[went] *= np.maximum(1.0 / 3.0, 1.0 - (2.0 * ratio - 1.0) ** 3)
        growth[went] = 2.0
        back = live[~taken]
        damping[back] *= growth[back]
        growth[back] = np.minimum(2.0 * growth[back], 1e6)
        np.clip(damping, 1e-15, 1e15, out=damping)
        done[went[stalled]] = True
        done |= (f < 1e-30) | (damping >= 1e15)
    data = np.einsum("ki,ki->k", r[:, :2 * n], r[:, :2 * n])
    violations = np.abs(r[:, 2 * n:]).max(axis=1) / PENALTY_WEIGHT
    return Screened(u, np.where(np.isfinite(data), data, np.nan), violations, run)
