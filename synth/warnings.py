"""Likely mistakes in a request or a result: plain checks that return notes, never raise and never ``warnings.warn``.

Each check is a function of engine inputs or results and returns a list of :class:`DesignWarning`. The checks of a
linkage and its analysis live here; each capability keeps the checks of its own results beside them
(:mod:`synth.balancing.warnings`, :mod:`synth.flywheel.warnings`, the drive's notes in :mod:`synth.gearing`), so
this module never imports a capability back. A warning
names the request field it concerns (as the HTTP edge spells it), the number that triggered it in SI units and
a sentence for people. The answer is still given: a warning says "look again", an error says "cannot".

Codes
-----
``length_likely_mm``        a length beyond 10 m: probably millimetres typed as metres
``mass_likely_grams``       a link or counterweight heavier than a solid steel cube the size of the whole machine
``inertia_without_mass``    a link with a moment of inertia but no mass (its weight and inertia force are lost)
``links_missing``           no link has any mass: every inertial output is zero
``link_left_out``           a link that carries the motion has neither mass nor inertia
``counterweight_beyond_link``  a counterweight farther from its joint than the link is long
``transmission_angle_low``  a four-bar's transmission angle under 40° (with the crank angles where it is)
``link_ratio_large``        the longest bar (the frame's pivot distance included) over the shortest beyond 10
``load_work_positive``      the loads do positive work over the cycle: they drive the machine (sign typed wrong?)
``drive_work_negative``     a flywheel's driving torque table does negative work over the cycle (sign typed wrong?)
``delta_out_of_range``      a target delta outside every machine type's usual range
``rim_speed_near_limit``    the flywheel's rim runs at 95 % or more of its speed limit
``redundant_constraint``    a linkage whose pairs repeat constraints (a passive link): it moves though 3n - 2p < 1,
                            and its reactions are statically indeterminate (the least-norm split is given)
``correction_radius_small`` a rotor correction heavier than all the rotor's unbalanced masses together
Gearing adds ``stage_ratio_out_of_range``, ``below_undercut_limit``, ``undercut``, ``representative_catalogue``,
``rotor_inertia_missing``, ``rated_power_exceeds`` and ``stage_not_sized`` (a stage the strength sizing cannot
size: not a cylindrical pair, or no module carries it), ``stage_ratio_at_limit`` (a split at a stage's bound),
``stage_ratio_at_teeth_limit`` (a machine's split at the largest or smallest ratio a tooth pair makes) and
``teeth_far_from_split`` (no train within the room around the split's ratios). A machine design gathers every stage's warnings, each with
its ``stage``, and adds ``motor_replaced`` (a motor the cycle overloads, stepped up) and ``check_failed`` (a target
the simulated machine misses), and ``motor_cannot_start`` (its starting torque through the train below
the torque holding the crank at rest); friction adds ``friction_coefficient_large`` (a coefficient above 1); ``length_likely_mm`` and ``mass_likely_grams`` refuse a machine before its chain.
The parts' strength adds ``bearing_small_oscillation`` (a rolling bearing swinging through less than 5°: its
rating life does not hold), ``bearing_heavy_load`` (a mean load above C/2) and ``shaft_axial_load`` (a helical
mesh's thrust, left out of the shaft's stresses and the bearings' radial lives).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from .kinematics import FourBar, PlanarLinkage, SliderCrank, SlottedLever
from .friction import PairFriction
from .model import Counterweight, FloatArray, Linkage

if TYPE_CHECKING:
    from .analysis import Analysis
    from .kinematics import Mechanism

# A solid steel cube as large as the machine bounds any one link's mass; beyond it the number was typed in grams.
STEEL_DENSITY = 7850.0  # [kg/m³]
LIKELY_MM_LENGTH = 10.0  # [m]
MIN_TRANSMISSION_ANGLE = math.radians(40.0)  # [rad]
# Longest over shortest bar a drawing office builds without a second look: beyond it the short link's bearings
# and the long link's stiffness are designed by the extreme, not by the mechanism.
MAX_LINK_RATIO = 10.0
# The seeds' table spans 1/300 to 1/20; presses, shears and crushers run up to about 1/5.
DELTA_RANGE = (1.0 / 600.0, 0.2)
RIM_SPEED_MARGIN = 0.95
#: Above this a coefficient of friction is accepted with a warning (the seeds' tables stay below 0.5).
LARGE_FRICTION_COEFFICIENT = 1.0


@dataclass(frozen=True, slots=True)
class DesignWarning:
    """A likely mistake: a code, the request field it concerns, the number [SI unit] and a sentence.

    Parameters
    ----------
    code : Stable identifier of the check (see the module docstring).
    field : Request field as the HTTP edge names it (``mechanism.links.crank.mass_kg``), None for the whole answer.
    value : The number that triggered it [``unit``], None when there is none.
    message : One sentence for people.
    unit : Unit of ``value`` (SI: m, kg, kg·m², rad, J, m/s, 1).
    ranges : Crank-angle ranges where it holds [rad], as (start, end) pairs.
    stage : The stage of a machine design that found it (analysis, balancing, drive, teeth, flywheel, motor,
        simulation); None outside a machine design.
    """

    code: str
    field: str | None
    value: float | None
    message: str
    unit: str = ""
    ranges: tuple[tuple[float, float], ...] = ()
    stage: str | None = None


@dataclass(frozen=True, slots=True)
class ValidityCheck:
    """A condition the answer's model needs, held against its limit: where the physics stops.

    ``name`` the condition (``motor_stalls``, ``follower_contact``, ...), ``value`` what the answer gives and
    ``limit`` what the model needs, both in ``unit`` ("" for a ratio); ``passed`` the condition holds; ``detail``
    what is compared, in words. A failed check always comes with a warning that names it, or the answer is
    refused instead.
    """

    name: str
    value: float
    limit: float
    passed: bool
    detail: str
    unit: str = ""


def link_lengths(mechanism: Mechanism) -> dict[str, float]:
    """Length of every bar link between its two joints [m]; blocks and rams have none."""
    if isinstance(mechanism, FourBar):
        return {"crank": mechanism.crank, "coupler": mechanism.coupler, "rocker": mechanism.rocker}
    if isinstance(mechanism, SliderCrank):
        return {"crank": mechanism.crank, "rod": mechanism.rod}
    if isinstance(mechanism, SlottedLever):
        return {"crank": mechanism.crank, "rocker": mechanism.rocker}
    if isinstance(mechanism, PlanarLinkage):
        # A link that slides on the frame carries whatever is fixed to it along its guide, like a block.
        sliding = {x for j in mechanism.joints if j.kind == "prismatic" and "frame" in j.links for x in j.links}
        return {k: v for k, v in mechanism.link_lengths().items() if k not in sliding}
    return {}


def _length_fields(mechanism: Mechanism) -> dict[str, float]:
    if isinstance(mechanism, FourBar):
        return {"ground_length_m": mechanism.ground, "crank_length_m": mechanism.crank,
                "coupler_length_m": mechanism.coupler, "rocker_length_m": mechanism.rocker}
    if isinstance(mechanism, SliderCrank):
        return {"crank_length_m": mechanism.crank, "rod_length_m": mechanism.rod}
    if isinstance(mechanism, SlottedLever):
        return {"crank_length_m": mechanism.crank, "ground_length_m": mechanism.ground,
                "rocker_length_m": mechanism.rocker, "ram_height_m": mechanism.ram_height}
    if isinstance(mechanism, PlanarLinkage):
        return {f"links.{i}.length_m": k.length for i, k in enumerate(mechanism.links) if len(k.joints) > 1}
    return {}


def bar_lengths(mechanism: Mechanism) -> dict[str, float]:
    """Every bar of the linkage with the frame's pivot distance (four-bar, shaper) [m], by request field."""
    bars = {f"{k}_length_m": v for k, v in link_lengths(mechanism).items()}
    if isinstance(mechanism, FourBar | SlottedLever):
        bars["ground_length_m"] = mechanism.ground
    if isinstance(mechanism, SliderCrank):
        bars = {"crank_length_m": mechanism.crank, "rod_length_m": mechanism.rod}
    return {k: v for k, v in bars.items() if v > 0}


