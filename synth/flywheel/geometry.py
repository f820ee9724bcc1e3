"""What the flywheel looks like and where it goes: rim or solid disc, on the crank shaft or a faster one.

A flywheel of inertia J on the crank does the same on a shaft turning r times faster with J/r² (seed 002:201-204).
For each shaft the least-mass body within the diameter, rim-speed (or stress) and proportion limits has a closed
form: a disc is as wide as its limits allow; a rim's best thickness ratio lies at an end of its range or where the
binding limit changes, the roots of a quintic. A bound first tells whether the shaft can hold the flywheel at all
and names the limit that binds when it cannot.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import numpy.typing as npt

from ..errors import Infeasible, InvalidInput


def rim_diameter(inertia: float, density: float, k1: float, k2: float) -> float:
    """Mean diameter [m] of a thin rim a = k1·D by b = k2·D with moment of inertia ``inertia`` [kg·m²].

    D = [4·J/(π·rho·k1·k2)]^(1/5) from m = rho·π·D·a·b and J = m·D²/4, ``density`` rho [kg/m³]
    (seed 002:195-206; the seed's formula (11) is blank and this reconstruction reproduces its 285 mm).
    """
    if inertia <= 0 or density <= 0 or k1 <= 0 or k2 <= 0:
        raise InvalidInput("inertia, density and proportions must be positive", field="geometry")
    return float((4 * inertia / (math.pi * density * k1 * k2)) ** 0.2)


@dataclass(frozen=True, slots=True)
class Shaft:
    """A shaft of the drive that can carry the flywheel: ``speed_ratio`` = its speed over the crank's [-]."""

    name: str
    speed_ratio: float


@dataclass(frozen=True, slots=True)
class GeometrySpec:
    """Material, limits and candidate shafts of the flywheel.

    ``density`` [kg/m³] (cast iron 7200, steel 7850); ``max_rim_speed`` at the outer radius [m/s] (cast iron
    25-30, steel higher) and/or ``allowable_stress`` [Pa] (thin rim: rho·v²; solid disc: (3 + nu)/8·rho·v² at
    the centre); ``max_diameter`` outer [m]; ``thickness_ratio`` a/D and ``width_ratio`` b/D ranges [-];
    ``shafts`` the candidates (the crank shaft, ratio 1, is always one of them).
    """

    shape: Literal["rim", "disc"] = "rim"
    density: float = 7200.0
    max_rim_speed: float | None = 30.0
    allowable_stress: float | None = None
    poisson: float = 0.3
    max_diameter: float | None = None
    thickness_ratio: tuple[float, float] = (0.1, 0.2)
    width_ratio: tuple[float, float] = (0.1, 0.2)
    shafts: tuple[Shaft, ...] = ()

    def __post_init__(self) -> None:
        if self.density <= 0:
            raise InvalidInput("density must be positive", field="geometry.density_kg_m3")
        for name, (lo, hi) in (("thickness_ratio", self.thickness_ratio), ("width_ratio", self.width_ratio)):
            if not 0 < lo <= hi:
                raise InvalidInput(f"{name} must be a range 0 < min <= max", field=f"geometry.{name}")
        for shaft in self.shafts:
            if not shaft.speed_ratio > 0:
                raise InvalidInput(f"shaft {shaft.name!r} needs a positive speed ratio", field="geometry.shafts")

    def speed_limit(self) -> tuple[float, str]:
        """Largest outer-rim speed [m/s] and the limit that sets it."""
        limits = [(math.inf, "")]
        if self.max_rim_speed is not None:
            limits.append((self.max_rim_speed, "max_rim_speed_m_s"))
        if self.allowable_stress is not None:
            factor = 1.0 if self.shape == "rim" else (3 + self.poisson) / 8
            limits.append((math.sqrt(self.allowable_stress / (factor * self.density)), "allowable_stress_Pa"))
        return min(limits)

    def candidates(self) -> tuple[Shaft, ...]:
        """The crank shaft and the given shafts."""
        given = tuple(s for s in self.shafts if s.name != "crank")
        return (Shaft("crank", 1.0),) + given


@dataclass(frozen=True, slots=True)
class FlywheelBody:
    """One flywheel on one shaft: inertia on that shaft [kg·m²], dimensions [m], mass [kg], rim speed [m/s].

    ``diameter`` is the rim's mean diameter (the disc's outer one); ``thickness`` the rim's radial thickness
    (None for a disc); ``inertia_check`` the inertia recomputed from the dimensions [kg·m²].
    """

    shaft: str
    speed_ratio: float
    shape: str
    inertia: float
    diameter: float
    outer_diameter: float
    thickness: float | None
    width: float
    mass: float
    rim_speed: float
    inertia_check: float


@dataclass(frozen=True, slots=True)
class PlacementMiss:
    """A shaft that cannot carry the flywheel, the limit that binds [name] and the largest inertia it allows."""

    shaft: str
    speed_ratio: float
    constraint: str
    max_inertia: float


@dataclass(frozen=True, slots=True)
class FlywheelDesign:
    """Every candidate shaft's outcome and the least-mass body among them."""

    bodies: tuple[FlywheelBody, ...]
    misses: tuple[PlacementMiss, ...]
    best: FlywheelBody


def _inertia(shape: str, density: float, d: float, a: float, b: float) -> float:
    if shape == "rim":
        return density * math.pi * b * d * a * (d * d + a * a) / 4
    return density * math.pi * b * d**4 / 32


_RIM_PEAK = float(next(r.real for r in np.roots([-2.0, 3.0, -4.0, 1.0]) if abs(r.imag) < 1e-12))


def _largest(spec: GeometrySpec, outer_limit: float) -> float:
    """Largest inertia [kg·m²] within an outer diameter: the greatest width ratio and, for a rim, the thickness
    ratio in range that makes t(1 + t²)/(1 + t)⁵ largest (it peaks where 1 - 4t + 3t² - 2t³ = 0, t ≈ 0.307)."""
    k2 = spec.width_ratio[1]
    if spec.shape == "rim":
        t = min(max(_RIM_PEAK, spec.thickness_ratio[0]), spec.thickness_ratio[1])
        d = outer_limit / (1 + t)
        return _inertia("rim", spec.density, d, t * d, k2 * d)
    return _inertia("disc", spec.density, outer_limit, 0.0, k2 * outer_limit)


def _disc(rho: float, inertia: float, k2: tuple[float, float], outer_limit: float) -> tuple[float, float, float]:
    # m = 8J/D² falls as D grows: the widest disc the outer limit and the least width ratio allow
    d = min(outer_limit, (32 * inertia / (math.pi * rho * k2[0])) ** 0.2)
    return d, 0.0, min(32 * inertia / (math.pi * rho * d**4), k2[1] * d)


def _rim(rho: float, inertia: float, k1: tuple[float, float], k2: tuple[float, float],
         outer_limit: float) -> tuple[float, float, float]:
    # With a = t·D the inertia holds at m = 4J/(D²(1 + t²)): the lightest rim makes D²(1 + t²) largest. At a
    # given t, D is the least of L/(1 + t) and the diameter at the least width ratio, (C_lo/(t(1 + t²)))^(1/5);
    # it exists when the width it leaves is within the greatest ratio. Both pieces of H(t) = D(t)²(1 + t²) are
    # quasiconvex in t > 0, so on every stretch where the binding piece and the feasibility do not change the
    # largest H lies at the stretch's ends: the range's ends and the roots of L⁵·t(1 + t²) = C·(1 + t)⁵.
    c_lo, c_hi = (4 * inertia / (math.pi * rho * k) for k in k2)

    def diameter(t: float) -> float:
        return min(outer_limit / (1 + t), float((c_lo / (t * (1 + t * t))) ** 0.2))

    # the thickness of the greatest capacity is feasible whenever the caller's bound let the shaft through
    candidates = [*k1, min(max(_RIM_PEAK, k1[0]), k1[1])]
    if math.isfinite(outer_limit):
        l5 = outer_limit**5
        # L⁵(t + t³) - C(1 + t)⁵, highest power first
        for roots in _roots([[-c, -5 * c, l5 - 10 * c, -10 * c, l5 - 5 * c, -c] for c in (c_lo, c_hi)]):
            candidates += [float(r.real) for r in roots
                           if abs(r.imag) <= 1e-9 * (1 + abs(r)) and k1[0] < r.real < k1[1]]
    feasible = [t for t in candidates if diameter(t) ** 5 * t * (1 + t * t) >= c_hi * (1 - 1e-9)]
    t = max(feasible, key=lambda t: diameter(t) ** 2 * (1 + t * t))
    d = diameter(t)
    b = 4 * inertia / (math.pi * rho * d**4 * t * (1 + t * t))
    return d, t * d, min(max(b, k2[0] * d), k2[1] * d)


def _roots(polynomials: list[list[float]]) -> list[npt.NDArray[np.inexact[Any]]]:
    """The roots of each polynomial (highest power first) as :func:`numpy.roots` finds them, the eigenvalues of
    its companion matrix, for all of them in one LAPACK call when none has a zero first or last coefficient."""
    p = np.asarray(polynomials, dtype=float)
    if not np.all(p[:, 0] != 0) or not np.all(p[:, -1] != 0):
        return [np.roots(row) for row in p]
    k, n = p.shape[0], p.shape[1] - 1
    companion = np.zeros((k, n, n))
    companion[:, np.arange(1, n), np.arange(n - 1)] = 1.0
    companion[:, 0, :] = -p[:, 1:] / p[:, :1]
    return list(np.linalg.eigvals(companion))


def _least_mass(spec: GeometrySpec, inertia: float, outer_limit: float) -> tuple[float, float, float]:
    """Mean (or outer) diameter, thickness and width [m] of the lightest body of ``inertia`` [kg·m²] whose outer
    diameter is at most ``outer_limit`` [m], in closed form; the caller has checked that one exists."""
    if spec.shape == "rim":
        return _rim(spec.density, inertia, spec.thickness_ratio, spec.width_ratio, outer_limit)
    return _disc(spec.density, inertia, spec.width_ratio, outer_limit)


def design_flywheel(
    inertia: float, spec: GeometrySpec, crank_speed_max: float
) -> FlywheelDesign:
    """The least-mass flywheel of crank-shaft inertia ``inertia`` [kg·m²] over the candidate shafts.

    ``crank_speed_max`` [rad/s] is the crank's largest speed in the cycle (it sets the rim speed). Raises
    Infeasible naming the binding limit when no shaft can carry it.
    """
    if not inertia > 0:
        raise InvalidInput("the flywheel inertia must be positive to give it a shape", field="geometry")
    v_lim, v_name = spec.speed_limit()
    if not math.isfinite(v_lim) and spec.max_diameter is None:
        raise InvalidInput(
            "give a rim-speed, stress or diameter limit: without one the lightest flywheel grows without bound",
            field="geometry.max_diameter_m",
        )
    bodies: list[FlywheelBody] = []
    misses: list[PlacementMiss] = []
    for shaft in spec.candidates():
        j_shaft = inertia / shaft.speed_ratio**2
        w_shaft = crank_speed_max * shaft.speed_ratio
        limits = [(2 * v_lim / w_shaft, v_name)] if math.isfinite(v_lim) else []
        if spec.max_diameter is not None:
            limits.append((spec.max_diameter, "max_diameter_m"))
        outer_limit, binding = min(limits) if limits else (math.inf, "")
        if math.isfinite(outer_limit) and _largest(spec, outer_limit) < j_shaft:
            misses.append(PlacementMiss(shaft.name, shaft.speed_ratio, binding, _largest(spec, outer_limit)))
            continue
        d, a, b = _least_mass(spec, j_shaft, outer_limit)
        outer = d + a
        mass = spec.density * math.pi * (d * a * b if spec.shape == "rim" else d * d * b / 4)
        bodies.append(
            FlywheelBody(
                shaft=shaft.name,
                speed_ratio=shaft.speed_ratio,
                shape=spec.shape,
                inertia=j_shaft,
                diameter=d,
                outer_diameter=outer,
                thickness=a if spec.shape == "rim" else None,
                width=b,
                mass=mass,
                rim_speed=0.5 * outer * w_shaft,
                inertia_check=_inertia(spec.shape, spec.density, d, a, b),
            )
        )
    if not bodies:
        # the fastest shaft holds the most; its limit is the one to relax
        worst = max(misses, key=lambda m: m.max_inertia * m.speed_ratio**2)
        raise Infeasible(
            f"no shaft can carry a flywheel of {inertia:.6g} kg·m² on the crank within the {worst.constraint} limit",
            constraint=f"geometry.{worst.constraint}",
            largest_crank_inertia_kgm2=worst.max_inertia * worst.speed_ratio**2,
            shaft=worst.shaft,
        )
    return FlywheelDesign(tuple(bodies), tuple(misses), min(bodies, key=lambda bd: bd.mass))
