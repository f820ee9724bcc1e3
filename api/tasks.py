"""Worker-side compositions of engine calls for endpoints whose work is more than one engine function.

Each is a plain module-level function of engine objects, so the whole of a request's work, analysis included,
runs in the worker under the request's deadline.
"""

from __future__ import annotations

from typing import Any

import synth


def flywheel_for_linkage(linkage: synth.Linkage, mean_speed: float, samples: int, max_samples: int,
                         delta: float, **sizing: Any) -> synth.FlywheelResult:
    """Analyse a linkage at its mean speed and size the flywheel on its reduced model."""
    analysis = synth.analyse(linkage, mean_speed, samples=samples, max_samples=max_samples)
    return synth.size_flywheel(synth.cycle_from_reduced(analysis.reduced), mean_speed, delta, **sizing)
