"""Materials of the machine's parts: strength limits, stiffness and density, each with its source.

The shipped table holds a few common grades at indicative figures (minimum values of the product standards, the
fatigue limit of a polished rotating-beam specimen estimated as Shigley's S'e = 0.5 Rm for steels); a user's
material carries every limit itself or is refused, so no check ever runs against a guessed limit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import InvalidInput

MPA = 1e6
GPA = 1e9


@dataclass(frozen=True, slots=True)
class Material:
    """One material: yield and ultimate strength, fatigue limit of the polished specimen S'e [Pa], Young's
    modulus [Pa], density [kg/m³] and where the figures come from."""

    name: str
    yield_strength: float
    ultimate_strength: float
    fatigue_limit: float
    elastic_modulus: float
    density: float
    source: str = "user"

    def validate(self, where: str = "material") -> Material:
        """Raise InvalidInput naming the field for a missing, non-positive or inconsistent limit."""
        for label, value in (("yield_strength_MPa", self.yield_strength),
                             ("ultimate_strength_MPa", self.ultimate_strength),
                             ("fatigue_limit_MPa", self.fatigue_limit),
                             ("elastic_modulus_GPa", self.elastic_modulus),
                             ("density_kg_m3", self.density)):
            if not (math.isfinite(value) and value > 0):
                raise InvalidInput(f"{where}: {label} must be a positive finite number, got {value!r}",
                                   field=f"{where}.{label}")
        if self.yield_strength > self.ultimate_strength:
            raise InvalidInput(f"{where}: the yield strength {self.yield_strength / MPA:g} MPa exceeds the "
                               f"ultimate strength {self.ultimate_strength / MPA:g} MPa",
                               field=f"{where}.yield_strength_MPa")
        if self.fatigue_limit > self.ultimate_strength:
            raise InvalidInput(f"{where}: the fatigue limit {self.fatigue_limit / MPA:g} MPa exceeds the "
                               f"ultimate strength {self.ultimate_strength / MPA:g} MPa",
                               field=f"{where}.fatigue_limit_MPa")
        return self


def _steel(name: str, re_mpa: float, rm_mpa: float, source: str) -> Material:
    return Material(name, re_mpa * MPA, rm_mpa * MPA, 0.5 * rm_mpa * MPA, 210 * GPA, 7850.0,
                    f"{source}; S'e = 0.5 Rm (Shigley, Mechanical Engineering Design, eq. 6-8)")


#: Indicative minimum figures; check them against the material certificate of the part's size.
MATERIALS: dict[str, Material] = {
    m.name: m for m in (
        _steel("S235JR", 235, 360, "EN 10025-2, thickness <= 16 mm: ReH >= 235 MPa, Rm 360-510 MPa"),
        _steel("S355J2", 355, 470, "EN 10025-2, thickness <= 16 mm: ReH >= 355 MPa, Rm 470-630 MPa"),
        _steel("C45E+N", 340, 620, "EN 10083-2, normalised, 16 < d <= 100 mm: ReH >= 340 MPa, Rm >= 620 MPa"),
        _steel("C45E+QT", 430, 650, "EN 10083-2, quenched and tempered, 40 < d <= 100 mm: Re >= 430 MPa, "
               "Rm 650-800 MPa"),
        _steel("42CrMo4+QT", 650, 900, "EN 10083-3, quenched and tempered, 40 < d <= 100 mm: Re >= 650 MPa, "
               "Rm 900-1100 MPa"),
        Material("EN AW-6082-T6", 250 * MPA, 290 * MPA, 95 * MPA, 70 * GPA, 2700.0,
                 "EN 755-2, extruded bar T6: Rp0.2 >= 250 MPa, Rm >= 290 MPa; fatigue strength at 5e8 cycles "
                 "about 95 MPa (aluminium has no true fatigue limit)"),
    )
}


def material(name: str, where: str = "material") -> Material:
    """The shipped material ``name``; InvalidInput naming the known ones otherwise."""
    try:
        return MATERIALS[name]
    except KeyError:
        raise InvalidInput(f"{where}: unknown material {name!r}; the table has {sorted(MATERIALS)}; or give "
                           "yield, ultimate and fatigue limits, Young's modulus and density", field=where) from None
