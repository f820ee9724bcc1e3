"""The whole-machine optimisation of the README's crank-rocker example against the design chain alone.

Run: ``.venv/bin/python -m bench.optimise``. The machine is the optimisation page's crank-rocker (static
balancing, least added mass). Prints wall times [s] of one chain run (/v1/machines/design on the chain's member),
the engine's optimisation in one process and the endpoint on two workers, and the objective before (the chain's
machine, and the best member of the densest evenly spread scan) and after (the optimum), with how the family was
covered. The cores are shared: the load average is printed beside the times.
"""

from __future__ import annotations

import os

import numpy as np

import synth
from bench._timing import best_of
from mechsynth_client import SynthClient
from mechsynth_client.schemas.optimise import CRANK_ROCKER_OPTIMISE_EXAMPLE, MachineOptimiseIn
from synth.machine.optimise import OBJECTIVES, normalisers, score

REPEAT = 1


def main() -> None:
    """Time the chain alone, the engine in one process and the endpoint on a two-worker pool."""
    body = MachineOptimiseIn.model_validate(CRANK_ROCKER_OPTIMISE_EXAMPLE)
    spec = body.to_engine(max_stages=6)
    result = synth.optimise_machine(spec)
    chain_machine = spec.machine(result.chain_linkage)
    t_chain = best_of(lambda: synth.design_machine(chain_machine), 3)
    t_engine = best_of(lambda: synth.optimise_machine(spec), REPEAT)
    os.environ["SYNTH_WORKERS"] = "2"
    with SynthClient.in_process("pool") as client:
        client.optimise_machine(body)  # workers start and import the engine once
        t_endpoint = best_of(lambda: client.optimise_machine(body), REPEAT)
    c = result.certificate
    norm = normalisers(result.members, c.scan.chain_parameter)
    scanned = [m for m in result.members if m.stage == "scan" and m.feasible and m.values is not None]
    best_scan = min(scanned, key=lambda m: score(spec, m.values, norm))  # type: ignore[arg-type]
    print(f"crank-rocker machine, {spec.samples} samples, {spec.balancing.mode} balancing, objective "
          f"{dict(spec.weights)}; load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    print(f"chain alone (one /v1/machines/design run)  {t_chain:6.2f} s")
    print(f"optimise_machine, one process             {t_engine:6.2f} s   {t_engine / t_chain:5.1f} chain runs")
    print(f"POST /v1/machines/optimise, 2 workers      {t_endpoint:6.2f} s   {t_endpoint / t_chain:5.1f} chain runs")
    k = OBJECTIVES.index("added_mass")
    assert best_scan.values is not None
    print(f"added mass: chain {result.chain.values[k] if result.chain.values else np.nan:.4f} kg, best of the "
          f"{len(c.scan.candidates)}-member scan {best_scan.values[k]:.4f} kg (u = {best_scan.parameter:.4f}), "
          f"optimum {result.values[k]:.4f} kg (u = {result.parameter:.4f})")
    cells = c.refinements
    print(f"family: {c.scan.grid_points} members checked kinematically, {c.members_designed} designed "
          f"({c.feasible_designed} feasible); cells {len(cells)}: "
          + ", ".join(f"{sum(r.status == s for r in cells)} {s}" for s in ("searched", "pruned", "unsearched"))
          + f"; plateaus walked {sum(r.plateaus for r in cells)}; binding {list(c.binding)}")


if __name__ == "__main__":
    main()
