"""Stage types of a drive (admissible ratio range, efficiency, sizing constant) and the stages of one layout.

The table is package data (``stage_types.json``); a request may override a stage's range and efficiency, or fix
its ratio.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache
from importlib import resources
from typing import Any

from ..errors import InvalidInput, TooLarge

_MM3_TO_M3 = 1e-9


@dataclass(frozen=True, slots=True)
class StageType:
    """One kind of transmission stage from the shipped table.

    ``ratio_min``/``ratio_max`` admissible single-stage ratio [-], ``efficiency`` default [-], ``toothed`` whether a
    pinion/gear tooth-number search applies, ``volume_coefficient`` c of the contact-stress sizing rule
    (pinion plus gear volume = c * T_pinion * (u + 1)(u^2 + 1)/u) [m³/(N·m)], None where no such rule is stated.
    """

    name: str
    description: str
    ratio_min: float
    ratio_max: float
    efficiency: float
    toothed: bool
    volume_coefficient: float | None


@dataclass(frozen=True, slots=True)
class Stage:
    """A stage of one layout: its type with any overrides, and a fixed ratio when the design prescribes one.

    ``ratio_min``/``ratio_max`` [-], ``efficiency`` [-], ``ratio`` fixed stage ratio or None [-],
    ``volume_coefficient`` [m³/(N·m)] or None.
    """

    type: str
    ratio_min: float
    ratio_max: float
    efficiency: float
    volume_coefficient: float | None
    toothed: bool
    ratio: float | None = None


@dataclass(frozen=True, slots=True)
class StageSpec:
    """A stage as asked for: a type name and optional overrides (None keeps the table's value)."""

    type: str
    ratio_min: float | None = None
    ratio_max: float | None = None
    efficiency: float | None = None
    ratio: float | None = None


@cache
def _table() -> dict[str, Any]:
    text = resources.files(__package__).joinpath("stage_types.json").read_text(encoding="utf-8")
    table: dict[str, Any] = json.loads(text)
    return table


def stage_types() -> dict[str, StageType]:
    """The shipped stage-type table by name, with each type's volume coefficient from the stated sizing rule."""
    table = _table()
    sizing = table["sizing"]
    out = {}
    for name, row in table["types"].items():
        coeff = None
        if row["K_d"] is not None:
            coeff = (math.pi / 4 * row["K_d"] ** 3 * sizing["K_H"]
                     / (sizing["sigma_HP_MPa"] ** 2 * row["load_share"]) * _MM3_TO_M3)
        out[name] = StageType(name, row["description"], row["ratio_min"], row["ratio_max"], row["efficiency"],
                              row["toothed"], coeff)
    return out


_ORDINALS = ("first", "second", "third", "fourth", "fifth", "sixth", "seventh", "eighth", "ninth", "tenth", "eleventh",
             "twelfth")


def stage_name(k: int) -> str:
    """A stage as every message names it, motor side first: 0 -> "the first stage" (the field says ``stages[0]``)."""
    return f"the {_ORDINALS[k]} stage" if 0 <= k < len(_ORDINALS) else f"stage {k + 1}"


def _positive(value: float | None, field: str) -> None:
    if value is not None and not (math.isfinite(value) and value > 0):
        raise InvalidInput(f"{field} must be a positive number, got {value}", field=field)


def make_stage(spec: StageSpec | str, field: str = "stages[0]") -> Stage:
    """One stage from a type name or a spec with overrides; ``field`` names it in errors.

    Raises InvalidInput for an unknown type (listing the known ones), a range with min > max, an efficiency
    outside (0, 1] or a fixed ratio outside the stage's range.
    """
    spec = StageSpec(spec) if isinstance(spec, str) else spec
    known = stage_types()
    if spec.type not in known:
        raise InvalidInput(
            f"unknown stage type {spec.type!r}; known types: {', '.join(sorted(known))}", field=f"{field}.type"
        )
    base = known[spec.type]
    for name in ("ratio_min", "ratio_max", "efficiency", "ratio"):
        _positive(getattr(spec, name), f"{field}.{name}")
    lo = base.ratio_min if spec.ratio_min is None else spec.ratio_min
    hi = base.ratio_max if spec.ratio_max is None else spec.ratio_max
    if lo > hi:
        raise InvalidInput(f"ratio_min {lo:g} exceeds ratio_max {hi:g}", field=f"{field}.ratio_min")
    eta = base.efficiency if spec.efficiency is None else spec.efficiency
    if eta > 1:
        raise InvalidInput(f"an efficiency cannot exceed 1, got {eta:g}", field=f"{field}.efficiency")
    if spec.ratio is not None and not lo <= spec.ratio <= hi:
        raise InvalidInput(
            f"fixed ratio {spec.ratio:g} is outside the {spec.type} stage's range [{lo:g}, {hi:g}]",
            field=f"{field}.ratio",
        )
    return Stage(spec.type, lo, hi, eta, base.volume_coefficient, base.toothed, spec.ratio)


def make_stages(
    spec: int | Sequence[StageSpec | str], *, max_stages: int, default_type: str = "spur", field: str = "stages"
) -> tuple[Stage, ...]:
    """The stages of a layout from a count (all ``default_type``) or a list of types/specs, motor side first.

    Raises TooLarge beyond ``max_stages`` and InvalidInput for an empty layout or a bad stage.
    """
    items: Sequence[StageSpec | str] = [default_type] * spec if isinstance(spec, int) else spec
    if len(items) < 1:
        raise InvalidInput("a drive needs at least one stage", field=field)
    if len(items) > max_stages:
        raise TooLarge("stages", max_stages, len(items), field=field)
    return tuple(make_stage(s, f"{field}[{i}]") for i, s in enumerate(items))


def chain_efficiency(stages: Sequence[Stage]) -> float:
    """Product of the stages' efficiencies [-] (series connection, seed 003:1001-1012)."""
    return math.prod(s.efficiency for s in stages)
