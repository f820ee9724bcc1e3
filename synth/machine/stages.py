"""The stages of a machine design, named: what a failing stage says and which stage each warning comes from.

A machine design runs analysis -> balancing -> drive -> teeth -> flywheel -> motor -> simulation. An error from
any of them carries its ``stage`` and says, in engineering terms, what failed and what to change; a solver's
own words (an IPOPT status, "shooting did not converge") are kept only as the status beside it. Every stage's
likely-mistake warnings are gathered at the top of the answer with their stage, and their fields are named as
the machine request spells them.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from dataclasses import replace
from typing import Literal

from ..errors import InvalidInput, SolverFailed, SynthError
from ..model import Linkage
from ..warnings import DesignWarning, check_linkage

Stage = Literal["analysis", "balancing", "drive", "teeth", "flywheel", "motor", "simulation", "foundation",
                "elastic_drive", "regulation", "strength"]
STAGES: tuple[Stage, ...] = ("analysis", "balancing", "drive", "teeth", "flywheel", "motor", "simulation",
                             "foundation", "elastic_drive", "regulation", "strength")

#: Likely-mistake codes that refuse a machine before its chain: the numbers are in other units, and the chain
#: would otherwise fail deep inside a solver instead of saying so.
REFUSED = ("length_likely_mm", "mass_likely_grams")

#: What a stage whose solver stopped without an answer means for the machine, and what to change.
_SOLVER_ADVICE: dict[str, str] = {
    "analysis": "the linkage's motion could not be computed; check the link lengths (in metres) and the branch",
    "balancing": "no counterweights were found within the limits; relax balancing.max_radius_m or "
                 "balancing.mass_budget_kg, or choose another balancing mode",
    "drive": "the ratio could not be split between the stages; free a stage's ratio (ratio_min, ratio_max) or "
             "add a stage",
    "teeth": "no tooth numbers give the stage ratios; raise drive.max_teeth or drive.tooth_tolerance",
    "flywheel": "the least flywheel for the chosen motor was not found: the motor's characteristic cannot hold "
                "the crank within the delta band at this load; a larger delta, a larger motor (drive.motor) or "
                "a lighter load makes it possible",
    "motor": "no motor of the catalogue carries the cycle; name a larger motor (drive.motor) or send a "
             "catalogue with larger ones",
    "simulation": "the assembled machine finds no steady motion: the motor cannot keep the crank turning "
                  "against the load through this train; check the loads' and the linkage's units, or choose a "
                  "larger motor (drive.motor) or a larger delta",
    "foundation": "the frame's motion on its isolators could not be computed; check the isolators' stiffness and "
                  "damping",
    "elastic_drive": "the drive with its elastic link finds no steady motion; check the link's stiffness and the "
                     "motor-side inertia",
    "strength": "the links' sections did not settle: the sized masses keep changing the loads that size them; "
                "give the links fixed sections or another shape",
    "regulation": "the speed after the load step could not be followed; a smaller step, a larger motor or other "
                  "regulator gains make it possible",
}


@contextmanager
def stage(name: Stage) -> Iterator[None]:
    """Run one stage: an engine error leaving it carries ``name``; a solver's failure is told in the machine's
    terms. An error already marked by an inner stage keeps its own."""
    try:
        yield
    except SynthError as exc:
        if exc.stage is None:
            exc.stage = name
            if isinstance(exc, SolverFailed):
                exc.args = (f"{name} stage: {_SOLVER_ADVICE[name]} (the solver said: {exc.args[0]})",)
            elif exc.args and isinstance(exc.args[0], str):
                exc.args = (f"{name} stage: {exc.args[0]}", *exc.args[1:])
        raise


def refuse_likely_mistakes(linkage: Linkage) -> list[DesignWarning]:
    """The single endpoints' likely-mistake checks on the machine's linkage, before the chain runs.

    Lengths that look like millimetres and masses that look like grams refuse the machine (InvalidInput with the
    check's ``code`` and the field); the other notes are returned, to join the analysis stage's warnings.
    """
    found = check_linkage(linkage)
    refused = [w for w in found if w.code in REFUSED]
    if refused:
        first = refused[0]
        others = ", ".join(f"{w.field} ({w.value:g} {w.unit})" for w in refused[1:])
        raise InvalidInput(
            f"{first.field}: {first.message} The machine is refused before its design: give lengths in metres "
            f"and masses in kilograms{f' (also {others})' if others else ''}", field=first.field, code=first.code)
    return [w for w in found if w.code not in REFUSED]


def _prefixed(field: str | None, prefix: str) -> str | None:
    if field is None or prefix == "":
        return field
    return f"{prefix}.{field}"


def staged(warnings: Iterable[DesignWarning], name: Stage, prefix: str = "") -> list[DesignWarning]:
    """Warnings of one stage, marked with it, their fields under ``prefix`` (the request's object that holds
    the stage's fields: ``drive`` for the drive's and teeth's)."""
    return [replace(w, stage=name, field=_prefixed(w.field, prefix)) for w in warnings]


def gathered(warnings: Iterable[DesignWarning]) -> tuple[DesignWarning, ...]:
    """Every stage's warnings in stage order, each code and field once."""
    seen: set[tuple[str, str | None]] = set()
    out: list[DesignWarning] = []
    order: dict[str, int] = {s: i for i, s in enumerate(STAGES)}
    for w in sorted(warnings, key=lambda w: order.get(w.stage or "", len(STAGES))):
        key = (w.code, w.field)
        if key not in seen:
            seen.add(key)
            out.append(w)
    return tuple(out)
