"""Cross-sections of the links: round bar, tube, rectangle of a given height/width ratio and IPE I-sections.

A link moves in the plane x-y, so it bends about the section's axis normal to that plane: the section's
``height`` lies in the plane of motion and ``width`` across it (out of the plane). ``second_moment`` and
``modulus`` are about the in-plane bending axis; ``second_moment_out`` is the one the link buckles about out of
the plane. An I-section stands with its web in the plane (its strong axis carries the in-plane bending).

A family (a shape with one free size) lists its candidates from a series of preferred sizes, lightest first; the
sizing takes the first that passes every check.
"""

from __future__ import annotations

import functools
import math
import sys
from dataclasses import dataclass, field
from typing import Literal

from ..errors import InvalidInput

MM = 1e-3
SectionKind = Literal["round", "tube", "rectangle", "ipe"]

#: Preferred sizes [mm] of round bars, tubes' outer diameters and flat bars' widths (ISO 3 R20/R40 rounded as
#: bar stock is sold).
SIZE_SERIES_MM: tuple[float, ...] = (
    3, 4, 5, 6, 8, 10, 12, 14, 16, 18, 20, 22, 25, 28, 30, 32, 35, 36, 40, 45, 50, 55, 56, 60, 63, 70, 75, 80,
    90, 100, 110, 120, 125, 140, 160, 180, 200, 220, 250)

#: IPE sections of EN 10365 (dimensions [mm]; area [cm²], second moments [cm⁴], elastic moduli [cm³], mass [kg/m]):
#: h, b, tw, tf, r, A, Iy, Wel_y, Iz, Wel_z.
IPE_TABLE: dict[str, tuple[float, ...]] = {
    "IPE 80": (80, 46, 3.8, 5.2, 5, 7.64, 80.1, 20.0, 8.49, 3.69),
    "IPE 100": (100, 55, 4.1, 5.7, 7, 10.3, 171.0, 34.2, 15.9, 5.79),
    "IPE 120": (120, 64, 4.4, 6.3, 7, 13.2, 318.0, 53.0, 27.7, 8.65),
    "IPE 140": (140, 73, 4.7, 6.9, 7, 16.4, 541.0, 77.3, 44.9, 12.3),
    "IPE 160": (160, 82, 5.0, 7.4, 9, 20.1, 869.0, 109.0, 68.3, 16.7),
}


@dataclass(frozen=True, slots=True)
class Section:
    """One cross-section: area [m²], second moments about the in-plane bending axis and the out-of-plane axis
    [m⁴], elastic section modulus for in-plane bending [m³], extents in and across the plane [m], the factor k of
    the largest shear stress tau = k V / A, and Shigley's equivalent diameter for the size factor kb [m]
    (Mechanical Engineering Design, Table 6-3: 0.370 d for a round, 0.808 sqrt(h b) for a rectangle)."""

    kind: SectionKind
    label: str
    area: float
    second_moment: float
    second_moment_out: float
    modulus: float
    height: float
    width: float
    shear_factor: float
    equivalent_diameter: float
    dimensions: dict[str, float] = field(default_factory=dict)

    @property
    def radius_of_gyration(self) -> float:
        """Least radius of gyration sqrt(I_min / A) [m]."""
        return math.sqrt(min(self.second_moment, self.second_moment_out) / self.area)


def round_bar(diameter: float) -> Section:
    """Solid round of ``diameter`` [m]."""
    d = _positive(diameter, "diameter_m")
    i = math.pi * d**4 / 64
    return Section("round", f"round {d / MM:g} mm", math.pi * d * d / 4, i, i, i / (d / 2), d, d, 4 / 3,
                   0.370 * d, {"diameter_m": d})


def tube(outer_diameter: float, wall: float) -> Section:
    """Round tube of ``outer_diameter`` and ``wall`` thickness [m]."""
    d = _positive(outer_diameter, "outer_diameter_m")
    t = _positive(wall, "wall_m")
    if 2 * t >= d:
        raise InvalidInput(f"a tube's wall {t / MM:g} mm is at least half its diameter {d / MM:g} mm",
                           field="section.wall_m")
    di = d - 2 * t
    i = math.pi * (d**4 - di**4) / 64
    return Section("tube", f"tube {d / MM:g}x{t / MM:g} mm", math.pi * (d * d - di * di) / 4, i, i, i / (d / 2),
                   d, d, 2.0, 0.370 * d, {"outer_diameter_m": d, "wall_m": t})


