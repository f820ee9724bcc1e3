"""Drive design benchmarks, each against a baseline run in the same process (medians).

1. Exact tooth search for a two-stage train with 12..60 teeth per wheel against plain enumeration of all
   49^4 wheel combinations (vectorised NumPy over the full grid, every rule applied per combination).
2. Three-stage tooth search, 12..36 against the engine's own plain enumeration, and 12..100 / 12..200 (2441^3
   and 10293^3 candidate combinations after deduplication), with the peak memory the search allocates.
3. The split's geometric programs (log space, Clarabel) against scipy.optimize.minimize (SLSQP in log-ratios
   with the product as an equality) on the same model.
4. ISO 6336 rating of a 3600-sample load spectrum in one vectorised call (stresses, Miner sums, safety factors)
   against rating the samples one by one with the single-torque rating and summing Miner by hand.
5. Sizing a stage for strength (ISO 54 modules, a bisection on the face width per module) against a plain grid
   of every module and 200 face widths; the grid's best must not be lighter.

6. The press and four-bar machines of the manual designed with their gears sized from the cyclic shaft torque,
   against the same design without sizing; the binding constraint per stage.

``python -m bench.gearing strength`` runs 4 to 6 only.
"""

from __future__ import annotations

import math
import statistics
import time
import tracemalloc
from collections.abc import Callable
from typing import Any

import numpy as np
from scipy.optimize import minimize

import synth
from synth.gearing.teeth import TIE, pairs_admissible
from api.translate.machine import machine_from


def _best_of(fn: Callable[[], Any], repeat: int) -> tuple[float, Any]:
    """Median wall time of ``repeat`` calls [s] and the last call's value."""
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def bench_teeth_three() -> None:
    stages = synth.make_stages(3, max_stages=6)
    print("\ntooth search, 3 stages (spur 1..6.3), closest ratio unless a tolerance is given")
    print(f"{'teeth':>8} {'target':>9} {'tol':>6} {'search ms':>10} {'peak MB':>8} {'baseline ms':>12} "
          f"{'ratio':>7}  {'error':>9} {'teeth':>5}")
    for top, target, tol in ((36, 7.3, None), (36, 5.0, 1e-3), (100, 57.3, None), (100, 123.4567, None),
                             (100, 40.0, 1e-3), (200, 57.3, None), (200, 123.4567, None), (200, 40.0, 1e-3)):
        rules = synth.ToothRules(min_teeth=12, max_teeth=top)
        t_search, res = _best_of(lambda: synth.tooth_numbers(target, stages, rules, tol, check_limit=0), 5)
        tracemalloc.start()
        synth.tooth_numbers(target, stages, rules, tol, check_limit=0)
        peak = tracemalloc.get_traced_memory()[1] / 1e6
        tracemalloc.stop()
        base = "-"
        ratio = "-"
        if top <= 36:
            t_base, ref = _best_of(lambda: synth.enumerate_tooth_numbers(target, stages, rules, tol), 2)
            assert ref is not None and abs(ref[0] - res.ratio_error) <= TIE and ref[1] == res.total_teeth
            base, ratio = f"{1e3 * t_base:.1f}", f"{t_base / t_search:.0f}x"
        print(f"{'12..' + str(top):>8} {target:9.4f} {tol or '-':>6} {1e3 * t_search:10.1f} {peak:8.1f} "
              f"{base:>12} {ratio:>7}  {res.ratio_error:9.2e} {res.total_teeth:5d}")


def plain_enumeration(target: float, stages: tuple[synth.Stage, ...], rules: synth.ToothRules,
                      tolerance: float | None) -> tuple[float, int]:
    """Every (z1, z2, z3, z4) in [min, max]^4, admissibility and objective evaluated per combination."""
    assert rules.min_teeth is not None
    z = np.arange(rules.min_teeth, rules.max_teeth + 1, dtype=np.int64)
    z1, z2, z3, z4 = (g.ravel() for g in np.meshgrid(z, z, z, z, indexing="ij"))
    ok = pairs_admissible(z1, z2, stages[0], rules) & pairs_admissible(z3, z4, stages[1], rules)
    err = np.abs((z2 / z1) * (z4 / z3) / target - 1)
    teeth = z1 + z2 + z3 + z4
    if tolerance is None:
        best = err[ok].min()
        pick = ok & (err <= best + TIE)
        return float(err[pick][np.argmin(teeth[pick])]), int(teeth[pick].min())
    pick = ok & (err <= tolerance)
    fewest = teeth[pick].min()
    return float(err[pick & (teeth == fewest)].min()), int(fewest)


