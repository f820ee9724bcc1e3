"""The run-down with the motor off, integrated in closed form over the crank angle.

With the motor switched off no torque on the crank depends on its speed: the load, the pairs' friction (tables
over the crank angle) and the brake (constant) act alone, and the rotor, train and flywheel only add inertia.
The equation of motion J(phi)·dw/dt + J'(phi)·w²/2 = M(phi) is then d(J·w²/2)/dphi = M(phi) (seed 000:597-612),
so the kinetic energy is the integral of the net torque over the angle, exact on the tables (linear between
the samples: each sample interval adds the trapezoid, and within it the energy is a quadratic in the angle).
The crank stops where that energy first reaches zero, found as the root of the quadratic. The only thing
approximated is the time, the integral of dphi/w with w = sqrt(2·K/J): Gauss-Legendre in every interval (in every
panel of the reported spacing on a finer grid), and over the last intervals before the stop (where 1/w grows without bound) in a variable that takes the square
root out, so the stop time of a rotor with constant inertia and torque is exact. The same integral by a rule of
lower order gives the time's error estimate the answer reports.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache

import numpy as np

from ..model import FloatArray

#: Gauss-Legendre points in each sample interval (and fewer, for the error estimate) on a grid of
#: REPORTED_PER_REVOLUTION samples; a finer grid takes them in each panel of that spacing (:func:`_points`).
_POINTS, _CHECK_POINTS = 6, 3
#: The last intervals before the stop, integrated in the variable that removes the square-root singularity, and
#: the Gauss-Legendre points there.
_TAIL_INTERVALS, _TAIL_POINTS, _TAIL_CHECK_POINTS = 8, 24, 12
#: Sample intervals whose times are evaluated together.
_BLOCK = 4096
#: Most states reported a revolution (finer tables are integrated on their own grid, reported on this one).
REPORTED_PER_REVOLUTION = 360


@dataclass(frozen=True, slots=True)
class Coast:
    """A run-down on the sample grid: ``angle`` from the start [rad], ``time`` [s], ``omega`` [rad/s] at every
    node passed (and at the stop, where omega is 0), (M,) each; ``stop_time`` [s] (None: still turning at
    the horizon); the works over the run [J]: ``friction_loss`` (pairs and brake), ``process_work`` (against
    the load; negative where it drives); ``time_error`` the time at the end by the lower-order rule, relative
    [-]."""

    angle: FloatArray
    time: FloatArray
    omega: FloatArray
    stop_time: float | None
    friction_loss: float
    process_work: float
    time_error: float


def _points(samples: int) -> tuple[int, int]:
    """Gauss-Legendre points per panel, and for the error estimate, on a grid of ``samples`` panels a revolution:
    about as many a revolution as on the reported grid (an n-point rule's error falls as the panel's 2n-th power,
    so shorter panels need fewer points for the same time), never fewer than 3 and 2."""
    scale = REPORTED_PER_REVOLUTION / samples
    return max(3, math.ceil(_POINTS * scale)), max(2, math.ceil(_CHECK_POINTS * scale))


@cache
def _gauss(points: int) -> tuple[FloatArray, FloatArray]:
    """Gauss-Legendre nodes and weights on [0, 1]."""
    x, w = np.polynomial.legendre.leggauss(points)
    return (x + 1) / 2, w / 2


def _hermite(k: FloatArray, s: FloatArray, step: float, j: FloatArray, dj: FloatArray) -> FloatArray:
    """J on the cubic Hermite curve through the closed tables, in interval ``k`` (mod the revolution) at the
    fraction ``s`` of it."""
    s2, s3 = s * s, s * s * s
    return np.asarray((2 * s3 - 3 * s2 + 1) * j[k] + (s3 - 2 * s2 + s) * step * dj[k]
                      + (3 * s2 - 2 * s3) * j[k + 1] + (s3 - s2) * step * dj[k + 1], dtype=float)


def _first_zero(a: FloatArray, b: FloatArray, c: FloatArray) -> tuple[int, float] | None:
    """The first interval where a + b·s + c·s² reaches zero for s in (0, 1], and the fraction s there."""
    end = a + b + c
    vertex = np.where(c > 0, -b / np.where(c > 0, 2 * c, 1.0), 2.0)
    inside = (vertex > 0) & (vertex < 1) & (a - b * b / np.where(c > 0, 4 * c, 1.0) <= 0)
    hit = np.flatnonzero((end <= 0) | inside)
    if not hit.size:
        return None
    i = int(hit[0])
    ai, bi, ci = float(a[i]), float(b[i]), float(c[i])
    if abs(ci) <= 1e-14 * (abs(bi) + abs(ai)):
        return i, min(max(-ai / bi, 0.0), 1.0)
    disc = max(bi * bi - 4 * ai * ci, 0.0)
    q = -(bi + math.copysign(math.sqrt(disc), bi)) / 2
    roots = [r for r in (q / ci, ai / q if q != 0 else math.inf) if 0 < r <= 1 + 1e-12]
    return i, min(min(roots), 1.0) if roots else 1.0


def coast(inertia: FloatArray, inertia_slope: FloatArray, load: FloatArray, resisting: FloatArray,
          constant_inertia: float, speed: float, max_time: float, max_nodes: int) -> Coast:
    """Run the crank down from ``speed`` [rad/s] at the first sample.

    ``inertia`` J_red [kg·m²], ``inertia_slope`` dJ_red/dphi [kg·m²/rad], ``load`` the load torque (positive
    drives) and ``resisting`` friction and brake (positive resists) on the crank [N·m], (N,) each, on uniform
    samples over one revolution (the last sample's successor the first); ``constant_inertia`` rotor, train and
    flywheel [kg·m²]. Integrates until the crank stops, ``max_time`` [s] passes or ``max_nodes`` samples are
    passed.
    """
    n = inertia.size
    h = 2 * math.pi / n
    j = np.append(inertia, inertia[0]) + constant_inertia
    dj = np.append(inertia_slope, inertia_slope[0])
    g = np.append(load - resisting, load[0] - resisting[0])
    # over each interval K(s) = K_k + h·(g_k·s + (g_k+1 - g_k)·s²/2)
    lin, quad = h * g[:-1], h * (g[1:] - g[:-1]) / 2
    gain = lin + quad
    per_rev = float(gain.sum())
    k0 = 0.5 * float(j[0]) * speed * speed
    cap = max(1, math.ceil(max_nodes / n))
    revs = min(math.ceil(k0 / -per_rev) + 1, cap) if per_rev < 0 else cap
    idx = np.arange(revs * n) % n
    start = k0 + np.concatenate(([0.0], np.cumsum(np.tile(gain, revs))[:-1]))
    hit = _first_zero(start, lin[idx], quad[idx])

    def inverse_speed(u: FloatArray) -> FloatArray:
        """dt/dphi = 1/w at ``u`` sample intervals from the start (within the intervals computed)."""
        k = np.minimum(np.floor(u).astype(int), start.size - 1)
        s = u - k
        r = idx[k]
        kin = start[k] + lin[r] * s + quad[r] * s * s
        return np.asarray(np.sqrt(_hermite(r, s, h, j, dj) / (2 * np.maximum(kin, 1e-300))), dtype=float)

    def panel_times(bounds: FloatArray, points: int) -> FloatArray:
        """Time over each panel between successive ``bounds`` [intervals from the start]."""
        x, w = _gauss(points)
        out = np.empty(bounds.size - 1)
        # in blocks: the memory a run-down takes stays that of a block, not of every point of every panel
        for lo in range(0, out.size, _BLOCK):
            b = bounds[lo: lo + _BLOCK + 1]
            width = np.diff(b)
            u = b[:-1, None] + width[:, None] * x[None, :]
            out[lo: lo + width.size] = h * width * (inverse_speed(u) @ w)
        return out

    def time_to(end: float, begin: float, points: int) -> float:
        """Time from ``begin`` to the stop at ``end`` [intervals]: with u = end - (end - begin)·sigma², K vanishes
        like sigma² and sigma·dt/dphi stays smooth."""
        sg, ws = _gauss(points)
        rest = end - begin
        return float(h * rest * 2 * np.sum(ws * sg * inverse_speed(end - rest * sg * sg)))

    # A finer grid than REPORTED_PER_REVOLUTION samples is reported at that spacing, and its time integrated in
    # panels of that spacing: within a panel the integrand is as smooth as the tables (their kinks at the fine
    # samples are of the order of the samples' spacing squared), so a panel takes the reported grid's rule.
    stride = max(1, n // REPORTED_PER_REVOLUTION)
    points, check_points = _points(n // stride)

    def panels(upto: int) -> FloatArray:
        return np.unique(np.append(np.arange(0, upto, stride), upto)).astype(float)

    if hit is None:
        m = start.size
        bounds = panels(m)
        time = np.concatenate(([0.0], np.cumsum(panel_times(bounds, points))))
        check = float(np.sum(panel_times(bounds, check_points)))
        end = float(m)
        nodes = bounds
        kin = np.append(start, start[-1] + gain[idx[-1]])[bounds.astype(int)]
    else:
        i, s_stop = hit
        end = i + s_stop
        head = max(i - _TAIL_INTERVALS, 0)
        bounds = panels(head)
        t_head = np.concatenate(([0.0], np.cumsum(panel_times(bounds, points))))
        t_stop = float(t_head[-1]) + time_to(end, head, _TAIL_POINTS)
        check = float(np.sum(panel_times(bounds, check_points))) + time_to(end, head, _TAIL_CHECK_POINTS)
        tail_nodes = np.arange(head + 1, i + 1)
        if stride > 1:
            tail_nodes = tail_nodes[tail_nodes % stride == 0]
        tail = [t_stop - time_to(end, float(k), _TAIL_POINTS) for k in tail_nodes]
        time = np.concatenate((t_head, tail, [t_stop]))
        nodes = np.concatenate((bounds, tail_nodes, [end]))
        kin = np.append(start[nodes[:-1].astype(int)], 0.0)
    m = int(math.floor(nodes[-1])) if hit is None else i + 1
    k = np.minimum(np.floor(nodes).astype(int), m - 1)
    jn = _hermite(idx[k], nodes - k, h, j, dj)
    omega = np.sqrt(2 * np.maximum(kin, 0.0) / jn)
    t_end = float(time[-1])
    stopped = hit is not None and t_end <= max_time
    # the nodes reported: the multiples of the reported spacing, and the last (the stop, or the horizon)
    shown = np.flatnonzero((nodes % stride == 0) | (np.arange(nodes.size) == nodes.size - 1))
    nodes, time, omega = nodes[shown], time[shown], omega[shown]
    if t_end > max_time:
        keep = int(np.searchsorted(time, max_time)) + 1
        nodes, time, omega = nodes[:keep], time[:keep], omega[:keep]
    # works over the angle run: the tables' trapezoids over whole intervals and the exact part of the last one
    full = int(math.floor(float(nodes[-1])))
    frac = float(nodes[-1] - full)
    res = np.append(resisting, resisting[0])
    ld = np.append(load, load[0])

    def work(v: FloatArray) -> float:
        per = h * (v[:-1] + v[1:]) / 2
        whole = float(np.sum(per)) * (full // n) + float(np.sum(per[: full % n]))
        r = full % n
        return whole + h * float(v[r] * frac + (v[r + 1] - v[r]) * frac * frac / 2)

    return Coast(nodes * h, time, omega, t_end if stopped else None, work(res), -work(ld),
                 abs(check - t_end) / max(t_end, 1e-300))
