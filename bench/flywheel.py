"""Flywheel benchmarks against baselines in the same run.

Run: ``.venv/bin/python -m bench.flywheel``.

1. Exact (Wittenbauer closed form) sizing against bisection on the simulated equation of motion: both find the
   constant inertia that gives a slider-crank compressor (3600 samples per turn) the target delta; the baseline
   bisects on the inertia, simulating the steady motion (work integral, mean speed by root finding) each step.
2. The motor check (periodic speed under a motor characteristic) against scipy's solve_ivp with Newton shooting
   on the initial energy (a Python right-hand side), on the same cycle and inertia; then the whole motor
   flywheel request (360 samples) in-process.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

import synth
from api.translate.linkage import linkage_from
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.flywheel import FlywheelIn
from bench._timing import asgi_medians, median_of

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


def shooting_delta(cycle: synth.ReducedCycle, constant_inertia: float, motor: Any) -> float:
    """The motor check as solve_ivp (RK45, rtol 1e-9) with Newton shooting on the initial energy: delta [-]."""
    nodes, inertia_n, torque_n = cycle.closed()
    total_n = inertia_n + constant_inertia

    def rhs(phi: float, y: np.ndarray) -> np.ndarray:
        j = np.interp(phi, nodes, total_n)
        w = np.sqrt(max(2 * y[0] / j, 1e-300))
        load = np.interp(phi, nodes, torque_n)
        return np.array([load + motor.slope * (motor.no_load_speed - w), -motor.slope / (j * w) * y[1]])

    def run(e0: float, dense: bool = False) -> Any:
        return solve_ivp(rhs, (nodes[0], nodes[-1]), [e0, 1.0], rtol=1e-9, atol=[1e-11 * e0, 1e-11],
                         dense_output=dense)

    e0 = 0.5 * float(total_n[0]) * motor.mean_speed(cycle) ** 2
    for _ in range(50):
        sol = run(e0)
        step = -(float(sol.y[0, -1]) - e0) / (float(sol.y[1, -1]) - 1.0)
        e0 += step
        if abs(step) <= 1e-6 * e0:
            break
    phi = cycle.dense(20_000)
    energy = run(e0, dense=True).sol(phi)[0]
    j, _, _ = cycle.evaluate(phi)
    return synth.speed_fluctuation(np.sqrt(2 * energy / (j + constant_inertia)))[2]


MOTOR = {"synchronous_speed_rpm": 1500, "rated_speed_rpm": 1440, "rated_torque_Nm": 60, "gear_ratio": 3,
         "efficiency": 0.95, "rotor_inertia_kgm2": 0.02}


def bench_motor() -> None:
    body = FlywheelIn.model_validate({
        "mechanism": {"type": "slider_crank", "crank_length_m": 0.06, "rod_length_m": 0.24,
                      "links": {"crank": {"mass_kg": 3, "com_m": [0.02, 0], "inertia_kgm2": 0.004},
                                "rod": {"mass_kg": 4, "com_m": [0.08, 0], "inertia_kgm2": 0.03},
                                "slider": {"mass_kg": 9}}},
        "loads": [{"type": "window", "force_N": 2500, "start_deg": 0, "end_deg": 180}],
        "samples": 360, "mean_speed_rpm": 495, "delta": 0.04, "motor": MOTOR})
    motor = synth.Motor(synchronous_speed=1500 * math.pi / 30, rated_speed=1440 * math.pi / 30, rated_torque=60.0,
                        gear_ratio=3.0, efficiency=0.95, rotor_inertia=0.02).reduced()
    linkage = linkage_from(body)
    cycle = synth.cycle_from_reduced(synth.analyse(linkage, motor.mean_speed(synth.cycle_from_reduced(
        synth.analyse(linkage, 50.0, samples=360).reduced)), samples=360).reduced)
    inertia = 0.5 + motor.inertia
    ours = synth.steady_speed_motor(cycle, inertia, motor).delta
    theirs = shooting_delta(cycle, inertia, motor)
    t_ours = median_of(lambda: synth.steady_speed_motor(cycle, inertia, motor), 9)
    t_theirs = median_of(lambda: shooting_delta(cycle, inertia, motor), 3)
    print(f"\nmotor check, {cycle.samples}-sample compressor cycle, J_c = {inertia:.3f} kg·m², medians")
    print(f"  periodic trapezoid + Newton + Richardson: delta {ours:.9f} in {t_ours * 1e3:7.2f} ms")
    print(f"  solve_ivp + Newton shooting:              delta {theirs:.9f} in {t_theirs * 1e3:7.2f} ms")
    print(f"  delta difference {abs(ours - theirs):.1e}, speed-up {t_theirs / t_ours:.1f}x")
    client = SynthClient.in_process()
    payload = body.model_dump(mode="json", exclude_none=True)
    t_req = median_of(lambda: client.http.post("/v1/flywheel", json=payload).raise_for_status(), 9)
    t_asgi = asgi_medians({"flywheel": ("POST", "/v1/flywheel", payload)}, 9)["flywheel"]
    print(f"POST /v1/flywheel with a motor, 360 samples, in-process (raw POST): over ASGI from an event loop "
          f"{t_asgi * 1e3:.1f} ms, through the synchronous client {t_req * 1e3:.1f} ms")


def main() -> None:
    """Time both on the same cycle and print inertias, their agreement and the speed ratio."""
    cycle = _cycle()
    t_exact, j_exact = _best(lambda: synth.exact_constant_inertia(cycle, MEAN_SPEED, DELTA), 20)
    t_bisect, j_bisect = _best(lambda: _bisection(cycle), 3)
    print(f"cycle: {cycle.samples} samples, mean speed {MEAN_SPEED} rad/s, target delta {DELTA}")
    print(f"exact closed form   J_c = {j_exact:.9f} kg·m²  {t_exact * 1e3:9.3f} ms")
    print(f"bisection on EoM    J_c = {j_bisect:.9f} kg·m²  {t_bisect * 1e3:9.3f} ms")
    print(f"relative difference {abs(j_exact / j_bisect - 1):.2e}   speed ratio {t_bisect / t_exact:.0f}x")
    bench_motor()


if __name__ == "__main__":
    main()
