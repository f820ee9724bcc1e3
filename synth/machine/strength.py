"""The machine's parts sized for strength: its links (to the fixed point, before balancing, so that balancing,
the flywheel and the drive see the real links), then on the machine as built (balanced, driven) every link's
checks again, every revolute joint's pin and bearing, the crank shaft and the key of each of its hubs.

Each part's checks join the machine's one list of checks; a part that fails one there (a link re-checked with the
counterweights balancing added, say) is a failed check and a warning, never a silent pass.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from ..analysis import Analysis
from ..strength.checks import PartCheck
from ..strength.crank_shaft import CrankShaftLayout, crank_shaft_loads, hub_torques
from ..strength.joints import JointPartSpec, JointParts, size_joints
from ..strength.keys import KeyResult, size_key
from ..strength.links import LinkSizing, LinkSpec, StrengthLimits, beam_forces, beam_links, size_link
from ..strength.materials import MATERIALS, Material
from ..strength.shafts import ShaftResult, ShaftSpec, size_shaft
from ..strength.sizing import LinkStrength, size_links
from ..model import Linkage
from ..warnings import DesignWarning


@dataclass(frozen=True, slots=True)
class StrengthChoice:
    """How the machine's parts are made: each bar's ``links`` spec (a bar not listed takes ``default_link``),
    the ``limits`` of the links, the joints' ``joint`` spec (overridden per joint by ``joints``), the crank shaft's
    ``shaft`` spec, ``shaft_material`` and ``layout`` (None: spans scaled from the crank), and the keys' allowed
    ``key_pressure`` [Pa] (None: the shaft material's yield over 2) and ``hub_length`` [m] (None: 1.5 d)."""

    default_link: LinkSpec = field(default_factory=lambda: LinkSpec(MATERIALS["S355J2"]))
    links: Mapping[str, LinkSpec] = field(default_factory=dict)
    limits: StrengthLimits = field(default_factory=StrengthLimits)
    joint: JointPartSpec = field(default_factory=lambda: JointPartSpec(MATERIALS["C45E+QT"]))
    joints: Mapping[str, JointPartSpec] = field(default_factory=dict)
    shaft: ShaftSpec | None = None
    shaft_material: Material = field(default_factory=lambda: MATERIALS["C45E+QT"])
    layout: CrankShaftLayout | None = None
    key_pressure: float | None = None
    hub_length: float | None = None

    def specs(self, bars: tuple[str, ...]) -> dict[str, LinkSpec]:
        """Every bar's spec."""
        return {name: self.links.get(name, self.default_link) for name in bars}


@dataclass(frozen=True, slots=True)
class MachineStrength:
    """The parts of the machine as built: ``sizing`` the links' fixed point (on the linkage before balancing),
    ``links`` each bar checked on the machine as built, ``joints`` each revolute joint's pin and bearing,
    ``crank_shaft`` and its hubs' ``keys``; ``checks`` every part's."""

    sizing: LinkStrength
    links: dict[str, LinkSizing]
    joints: dict[str, JointParts]
    crank_shaft: ShaftResult
    keys: dict[str, KeyResult]
    layout: CrankShaftLayout
    checks: tuple[PartCheck, ...]
    warnings: tuple[DesignWarning, ...] = ()

    @property
    def link_mass(self) -> float:
        """The sized bars [kg]."""
        return sum(s.mass for s in self.links.values())


def size_machine_links(choice: StrengthChoice, linkage: Linkage, speed: float, samples: int) -> LinkStrength:
    """The links of the machine's linkage sized to the fixed point (every bar)."""
    from ..analysis import analyse

    probe = analyse(linkage, speed, samples=min(samples, 8))
    return size_links(linkage, speed, choice.specs(beam_links(probe)), choice.limits, samples=samples)


def _link_checks(s: LinkSizing) -> list[PartCheck]:
    out = []
    for c in s.checks:
        safety = c.safety if math.isfinite(c.safety) else 1e300
        out.append(PartCheck(f"link {s.link}", f"link_{c.name}", safety, c.required, "1",
                             f"least factor of safety of link {s.link!r} ({s.section.label}) over the cycle, "
                             f"{c.method}, at {math.degrees(c.phi):.1f} deg, {c.x * 1e3:.0f} mm along it",
                             at_least=True))
    return out


def default_layout(analysis: Analysis) -> CrankShaftLayout:
    """A crank shaft between two bearings a crank length apart, the crank overhung half a crank length beyond
    bearing B and the drive coupled in the middle."""
    r = analysis.linkage.mechanism.crank
    return CrankShaftLayout(span=r, crank_position=1.5 * r, drive_position=0.5 * r)


def parts_of_machine(choice: StrengthChoice, sizing: LinkStrength, built: Analysis) -> MachineStrength:
    """Every part checked or sized on ``built``, the analysis of the machine as built (balanced)."""
    specs = choice.specs(tuple(sizing.links))
    # each bar as sized, checked under the machine's loads as built (a counterweight's arm, beyond the bar,
    # checked with the bar's section); its mass stays the sized bar's, the one the analysis used
    links = {name: dataclasses.replace(size_link(beam_forces(built, name),
                                                 dataclasses.replace(specs[name], section=s.section), choice.limits),
                                       sized=s.sized, mass_props=s.mass_props)
             for name, s in sizing.links.items()}
    joints = size_joints(built, choice.joint, choice.joints)
    layout = choice.layout or default_layout(built)
    spec = choice.shaft or ShaftSpec(span=layout.span)
    shaft = size_shaft("crank shaft", crank_shaft_loads(built, layout), spec, choice.shaft_material)
    torques = hub_torques(built)
    hubs = ["crank", "coupling" if layout.drive == "coupling" else "drive"]
    if layout.flywheel_position is not None:
        hubs.append("flywheel")
    pressure = choice.key_pressure or choice.shaft_material.yield_strength / 2.0
    hub_length = choice.hub_length or 1.5 * shaft.diameter
    keys = {hub: size_key(f"{hub} hub", shaft.diameter, torques[hub], pressure, hub_length=hub_length)
            for hub in hubs}
    checks: list[PartCheck] = []
    for s in links.values():
        checks += _link_checks(s)
    for j in joints.values():
        checks += j.checks
    checks += shaft.checks
    for k in keys.values():
        checks += k.checks
    warnings = [w for j in joints.values() for w in j.warnings] + list(shaft.warnings)
    warnings += [DesignWarning("check_failed", "strength", c.value,
                               f"{c.part} fails its {c.name} check ({c.value:.4g} against {c.limit:.4g}): "
                               f"{c.meaning}", c.unit, stage="strength")
                 for c in checks if not c.passed]
    return MachineStrength(sizing, links, joints, shaft, keys, layout, tuple(checks), tuple(warnings))


def link_masses(strength: MachineStrength) -> dict[str, float]:
    """Each sized bar's mass [kg]."""
    return {name: s.mass for name, s in strength.links.items()}


def peak(values: np.ndarray) -> float:
    """Largest |value| [unit of the values]."""
    return float(np.max(np.abs(values)))
