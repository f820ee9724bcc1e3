"""The whole-machine optimisations against the design chain alone, on three functions, in compute units.

Run: ``.venv/bin/python -m bench.optimise``. The machines are the optimisation page's: the crank-rocker of the
README (static balancing, least added mass), the slider-crank press (motor power and RMS shaking force alike)
and the six-bar press with two free dimensions (least machine mass, ``/v1/machines/optimise-linkage``). Every
time is printed in units of the machine's compute unit (``bench._timing.compute_unit``, a fixed numpy-and-JSON
task timed in the same run) or as a ratio, since machines differ 2-3x in speed and a busy one more. For each
function: one chain run (``/v1/machines/design`` on the chain's member, or on the six-bar as drawn), the engine's
optimisation in one process and the endpoint on a two-worker pool (also in chain runs), and the objective before
and after; for the crank-rocker also the best member of the densest evenly spread scan, the endpoint's stages
timed in CPU seconds with the longest path through them on two workers and each stage's share of it, and one
steady member of the scan with the shares of its parts; for the six-bar also the engine's whole optimisation as
one task on the same pool (as the endpoint ran before it spread its stages) and its stages in CPU time likewise.
The load average is printed first. Completes in a minute or two.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import synth
from bench._timing import best_of, compute_unit, median_of
from api.translate.optimise import linkage_optimise_from, machine_optimise_from
from mechsynth_client import SynthClient
from mechsynth_client.schemas.optimise import (
    CRANK_ROCKER_OPTIMISE_EXAMPLE,
    SIX_BAR_OPTIMISE_EXAMPLE,
    SLIDER_CRANK_OPTIMISE_EXAMPLE,
    LinkageOptimiseIn,
    MachineOptimiseIn,
)
from synth.machine import optimise as opt
from synth.machine.optimise import OBJECTIVES, normalisers, score
from api.execution.optimise import member_tasks
from synth.machine import optimise_linkage as lo
from synth.machine.optimise_linkage import optimise_linkage


def _once(fn: Callable[[], Any]) -> tuple[Any, float]:
    t0 = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t0


def _line(name: str, t_chain: float, t_engine: float, t_endpoint: float, before: str, after: str,
          unit: float) -> None:
    print(f"{name:13s} chain {t_chain / unit:5.1f} units | engine {t_engine / unit:6.1f} units "
          f"({t_engine / t_chain:5.1f} chains) | endpoint, 2 workers {t_endpoint / unit:6.1f} units "
          f"({t_endpoint / t_chain:5.1f} chains; {t_endpoint:.2f} s here) | {before} -> {after}")


def main() -> None:
    """Time the chain alone, the engine in one process and the endpoint on a two-worker pool, per function."""
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    unit = compute_unit()
    family = {"crank-rocker": (CRANK_ROCKER_OPTIMISE_EXAMPLE, "added_mass"),
              "slider-crank": (SLIDER_CRANK_OPTIMISE_EXAMPLE, None)}
    engine: dict[str, tuple[Any, float, float, MachineOptimiseIn]] = {}
    for name, (example, _) in family.items():
        body = MachineOptimiseIn.model_validate(example)
        spec = machine_optimise_from(body, max_stages=6)
        result, t_engine = _once(lambda spec=spec: synth.optimise_machine(spec))  # type: ignore[misc]
        chain_machine = spec.machine(result.chain_linkage)
        t_chain = best_of(lambda m=chain_machine: synth.design_machine(m), 2)  # type: ignore[misc]
        engine[name] = (result, t_chain, t_engine, body)
    six = LinkageOptimiseIn.model_validate(SIX_BAR_OPTIMISE_EXAMPLE)
    six_spec = linkage_optimise_from(six, 6)
    six_result, t_six_engine = _once(lambda: optimise_linkage(six_spec))
    t_six_chain = best_of(lambda: synth.design_machine(six_spec.machine), 2)
    os.environ["SYNTH_WORKERS"] = "2"
    with SynthClient.in_process("pool") as client:
        # the workers start and warm (as the service's start waits for them) before anything is timed
        client.http.app.state.solvers.start()  # type: ignore[attr-defined]
        client.optimise_machine(engine["crank-rocker"][3])
        endpoint = {name: _once(lambda b=body: client.optimise_machine(b))[1]  # type: ignore[misc]
                    for name, (_, _, _, body) in engine.items()}
        six_spread, t_six_endpoint = _once(lambda: client.optimise_linkage(six))
        # as the endpoint ran before its stages were spread: the engine's whole optimisation as one task
        executor = client.http.app.state.solvers.executor  # type: ignore[attr-defined]
        six_one_task, t_six_one_task = _once(lambda: executor.submit(optimise_linkage, six_spec).result())
    unit = min(unit, compute_unit())
    print(f"compute unit {unit * 1e3:.1f} ms (a fixed numpy-and-JSON task, bench._timing.compute_unit, timed in "
          "this run); every figure below in units of it")
    for name, (result, t_chain, t_engine, body) in engine.items():
        spec = result.spec
        norm = normalisers(result.members, result.certificate.scan.chain_parameter)
        before = f"score {result.chain_score:.4f}" if result.chain_score is not None else "chain infeasible"
        after = f"score {result.score:.4f}"
        if name == "crank-rocker":
            k = OBJECTIVES.index("added_mass")
            scanned = [m for m in result.members if m.stage == "scan" and m.feasible and m.values is not None]
            best = min(scanned, key=lambda m: score(spec, m.values, norm))
            assert result.chain.values is not None and best.values is not None
            before = (f"added mass {result.chain.values[k]:.4f} kg (best of the {len(scanned)}-member scan "
                      f"{best.values[k]:.4f} kg)")
            after = f"{result.values[k]:.4f} kg"
        _line(name, t_chain, t_engine, endpoint[name], before, after, unit)
    own = six_result.members[0]
    before = (f"machine mass as drawn {own.values[3]:.3f} kg" if own.values is not None
              else "as drawn: infeasible")
    _line("six-bar", t_six_chain, t_six_engine, t_six_endpoint, before, f"{six_result.values[3]:.3f} kg "
          f"({six_result.certificate.sampled} sampled, {six_result.certificate.refine_runs} refinement runs)", unit)
    same = (six_spread.values["machine_mass"] == six_result.values[3] == six_one_task.values[3]
            and [f.value_m for f in six_spread.free] == list(six_result.x))
    print(f"{'':13s} endpoint before: one task {t_six_one_task / unit:6.1f} units; after: its stages spread over "
          f"2 workers {t_six_endpoint / unit:6.1f} units ({t_six_one_task / t_six_endpoint:.1f} x); "
          f"{'the same answer' if same else 'ANSWERS DIFFER'}")

    path = critical_path(engine["crank-rocker"][3])
    print(f"{'':13s} critical path {path['path'] / unit:.1f} units: "
          + ", ".join(f"{k} {100 * v / path['path']:.0f} %" for k, v in path.items() if k != "path"))
    member_costs(engine["crank-rocker"][3], unit)
    six_bar_critical_path(six, unit)


def _cpu(fn: Callable[[], Any]) -> tuple[Any, float]:
    t0 = time.process_time()
    out = fn()
    return out, time.process_time() - t0


def _two_workers(times: list[float]) -> float:
    """The time two workers take for tasks handed out in order, each to the first free worker."""
    busy = [0.0, 0.0]
    for t in times:
        busy[busy.index(min(busy))] += t
    return max(busy)


def _cells_on_two_workers(cells: list[tuple[float, list[float]]]) -> float:
    """The time two workers take for a round of cells as the endpoint runs them: the cells' walks first, each on
    the first free worker; each cell's plateaus' searches once its walk is done, each taken by the first free
    worker in the order they were handed out."""
    free = [0.0, 0.0]
    searches: list[tuple[float, float]] = []
    for walk, timed in cells:
        w = free.index(min(free))
        free[w] += walk
        searches += [(free[w], t) for t in timed]
    for found_at, t in sorted(searches, key=lambda s: s[0]):
        w = free.index(min(free))
        free[w] = max(free[w], found_at) + t
    return max(free)


def critical_path(body: MachineOptimiseIn) -> dict[str, float]:
    """The endpoint's stages on the crank-rocker run in this process, each timed in CPU seconds (which a busy
    machine stretches far less than wall time), and the longest path through them on two workers."""
    spec = machine_optimise_from(body, max_stages=6)
    scan, t_scan = _cpu(lambda: opt.scan_family(spec))
    shares = [_cpu(lambda s=s: opt.scan_members(spec, s, scan.chain_parameter))  # type: ignore[misc]
              for s in member_tasks(scan.candidates, scan.chain_parameter)]
    by = {m.parameter: m for part, _ in shares for m in part}
    members = tuple(by[u] for u in scan.candidates)
    t_members = _two_workers([t for _, t in shares])
    t_scan_cpu = sum(t for _, t in shares)
    while todo := opt.members_to_design(spec, scan, members):
        round_ = [_cpu(lambda u=u: opt.design_members(spec, [u])) for u in todo]  # type: ignore[misc]
        members = opt.with_designed(members, (m for part, _ in round_ for m in part))
        t_members += _two_workers([t for _, t in round_])
        t_scan_cpu += sum(t for _, t in round_)
    walks: list[Any] = []
    seen: list[Any] = []
    cut: list[float] = []
    searched: list[float] = []
    t_cells = 0.0
    while todo := opt.next_cells(spec, scan, members + opt.designed(seen), [(r.lo, r.hi) for r, _ in walks]):
        round_: list[tuple[float, list[float]]] = []
        for r in todo:
            walk, t_walk = _cpu(lambda r=r: opt.cell_plateaus(spec, members, r))  # type: ignore[misc]
            timed = [_cpu(lambda p=p: opt.search_plateau(spec, scan, members, p))  # type: ignore[misc]
                     for p in walk[1]]
            walks.append(walk)
            seen += [m for m, _ in timed]
            round_.append((t_walk, [t for _, t in timed]))
        cut += [t for t, _ in round_]
        searched += [t for _, ts in round_ for t in ts]
        t_cells += _cells_on_two_workers(round_)
    _, t_end = _cpu(lambda: opt.conclude_search(spec, scan, members, walks, seen))
    path = t_scan + t_members + t_cells + t_end
    print(f"crank-rocker on 2 workers, CPU s here: scan {t_scan:.3f} | members {t_scan_cpu:.2f} ({shares[0][1]:.2f} "
          f"the chain's sized one; {sum(m.stage == opt.BOUNDED for m in members)} bounded only), {t_members:.2f} "
          f"on 2 workers | cells cut {' + '.join(f'{t:.2f}' for t in cut)}, {len(searched)} plateaus searched "
          f"{sum(searched):.2f}, {t_cells:.2f} on 2 workers | conclusion {t_end:.2f} | critical path {path:.2f} s")
    return {"scan": t_scan, "members": t_members, "cells": t_cells, "conclusion": t_end, "path": path}


def member_costs(body: MachineOptimiseIn, unit: float, members: int = 16) -> None:
    """A steady member of the crank-rocker's scan (what the search designs most) in units, and its parts: analysis
    and balancing, the drive's split and teeth, the flywheel's motor program and the simulations that check it."""
    from synth.machine import chain
    from synth.machine import optimise_light as light

    spec = machine_optimise_from(body, max_stages=6)
    scan = opt.scan_family(spec)
    picks = scan.candidates[1 :: max(1, len(scan.candidates) // members)][:members]
    machines = [replace(m, drive=replace(m.drive, strength=None))
                for m in (spec.machine(opt.member_linkage(spec, u)) for u in picks)]
    spent = {"flywheel's motor program": 0.0, "simulation": 0.0}
    wrapped = {"motor_constant_inertia": "flywheel's motor program", "simulate_machine": "simulation"}
    originals = {name: getattr(chain, name) for name in wrapped}

    def timing(name: str) -> Callable[..., Any]:
        def call(*args: Any, **kwargs: Any) -> Any:
            t0 = time.perf_counter()
            try:
                return originals[name](*args, **kwargs)
            finally:
                spent[wrapped[name]] += time.perf_counter() - t0
        return call

    for m in machines[:2]:
        light.steady_member(m)  # programs built, caches filled
    t_front = median_of(lambda: [light._front(m, 20.0) for m in machines], 2) / len(machines)
    try:
        for name in wrapped:
            setattr(chain, name, timing(name))
        t0 = time.perf_counter()
        for m in machines:
            light.steady_member(m)
        t_member = (time.perf_counter() - t0) / len(machines)
    finally:
        for name, fn in originals.items():
            setattr(chain, name, fn)
    parts = {"analysis and balancing": t_front, **{k: v / len(machines) for k, v in spent.items()}}
    parts["split, teeth and the rest"] = t_member - sum(parts.values())
    print(f"{'':13s} a steady member {t_member / unit:.2f} units ({t_member * 1e3:.0f} ms here): "
          + ", ".join(f"{k} {100 * v / t_member:.0f} %" for k, v in parts.items()))


def six_bar_critical_path(body: LinkageOptimiseIn, unit: float) -> None:
    """The linkage endpoint's stages on the six-bar run in this process, each timed in CPU seconds, and the
    longest path through them on two workers (the sample's members in two interleaved shares, the starts handed
    out in order), against their sum: the engine's time in one process."""
    spec = linkage_optimise_from(body, 6)
    scan, t_scan = _cpu(lambda: lo.scan_box(spec))
    feasible = scan.feasible
    shares = [_cpu(lambda s=s: lo.design_sample(spec, scan, feasible[s::2])) for s in range(2)]  # type: ignore[misc]
    members = scan.members([pair for part, _ in shares for pair in part])
    starts = [_cpu(lambda k=k: lo.refine_start(spec, scan, members, k))  # type: ignore[misc]
              for k in range(spec.refined)]
    _, t_end = _cpu(lambda: lo.conclude_linkage(spec, scan, members, [r for r, _ in starts]))
    total = t_scan + sum(t for _, t in shares) + sum(t for _, t in starts) + t_end
    path = t_scan + max(t for _, t in shares) + _two_workers([t for _, t in starts]) + t_end
    print(f"six-bar on 2 workers, CPU in units: scan {t_scan / unit:.1f} | members "
          f"{' + '.join(f'{t / unit:.1f}' for _, t in shares)} | starts "
          f"{' + '.join(f'{t / unit:.1f}' for _, t in starts)} | conclusion {t_end / unit:.1f} | one process "
          f"{total / unit:.1f}, critical path {path / unit:.1f} ({total / path:.1f} x)")


if __name__ == "__main__":
    main()