def link_ratio_warning(mechanism: Mechanism, limit: float = MAX_LINK_RATIO) -> list[DesignWarning]:
    """``link_ratio_large`` when the longest bar over the shortest exceeds ``limit`` [-]."""
    bars = bar_lengths(mechanism)
    if len(bars) < 2:
        return []
    longest, shortest = max(bars, key=lambda k: bars[k]), min(bars, key=lambda k: bars[k])
    ratio = bars[longest] / bars[shortest]
    if ratio <= limit:
        return []
    return [DesignWarning(
        "link_ratio_large", f"mechanism.{shortest}", ratio,
        f"the {longest.removesuffix('_length_m')} is {ratio:.3g} times the {shortest.removesuffix('_length_m')} "
        f"(beyond {limit:g}): a linkage a drawing office would not build as it is; bound the lengths or their "
        "ratio", "1")]


def transmission_angle_warning(phi: FloatArray, tau: FloatArray) -> list[DesignWarning]:
    """``transmission_angle_low`` where the transmission angle ``tau`` [rad] at crank angles ``phi`` [rad]
    comes within 40° of a dead position (0 or 180°)."""
    deviation = np.minimum(tau, np.pi - tau)
    low = deviation < MIN_TRANSMISSION_ANGLE
    if not np.any(low):
        return []
    worst = float(deviation.min())
    ranges = _ranges(phi, low)
    where = ", ".join(f"{math.degrees(a) % 360:.4g}–{math.degrees(b) % 360:.4g}°" for a, b in ranges)
    return [DesignWarning(
        "transmission_angle_low", "mechanism", worst,
        f"the transmission angle falls to {math.degrees(worst):.3g}° (under 40°) at crank angles {where}: "
        "the coupler pushes the rocker nearly along it and the bearings carry the load", "rad", ranges)]


