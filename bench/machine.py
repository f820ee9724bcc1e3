"""The whole-machine design chain at 360 samples, in-process, against the same work done stage by stage.

Run: ``.venv/bin/python -m bench.machine``. The machine is the README's slider-crank press (one helical stage,
static balancing, flywheel on the lightest shaft). The baseline is what a user of the single capabilities does
for the same machine: analyse, balance, re-analyse, choose the drive, pick teeth, then ``size_flywheel`` with the
motor (every method, each checked by the adaptive shooting of ``steady_speed_motor``). Prints medians [ms], the
ratios, the same design at 3 600 samples against 360, and the chain in compute units timed in the same run
(:func:`bench._timing.compute_unit`): the goals are at most 4 units at 360 samples and at most twice that time at
3 600. Then each stage's share of the chain (cProfile's cumulative time of the stage's function, so shares of
Python-heavy stages read a little high), and the goals as they are judged: ``POST /v1/machines/design`` on the
service's own app and workers in-process (MachineIn's example 0, at 360 and 3 600 samples, each request new to
the service), in units.
"""

from __future__ import annotations

import cProfile
import math
import pstats
import statistics
import time
from collections.abc import Callable

import synth
from bench._timing import compute_unit
from api.translate.machine import machine_from
from mechsynth_client.schemas.machine import PRESS_EXAMPLE, MachineIn

REPEATS = 7


def _median_ms(fn: Callable[[], object], repeats: int = REPEATS) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return 1e3 * statistics.median(times)


def _stage_by_stage(spec: synth.MachineSpec) -> float:
    """The same chain through the single capabilities; returns the flywheel inertia [kg·m²]."""
    linkage, w = spec.linkage, spec.speed
    synth.analyse(linkage, w, samples=spec.samples)
    sc = synth.balance_slider_crank(linkage, w, samples=spec.samples)
    balanced = synth.analyse(linkage.with_counterweights([sc.crank_counterweight]), w, samples=spec.samples)
    cycle = synth.cycle_from_reduced(balanced.reduced)
    power = -cycle.cycle_work / cycle.period * w
    d = spec.drive
    drive = synth.design_drive(power, w, d.stages, synchronous_speed=d.synchronous_speed, inertia=d.inertia)
    u = drive.split.stage_ratios[0]
    stage = d.stages[0]
    teeth = synth.tooth_numbers(u, [synth.Stage(stage.type, u * 0.95, u * 1.05, stage.efficiency,
                                                stage.volume_coefficient, stage.toothed)])
    motor = synth.Motor.from_catalogue(drive.motor, teeth.total_ratio, drive.chain_efficiency)
    result = synth.size_flywheel(cycle, motor.reduced().mean_speed(cycle), spec.delta, motor=motor,
                                 geometry=spec.flywheel.geometry)
    return result.design.flywheel_inertia


#: The chain's stages as the profile names their functions: (label, file suffix, function name).
STAGES = (("analysis", "synth/analysis.py", "analyse"), ("balancing", "synth/machine/chain.py", "_balance"),
          ("drive and teeth", "synth/gearing/drive.py", "design_drive"),
          ("gear sizing for strength", "synth/gearing/sizing.py", "size_stage"),
          ("flywheel", "synth/machine/chain.py", "_flywheel"),
          ("start-up", "synth/machine/startup.py", "simulate_startup"),
          ("run-down", "synth/machine/startup.py", "simulate_rundown"),
          ("steady simulation", "synth/machine/simulate.py", "simulate_machine"))


def _shares(spec: synth.MachineSpec) -> list[tuple[str, float]]:
    """Each stage's share of one chain run, from cProfile's cumulative times (a stage's first call only counts
    where stages nest: the steady simulation also runs inside start-up and run-down)."""
    profile = cProfile.Profile()
    profile.enable()
    synth.design_machine(spec)
    profile.disable()
    stats = pstats.Stats(profile).stats  # type: ignore[attr-defined]
    total = max((v[3] for (f, _, name), v in stats.items() if f.endswith("chain.py") and name == "design_machine"),
                default=0.0)
    out = []
    for label, suffix, fn in STAGES:
        cum = sum(v[3] for (f, _, name), v in stats.items() if f.endswith(suffix) and name == fn)
        out.append((label, cum / total if total else 0.0))
    return out


