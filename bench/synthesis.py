"""Dimensional synthesis: the crank-rocker family search against differential evolution, path generation's
batched screening and IPOPT polish against the former multistart and SLSQP with finite differences.

Run: ``.venv/bin/python -m bench.synthesis``. Prints medians. Crank-rocker: one request of the seed's fish-tail
variant (psi = 40°, Q = 1.1) through the engine and through the in-process HTTP client, and
``scipy.optimize.differential_evolution`` (the kind of meta-heuristic other synthesis tools use) maximising the
same objective over the same one-parameter family. Path: 10 points on a known coupler curve, 32 Sobol starts,
the engine (every start screened by a compiled Levenberg-Marquardt loop, the best distinct designs polished by
IPOPT) against the former multistart of one IPOPT solve per start (:mod:`bench.path_reference`), alternated in
one process, both with the same best residual; the screening alone against its former numpy form, every start's
step stacked in array calls (:mod:`bench.path_screening_numpy`), both ending at the same points; the request
through the in-process service, in units of the machine's compute unit (goal: at most 2), with the engine's
share of it; and SLSQP with finite differences from the same starts.
"""

from __future__ import annotations

import math
import statistics
import time
from collections.abc import Callable
from typing import cast

import numpy as np
from scipy.optimize import differential_evolution, minimize

import synth
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.synthesis import CrankRockerIn
from synth.synthesis.crank_rocker import _Evaluate
from synth.synthesis.family import feasible
from synth.synthesis.path import _DESIGN, _coupler_points, _initial_points, _problem, _program, _starts
from synth.synthesis.path_screening import Screened, screen
from mechsynth_client.schemas.synthesis import PathIn
from bench.path_reference import reference_starts
from bench import path_screening_numpy
from bench._timing import compute_unit, interleaved

SPEC = synth.CrankRockerSpec(math.radians(40.0), 1.1, "rocker", 0.15)
SLSQP_STARTS = 8


