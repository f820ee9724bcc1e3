"""Gear materials: ISO 6336-5 allowable stress numbers by grade, and the S-N curves of ISO 6336-2/-3 by group.

The grade table is package data (``materials.json``). A grade's group (St, V, Eh, IF, NT, NV, GGG, GG) selects
its life factors Z_NT and Y_NT, its running-in allowances and its root-notch and roughness sensitivities.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from functools import cache, lru_cache
from importlib import resources
from typing import Any

import numpy as np

from ..errors import InvalidInput
from ..model import FloatArray

MPA = 1e6

SURFACE_HARDENED = frozenset({"Eh", "IF", "NT", "NV"})


@dataclass(frozen=True, slots=True)
class GearMaterial:
    """One material grade.

    ``group`` ISO 6336 material group; ``sigma_Hlim`` contact and ``sigma_Flim`` root endurance limits [Pa];
    ``hardness_HB`` surface hardness [HB]; ``yield_strength`` [Pa]; ``elastic_modulus`` [Pa]; ``poisson`` [-];
    ``density`` [kg/m³].
    """

    name: str
    group: str
    description: str
    sigma_Hlim: float
    sigma_Flim: float
    hardness_HB: float
    yield_strength: float
    elastic_modulus: float
    poisson: float
    density: float

    @property
    def surface_hardened(self) -> bool:
        """Case-hardened, induction/flame hardened or nitrided flanks."""
        return self.group in SURFACE_HARDENED


@cache
def _table() -> dict[str, Any]:
    text = resources.files(__package__).joinpath("materials.json").read_text(encoding="utf-8")
    table: dict[str, Any] = json.loads(text)
    return table


@cache
def _grades() -> dict[str, GearMaterial]:
    # built once: a sizing looks its two grades up for every candidate it rates
    return {
        name: GearMaterial(name, row["group"], row["description"], row["sigma_Hlim_MPa"] * MPA,
                           row["sigma_Flim_MPa"] * MPA, row["hardness_HB"], row["yield_MPa"] * MPA,
                           row["E_MPa"] * MPA, row["poisson"], row["density_kg_m3"])
        for name, row in _table()["grades"].items()
    }


def gear_materials() -> dict[str, GearMaterial]:
    """The shipped material grades by name."""
    return dict(_grades())


def gear_material(name: str, field: str = "material") -> GearMaterial:
    """A grade by name; an unknown name raises InvalidInput naming ``field`` and listing the known grades."""
    known = _grades()
    if name not in known:
        raise InvalidInput(f"unknown gear material {name!r}; known grades: {', '.join(sorted(known))}", field=field)
    return known[name]


# S-N curves as (load cycles, life factor) knots, interpolated linearly in log-log (ISO 6336-2:2006 table 2 and
# ISO 6336-3:2006 table 3; the knee-to-10^10 branch is the "normal" 0.85 line, extended beyond 10^10).
_ZNT = {
    "pitting_permitted": ((6e5, 1.6), (1e7, 1.3), (1e9, 1.0), (1e10, 0.85)),
    "St": ((1e5, 1.6), (5e7, 1.0), (1e10, 0.85)),
    "GG": ((1e5, 1.3), (2e6, 1.0), (1e10, 0.85)),
    "NV_nitrocarburised": ((1e5, 1.1), (2e6, 1.0), (1e10, 0.85)),
}
_ZNT_GROUP = {"St": "St", "V": "St", "Eh": "St", "IF": "St", "GGG": "St", "NT": "GG", "NV": "GG", "GG": "GG"}
_YNT = {
    "V": ((1e4, 2.5), (3e6, 1.0), (1e10, 0.85)),
    "Eh": ((1e3, 2.5), (3e6, 1.0), (1e10, 0.85)),
    "NT": ((1e3, 1.6), (3e6, 1.0), (1e10, 0.85)),
}
_YNT_GROUP = {"St": "V", "V": "V", "GGG": "V", "Eh": "Eh", "IF": "Eh", "NT": "NT", "NV": "NT", "GG": "NT"}


@lru_cache(maxsize=64)
def _curve(knots: tuple[tuple[float, float], ...]) -> tuple[FloatArray, FloatArray]:
    """log N and log factor at the knots (read-only: shared by every call on the same curve)."""
    n = np.log([k[0] for k in knots])
    f = np.log([k[1] for k in knots])
    n.flags.writeable = f.flags.writeable = False
    return n, f


def _life_factor(knots: tuple[tuple[float, float], ...], cycles: FloatArray) -> FloatArray:
    n, f = _curve(knots)
    logn = np.log(np.maximum(np.asarray(cycles, dtype=float), 1.0))
    slope = (f[-1] - f[-2]) / (n[-1] - n[-2])
    inside = np.interp(logn, n, f)          # flat (static value) below the first knot
    beyond = f[-1] + slope * (logn - n[-1])  # the last branch goes on past 10^10
    return np.asarray(np.exp(np.where(logn > n[-1], beyond, inside)), dtype=float)


@lru_cache(maxsize=64)
def _inverse_curve(knots: tuple[tuple[float, float], ...]) -> tuple[FloatArray, FloatArray, float, float, float, float]:
    """What the inverse of a curve needs, once per curve: the knots reversed (log factor ascending), the last
    branch's slope and end, and the static value (with the margin a factor must pass to count as above it)."""
    n, f = _curve(knots)
    slope = (f[-1] - f[-2]) / (n[-1] - n[-2])
    return (np.ascontiguousarray(f[::-1]), np.ascontiguousarray(n[::-1]), float(slope), float(f[-1]), float(n[-1]),
            float(f[0] * (1 + 1e-12)))


