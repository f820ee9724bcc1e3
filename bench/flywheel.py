"""Exact (Wittenbauer closed form) flywheel sizing against bisection on the simulated equation of motion.

Run: ``.venv/bin/python -m bench.flywheel``. Both find the constant inertia that gives a slider-crank compressor
(3600 samples per turn) the target delta; the baseline bisects on the inertia, simulating the steady motion
(work integral, mean speed by root finding) at every step. Prints both inertias and the speed ratio.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

import synth

SAMPLES = 3600
MEAN_SPEED = 50.0  # [rad/s]
DELTA = 0.02


def _cycle() -> synth.ReducedCycle:
    linkage = synth.Linkage(
        synth.SliderCrank(0.06, 0.24),
        links={
            "crank": synth.MassProps(3.0, (0.02, 0.0), 0.004),
            "rod": synth.MassProps(4.0, (0.08, 0.0), 0.03),
            "slider": synth.MassProps(9.0),
        },
        loads=(synth.ProcessLoad("window", 2500.0, 0.0, math.pi),),
    )
    cycle, _ = synth.cycle_from_reduced(synth.analyse(linkage, MEAN_SPEED, samples=SAMPLES).reduced).balanced()
    return cycle


def _bisection(cycle: synth.ReducedCycle, rel: float = 1e-7) -> float:
    """Constant inertia whose simulated delta is DELTA, by bisection (delta falls as the inertia grows)."""
    lo, hi = 1e-6, 1.0
    while synth.steady_speed(cycle, hi, MEAN_SPEED).delta > DELTA:
        lo, hi = hi, hi * 2
    while hi - lo > rel * hi:
        mid = 0.5 * (lo + hi)
        if synth.steady_speed(cycle, mid, MEAN_SPEED).delta > DELTA:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def _best(fn: Callable[[], float], repeats: int) -> tuple[float, float]:
    times, value = [], 0.0
    for _ in range(repeats):
        t0 = time.perf_counter()
        value = fn()
        times.append(time.perf_counter() - t0)
    return min(times), value


def main() -> None:
    """Time both on the same cycle and print inertias, their agreement and the speed ratio."""
    cycle = _cycle()
    t_exact, j_exact = _best(lambda: synth.exact_constant_inertia(cycle, MEAN_SPEED, DELTA), 20)
    t_bisect, j_bisect = _best(lambda: _bisection(cycle), 3)
    print(f"cycle: {cycle.samples} samples, mean speed {MEAN_SPEED} rad/s, target delta {DELTA}")
    print(f"exact closed form   J_c = {j_exact:.9f} kg·m²  {t_exact * 1e3:9.3f} ms")
    print(f"bisection on EoM    J_c = {j_bisect:.9f} kg·m²  {t_bisect * 1e3:9.3f} ms")
    print(f"relative difference {abs(j_exact / j_bisect - 1):.2e}   speed ratio {t_bisect / t_exact:.0f}x")


if __name__ == "__main__":
    main()