def _median(fn: Callable[[], object], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def _median_cpu(fn: Callable[[], object], repeats: int) -> float:
    """Median processor time [s]: on a shared machine it shows the work, where wall time shows the waiting too."""
    times = []
    for _ in range(repeats):
        t0 = time.process_time()
        fn()
        times.append(time.process_time() - t0)
    return statistics.median(times)


def _de_objective(u: np.ndarray) -> float:
    values = _Evaluate(SPEC)(np.atleast_1d(u))
    return -float(values.value[0]) if feasible(values.slack)[0] else 10.0


def _de() -> float:
    res = differential_evolution(_de_objective, [(-1.0, 1.0)], seed=0, tol=1e-10, polish=True)
    return -float(res.fun)


def _path_spec() -> synth.PathSpec:
    fb = synth.FourBar(0.30, 0.10, 0.35, 0.25, 1)
    phi = np.radians(np.linspace(0.0, 324.0, 10))
    an = synth.analyse(synth.Linkage(fb), 1.0, phi=phi, points={"P": ("coupler", (0.15, 0.08))})
    targets = an.motion.point_pos["P"]
    bounds, box, cp = synth.default_path_limits(targets)
    return synth.PathSpec(targets, None, bounds, box, cp, starts=32, seed=1)


def _slsqp(spec: synth.PathSpec, starts: int) -> float:
    """Best sum of squared residuals [m²] SLSQP reaches from the first ``starts`` starts, on the same model."""
    t, n = spec.targets, spec.targets.shape[0]
    best = math.inf
    for k, start in enumerate(_starts(spec)[:starts]):
        branch = 1.0 if k % 2 == 0 else -1.0

        def f(x: np.ndarray) -> float:
            px, py = _coupler_points(x[:_DESIGN], x[_DESIGN:], branch)
            return float(np.sum((px - t[:, 0]) ** 2 + (py - t[:, 1]) ** 2))

        def g(x: np.ndarray) -> np.ndarray:
            a, b, c, d = x[3:7]
            phi = x[_DESIGN:]
            return np.concatenate([[b - a, c - a, d - a, c + d - a - b, b + d - a - c, b + c - a - d],
                                   np.diff(phi), [phi[0] + 2 * math.pi - phi[-1]]])

        x0 = np.concatenate([start[:_DESIGN], start[_DESIGN] + 2 * math.pi * np.arange(n) / n])
        with np.errstate(all="ignore"):
            res = minimize(f, x0, method="SLSQP", constraints=[{"type": "ineq", "fun": g}],
                           options={"maxiter": 300, "ftol": 1e-14})
        if np.isfinite(res.fun):
            best = min(best, float(res.fun))
    return best


def main() -> None:
    """Time both problems against their baselines and print medians, agreement and ratios."""
    answer = synth.synthesise_crank_rocker(SPEC)
    engine = _median(lambda: synth.synthesise_crank_rocker(SPEC), 21)
    body = CrankRockerIn(swing_deg=40.0, time_ratio=1.1, scale_length_m=0.15, speed_rpm=180)
    with SynthClient.in_process() as client:
        client.synthesise_crank_rocker(body)
        request = _median(lambda: client.synthesise_crank_rocker(body), 21)
    de_value = _de()
    de = _median(_de, 5)
    engine_cpu = _median_cpu(lambda: synth.synthesise_crank_rocker(SPEC), 21)
    print(f"crank-rocker (psi 40°, Q 1.1): engine {engine * 1e3:.1f} ms wall, {engine_cpu * 1e3:.1f} ms CPU, "
          f"HTTP request {request * 1e3:.1f} ms wall (medians); differential evolution {de * 1e3:.1f} ms -> "
          f"{de / engine:.1f}x slower")
    print(f"  min transmission angle: family search {math.degrees(answer.objective_value):.9f}°, "
          f"differential evolution {math.degrees(de_value):.9f}°; certified gap <= "
          f"{math.degrees(answer.optimality.gap_bound):.2e}°")
    spec = _path_spec()
    _program(10, False, 1), _program(10, False, -1)
    path_generation(spec)
    t0 = time.perf_counter()
    slsqp_best = _slsqp(spec, SLSQP_STARTS)
    slsqp = (time.perf_counter() - t0) / SLSQP_STARTS
    print(f"  SLSQP, finite differences, plain sum of squares, first {SLSQP_STARTS} starts: {slsqp * 1e3:.0f} ms per "
          f"start, best RMS residual {math.sqrt(slsqp_best / 10):.2e} m")


def _screenings(spec: synth.PathSpec) -> dict[str, Callable[[], object]]:
    """The screening of every start, compiled and in its former numpy form, from the same initial points."""
    targets, offsets, timed, frame, _, bounds = _problem(spec)
    x0, branches = _initial_points(spec, range(spec.starts), frame, targets, offsets, timed)
    m = x0.shape[1] - 2 * targets.shape[0]
    unit_targets = (targets - frame.centre) / frame.scale
    args = (x0[:, :m], branches, unit_targets, offsets, timed, bounds["lbx"][:m], bounds["ubx"][:m],
            math.cos(spec.min_transmission_angle), synth.synthesis.path.GRASHOF_MARGIN,
            synth.synthesis.path.SCREEN_ITERATIONS)
    return {"compiled": lambda: screen(*args, time.monotonic() + 60.0, 60.0),
            "numpy": lambda: path_screening_numpy.screen(*args, time.monotonic() + 60.0, 60.0)}


def path_generation(spec: synth.PathSpec) -> None:
    """The engine against the former multistart (one IPOPT solve per start), alternated in one process; the
    screening against its former numpy form; and the request through the in-process service, in compute units.
    Both multistarts must reach the same best residual and both screenings the same points."""
    result = synth.synthesise_path(spec)
    everything = range(spec.starts)
    old = reference_starts(spec, everything)
    t = interleaved({"former": lambda: reference_starts(spec, everything),
                     "now": lambda: synth.synthesise_path(spec)}, 5)
    screenings = _screenings(spec)
    compiled, stacked = (cast(Screened, screenings[k]()) for k in ("compiled", "numpy"))
    ends = np.isfinite(stacked.objectives)
    assert np.array_equal(ends, np.isfinite(compiled.objectives)), "the screenings end differently"
    assert np.allclose(compiled.unknowns[ends], stacked.unknowns[ends], rtol=1e-6, atol=1e-6), \
        "the screenings end at different points"
    s = interleaved(screenings, 7)
    body = PathIn(points_m=spec.targets.tolist(), starts=spec.starts, seed=spec.seed)
    with SynthClient.in_process() as client:
        answer = client.synthesise_path(body)
        request = _median(lambda: client.synthesise_path(body), 7)
    unit = compute_unit()
    scale = float(np.ptp(spec.targets, axis=0).max())
    n = spec.targets.shape[0]
    f_old = float(np.nanmin(old.objectives)) * scale**2
    f_new = float(np.sum(result.residuals**2))
    assert math.isclose(f_old, f_new, rel_tol=1e-3, abs_tol=1e-18), "the best residuals differ"
    exact = [f for f in (*answer.fits, *answer.cognates) if f.max_residual_m < 1e-9]
    print(f"path generation (10 points, 32 starts; unit {unit * 1e3:.1f} ms): engine {t['now'][1] * 1e3:.1f} ms "
          f"({t['now'][1] / unit:.2f} units), former multistart {t['former'][1] * 1e3:.0f} ms "
          f"({t['former'][1] / unit:.1f} units) -> {t['former'][1] / t['now'][1]:.1f}x (medians, alternated); "
          f"request {request / unit:.2f} units (goal <= 2), the engine {t['now'][1] / request:.0%} of it")
    print(f"  screening of the 32 starts: compiled {s['compiled'][1] * 1e3:.1f} ms, former numpy form "
          f"{s['numpy'][1] * 1e3:.1f} ms -> {s['numpy'][1] / s['compiled'][1]:.1f}x (medians, alternated; the same "
          f"end points)")
    print(f"  best RMS residual former {math.sqrt(f_old / n):.2e} m, now {math.sqrt(f_new / n):.2e} m; "
          f"{len(answer.fits)} fits polished, {len(exact)} distinct exact fits answered with the cognates "
          f"(goal >= 2), {answer.starts_at_best}/32 starts in the answer's basin")


if __name__ == "__main__":
    main()