def bench_teeth() -> None:
    stages = synth.make_stages(2, max_stages=6)
    rules = synth.ToothRules(min_teeth=12, max_teeth=60)
    print("tooth search, 2 stages, 12..60 teeth per wheel (49^4 = 5.76e6 combinations)")
    print(f"{'target':>8} {'tol':>6} {'search ms':>10} {'plain ms':>10} {'speed-up':>9}  {'error':>10} {'teeth':>5}  agree")
    for target, tol in ((7.3, None), (9.87, None), (12.0, None), (13.5, None), (11.11, 0.01), (6.66, 0.002)):
        t_search, res = _best_of(lambda: synth.tooth_numbers(target, stages, rules, tol, check_limit=0), 5)
        t_plain, ref = _best_of(lambda: plain_enumeration(target, stages, rules, tol), 2)
        agree = abs(ref[0] - res.ratio_error) <= TIE and ref[1] == res.total_teeth
        tol_s = "-" if tol is None else f"{tol:g}"
        print(f"{target:8.3f} {tol_s:>6} {1e3 * t_search:10.2f} {1e3 * t_plain:10.1f} {t_plain / t_search:8.0f}x"
              f"  {res.ratio_error:10.2e} {res.total_teeth:5d}  {agree}")


def _scipy_split(total: float, stages: tuple[synth.Stage, ...], objective: str,
                 model: synth.InertiaModel) -> tuple[np.ndarray, float]:
    def f(x: np.ndarray) -> float:
        u = np.exp(x)
        if objective == "min_volume":
            v = synth.gear_volume(u, stages)
            assert v is not None
            return v
        return synth.reduced_train_inertia(u, model)

    n = len(stages)
    bounds = [(math.log(s.ratio_min), math.log(s.ratio_max)) for s in stages]
    x0 = np.full(n, math.log(total) / n)
    res = minimize(f, x0, method="SLSQP", bounds=bounds, options={"ftol": 1e-14, "maxiter": 500},
                   constraints=[{"type": "eq", "fun": lambda x: np.sum(x) - math.log(total)}])
    return np.exp(res.x), float(res.fun)


def bench_split() -> None:
    print("\nratio split: geometric program (log space, Clarabel) vs scipy.optimize.minimize (SLSQP), medians")
    print(f"{'case':>26} {'GP ms':>7} {'scipy ms':>9} {'speed-up':>9} {'rel. objective diff':>20}  ratios GP | scipy")
    model = synth.InertiaModel(pinion_inertia=1e-3, load_inertia=0.5)
    cases = [
        ("min_inertia, 2 stages U=12", 12.0, synth.make_stages(2, max_stages=6), "min_inertia"),
        ("min_inertia, 3 stages U=60", 60.0, synth.make_stages(3, max_stages=6), "min_inertia"),
        ("min_volume, 3 stages U=60", 60.0, synth.make_stages(["helical", "helical", "spur"], max_stages=6),
         "min_volume"),
        ("min_inertia, 4 stages U=300", 300.0, synth.make_stages(4, max_stages=6), "min_inertia"),
    ]
    for name, total, stages, objective in cases:
        t_gp, gp = _best_of(lambda: synth.split_ratio(total, stages, objective, inertia=model), 21)
        t_sp, (u_sp, f_sp) = _best_of(lambda: _scipy_split(total, stages, objective, model), 21)
        diff = (f_sp - gp.objective_value) / gp.objective_value
        print(f"{name:>26} {1e3 * t_gp:7.2f} {1e3 * t_sp:9.2f} {t_sp / t_gp:8.1f}x {diff:20.2e}  "
              f"{np.round(gp.stage_ratios, 4).tolist()} | {np.round(u_sp, 4).tolist()}")


