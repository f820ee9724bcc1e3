"""Tooth numbers of any train: serial trains of external meshes and trains with planetary stages.

The two searches share their rules and result types (:mod:`synth.gearing.teeth`); the planetary search builds
on the serial one's, so the choice between them is made here, above both.
"""

from __future__ import annotations

from collections.abc import Sequence

from .planetary import planetary_tooth_numbers
from .stages import Stage
from .teeth import ENUMERATION_CHECK_LIMIT, ToothResult, ToothRules, serial_tooth_numbers


def tooth_numbers(target: float, stages: Sequence[Stage], rules: ToothRules | None = None,
                  tolerance: float | None = None, *, check_limit: int = ENUMERATION_CHECK_LIMIT,
                  planets: int = 3) -> ToothResult:
    """Integer tooth numbers of a train whose ratio best meets ``target`` [-], motor side first.

    Parameters
    ----------
    target : total ratio U [-].
    stages : the train's toothed stages (their ratio ranges bound each mesh).
    rules : pressure angle [rad], addendum and profile shift [-], min/max teeth, hunting, reverted.
    tolerance : relative ratio tolerance [-]; given, the fewest teeth within it, else the closest ratio.
    check_limit : run the plain enumeration as a check when it has at most this many combinations.
    planets : planets per planetary stage [-].

    Raises Infeasible when the search is empty (``constraint`` names what to relax), InvalidInput, TooLarge.
    """
    if any(s.type == "planetary" for s in stages):
        return planetary_tooth_numbers(target, stages, rules, tolerance, planets=planets, check_limit=check_limit)
    return serial_tooth_numbers(target, stages, rules, tolerance, check_limit=check_limit)
