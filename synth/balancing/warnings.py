"""Likely mistakes in a balancing answer: the linkage's own checks, counterweights beyond their links and rotor
corrections on too small a radius (see :mod:`synth.warnings` for the codes)."""

from __future__ import annotations

from collections.abc import Sequence

from ..warnings import DesignWarning, check_analysis, check_counterweights
from .fourbar import BalanceResult
from .rotors import RotorBalance, RotorMass


def check_balance(result: BalanceResult) -> list[DesignWarning]:
    """:func:`check_analysis` of the linkage before balancing and counterweights placed beyond their links
    (allowed by a ``max_radius_m`` longer than the link)."""
    before = result.analysis_before
    return check_analysis(before) + check_counterweights(before.linkage, result.counterweights, "max_radius_m")


def check_rotor(masses: Sequence[RotorMass], result: RotorBalance) -> list[DesignWarning]:
    """A correction heavier than all the rotor's unbalanced masses together: its radius is chosen small."""
    total = sum(m.mass for m in masses)
    out: list[DesignWarning] = []
    for i, c in enumerate(result.corrections):
        if total > 0 and c.mass > total:
            out.append(DesignWarning(
                "correction_radius_small", f"corrections[{i}].radius_m", c.radius,
                f"the correction needs {c.mass:.4g} kg, more than the {total:.4g} kg of unbalanced masses: "
                "a larger correction radius needs less", "m"))
    return out
