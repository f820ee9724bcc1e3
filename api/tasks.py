"""Worker-side compositions of engine calls for endpoints whose work is more than one engine function.

Each is a plain module-level function of engine objects, so the whole of a request's work, analysis included,
runs in the worker under the request's deadline.
"""

from __future__ import annotations

from typing import Any

import synth
from synth.machine.report import design_report_pdf, design_summary_png

from .schemas.machine import MachineDesignOut

DesignAndAlternatives = tuple[synth.MachineDesign, tuple[synth.Alternative, ...]]


def flywheel_for_linkage(linkage: synth.Linkage, mean_speed: float, samples: int, max_samples: int,
                         delta: float, **sizing: Any) -> synth.FlywheelResult:
    """Analyse a linkage at its mean speed and size the flywheel on its reduced model."""
    analysis = synth.analyse(linkage, mean_speed, samples=samples, max_samples=max_samples)
    return synth.size_flywheel(synth.cycle_from_reduced(analysis.reduced), mean_speed, delta, **sizing)


def design_machine(spec: synth.MachineSpec, alternatives: bool, time_limit_s: float) -> DesignAndAlternatives:
    """The whole-machine design and, when asked, the same machine with the other balancing modes."""
    result = synth.design_machine(spec, time_limit_s=time_limit_s)
    others = synth.alternatives(spec, time_limit_s=time_limit_s) if alternatives else ()
    return result, others


def design_out(pair: DesignAndAlternatives) -> MachineDesignOut:
    """The design's JSON answer."""
    return MachineDesignOut.from_engine(*pair)


def design_png(pair: DesignAndAlternatives) -> bytes:
    """The design's one-page summary."""
    return design_summary_png(pair[0])


def design_pdf(pair: DesignAndAlternatives) -> bytes:
    """The design's multi-page report."""
    return design_report_pdf(*pair)