def _inverse_life(knots: tuple[tuple[float, float], ...], factor: FloatArray) -> FloatArray:
    """Load cycles at which the life factor equals ``factor``; 0 above the static value, inf never below."""
    f_up, n_up, slope, f_end, n_end, static = _inverse_curve(knots)
    logf = np.maximum(np.asarray(factor, dtype=float), 1e-300)
    np.log(logf, out=logf)
    # f decreases with n: interpolate on the reversed knots; below the last knot the last branch goes on.
    logn = np.interp(logf, f_up, n_up)
    low = logf < f_end
    if low.any():
        beyond = logf - f_end
        beyond /= slope
        beyond += n_end
        np.copyto(logn, beyond, where=low)
    # Beyond ~1e300 cycles a stress does no damage worth counting: clip before exp so nothing overflows.
    np.maximum(logn, -700.0, out=logn)
    np.minimum(logn, 700.0, out=logn)
    np.exp(logn, out=logn)
    logn[logf > static] = 0.0
    return np.asarray(logn, dtype=float)


def contact_life_curve(material: GearMaterial, pitting_permitted: bool = False) -> tuple[tuple[float, float], ...]:
    """Knots (load cycles, Z_NT) of the material's contact S-N curve (ISO 6336-2 table 2)."""
    if pitting_permitted and _ZNT_GROUP[material.group] == "St":
        return _ZNT["pitting_permitted"]
    return _ZNT[_ZNT_GROUP[material.group]]


def root_life_curve(material: GearMaterial) -> tuple[tuple[float, float], ...]:
    """Knots (load cycles, Y_NT) of the material's root S-N curve (ISO 6336-3 table 3)."""
    return _YNT[_YNT_GROUP[material.group]]


def life_factor_contact(material: GearMaterial, cycles: FloatArray | float,
                        pitting_permitted: bool = False) -> FloatArray:
    """Z_NT at ``cycles`` load cycles [-]."""
    return _life_factor(contact_life_curve(material, pitting_permitted), np.asarray(cycles, dtype=float))