def _carries_motion(mechanism: Mechanism, link: str) -> bool:
    """True for a link whose mass matters to the user: not the crank (often balanced about its pivot and counted
    in the constant inertia) and not a small sliding block, unless the block is the working member."""
    topo = mechanism.topology
    if link == topo.crank:
        return False
    if link == topo.output:
        return True
    points = {j.point for j in topo.joints if link in j.bodies}
    return len(points) > 1


def check_linkage(linkage: Linkage) -> list[DesignWarning]:
    """Units and left-out data of a linkage: lengths in mm, masses in g, inertia without mass, massless links,
    counterweights beyond their links."""
    mech = linkage.mechanism
    out: list[DesignWarning] = []
    lengths = _length_fields(mech)
    for name, value in lengths.items():
        if value > LIKELY_MM_LENGTH:
            out.append(DesignWarning(
                "length_likely_mm", f"mechanism.{name}", value,
                f"{name} is {value:g} m, beyond any linkage of a machine; was it typed in millimetres?", "m"))
    size = max(lengths.values(), default=0.0)
    heavy = STEEL_DENSITY * size**3
    links = mech.topology.links
    props = {name: linkage.links.get(name) for name in links}
    for name, p in props.items():
        where = f"mechanism.links.{name}"
        if p is None:
            continue
        if size > 0 and p.mass > heavy:
            out.append(DesignWarning(
                "mass_likely_grams", f"{where}.mass_kg", p.mass,
                f"the {name} weighs {p.mass:g} kg, more than a solid steel cube of {size:g} m (the machine's size, "
                f"{heavy:.3g} kg); was it typed in grams?", "kg"))
        if p.inertia > 0 and p.mass == 0:
            out.append(DesignWarning(
                "inertia_without_mass", f"{where}.inertia_kgm2", p.inertia,
                f"the {name} has a moment of inertia but no mass: its weight and inertia force are left out; "
                "give mass_kg too", "kg·m²"))
    massless = [n for n, p in props.items() if p is None or (p.mass == 0 and p.inertia == 0)]
    if len(massless) == len(links) and not linkage.counterweights:
        out.append(DesignWarning(
            "links_missing", "mechanism.links", None,
            "no link has a mass or an inertia: forces, torques and the reduced inertia come only from the loads; "
            "give mechanism.links"))
    else:
        for name in massless:
            if _carries_motion(mech, name):
                out.append(DesignWarning(
                    "link_left_out", f"mechanism.links.{name}", None,
                    f"the {name} has neither mass nor inertia and is treated as massless; was it left out?"))
    for i, cw in enumerate(linkage.counterweights):
        if size > 0 and cw.mass > heavy:
            out.append(DesignWarning(
                "mass_likely_grams", f"counterweights[{i}].mass_kg", cw.mass,
                f"a {cw.mass:g} kg counterweight outweighs a solid steel cube of {size:g} m (the machine's size, "
                f"{heavy:.3g} kg); was it typed in grams?", "kg"))
    out += check_counterweights(linkage, linkage.counterweights, "counterweights")
    if isinstance(mech, PlanarLinkage) and mech.redundancy is not None:
        r = mech.redundancy
        out.append(DesignWarning(
            "redundant_constraint", f"mechanism.joints.{r.redundant_pairs[0]}",
            float(r.mobility_geometric - r.mobility_structural),
            f"pairs {list(r.redundant_pairs)} are redundant constraints: {r.explanation()}; the reactions are "
            "statically indeterminate and given as the least-norm split", "1"))
    return out


