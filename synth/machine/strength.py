"""The machine's parts sized for strength: its links (to the fixed point, before balancing, so that balancing,
the flywheel and the drive see the real links), then on the machine as built (balanced, driven) every link's
checks again, every revolute joint's pin and bearing, and the crank shaft with its bearings and hub keys.

Each part's checks join the machine's one list of checks; a part that fails one there (a link re-checked with the
counterweights balancing added, say) is a failed check and a warning, never a silent pass.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field

from ..analysis import Analysis, analyse
from ..model import Linkage
from ..strength.checks import PartCheck
from ..strength.crank_shaft import CrankShaftLayout
from ..strength.joints import JointPartSpec
from ..strength.links import LinkSizing, LinkSpec, StrengthLimits, beam_forces, beam_links, size_link
from ..strength.materials import MATERIALS
from ..strength.parts import CrankShaftSpec, HubKeySpec, Parts, PartsSpec, size_parts
from ..strength.shafts import ShaftSpec
from ..strength.sizing import LinkStrength, size_links
from ..warnings import DesignWarning


@dataclass(frozen=True, slots=True)
class StrengthChoice:
    """How the machine's parts are made: each bar's ``links`` spec (a bar not listed takes ``default_link``),
    the links' ``limits``, and the joints' and crank shaft's ``parts`` (None: every joint by
    :func:`default_parts`' rules)."""

    default_link: LinkSpec = field(default_factory=lambda: LinkSpec(MATERIALS["S355J2"]))
    links: Mapping[str, LinkSpec] = field(default_factory=dict)
    limits: StrengthLimits = field(default_factory=StrengthLimits)
    parts: PartsSpec | None = None

    def specs(self, bars: tuple[str, ...]) -> dict[str, LinkSpec]:
        """Every bar's spec."""
        return {name: self.links.get(name, self.default_link) for name in bars}


@dataclass(frozen=True, slots=True)
class MachineStrength:
    """The parts of the machine as built: ``sizing`` the links' fixed point (on the linkage before balancing),
    ``links`` each bar checked on the machine as built, ``parts`` the joints' and the crank shaft's; ``checks``
    every part's, links first."""

    sizing: LinkStrength
    links: dict[str, LinkSizing]
    parts: Parts
    checks: tuple[PartCheck, ...]
    warnings: tuple[DesignWarning, ...] = ()

    @property
    def link_mass(self) -> float:
        """The sized bars [kg]."""
        return sum(s.mass for s in self.links.values())


def size_machine_links(choice: StrengthChoice, linkage: Linkage, speed: float, samples: int) -> LinkStrength:
    """The links of the machine's linkage sized to the fixed point (every bar)."""
    probe = analyse(linkage, speed, samples=min(samples, 8))
    return size_links(linkage, speed, choice.specs(beam_links(probe)), choice.limits, samples=samples)


def default_crank_shaft(analysis: Analysis) -> CrankShaftSpec:
    """The crank shaft laid out from the crank length r: bearings r apart, the crank overhung r/2 beyond bearing
    B, the coupling midway; 42CrMo4 quenched and tempered; crank and coupling hubs r long, keyed at half the
    shaft's yield strength."""
    r = analysis.linkage.mechanism.crank
    material = MATERIALS["42CrMo4+QT"]
    layout = CrankShaftLayout(span=r, crank_position=1.5 * r, drive_position=0.5 * r)
    keys = tuple(HubKeySpec(hub, r, material.yield_strength / 2.0) for hub in ("crank", "coupling"))
    return CrankShaftSpec(layout, material, ShaftSpec(span=r), keys=keys)


def default_parts(analysis: Analysis) -> PartsSpec:
    """Every joint a C45 pin in a clevis on an oil-impregnated bronze bushing, and the default crank shaft."""
    return PartsSpec(JointPartSpec(MATERIALS["C45E+QT"]), crank_shaft=default_crank_shaft(analysis))


def _link_checks(s: LinkSizing) -> list[PartCheck]:
    out = []
    for c in s.checks:
        safety = c.safety if math.isfinite(c.safety) else 1e300
        out.append(PartCheck(f"link {s.link}", f"link_{c.name}", safety, c.required, "1",
                             f"least factor of safety of link {s.link!r} ({s.section.label}) over the cycle, "
                             f"{c.method}, at {math.degrees(c.phi):.1f} deg, {c.x * 1e3:.0f} mm along it",
                             at_least=True))
    return out


def parts_of_machine(choice: StrengthChoice, sizing: LinkStrength, built: Analysis) -> MachineStrength:
    """Every part checked or sized on ``built``, the analysis of the machine as built (balanced)."""
    specs = choice.specs(tuple(sizing.links))
    # each bar as sized, checked under the machine's loads as built (a counterweight's arm, beyond the bar,
    # checked with the bar's section); its mass stays the sized bar's, the one the analysis used
    links = {name: dataclasses.replace(size_link(beam_forces(built, name),
                                                 dataclasses.replace(specs[name], section=s.section), choice.limits),
                                       sized=s.sized, mass_props=s.mass_props)
             for name, s in sizing.links.items()}
    spec = choice.parts if choice.parts is not None else default_parts(built)
    if spec.crank_shaft is None:
        spec = dataclasses.replace(spec, crank_shaft=default_crank_shaft(built))
    parts = size_parts(built, spec)
    checks = [c for s in links.values() for c in _link_checks(s)] + list(parts.checks)
    warnings = list(parts.warnings)
    warnings += [DesignWarning("check_failed", "strength", c.value,
                               f"{c.part} fails its {c.name} check ({c.value:.4g} against {c.limit:.4g}): "
                               f"{c.meaning}", c.unit, stage="strength")
                 for c in checks if not c.passed]
    return MachineStrength(sizing, links, parts, tuple(checks), tuple(warnings))