def life_factor_root(material: GearMaterial, cycles: FloatArray | float) -> FloatArray:
    """Y_NT at ``cycles`` load cycles [-]."""
    return _life_factor(root_life_curve(material), np.asarray(cycles, dtype=float))


def cycles_to_failure(knots: tuple[tuple[float, float], ...], factor: FloatArray) -> FloatArray:
    """Load cycles the S-N curve allows at a stress of ``factor`` times the endurance-limit stress [-]."""
    return _inverse_life(knots, factor)


# Slip-layer thickness rho' [mm] of the relative notch sensitivity (ISO 6336-3 table 4), by group.
SLIP_LAYER_MM = {"St": 0.0833, "V": 0.0281, "GGG": 0.0314, "Eh": 0.0030, "IF": 0.0030, "NT": 0.1005,
                 "NV": 0.1005, "GG": 0.3095}


def relative_roughness_factor(group: str, rz_um: float) -> float:
    """Y_RrelT for a root roughness Rz < 16 µm (ISO 6336-3 method B) [-]."""
    if group in ("V", "GGG", "Eh", "IF"):
        return float(1.674 - 0.529 * (rz_um + 1) ** 0.1)
    if group == "St":
        return float(5.306 - 4.203 * (rz_um + 1) ** 0.01)
    return float(4.299 - 3.259 * (rz_um + 1) ** 0.005)


def root_size_factor(group: str, module_mm: float) -> float:
    """Y_X for long life (ISO 6336-3 table 5) [-]."""
    if group in ("St", "V", "GGG"):
        return 1.0 if module_mm <= 5 else max(1.03 - 0.006 * module_mm, 0.85)
    if group in ("Eh", "IF", "NT", "NV"):
        return 1.0 if module_mm <= 5 else max(1.05 - 0.01 * module_mm, 0.80)
    return 1.0 if module_mm <= 5 else max(1.075 - 0.015 * module_mm, 0.70)


def running_in(group: str, sigma_Hlim: float, deviation_um: FloatArray | float) -> FloatArray:
    """Running-in allowance y_alpha of a pitch or profile deviation [µm] (ISO 6336-1 §8.3.4) by group."""
    dev = np.asarray(deviation_um, dtype=float)
    if group in ("St", "V", "GGG"):
        return np.asarray(160.0 / (sigma_Hlim / MPA) * dev, dtype=float)
    if group == "GG":
        return np.asarray(0.275 * dev, dtype=float)
    return np.asarray(np.minimum(0.075 * dev, 3.0), dtype=float)


def running_in_helix(group: str, sigma_Hlim: float, deviation_um: FloatArray | float) -> FloatArray:
    """Running-in allowance y_beta of the mesh misalignment [µm] (ISO 6336-1 §7.6.4) by group."""
    dev = np.asarray(deviation_um, dtype=float)
    if group in ("St", "V", "GGG"):
        s = sigma_Hlim / MPA
        return np.asarray(np.minimum(320.0 / s * dev, 25600.0 / s), dtype=float)
    if group == "GG":
        return np.asarray(np.minimum(0.55 * dev, 45.0), dtype=float)
    return np.asarray(np.minimum(0.15 * dev, 6.0), dtype=float)


def running_in_tip_relief(sigma_Hlim: float) -> float:
    """C_ay, the tip relief running-in gives [µm] (ISO 6336-1 §6.5.9)."""
    return (sigma_Hlim / MPA / 97.0 - 18.45) ** 2 / 18.0 + 1.5


def elasticity_factor(m1: GearMaterial, m2: GearMaterial) -> float:
    """Z_E [√(N/mm²)] from both gears' elastic moduli and Poisson ratios (ISO 6336-2 §7)."""
    c = (1 - m1.poisson**2) / (m1.elastic_modulus / MPA) + (1 - m2.poisson**2) / (m2.elastic_modulus / MPA)
    return math.sqrt(1.0 / (math.pi * c))