def check_counterweights(linkage: Linkage, counterweights: Sequence[Counterweight], field: str) -> list[DesignWarning]:
    """Counterweights placed farther from their link's first joint than the link is long.

    ``field`` names them in the request: ``counterweights`` (given ones, by index) or ``max_radius_m`` (placed by a
    balancing program within that limit, by link).
    """
    lengths = link_lengths(linkage.mechanism)
    out: list[DesignWarning] = []
    for i, cw in enumerate(counterweights):
        radius = math.hypot(*cw.position)
        length = lengths.get(cw.link)
        if length is not None and cw.mass > 0 and radius > length * (1 + 1e-9):
            where = f"{field}.{cw.link}" if field == "max_radius_m" else f"{field}[{i}].position_m"
            out.append(DesignWarning(
                "counterweight_beyond_link", where, radius,
                f"the counterweight on the {cw.link} sits {radius:.4g} m from its joint, beyond the "
                f"{length:.4g} m link: it needs an arm of its own", "m"))
    return out


def _ranges(phi: FloatArray, mask: NDArray[np.bool_]) -> tuple[tuple[float, float], ...]:
    """Runs of consecutive samples where ``mask`` holds, as (first, last) crank angles [rad], joined over 2π."""
    idx = np.flatnonzero(mask)
    if idx.size == 0:
        return ()
    breaks = np.flatnonzero(np.diff(idx) > 1)
    starts = np.concatenate([[idx[0]], idx[breaks + 1]])
    ends = np.concatenate([idx[breaks], [idx[-1]]])
    runs = [(float(phi[s]), float(phi[e])) for s, e in zip(starts, ends, strict=True)]
    if len(runs) > 1 and mask[0] and mask[-1]:
        first = runs.pop(0)
        runs[-1] = (runs[-1][0], first[1])
    return tuple(runs)


def angle_ranges(phi: FloatArray, mask: NDArray[np.bool_]) -> tuple[tuple[float, float], ...]:
    """Runs of consecutive samples where ``mask`` holds, as (first, last) angles [rad], joined over 2π."""
    return _ranges(phi, mask)


def _full_uniform_cycle(phi: FloatArray) -> bool:
    if phi.size < 3:
        return False
    step = 2 * math.pi / phi.size
    return bool(np.allclose(np.diff(phi), step, rtol=1e-9, atol=1e-12))


def check_analysis(an: Analysis) -> list[DesignWarning]:
    """:func:`check_linkage`, a four-bar's transmission angle under 40°, loads that drive the machine."""
    out = check_linkage(an.linkage)
    phi = an.motion.phi
    tau = an.transmission_angle
    if tau is not None:
        out += transmission_angle_warning(phi, tau)
    out += link_ratio_warning(an.linkage.mechanism)
    if (an.linkage.loads or an.linkage.torques) and _full_uniform_cycle(phi):
        torque = an.reduced.load_torque
        work = float(np.mean(torque)) * 2 * math.pi
        if work > 1e-9 * float(np.max(np.abs(torque))) * 2 * math.pi:
            field = "loads" if an.linkage.loads else "torques"
            out.append(DesignWarning(
                "load_work_positive", field, work,
                f"the loads do {work:.4g} J of positive work per revolution: they drive the crank and the motor "
                "would brake; a resisting load is given as a positive magnitude acting against the output's motion, "
                "a resisting torque on a link turns against it", "J"))
    if an.friction is not None:
        out += check_friction(an.friction.pairs)
    return out


def check_friction(pairs: Sequence[PairFriction], field: str = "friction") -> list[DesignWarning]:
    """Coefficients of friction above 1, beyond the dry pairs of the seeds' tables (steel on steel 0.15-0.2,
    seed 000:557-569)."""
    out = []
    for p in pairs:
        given = [("coefficient", p.coefficient)]
        if p.static_coefficient is not None:
            given.append(("static_coefficient", p.static_coefficient))
        for label, value in given:
            if value > LARGE_FRICTION_COEFFICIENT:
                out.append(DesignWarning(
                    "friction_coefficient_large", f"{field}.{p.joint}.{label}", value,
                    f"pair {p.joint}: a {label.replace('_', ' ')} of {value:g} is above 1, beyond the dry pairs of "
                    "the seeds' tables (steel on steel 0.15-0.2); check the value", "1"))
    return out