def _sizing_ms(spec: synth.MachineSpec) -> float:
    """Median time per design the chain spends sizing its gears for strength [ms] (its calls of size_stage)."""
    from unittest import mock

    from synth.machine import chain

    real = chain.size_stage
    spent: list[float] = []

    def timed(*args: object, **kwargs: object) -> object:
        t0 = time.perf_counter()
        try:
            return real(*args, **kwargs)  # type: ignore[arg-type]
        finally:
            spent.append(time.perf_counter() - t0)

    per_design = []
    with mock.patch.object(chain, "size_stage", timed):
        for _ in range(REPEATS):
            spent.clear()
            synth.design_machine(spec)
            per_design.append(sum(spent))
    return 1e3 * statistics.median(per_design)


def _service(unit_s: float) -> None:
    """The goals as judged: the service's own app and workers in-process, POST /v1/machines/design."""
    from fastapi.testclient import TestClient

    from api.app import app

    body = dict(MachineIn.model_json_schema()["examples"][0], samples=360)
    runs = iter(range(1, 1000))
    with TestClient(app, base_url="http://127.0.0.1") as client:
        def post(samples: int) -> float:
            # delta a part in 1e9 apart each time: the web process holds the designs it just made, and a request
            # it holds is answered without the chain this measures
            request = dict(body, samples=samples, delta=body["delta"] * (1 + 1e-9 * next(runs)))
            t0 = time.perf_counter()
            r = client.post("/v1/machines/design", json=request)
            assert r.status_code == 200, r.text[:300]
            return time.perf_counter() - t0

        post(360)
        post(3600)
        t360 = statistics.median(post(360) for _ in range(5))
        t3600 = statistics.median(post(3600) for _ in range(3))
    print(f"service POST /v1/machines/design: 360 samples {t360 / unit_s:.1f} units (goal <= 4), "
          f"3 600/360 {t3600 / t360:.2f}x (goal <= 2)   ({1e3 * t360:.0f} and {1e3 * t3600:.0f} ms here)")


def main() -> None:
    """Time the chain and the stage-by-stage baseline on the same machine; print medians and the ratio."""
    spec = machine_from(MachineIn.model_validate(PRESS_EXAMPLE), max_stages=6)
    design = synth.design_machine(spec)
    t_chain = _median_ms(lambda: synth.design_machine(spec))
    t_base = _median_ms(lambda: _stage_by_stage(spec), repeats=3)
    red = design.balanced.reduced
    cycle = synth.MachineCycle(red.phi, red.inertia, red.inertia_slope, red.load_torque)
    j_total = design.flywheel.constant_inertia + design.flywheel_inertia
    t_sim = _median_ms(lambda: synth.simulate_machine(cycle, j_total, design.motor))
    reduced_cycle = synth.cycle_from_reduced(red)
    t_shoot = _median_ms(lambda: synth.steady_speed_motor(reduced_cycle, j_total, design.motor.reduced()), 3)
    print(f"machine: slider-crank press, {spec.samples} samples, {spec.balancing.mode} balancing, "
          f"motor {design.drive.motor.name}, flywheel {design.flywheel_inertia:.4g} kg·m², "
          f"simulated delta {design.motion.delta:.6g} (target {spec.delta})")
    print(f"design_machine (whole chain)        median {t_chain:8.1f} ms")
    print(f"stage by stage (single capabilities) median {t_base:8.1f} ms   ratio {t_base / t_chain:5.1f}x")
    print(f"simulate_machine (RK4 + Newton)     median {t_sim:8.1f} ms")
    print(f"steady_speed_motor (solve_ivp)      median {t_shoot:8.1f} ms   ratio {t_shoot / t_sim:5.1f}x")
    fine = machine_from(MachineIn.model_validate({**PRESS_EXAMPLE, "samples": 3600}), max_stages=6)
    synth.design_machine(fine)
    t_fine = _median_ms(lambda: synth.design_machine(fine), repeats=3)
    t_sizing = _sizing_ms(spec)
    unit_ms = 1e3 * compute_unit()
    print(f"design_machine at 3 600 samples     median {t_fine:8.1f} ms   ratio to 360 {t_fine / t_chain:5.2f}x "
          f"(goal <= 2)")
    print(f"compute unit {unit_ms:.1f} ms: the chain at 360 samples {t_chain / unit_ms:.1f} units (goal <= 4), "
          f"stage by stage {t_base / unit_ms:.1f} units   (speed {spec.speed / (math.pi / 30):.0f} rpm)")
    print(f"gear sizing for strength in the chain: {t_sizing:.1f} ms a design, {t_sizing / unit_ms:.2f} units "
          f"({100 * t_sizing / t_chain:.0f} % of the chain)")
    print("shares of the chain at 360 samples (cProfile, cumulative): " + ", ".join(
        f"{label} {100 * share:.0f} %" for label, share in _shares(spec)))
    _service(min(unit_ms / 1e3, compute_unit()))


if __name__ == "__main__":
    main()
