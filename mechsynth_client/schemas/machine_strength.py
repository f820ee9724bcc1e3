"""Schemas of a machine's ``strength`` block: its links sized to their fixed point, and its joints' and crank
shaft's parts, as built."""

from __future__ import annotations

from pydantic import BaseModel, Field

from .strength import LinkSectionOut, SizingIterationOut, StrengthFields
from .strength_parts import PartsIn, PartsOut


class MachineStrengthIn(StrengthFields):
    """The machine's parts sized for strength: its links (to the fixed point, before balancing), then on the
    machine as built every revolute joint's pin and bearing and the crank shaft with its bearings and keys."""

    parts: PartsIn = Field(default_factory=PartsIn, description="Pins, bearings and the crank shaft, as in POST "
                           "/v1/strength's parts; without a crank_shaft, the machine's is laid out from the crank: "
                           "bearings a crank length apart, the crank overhung half a crank length beyond B, the "
                           "coupling between them, 42CrMo4, crank and coupling hubs a crank length long keyed at "
                           "half the shaft's yield strength.")


class MachineStrengthOut(BaseModel):
    """The machine's parts as built."""

    links: list[LinkSectionOut] = Field(description="Each bar as sized, checked on the machine as built.")
    iterations: list[SizingIterationOut] = Field(description="The links' fixed point, on the linkage before "
                                                 "balancing.")
    link_mass_kg: float = Field(description="All sized bars [kg].")
    parts: PartsOut = Field(description="Every joint's pin and bearing, the crank shaft, its bearings and keys.")