TR_SPEC = synth.GearPairSpec(17, 103, 8e-3, 100e-3, math.radians(15.8), (0.145, 0.0), 500e-3, 5,
                             ("case_hardened_MQ", "case_hardened_MQ"), 320e-6, 1.0e-6, 10e-6, 70e-6, None,
                             synth.BasicRack(1.0, 1.4, 0.39))
TR_DUTY = synth.Duty(1.0, 50_000.0, 1.0, 1.0)


def _loop_spectrum(torque: np.ndarray, speed: float) -> float:
    """Baseline: one rating per sample, Miner's sum on the pinion's contact S-N curve by hand."""
    from synth.gearing.materials import contact_life_curve, cycles_to_failure
    damage = 0.0
    for t in torque:
        r = synth.rate_pair(TR_SPEC, float(t), speed, TR_DUTY)
        ref = r.contact_limit[0] / r.factor("Z_NT").pinion
        knots = contact_life_curve(r.materials[0])
        damage += r.load_cycles[0] / torque.size / float(cycles_to_failure(knots, np.array([r.contact_stress[0] / ref]))[0])
    return damage


def bench_rating() -> None:
    speed = 360 * math.pi / 30
    torque = 9000.0 * (1 + 0.3 * np.sin(np.linspace(0, 2 * np.pi, 3600, endpoint=False)))
    print("\nISO 6336 rating on a load spectrum (ISO/TR 6336-30 example 1 pair, 3600 samples)")
    t_one, single = _best_of(lambda: synth.rate_pair(TR_SPEC, 9000.0, speed, TR_DUTY), 21)
    t_vec, spec = _best_of(lambda: synth.rate_spectrum(TR_SPEC, torque, speed, TR_DUTY), 7)
    t_loop, damage = _best_of(lambda: _loop_spectrum(torque, speed), 3)
    assert abs(damage / spec.damage_contact[0] - 1) < 1e-9
    print(f"  single torque {1e3 * t_one:.2f} ms; spectrum vectorised {1e3 * t_vec:.1f} ms (incl. both Miner "
          f"safety bisections), per-sample loop {1e3 * t_loop:.0f} ms (damage only): {t_loop / t_vec:.0f}x")
    print(f"  S_H pinion {single.safety_contact[0]:.4f} at 9000 N·m; on the spectrum {spec.safety_contact[0]:.4f}, "
          f"damage {spec.damage_contact[0]:.3f}, equivalent torque {spec.equivalent_torque_contact[0]:.0f} N·m")


def _grid_sizing(ratio: float, load: synth.StageLoad, rules: synth.SizingRules) -> float:
    """Baseline: every module of the series against 200 face widths between the ratio limits."""
    best = math.inf
    z1 = rules.pinion_teeth
    z2 = round(ratio * z1)
    for m in synth.module_series(rules.series):
        d1, d2 = z1 * m, z2 * m
        for b in np.linspace(rules.min_face_width_ratio * d1, rules.max_face_width_ratio * d1, 200):
            spec = synth.GearPairSpec(z1, z2, m, float(b), 0.0, (0.0, 0.0), None, rules.accuracy_grade,
                                      rules.materials, max_face_width_ratio=rules.max_face_width_ratio * 1.000001)
            r = synth.rate_pair(spec, float(load.torque), load.speed, rules.duty)
            if (min(r.safety_contact) >= rules.duty.min_safety_contact
                    and min(r.safety_root) >= rules.duty.min_safety_root):
                best = min(best, 7830 * math.pi / 4 * float(b) * (d1**2 + d2**2))
                break
    return best


