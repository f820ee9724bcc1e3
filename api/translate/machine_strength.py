"""Translation between a machine's ``strength`` block and the engine."""

from __future__ import annotations

import dataclasses

import synth
from synth.machine.strength import MachineStrength, StrengthChoice

from mechsynth_client.schemas.machine import MachineDesignOut
from mechsynth_client.schemas.machine_strength import MachineStrengthIn, MachineStrengthOut
from mechsynth_client.schemas.strength import SizingIterationOut
from .strength import is_bar, limits_from, link_out, specs_from
from .strength_parts import parts_out, parts_spec


def machine_strength_from(m: MachineStrengthIn, linkage: synth.Linkage) -> StrengthChoice:
    """Engine strength choice of a machine's ``strength`` block (its parts as POST /v1/strength's parts)."""
    bars = tuple(n for n in linkage.mechanism.topology.links if is_bar(linkage, n))
    specs = specs_from(m, bars, "strength.")
    parts = parts_spec(m.parts, "strength.parts.")
    return StrengthChoice(links=specs, limits=limits_from(m.limits), parts=parts)


def with_strength(spec: synth.MachineSpec, m: MachineStrengthIn | None) -> synth.MachineSpec:
    """The machine with its strength block, when the request has one."""
    if m is None:
        return spec
    return dataclasses.replace(spec, strength=machine_strength_from(m, spec.linkage))


def machine_strength_out(s: MachineStrength) -> MachineStrengthOut:
    """Wire form of the machine's parts."""
    return MachineStrengthOut(
        links=[link_out(x) for x in s.links.values()],
        iterations=[SizingIterationOut(masses_kg=i.masses, sections=i.sections, largest_change_kg=i.largest_change)
                    for i in s.sizing.iterations],
        link_mass_kg=s.link_mass, parts=parts_out(s.parts))


def with_strength_out(design: synth.MachineDesign, out: MachineDesignOut) -> MachineDesignOut:
    """A machine design's answer with its ``strength`` block filled in."""
    if design.strength is None:
        return out
    return out.model_copy(update={"strength": machine_strength_out(design.strength)})
