"""Dimensional synthesis: the crank-rocker family search against differential evolution, path generation with
CasADi/IPOPT against SLSQP with finite differences on the same starts.

Run: ``.venv/bin/python -m bench.synthesis``. Prints medians. Crank-rocker: one request of the seed's fish-tail
variant (psi = 40°, Q = 1.1) through the engine and through the in-process HTTP client, and
``scipy.optimize.differential_evolution`` (the kind of meta-heuristic other synthesis tools use) maximising the
same objective over the same one-parameter family. Path: 10 points on a known coupler curve, 32 Sobol starts,
IPOPT with exact derivatives (program built once, as in a worker) against SLSQP from the same starts; the
engine's per-start solve against its former one (:mod:`bench.path_reference`), alternated in one process; and the
32 starts on one and two pool workers against the goal of 300 ms.
"""

from __future__ import annotations

import math
import statistics
import time
from collections.abc import Callable

import numpy as np
from scipy.optimize import differential_evolution, minimize

import synth
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.synthesis import CrankRockerIn
from synth.synthesis.crank_rocker import _Evaluate
from synth.synthesis.family import feasible
from synth.synthesis.path import _DESIGN, _coupler_points, _program, _starts
from bench.path_reference import reference_starts
from bench._timing import interleaved

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
    result = synth.synthesise_path(spec)
    ipopt = _median(lambda: synth.synthesise_path(spec), 3)
    ipopt_cpu = _median_cpu(lambda: synth.synthesise_path(spec), 3)
    t0 = time.perf_counter()
    slsqp_best = _slsqp(spec, SLSQP_STARTS)
    slsqp = (time.perf_counter() - t0) / SLSQP_STARTS
    print(f"path generation (10 points, 32 starts): IPOPT {ipopt:.2f} s wall, {ipopt_cpu:.2f} s CPU (medians of 3), "
          f"{ipopt / 32 * 1e3:.0f} ms "
          f"per start, largest residual {result.residuals.max():.2e} m, {result.starts_at_best}/32 starts at the "
          f"best")
    print(f"  SLSQP, finite differences, plain sum of squares, first {SLSQP_STARTS} starts: {slsqp * 1e3:.0f} ms per "
          f"start, best RMS residual {math.sqrt(slsqp_best / 10):.2e} m -> IPOPT {slsqp / (ipopt / 32):.1f}x "
          f"faster per start")
    per_start(spec, result)
    parallel_starts(spec, result)


def _design(result: synth.PathResult) -> np.ndarray:
    """Pivot x, y [m], ground angle [rad], crank, coupler, rocker, ground [m], coupler point [m]."""
    fb = result.fourbar
    return np.array([*result.crank_pivot, result.ground_angle, fb.crank, fb.coupler, fb.rocker, fb.ground,
                     *result.coupler_point])


def per_start(spec: synth.PathSpec, result: synth.PathResult) -> None:
    """The engine's starts against the former per-start solve (metres, IPOPT's default step computation,
    arguments converted on every call), all 32 in this process, alternated; the best design must agree."""
    from synth.synthesis.path import path_starts

    everything = range(spec.starts)
    old = reference_starts(spec, everything)
    new = path_starts(spec, everything)
    t = interleaved({"old": lambda: reference_starts(spec, everything), "new": lambda: path_starts(spec, everything)},
                    7)
    design = _design(result)
    gap = np.abs(design - old.best_design)
    gap[2] = abs(math.remainder(design[2] - old.best_design[2], 2 * math.pi))
    scale = float(np.ptp(spec.targets, axis=0).max())
    n = spec.targets.shape[0]
    f_old, f_new = np.nanmin(old.objectives), np.nanmin(new.objectives)
    it_old, it_new = sum(old.iterations), sum(new.iterations)
    print(f"  per start, 32 starts in one process (alternated, min / median): former solve "
          f"{t['old'][0] / 32 * 1e3:.1f} / {t['old'][1] / 32 * 1e3:.1f} ms, {it_old / 32:.1f} IPOPT iterations "
          f"({t['old'][1] / it_old * 1e6:.0f} us each); now {t['new'][0] / 32 * 1e3:.1f} / "
          f"{t['new'][1] / 32 * 1e3:.1f} ms, {it_new / 32:.1f} iterations ({t['new'][1] / it_new * 1e6:.0f} us "
          f"each) -> {t['old'][1] / t['new'][1]:.2f}x")
    assert np.max(gap) < 1e-6, "the former solve found another best design"
    assert math.isclose(f_old, f_new, rel_tol=1e-6, abs_tol=1e-9 / scale**2), "the best objectives differ"
    print(f"  best design the same to {np.max(gap):.1e} (m, rad): best RMS residual former "
          f"{math.sqrt(f_old * scale**2 / n):.2e} m, now {math.sqrt(f_new * scale**2 / n):.2e} m; starts at the "
          f"best {int(np.sum(old.objectives <= f_old + 1e-9 / scale**2 + 1e-6 * f_old))}/32 former, "
          f"{result.starts_at_best}/32 now")


def parallel_starts(spec: synth.PathSpec, serial: synth.PathResult, workers: int = 2) -> None:
    """The same 32 starts dealt to ``workers`` pool workers (as the service runs them), to one worker, and the
    former solve dealt alike, alternated; the best design must be the one of a run of all starts in order."""
    from synth.execution import LocalPoolExecutor, limit_threads
    from synth.synthesis.path import best_path, path_starts, start_chunks

    limit_threads()
    chunks = start_chunks(spec, workers)
    pool = LocalPoolExecutor(workers, preload=["synth.synthesis.path", "bench.path_reference"])
    try:
        def spread() -> synth.PathResult:
            futures = [pool.submit(path_starts, spec, chunk) for chunk in chunks]
            return best_path(spec, [f.result() for f in futures])

        def one() -> synth.PathResult:
            return best_path(spec, [pool.submit(path_starts, spec, tuple(range(spec.starts))).result()])

        def former() -> None:
            for future in [pool.submit(reference_starts, spec, chunk) for chunk in chunks]:
                future.result()

        for _ in range(2):   # every worker builds its IPOPT programs once
            spread(), former()
        t = interleaved({"former": former, "one": one, "spread": spread}, 7)
        same = spread()
    finally:
        pool.shutdown()
    assert np.array_equal(same.residuals, serial.residuals), "the spread starts found another design"
    print(f"  the 32 starts on {workers} workers, {len(chunks)} chunks (alternated, min / median): "
          f"{t['spread'][0] * 1e3:.0f} / {t['spread'][1] * 1e3:.0f} ms (goal <= 300 ms); on 1 worker "
          f"{t['one'][0] * 1e3:.0f} / {t['one'][1] * 1e3:.0f} ms ({t['one'][1] / t['spread'][1]:.2f}x); former "
          f"solve on {workers} workers {t['former'][0] * 1e3:.0f} / {t['former'][1] * 1e3:.0f} ms; same best "
          f"design as one run of all starts in order")


if __name__ == "__main__":
    main()
