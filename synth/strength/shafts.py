"""A machine shaft between two bearings sized for fatigue over the cycle: the crank shaft and each gear shaft.

Inputs: :class:`ShaftLoad` items, each at an axial position z along the shaft [m] (bearings A at z = 0 and B at
z = ``span``; a load may overhang), with its transverse force over the cycle in the frame of the page, shape
(N, 2) [N], a concentrated bending moment (N, 2) [N·m] (a helical gear's axial force at its pitch radius), an
axial force (N,) [N] and the torque it puts on the shaft (N,) [N·m]; :func:`gear_mesh_forces` makes the load of a
gear from its torque; the shaft's material (:class:`synth.strength.materials.Material`), surface and notches.
Output: :func:`size_shaft` gives a :class:`ShaftResult`: the least diameter for the design factor, the standard
diameter chosen, the fatigue and yield factors of safety at it and at every section, the bending moment and torque
over the cycle at each section, and the bearing reactions over the cycle (N, 2) [N] for :mod:`.bearings`.

Method: Shigley's DE-Goodman (Budynas & Nisbett, *Shigley's Mechanical Engineering Design*, §7-4, eqs. 7-7 and
7-8): 1/n = 16/(pi d³) [ (4 (Kf Ma)² + 3 (Kfs Ta)²)^½ / Se + (4 (Kf Mm)² + 3 (Kfs Tm)²)^½ / Sut ], the
endurance limit Se at the part by Marin (surface, size by the diameter itself, reliability; :mod:`.fatigue`),
solved for d by successive trials on the size factor as Shigley does; the first-cycle yield by the von Mises
stress's peak over the cycle, n_y = Sy / sigma'_max (eq. 7-15, here the history's true peak).

The bending stress a surface fibre sees comes from the moment vector at the section and the fibre's angle: a shaft
that turns a whole number of times per crank cycle (the crank shaft) carries its fibres through the same history
every cycle, so each of 72 fibres' own range and mean is used; any other shaft (a gear shaft at a ratio) sees every
fibre pass every direction of the load, so the bending is taken fully reversed at the peak moment (Shigley's
rotating shaft, Ma = |M|max, Mm = 0). Torque's range and mean come from its history.

Where it stops: notch factors are Shigley's first-iteration estimates (Table 7-1: a shoulder fillet at the bearings,
an end-milled keyseat under a hub) taken as Kf = Kt unless given; no deflection, slope or critical speed check;
bearings are simple supports; the axial force is carried by bearing A and left out of the stresses (small in a
shaft) and out of the bearings' lives (``shaft_axial_load`` warns).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ..errors import Infeasible, InvalidInput
from ..model import FloatArray
from ..warnings import DesignWarning
from .checks import PartCheck
from .fatigue import reliability_factor, size_factor, surface_factor
from .materials import Material

#: Shigley Table 7-1, first-iteration stress-concentration factors (Kt bending, Kts torsion).
NOTCHES: dict[str, tuple[float, float]] = {
    "none": (1.0, 1.0),
    "shoulder_sharp": (2.7, 2.2),
    "shoulder_rounded": (1.7, 1.5),
    "keyseat_end_mill": (2.14, 3.0),
    "keyseat_sled_runner": (1.7, 3.0),
    "retaining_ring_groove": (5.0, 3.0),
}
#: Standard shaft diameters [m]: rolling-bearing bores (10..17 mm, then every 5 mm) up to 500 mm.
STANDARD_SHAFT_DIAMETERS: tuple[float, ...] = tuple(d / 1000.0 for d in (10, 12, 15, 17, *range(20, 505, 5)))
_FIBRES = 72


@dataclass(frozen=True, slots=True)
class ShaftLoad:
    """One load on the shaft at ``position`` z [m] from bearing A: ``force`` transverse (N, 2) [N] in the page
    frame, ``moment`` concentrated bending moment (N, 2) [N·m] or None, ``axial`` (N,) [N] or None, ``torque``
    put on the shaft about its axis (N,) [N·m] or None; ``notch`` the section's notch under it (Table 7-1 name)."""

    name: str
    position: float
    force: FloatArray
    moment: FloatArray | None = None
    axial: FloatArray | None = None
    torque: FloatArray | None = None
    notch: str = "keyseat_end_mill"


