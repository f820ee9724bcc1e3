"""The machine's joints and crank shaft sized together from one analysis: one plain call for a worker.

Input: an :class:`synth.analysis.Analysis` over one uniform cycle (the linkage as built) and a
:class:`PartsSpec`: the joints' default and per-joint specs (:class:`synth.strength.joints.JointPartSpec`), an
optional bearing catalogue replacing the shipped one, and an optional :class:`CrankShaftSpec` (layout, material,
fatigue conditions, bearings' life, hub keys). Output: :func:`size_parts` gives :class:`Parts`: every revolute
joint's pin and bearing (but the crank's pivot when the crank shaft is sized: that joint is the shaft's journal on
its two bearings), the crank shaft with its bearings and its hubs' keys, one list of every check and one of every
warning.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from ..analysis import Analysis
from ..errors import InvalidInput
from ..warnings import DesignWarning
from .bearings import RollingBearing, RollingBearingResult, select_rolling_bearing
from .checks import PartCheck
from .crank_shaft import CrankShaftLayout, crank_pivot, crank_shaft_loads, hub_torques
from .joints import JointPartSpec, JointParts, cycle_time, size_joints
from .keys import KeyForm, KeyResult, size_key
from .materials import Material
from .shafts import ShaftResult, ShaftSpec, size_shaft


@dataclass(frozen=True, slots=True)
class HubKeySpec:
    """A hub keyed to the crank shaft: ``hub`` one of crank, drive, flywheel, counterweight; ``hub_length`` [m];
    ``allowed_pressure`` [Pa]; the key's ``form``, ``count`` and ``application_factor``."""

    hub: str
    hub_length: float
    allowed_pressure: float
    form: KeyForm = "A"
    count: int = 1
    application_factor: float = 1.0


@dataclass(frozen=True, slots=True)
class CrankShaftSpec:
    """The crank shaft: its ``layout``, ``material``, fatigue ``shaft`` spec (span and turns are the layout's and
    one), the life its two rolling bearings must reach [h] and the ``keys`` of its hubs."""

    layout: CrankShaftLayout
    material: Material
    shaft: ShaftSpec
    bearing_life_hours: float = 40000.0
    keys: tuple[HubKeySpec, ...] = ()


@dataclass(frozen=True, slots=True)
class PartsSpec:
    """Every joint's ``default`` spec and ``joints`` overriding it by name; ``catalogue`` of rolling bearings
    replacing the shipped one (None: shipped); ``crank_shaft`` (None: not sized)."""

    default: JointPartSpec
    joints: Mapping[str, JointPartSpec] = field(default_factory=dict)
    catalogue: tuple[RollingBearing, ...] | None = None
    crank_shaft: CrankShaftSpec | None = None


@dataclass(frozen=True, slots=True)
class CrankShaftParts:
    """The sized crank ``shaft``, its ``bearings`` A and B, and its hubs' ``keys`` by hub."""

    shaft: ShaftResult
    bearings: tuple[RollingBearingResult, RollingBearingResult]
    keys: dict[str, KeyResult]


@dataclass(frozen=True, slots=True)
class Parts:
    """The sized parts: ``joints`` by name, the ``crank_shaft`` (or None), every ``checks`` and ``warnings``."""

    joints: dict[str, JointParts]
    crank_shaft: CrankShaftParts | None
    checks: tuple[PartCheck, ...]
    warnings: tuple[DesignWarning, ...]

    @property
    def passed(self) -> bool:
        """Every check of every part met."""
        return all(c.passed for c in self.checks)


def size_parts(analysis: Analysis, spec: PartsSpec) -> Parts:
    """Size every revolute joint's pin and bearing and, when asked, the crank shaft, its bearings and keys."""
    # With the crank shaft sized, the crank's pivot is its journal on two bearings, not a pin.
    exclude = (crank_pivot(analysis),) if spec.crank_shaft is not None else ()
    joints = size_joints(analysis, spec.default, spec.joints, catalogue=spec.catalogue, exclude=exclude)
    checks = [c for j in joints.values() for c in j.checks]
    notes = [w for j in joints.values() for w in j.warnings]
    crank: CrankShaftParts | None = None
    if spec.crank_shaft is not None:
        cs = spec.crank_shaft
        shaft_spec = ShaftSpec(cs.layout.span, 1.0, cs.shaft.design_factor, cs.shaft.surface, cs.shaft.reliability,
                               cs.shaft.bearing_notch, cs.shaft.notch_sensitivity)
        shaft = size_shaft("crank shaft", crank_shaft_loads(analysis, cs.layout), shaft_spec, cs.material)
        period = cycle_time(analysis)
        speed = np.full(analysis.motion.phi.size, abs(float(analysis.motion.omega_crank)))
        a, b = (select_rolling_bearing(f"crank shaft bearing {x}", r, speed, period, min_bore=shaft.diameter,
                                       required_life_hours=cs.bearing_life_hours, catalogue=spec.catalogue)
                for x, r in (("A", shaft.bearing_a), ("B", shaft.bearing_b)))
        torques = hub_torques(analysis)
        if unknown := [k.hub for k in cs.keys if k.hub not in torques]:
            raise InvalidInput(f"hubs {unknown} are not on the crank shaft; its hubs are {sorted(torques)}",
                               field="crank_shaft.keys")
        keys = {k.hub: size_key(f"{k.hub} hub", shaft.diameter, torques[k.hub], k.allowed_pressure,
                                hub_length=k.hub_length, form=k.form, count=k.count,
                                application_factor=k.application_factor) for k in cs.keys}
        crank = CrankShaftParts(shaft, (a, b), keys)
        checks += [*shaft.checks, *a.checks, *b.checks, *(c for k in keys.values() for c in k.checks)]
        notes += [*shaft.warnings, *a.warnings, *b.warnings]
    return Parts(joints, crank, tuple(checks), tuple(notes))