def rectangle(width: float, height: float) -> Section:
    """Flat bar ``width`` across the plane by ``height`` in it [m]."""
    b = _positive(width, "width_m")
    h = _positive(height, "height_m")
    return Section("rectangle", f"flat {h / MM:g}x{b / MM:g} mm", b * h, b * h**3 / 12, h * b**3 / 12, b * h * h / 6,
                   h, b, 1.5, 0.808 * math.sqrt(h * b), {"width_m": b, "height_m": h})


def ipe(name: str) -> Section:
    """An IPE section of EN 10365 by name (``"IPE 80"`` .. ``"IPE 160"``), its web in the plane of motion."""
    try:
        h, b, tw, tf, _r, a, iy, wy, iz, _wz = IPE_TABLE[name]
    except KeyError:
        raise InvalidInput(f"unknown I-section {name!r}; the table has {list(IPE_TABLE)}",
                           field="section.name") from None
    area = a * 1e-4
    # the web carries the shear: tau = V / (tw (h - 2 tf))
    shear = area / (tw * (h - 2 * tf) * MM * MM)
    return Section("ipe", name, area, iy * 1e-8, iz * 1e-8, wy * 1e-6, h * MM, b * MM, shear,
                   0.808 * math.sqrt(h * b) * MM, {"height_m": h * MM, "width_m": b * MM, "web_m": tw * MM,
                                                    "flange_m": tf * MM})


def i_section_properties(h: float, b: float, tw: float, tf: float, r: float) -> tuple[float, float]:
    """Area [m²] and strong-axis second moment [m⁴] of a rolled I from its dimensions [m], the root fillets
    taken as four corners of (4 - pi) r² at the web's toes (their own second moment neglected)."""
    web = h - 2 * tf
    fillet = (4 - math.pi) * r * r
    area = 2 * b * tf + web * tw + fillet
    # fillet centroid: 0.2234 r from the flange's inner face for a (1 - pi/4) r² spandrel
    y_f = web / 2 - 0.2234 * r
    i = b * h**3 / 12 - (b - tw) * web**3 / 12 + fillet * y_f * y_f
    return area, i


@dataclass(frozen=True, slots=True)
class SectionFamily:
    """A shape with one free size: ``kind``, the tube's wall as a fraction of its diameter or the rectangle's
    height/width ratio, and the bounds of the free size [m] (the IPE table bounds itself)."""

    kind: SectionKind = "rectangle"
    ratio: float = 3.0
    min_size: float = 3 * MM
    max_size: float = 250 * MM

    def candidates(self) -> tuple[Section, ...]:
        """Every admissible section of the family, lightest first."""
        return _candidates(self)


# The thinnest wall (of the diameter) or flattest bar (height over width, and its inverse) a family may ask for.
MIN_RATIO = 1e-3


@functools.lru_cache(maxsize=256)
def _candidates(family: SectionFamily) -> tuple[Section, ...]:
    """The family's sections, lightest first (computed once per family: every pass of the sizing asks)."""
    if family.kind == "ipe":
        return tuple(ipe(n) for n in IPE_TABLE)
    if not (math.isfinite(family.ratio) and family.ratio > 0):
        raise InvalidInput(f"section ratio must be positive, got {family.ratio!r}", field="section.ratio")
    if not MIN_RATIO <= family.ratio <= 1 / MIN_RATIO:
        # a wall a thousandth of the tube, a bar a thousand times wider than high: a sheet, not a link (and its
        # second moments underflow for subnormal ratios)
        raise InvalidInput(f"section ratio {family.ratio:g} is outside {MIN_RATIO:g}..{1 / MIN_RATIO:g}",
                           field="section.ratio")
    if family.kind == "tube" and family.ratio >= 0.5:
        raise InvalidInput("a tube's wall/diameter ratio must be below 0.5", field="section.ratio")
    sizes = [s * MM for s in SIZE_SERIES_MM if family.min_size - 1e-12 <= s * MM <= family.max_size + 1e-12]
    if not sizes:
        raise InvalidInput(f"no preferred size between {family.min_size / MM:g} and {family.max_size / MM:g} mm",
                           field="section.min_size_mm")
    if family.kind == "round":
        out = [round_bar(s) for s in sizes]
    elif family.kind == "tube":
        out = [tube(s, family.ratio * s) for s in sizes]
    else:
        out = [rectangle(s, family.ratio * s) for s in sizes]
    return tuple(sorted(out, key=lambda sec: sec.area))


def _positive(value: float, name: str) -> float:
    if not (math.isfinite(value) and value > 0):
        raise InvalidInput(f"section {name} must be a positive finite number, got {value!r}", field=f"section.{name}")
    if not value**4 >= sys.float_info.min:
        # a second moment goes as size⁴: below this it underflows and every stress divides by zero
        raise InvalidInput(f"section {name} {value:g} m is too small to compute with", field=f"section.{name}")
    return float(value)