@dataclass(frozen=True, slots=True)
class ShaftSpec:
    """The shaft: ``span`` between bearings A (z = 0) and B [m]; ``turns_per_cycle`` the shaft's revolutions
    per crank cycle (1 for the crank shaft; any ratio for a gear shaft); ``design_factor`` n [-]; ``surface``
    finish for Marin's ka; ``reliability`` for ke; ``bearing_notch`` at the bearing seats (Table 7-1 name);
    ``notch_sensitivity`` q, Kf = 1 + q (Kt - 1) (1 takes Kf = Kt)."""

    span: float
    turns_per_cycle: float = 1.0
    design_factor: float = 2.0
    surface: str = "machined"
    reliability: float = 0.99
    bearing_notch: str = "shoulder_rounded"
    notch_sensitivity: float = 1.0


@dataclass(frozen=True, slots=True)
class ShaftSection:
    """One checked section at ``position`` z [m] with its notch factors ``kf``, ``kfs``; over the cycle
    ``moment`` (N, 2) [N·m] and ``torque`` (N,) [N·m]; at the chosen diameter ``fatigue_safety`` (DE-Goodman) and
    ``yield_safety`` [-]; ``diameter_required`` the least diameter this section alone needs [m]."""

    name: str
    position: float
    kf: float
    kfs: float
    moment: FloatArray
    torque: FloatArray
    diameter_required: float
    fatigue_safety: float = math.inf
    yield_safety: float = math.inf


@dataclass(frozen=True, slots=True)
class ShaftResult:
    """A sized shaft: ``diameter_required`` [m], ``diameter`` the standard one chosen [m], ``endurance_limit`` Se
    at it [Pa], ``fatigue_safety`` and ``yield_safety`` the least over the sections [-], ``sections`` each checked
    place, ``bearing_a`` and ``bearing_b`` the radial reactions on the bearings over the cycle (N, 2) [N],
    ``axial`` the axial force on bearing A (N,) [N], ``checks`` and ``warnings``."""

    shaft: str
    diameter_required: float
    diameter: float
    endurance_limit: float
    fatigue_safety: float
    yield_safety: float
    sections: tuple[ShaftSection, ...]
    bearing_a: FloatArray
    bearing_b: FloatArray
    axial: FloatArray
    checks: tuple[PartCheck, ...]
    warnings: tuple[DesignWarning, ...] = field(default=())


