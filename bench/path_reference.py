"""Path generation's per-start solve as it was before the working frame, kept as the benchmark's baseline.

The same lifted least-squares NLP as :mod:`synth.synthesis.path`, but in metres with the targets' extent as a
parameter, IPOPT's default step computation (residual check and iterative refinement of every step), the
crank angles fitted start by start and the solver's arguments converted on every call. It shares the Sobol
starts, bounds and constraints of the engine, so both run the same starts of the same problem.
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from synth.model import FloatArray
from synth.synthesis.path import _DESIGN, GRASHOF_MARGIN, PathSpec, _box, _coupler_points, _starts


@dataclass(frozen=True, slots=True)
class ReferenceStarts:
    """Objective of each start [m² over the extent squared] (NaN where IPOPT failed), IPOPT iterations of each,
    and the best start's index and design in metres (pivot x, y, ground angle, four lengths, coupler point)."""

    objectives: FloatArray
    iterations: tuple[int, ...]
    best_start: int
    best_design: FloatArray


@functools.lru_cache(maxsize=8)
def _program(n: int, timed: bool, branch: int) -> Any:
    z = ca.SX.sym("z", _DESIGN)
    phi = ca.SX.sym("phi", 1 if timed else n)
    targets = ca.SX.sym("targets", n, 2)
    offsets = ca.SX.sym("offsets", n)
    scale = ca.SX.sym("scale")
    cos_mu = ca.SX.sym("cos_mu")
    angles = phi[0] + offsets if timed else phi
    px, py = _coupler_points(z, angles, float(branch))
    r = ca.SX.sym("r", 2 * n)
    f = ca.sumsqr(r) / (scale * scale)
    a, b, c, d = z[3], z[4], z[5], z[6]
    g = [b - a, c - a, d - a, c + d - a - b, b + d - a - c, b + c - a - d]
    for far in (d - a, d + a):
        cosine = b * b + c * c - far * far
        g += [(2 * b * c * cos_mu - cosine) / (scale * scale), (2 * b * c * cos_mu + cosine) / (scale * scale)]
    if not timed:
        g += [phi[i + 1] - phi[i] for i in range(n - 1)] + [phi[0] + 2 * math.pi - phi[n - 1]]
    g += [ca.vertcat(px - targets[:, 0], py - targets[:, 1]) - r]
    nlp = {"x": ca.vertcat(z, phi, r), "p": ca.vertcat(ca.vec(targets), offsets, scale, cos_mu), "f": f,
           "g": ca.vertcat(*g)}
    opts = {"print_time": False, "show_eval_warnings": False, "ipopt.print_level": 0, "ipopt.sb": "yes",
            "ipopt.tol": 1e-12, "ipopt.acceptable_tol": 1e-9, "ipopt.max_iter": 120}
    return ca.nlpsol("path_reference", "ipopt", nlp, opts)


def _first_angles(start: FloatArray, targets: FloatArray, offsets: FloatArray, timed: bool, branch: int) -> FloatArray:
    n = targets.shape[0]
    steps = offsets if timed else 2 * math.pi * np.arange(n) / n
    shifts = np.linspace(0.0, 2 * math.pi, 72, endpoint=False)
    phi = shifts[:, None] + steps[None, :]
    with np.errstate(all="ignore"):
        px, py = _coupler_points(start[:_DESIGN], phi, float(branch))
    miss = np.nan_to_num((px - targets[:, 0]) ** 2 + (py - targets[:, 1]) ** 2, nan=np.inf).sum(axis=1)
    first = shifts[int(np.argmin(miss))]
    return np.array([first]) if timed else first + steps


def reference_starts(spec: PathSpec, indices: Sequence[int]) -> ReferenceStarts:
    """Run the starts ``indices`` one after another as the engine did before its working frame."""
    targets = np.asarray(spec.targets, dtype=float)
    n = targets.shape[0]
    timed = spec.crank_angles is not None
    offsets = np.zeros(n) if spec.crank_angles is None else np.asarray(spec.crank_angles) - spec.crank_angles[0]
    scale = float(np.ptp(targets, axis=0).max()) or 1.0
    params = np.concatenate([targets.T.reshape(-1), offsets, [scale, math.cos(spec.min_transmission_angle)]])
    lo, hi = _box(spec)
    lbx_z, ubx_z = lo[:_DESIGN], hi[:_DESIGN]
    lbx_z[2], ubx_z[2] = -3 * math.pi, 3 * math.pi
    n_phi = 1 if timed else n
    n_g = 10 + (0 if timed else n)
    bounds = {
        "lbx": np.concatenate([lbx_z, np.full(n_phi, -4 * math.pi), np.full(2 * n, -np.inf)]),
        "ubx": np.concatenate([ubx_z, np.full(n_phi, 4 * math.pi), np.full(2 * n, np.inf)]),
        "lbg": np.concatenate([np.full(6, GRASHOF_MARGIN * scale), np.zeros(n_g - 6), np.zeros(2 * n)]),
        "ubg": np.concatenate([np.full(n_g, np.inf), np.zeros(2 * n)]),
    }
    starts = _starts(spec)
    deadline = time.monotonic() + spec.time_limit
    objectives = np.full(len(indices), np.nan)
    iterations = []
    best: tuple[int, float, FloatArray] | None = None
    for done, k in enumerate(indices):
        if time.monotonic() > deadline:
            raise TimeoutError("the reference starts outran the time limit")
        start = starts[k]
        branch = spec.branch or (1 if k % 2 == 0 else -1)
        solver = _program(n, timed, branch)
        angles0 = _first_angles(start, targets, offsets, timed, branch)
        with np.errstate(all="ignore"):
            px0, py0 = _coupler_points(start[:_DESIGN], angles0[0] + offsets if timed else angles0, float(branch))
        r0 = np.nan_to_num(np.concatenate([px0 - targets[:, 0], py0 - targets[:, 1]]))
        sol = solver(x0=np.concatenate([start[:_DESIGN], angles0, r0]), p=params, **bounds)
        stats = solver.stats()
        iterations.append(int(stats["iter_count"]))
        if stats["return_status"] in ("Solve_Succeeded", "Solved_To_Acceptable_Level"):
            objectives[done] = float(sol["f"])
            if best is None or objectives[done] < best[1]:
                best = (k, objectives[done], np.asarray(sol["x"]).reshape(-1)[:_DESIGN])
    if best is None:
        raise RuntimeError("no reference start converged")
    return ReferenceStarts(objectives, tuple(iterations), best[0], best[2])
