"""Admissible coefficient of speed fluctuation per machine type, from the seeds' table (package data)."""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import cache
from importlib import resources

from ..errors import InvalidInput


@dataclass(frozen=True, slots=True)
class MachineType:
    """One row of the admissible-delta table: ``delta_min`` and ``delta_max`` [-] (seed 003:443-453)."""

    name: str
    label: str
    delta_min: float
    delta_max: float

    @property
    def default_delta(self) -> float:
        """The tightest admissible value of the range [-]."""
        return self.delta_min


@cache
def machine_types() -> tuple[MachineType, ...]:
    """The seeds' table of admissible delta per machine type, in table order.

    Notes
    -----
    Stored as denominators (the seed writes 1/200...1/300), so the values are exact quotients.
    """
    raw = json.loads(resources.files(__package__).joinpath("admissible_delta.json").read_text())
    return tuple(
        MachineType(name, row["label"], 1.0 / max(row["denominators"]), 1.0 / min(row["denominators"]))
        for name, row in raw["machine_types"].items()
    )


def admissible_delta(machine_type: str) -> float:
    """Tightest admissible delta [-] of ``machine_type``; InvalidInput naming the known types otherwise."""
    for row in machine_types():
        if row.name == machine_type:
            return row.default_delta
    known = ", ".join(r.name for r in machine_types())
    raise InvalidInput(f"unknown machine type {machine_type!r}; known: {known}", field="machine_type")