def gear_mesh_forces(
    torque: ArrayLike,
    pitch_radius: float,
    mesh_angle: float,
    *,
    pressure_angle: float = math.radians(20.0),
    helix_angle: float = 0.0,
    hand: int = 1,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The mesh's forces on a gear that puts ``torque`` (N,) [N·m] (counter-clockwise positive, seen from +z)
    into its shaft: the transverse force (N, 2) [N], the bending moment of the axial force at the pitch radius
    (N, 2) [N·m] and the axial force (N,) [N].

    ``pitch_radius`` r [m]; ``mesh_angle`` direction from this gear's axis to the mating gear's [rad];
    ``pressure_angle`` alpha_n normal [rad]; ``helix_angle`` beta [rad]; ``hand`` +1 or -1 sets the axial force's
    sign. Tangential W_t = T/r, radial W_r = |W_t| tan(alpha_n)/cos(beta) toward this gear's axis, axial
    W_a = W_t tan(beta) (Shigley §13-16, eqs. 13-40).
    """
    t = np.asarray(torque, dtype=float)
    if not (math.isfinite(pitch_radius) and pitch_radius > 0.0):
        raise InvalidInput(f"a gear's pitch radius must be positive, got {pitch_radius!r}", field="pitch_radius")
    if not (0.0 <= helix_angle < math.radians(45.0)) or not (0.0 < pressure_angle < math.radians(45.0)):
        raise InvalidInput("a gear's helix angle must be in [0, 45) deg and its pressure angle in (0, 45) deg",
                           field="helix_angle")
    e = np.array([math.cos(mesh_angle), math.sin(mesh_angle)])
    tangent = np.array([-e[1], e[0]])
    wt = t / pitch_radius
    wr = np.abs(wt) * math.tan(pressure_angle) / math.cos(helix_angle)
    force = wt[:, None] * tangent[None, :] - wr[:, None] * e[None, :]
    wa = float(np.sign(hand)) * wt * math.tan(helix_angle)
    # The axial force at the pitch point r e: moment r e x (0, 0, W_a) = r W_a (e_y, -e_x).
    moment = (pitch_radius * wa)[:, None] * np.array([e[1], -e[0]])[None, :]
    return force, moment, wa


def gear_shaft_loads(
    torque: ArrayLike,
    gear: tuple[float, float, float],
    pinion: tuple[float, float, float],
    *,
    pressure_angle: float = math.radians(20.0),
    helix_angle: float = 0.0,
) -> list[ShaftLoad]:
    """The loads on an intermediate shaft of a gear train: its ``gear`` takes ``torque`` (N,) [N·m] from the
    stage before and its ``pinion`` hands it on; each given as (axial position [m], pitch radius [m], mesh
    direction to its mate [rad]). The same helix angle and hand on both, as a countershaft is built so that the
    driven gear's and the driving pinion's thrusts oppose (Shigley §13-16)."""
    t = np.asarray(torque, dtype=float)
    loads = []
    for name, (z, r, angle), sign in (("gear", gear, 1.0), ("pinion", pinion, -1.0)):
        force, moment, axial = gear_mesh_forces(sign * t, r, angle, pressure_angle=pressure_angle,
                                                helix_angle=helix_angle)
        loads.append(ShaftLoad(name, z, force, moment=moment, axial=axial, torque=sign * t))
    return loads


def _notch(name: str, where: str) -> tuple[float, float]:
    try:
        return NOTCHES[name]
    except KeyError:
        raise InvalidInput(f"{where}: unknown notch {name!r}; one of {sorted(NOTCHES)}", field=where) from None


def bearing_reactions(loads: Sequence[ShaftLoad], span: float) -> tuple[FloatArray, FloatArray]:
    """Radial reactions of bearings A (z = 0) and B (z = span) on the shaft over the cycle, (N, 2) each [N], from
    the shaft's equilibrium of forces and of bending moments about A."""
    fz = sum((ld.position * ld.force for ld in loads), start=np.zeros_like(loads[0].force))
    f = sum((ld.force for ld in loads), start=np.zeros_like(loads[0].force))
    m = sum((ld.moment for ld in loads if ld.moment is not None), start=np.zeros_like(loads[0].force))
    # Moments about A: e_z x (span R_B + sum z F) + sum M = 0, with e_z x v = (-v_y, v_x).
    rb = np.stack([-(fz[:, 0] + m[:, 1]) / span, (m[:, 0] - fz[:, 1]) / span], axis=1)
    ra = -f - rb
    return ra, rb


def _internal(loads: Sequence[ShaftLoad], ra: FloatArray, rb: FloatArray, span: float, z: float, inclusive: bool
              ) -> tuple[FloatArray, FloatArray]:
    """Bending moment (N, 2) and torque (N,) carried by the section at z from everything on its left (bearing
    reactions included)."""
    n = ra.shape[0]
    moment = np.zeros((n, 2))
    torque = np.zeros(n)
    items = [(0.0, ra, None, None), (span, rb, None, None),
             *((ld.position, ld.force, ld.moment, ld.torque) for ld in loads)]
    for zj, fj, mj, tj in items:
        if zj < z or (inclusive and zj == z):
            arm = zj - z
            # moment about the section's centre of the force at z_j: (z_j - z) e_z x F = (z_j - z)(-F_y, F_x)
            moment += arm * np.stack([-fj[:, 1], fj[:, 0]], axis=1)
            if mj is not None:
                moment += mj
            if tj is not None:
                torque += tj
    return -moment, -torque


def _fibre_amplitude_mean(moment: FloatArray, turns_per_cycle: float) -> tuple[FloatArray, FloatArray]:
    """Bending moment amplitude and mean seen by each surface fibre [N·m], shape (F,); one fully reversed entry
    at the peak moment for a shaft that does not turn a whole number of times per cycle."""
    k = turns_per_cycle
    if abs(k - round(k)) > 1e-9:
        return np.array([float(np.hypot(moment[:, 0], moment[:, 1]).max())]), np.array([0.0])
    n = moment.shape[0]
    return _fixed_fibres(moment, round(k) * 2.0 * math.pi * np.arange(n) / n)


def _fixed_fibres(moment: FloatArray, theta: FloatArray) -> tuple[FloatArray, FloatArray]:
    psi = np.linspace(0.0, 2.0 * math.pi, _FIBRES, endpoint=False)
    alpha = theta[:, None] + psi[None, :]
    # Normal stress at the fibre at angle alpha: (M_x sin(alpha) - M_y cos(alpha)) 32/(pi d³).
    m = moment[:, 0, None] * np.sin(alpha) - moment[:, 1, None] * np.cos(alpha)
    hi, lo = m.max(axis=0), m.min(axis=0)
    return 0.5 * (hi - lo), 0.5 * np.abs(hi + lo)


def _demand(ma: FloatArray, mm: FloatArray, torque: FloatArray, kf: float, kfs: float, endurance: float,
            ultimate: float) -> float:
    """max over the fibres of (A/Se + B/Sut) of Shigley eq. 7-8 [N·m/Pa]."""
    ta = 0.5 * float(torque.max() - torque.min())
    tm = 0.5 * abs(float(torque.max() + torque.min()))
    a = np.sqrt(4.0 * (kf * ma) ** 2 + 3.0 * (kfs * ta) ** 2)
    b = np.sqrt(4.0 * (kf * mm) ** 2 + 3.0 * (kfs * tm) ** 2)
    return float(np.max(a / endurance + b / ultimate))


def de_goodman_diameter(ma: ArrayLike, mm: ArrayLike, ta: float, tm: float, kf: float, kfs: float,
                        endurance: float, ultimate: float, design_factor: float) -> float:
    """Shigley eq. 7-8: d = (16 n/pi [A/Se + B/Sut])^(1/3) [m] for bending amplitude and mean ``ma``, ``mm``
    [N·m] (arrays: the largest over them) and torque amplitude and mean ``ta``, ``tm`` [N·m]."""
    a = np.sqrt(4.0 * (kf * np.asarray(ma, dtype=float)) ** 2 + 3.0 * (kfs * ta) ** 2)
    b = np.sqrt(4.0 * (kf * np.asarray(mm, dtype=float)) ** 2 + 3.0 * (kfs * tm) ** 2)
    return float((16.0 * design_factor / math.pi * np.max(a / endurance + b / ultimate)) ** (1.0 / 3.0))


def de_goodman_safety(ma: float, mm: float, ta: float, tm: float, kf: float, kfs: float, diameter: float,
                      endurance: float, ultimate: float) -> float:
    """Shigley eq. 7-7: the DE-Goodman factor of safety at ``diameter`` [m] (moments [N·m], strengths [Pa])."""
    a = math.sqrt(4.0 * (kf * ma) ** 2 + 3.0 * (kfs * ta) ** 2)
    b = math.sqrt(4.0 * (kf * mm) ** 2 + 3.0 * (kfs * tm) ** 2)
    demand = 16.0 / (math.pi * diameter**3) * (a / endurance + b / ultimate)
    return math.inf if demand == 0.0 else 1.0 / demand


def standard_shaft_diameter(required: float) -> float | None:
    """The smallest standard shaft diameter at least ``required`` [m], None beyond the table."""
    for d in STANDARD_SHAFT_DIAMETERS:
        if d >= required * (1.0 - 1e-12):
            return d
    return None


def size_shaft(shaft: str, loads: Sequence[ShaftLoad], spec: ShaftSpec, material: Material) -> ShaftResult:
    """Size ``shaft`` for fatigue by DE-Goodman and check its first-cycle yield (see the module's docstring).

    Every section under a load (both sides of it) and both bearing seats is checked; the diameter is one for the
    whole shaft, the largest any section needs. :class:`Infeasible` names the shaft when no standard diameter
    up to 500 mm reaches the design factor.
    """
    _validate(shaft, loads, spec, material)
    ra, rb = bearing_reactions(loads, spec.span)
    q = spec.notch_sensitivity
    sections: list[tuple[str, float, float, float, FloatArray, FloatArray]] = []
    kt_b = _notch(spec.bearing_notch, f"{shaft}.bearing_notch")
    places = [("bearing A", 0.0, kt_b), ("bearing B", spec.span, kt_b)]
    places += [(ld.name, ld.position, _notch(ld.notch, f"{shaft}.{ld.name}.notch")) for ld in loads]
    for name, z, (kt, kts) in places:
        kf, kfs = 1.0 + q * (kt - 1.0), 1.0 + q * (kts - 1.0)
        for side, inclusive in (("left", False), ("right", True)):
            m, t = _internal(loads, ra, rb, spec.span, z, inclusive)
            sections.append((f"{name} ({side})", z, kf, kfs, m, t))
    ka = surface_factor(material.ultimate_strength, spec.surface)
    ke = reliability_factor(spec.reliability)
    fibres = [_fibre_amplitude_mean(m, spec.turns_per_cycle) for _, _, _, _, m, _ in sections]

    def needed(d: float) -> tuple[float, FloatArray]:
        se = ka * size_factor(d) * ke * material.fatigue_limit
        per = np.array([_demand(ma, mm, t, kf, kfs, se, material.ultimate_strength)
                        for (ma, mm), (_, _, kf, kfs, _, t) in zip(fibres, sections)])
        return se, (16.0 * spec.design_factor / math.pi * per) ** (1.0 / 3.0)

    # Successive trials on the size factor (Shigley §7-4): start at kb = 0.9's diameter, stop when d settles.
    d = 0.03
    for _ in range(50):
        _, per_d = needed(d)
        new = float(per_d.max())
        if abs(new - d) <= 1e-9 * max(d, 1e-6):
            d = new
            break
        d = new
    required = max(d, 1e-4)
    chosen = standard_shaft_diameter(required)
    if chosen is None:
        raise Infeasible(f"shaft {shaft}: DE-Goodman needs a diameter of {required * 1e3:.0f} mm, beyond 500 mm",
                         constraint="shaft_fatigue", shaft=shaft, diameter_required_m=required)
    se, per_d = needed(required)
    se_chosen = ka * size_factor(chosen) * ke * material.fatigue_limit
    done: list[ShaftSection] = []
    for (name, z, kf, kfs, m, t), (ma, mm), dreq in zip(sections, fibres, per_d):
        ta = 0.5 * float(t.max() - t.min())
        tm = 0.5 * abs(float(t.max() + t.min()))
        n_f = min(de_goodman_safety(float(a), float(b), ta, tm, kf, kfs, chosen, se_chosen,
                                    material.ultimate_strength) for a, b in zip(ma, mm))
        sigma = 32.0 * kf * np.hypot(m[:, 0], m[:, 1]) / (math.pi * chosen**3)
        tau = 16.0 * kfs * t / (math.pi * chosen**3)
        vm = float(np.max(np.sqrt(sigma**2 + 3.0 * tau**2)))
        n_y = math.inf if vm == 0.0 else material.yield_strength / vm
        done.append(ShaftSection(name, z, kf, kfs, m, t, float(dreq), n_f, n_y))
    n_fat = min(s.fatigue_safety for s in done)
    n_yield = min(s.yield_safety for s in done)
    checks = (
        PartCheck(shaft, "shaft_fatigue_safety", n_fat, spec.design_factor, "1",
                  "DE-Goodman factor of safety at the shaft's worst section (Shigley eq. 7-7)", at_least=True),
        PartCheck(shaft, "shaft_yield_safety", n_yield, spec.design_factor, "1",
                  "first-cycle yield: Sy over the von Mises stress's peak over the cycle", at_least=True),
    )
    axial = sum((ld.axial for ld in loads if ld.axial is not None), start=np.zeros(ra.shape[0]))
    notes: list[DesignWarning] = []
    if float(np.abs(axial).max()) > 0.0:
        notes.append(DesignWarning("shaft_axial_load", shaft, float(np.abs(axial).max()),
                                   f"shaft {shaft} carries up to {float(np.abs(axial).max()):.0f} N axially on "
                                   "bearing A: left out of its stresses and of the bearings' radial lives", "N"))
    return ShaftResult(shaft, required, chosen, se_chosen, n_fat, n_yield, tuple(done), ra, rb, -axial, checks,
                       tuple(notes))


def _validate(shaft: str, loads: Sequence[ShaftLoad], spec: ShaftSpec, material: Material) -> None:
    material.validate(f"{shaft}.material")
    if not loads:
        raise InvalidInput(f"shaft {shaft}: no loads", field=f"{shaft}.loads")
    if not (math.isfinite(spec.span) and spec.span > 0.0):
        raise InvalidInput(f"shaft {shaft}: the bearing span must be positive, got {spec.span!r}",
                           field=f"{shaft}.span")
    if not (math.isfinite(spec.design_factor) and spec.design_factor >= 1.0):
        raise InvalidInput(f"shaft {shaft}: the design factor must be at least 1, got {spec.design_factor!r}",
                           field=f"{shaft}.design_factor")
    if not (0.0 <= spec.notch_sensitivity <= 1.0):
        raise InvalidInput(f"shaft {shaft}: the notch sensitivity must be in [0, 1]",
                           field=f"{shaft}.notch_sensitivity")
    if not math.isfinite(spec.turns_per_cycle):
        raise InvalidInput(f"shaft {shaft}: turns per cycle must be finite", field=f"{shaft}.turns_per_cycle")
    n = np.asarray(loads[0].force).shape[0]
    for ld in loads:
        where = f"{shaft}.{ld.name}"
        if not math.isfinite(ld.position):
            raise InvalidInput(f"{where}: the position must be finite", field=f"{where}.position")
        if np.shape(ld.force) != (n, 2) or not np.all(np.isfinite(ld.force)):
            raise InvalidInput(f"{where}: the force must be finite, shape ({n}, 2)", field=f"{where}.force")
        if ld.moment is not None and (np.shape(ld.moment) != (n, 2) or not np.all(np.isfinite(ld.moment))):
            raise InvalidInput(f"{where}: the moment must be finite, shape ({n}, 2)", field=f"{where}.moment")
        for name in ("axial", "torque"):
            v = getattr(ld, name)
            if v is not None and (np.shape(v) != (n,) or not np.all(np.isfinite(v))):
                raise InvalidInput(f"{where}: the {name} must be finite, shape ({n},)", field=f"{where}.{name}")