def bench_sizing() -> None:
    rules = synth.SizingRules(materials=("case_hardened_MQ", "case_hardened_MQ"),
                              duty=synth.Duty(1.25, 20_000.0, 1.1, 1.5))
    load = synth.StageLoad(400.0, 1450 * math.pi / 30)
    print("\nsizing one stage for strength (u = 4, 400 N·m at 1450 rpm, case-hardened)")
    t_size, sized = _best_of(lambda: synth.size_stage(4.0, load, rules), 5)
    t_grid, best = _best_of(lambda: _grid_sizing(4.0, load, rules), 1)
    assert sized.mass <= best * (1 + 1e-9)
    print(f"  enumeration + bisection {1e3 * t_size:.0f} ms, module {sized.module * 1e3:g} mm, b "
          f"{sized.face_width * 1e3:.2f} mm, {sized.mass:.3f} kg, binding {sized.binding}; plain grid "
          f"{1e3 * t_grid:.0f} ms, {best:.3f} kg: {t_grid / t_size:.0f}x")
    torque = 400.0 * (0.6 + 0.4 * np.sin(np.linspace(0, 2 * np.pi, 360, endpoint=False)))
    t_spec, sized_s = _best_of(lambda: synth.size_stage(4.0, synth.StageLoad(torque, load.speed), rules), 3)
    print(f"  on a 360-sample spectrum (peak 400 N·m): {1e3 * t_spec:.0f} ms, module {sized_s.module * 1e3:g} mm, "
          f"b {sized_s.face_width * 1e3:.2f} mm, {sized_s.mass:.3f} kg, binding {sized_s.binding}")


def _press_loads(samples: int) -> list[tuple[Any, ...]]:
    """The arguments of the README press's calls of size_stage in its design at ``samples`` samples."""
    from unittest import mock

    from mechsynth_client.schemas.machine import PRESS_EXAMPLE, MachineIn
    from synth.machine import chain

    with mock.patch.object(chain, "size_stage", wraps=chain.size_stage) as sizing:
        synth.design_machine(machine_from(MachineIn.model_validate({**PRESS_EXAMPLE, "samples": samples}), 6))
    return [(c.args, c.kwargs) for c in sizing.call_args_list]


def bench_press_sizing() -> None:
    from bench._timing import compute_unit
    print("\nthe README press's stage sized for strength on its cyclic torque (as its design sizes it)")
    for samples in (360, 3600):
        (args, kwargs), = _press_loads(samples)
        t, sized = _best_of(lambda: synth.size_stage(*args, **kwargs), 7)
        unit = compute_unit()
        print(f"  {samples:5d} samples ({args[1].torque.size} torque samples): {1e3 * t:.1f} ms = {t / unit:.2f} "
              f"compute units ({1e3 * unit:.1f} ms); module {sized.module * 1e3:g} mm, b "
              f"{sized.face_width * 1e3:.4f} mm, S_H {min(sized.safety_contact):.6f}, S_F "
              f"{min(sized.safety_root):.6f}, binding {sized.binding}, {sized.modules_examined} modules examined")


def bench_machines() -> None:
    from mechsynth_client.schemas.machine import FOURBAR_MACHINE_EXAMPLE, PRESS_EXAMPLE, MachineIn
    print("\nmachines of the manual: gears sized from the cyclic torque of the simulated steady motion")
    for name, body in (("press", PRESS_EXAMPLE), ("four-bar", FOURBAR_MACHINE_EXAMPLE)):
        m = MachineIn.model_validate(body)
        off = m.model_copy(update={"drive": m.drive.model_copy(update={"size_gears": False})})
        t_on, d = _best_of(lambda: synth.design_machine(machine_from(m, 12)), 3)
        t_off, _ = _best_of(lambda: synth.design_machine(machine_from(off, 12)), 3)
        assert d.gears is not None
        stages = "; ".join(
            f"stage {g.stage + 1}: m {g.module * 1e3:g} mm, z {g.pinion_teeth}:{g.gear_teeth}, b "
            f"{g.face_width * 1e3:.1f} mm, a {g.centre_distance * 1e3:.1f} mm, S_H {min(g.safety_contact):.3f}, "
            f"S_F {min(g.safety_root):.2f}, binding {g.binding}" for g in d.gears.stages if g is not None)
        print(f"  {name:>8}: {1e3 * t_on:.0f} ms with sizing, {1e3 * t_off:.0f} ms without "
              f"({t_on / t_off:.1f}x); {stages}")


def main(only: str | None = None) -> None:
    """Tooth searches, ratio splits, ratings and sizing against their baselines."""
    if only != "strength":
        bench_teeth()
        bench_teeth_three()
        bench_split()
    bench_rating()
    bench_sizing()
    bench_press_sizing()
    bench_machines()


if __name__ == "__main__":
    import sys
    main(sys.argv[1] if len(sys.argv) > 1 else None)
