"""What a worker does before it takes its first request: import, build and run each capability's programs once.

The solvers are compiled on first use (CasADi's flywheel motor NLP, the convex problems of
balancing, the ISO 6336 tables, the numba loops of the steady simulation, of the flywheel's Newton
iteration, of path synthesis and of the answers' curves), so without this
the first heavy request after a start paid about as much again as its own work. A request worker runs :func:`warm_worker` once, right after it is forked and before its slot
hands it a task (a replaced worker too): one small representative task per capability, at the sizes the README's
requests use, so their programs are the ones later requests reuse. A failure here only costs the first request its speed:
it is logged and the worker takes work as usual.
"""

from __future__ import annotations

import logging
import time

import numpy as np

import synth
from synth.machine.optimise import design_members, scan_family

from mechsynth_client.schemas.machine import PRESS_EXAMPLE, MachineIn
from mechsynth_client.schemas.optimise import CRANK_ROCKER_OPTIMISE_EXAMPLE, MachineOptimiseIn

from ..curve_text import curve_bytes
from ..translate.machine import machine_from
from ..translate.optimise import machine_optimise_from

log = logging.getLogger("synth.service")

_MAX_STAGES = 6


def _optimisation_member() -> None:
    spec = machine_optimise_from(MachineOptimiseIn.model_validate(CRANK_ROCKER_OPTIMISE_EXAMPLE), _MAX_STAGES)
    scan = scan_family(spec)
    others = [u for u in scan.candidates if u != scan.chain_parameter][:1]
    design_members(spec, [scan.chain_parameter, *others], size_gears_at=(scan.chain_parameter,))


def _curve_text() -> None:
    curve_bytes(np.zeros((2, 2)))


def _path() -> None:
    # Three points, one start on each branch: the screening's compiled kernels loaded from numba's cache.
    targets = np.array([[0.0, 0.0], [0.1, 0.05], [0.2, 0.0]])
    bounds, box, coupler_point = synth.default_path_limits(targets)
    synth.synthesise_path(synth.PathSpec(targets, None, bounds, box, coupler_point, starts=2))


def _machine() -> None:
    spec = machine_from(MachineIn.model_validate(PRESS_EXAMPLE), _MAX_STAGES)
    synth.design_machine(spec)


#: The README's press designed whole (analysis, balancing, drive, teeth, gears for strength, the flywheel with its
#: motor NLP, the steady, start-up and run-down simulations), two members of its crank-rocker optimisation
#: (the scan, the four-bar's static balancing, the chain's own member with its gears sized), the compiled
#: writer of a JSON answer's curves and a small path synthesis.
WARM_STEPS = (("the machine's chain", _machine),
              ("the optimisation's member", _optimisation_member),
              ("the curves' JSON writer", _curve_text),
              ("path synthesis", _path))


def warm_worker() -> float:
    """Run every capability once in this process; the time it took [s]."""
    t0 = time.perf_counter()
    for name, step in WARM_STEPS:
        try:
            step()
        except Exception:  # a worker that cannot warm still works, only its first request is slower
            log.exception("warming %s failed; the worker takes work without it", name)
    return time.perf_counter() - t0
