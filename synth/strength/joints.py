"""Every revolute joint of an analysed linkage with its pin and its bearing, from the cycle's reactions.

Input: an :class:`synth.analysis.Analysis` over one whole cycle sampled uniformly (its joint reactions, its
links' angular speeds and the crank speed) and a :class:`JointPartSpec` per joint (or one for all): how the pin is
held, its material, and a plain bushing or a rolling bearing with the life it must reach. Output:
:func:`size_joints` gives a :class:`JointParts` per revolute joint: the pin (:mod:`.pins`), the bushing or the
rolling bearing (:mod:`.bearings`) on that pin, the relative speed of the joint's two links over the cycle, every
check and every warning. A rolling bearing whose bore is larger than the pin needs enlarges the pin to its bore;
so does a bushing that could not carry the load within 1.5 bores of length on the pin's own diameter.

The pin of a frame joint is the bearing seat of a fixed pivot (the crank's pivot is the crank shaft's, see
:mod:`.shafts`). The reaction a pin carries is the joint's reaction as the kinetostatics gives it; the relative
speed is w(second link) - w(first link), the frame not turning.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from ..analysis import Analysis
from ..errors import Infeasible, InvalidInput
from ..model import FloatArray
from ..warnings import DesignWarning
from .bearings import (
    BearingType,
    BushingMaterial,
    BushingResult,
    RollingBearing,
    RollingBearingResult,
    bushing_materials,
    bushing_min_diameter,
    select_rolling_bearing,
    size_bushing,
)
from .checks import PartCheck
from .materials import Material
from .pins import PinJoint, PinLimits, PinResult, load_kind, roloff_limits, size_pin, standard_pin_diameter

BearingKind = Literal["bushing", "rolling"]


@dataclass(frozen=True, slots=True)
class JointPartSpec:
    """How one joint is built. ``pin`` the pin's arrangement; ``pin_material`` its material (its ultimate
    strength sets the allowable stresses by Roloff/Matek's fractions for the cycle's kind of load) and
    ``member_strength`` the weaker joined member's ultimate strength [Pa] (None: the pin's); ``limits`` explicit
    allowable stresses instead; ``pin_fixed_in`` the link the pin is pressed into (None: it turns in both);
    ``bearing`` ``bushing`` or ``rolling``; ``bushing_material`` by name or as limits; ``bushing_length`` [m] or
    None to size it; ``life_hours`` the rolling bearing's required basic rating life [h]; ``static_safety`` its
    C0/P0 [-]; ``bearing_types`` the rolling types allowed (None: all)."""

    pin_material: Material
    pin: PinJoint = field(default_factory=PinJoint)
    member_strength: float | None = None
    limits: PinLimits | None = None
    pin_fixed_in: str | None = None
    bearing: BearingKind = "bushing"
    bushing_material: str | BushingMaterial = "sintered_bronze_oil"
    bushing_length: float | None = None
    life_hours: float = 20000.0
    static_safety: float = 1.0
    bearing_types: tuple[BearingType, ...] | None = None


@dataclass(frozen=True, slots=True)
class JointParts:
    """One revolute joint's parts: the ``pin``, its ``bushing`` or ``rolling`` bearing (the other None), the
    ``relative_speed`` of its links over the cycle (N,) [rad/s], every ``checks`` and ``warnings``."""

    joint: str
    links: tuple[str | None, str]
    pin: PinResult
    bushing: BushingResult | None
    rolling: RollingBearingResult | None
    relative_speed: FloatArray
    checks: tuple[PartCheck, ...]
    warnings: tuple[DesignWarning, ...]

    @property
    def passed(self) -> bool:
        """Every check met."""
        return all(c.passed for c in self.checks)


def cycle_time(analysis: Analysis) -> float:
    """The duration of the analysed cycle [s]; InvalidInput unless the samples cover one crank revolution
    uniformly at a steady crank speed (the bearings' means are means over time)."""
    phi = np.asarray(analysis.motion.phi, dtype=float)
    w = float(analysis.motion.omega_crank)
    n = phi.size
    step = 2.0 * math.pi / n if n else 0.0
    if n < 2 or w == 0.0 or not np.allclose(np.diff(phi), step, rtol=1e-9, atol=1e-12):
        raise InvalidInput("sizing the joints needs one whole crank revolution sampled uniformly at a steady, "
                           "non-zero crank speed", field="samples")
    return 2.0 * math.pi / abs(w)


def relative_speed(analysis: Analysis, links: tuple[str | None, str]) -> FloatArray:
    """w(second) - w(first) over the cycle (N,) [rad/s]; the frame and a link without an angle do not turn."""
    omega = analysis.motion.link_omega
    n = analysis.motion.phi.size
    zero = np.zeros(n)

    def w(link: str | None) -> FloatArray:
        return zero if link is None else np.asarray(omega.get(link, zero), dtype=float)

    out: FloatArray = w(links[1]) - w(links[0])
    return out


def size_joints(
    analysis: Analysis,
    default: JointPartSpec,
    specs: Mapping[str, JointPartSpec] | None = None,
    *,
    catalogue: tuple[RollingBearing, ...] | None = None,
    exclude: tuple[str, ...] = (),
) -> dict[str, JointParts]:
    """Pin and bearing of every revolute joint of ``analysis`` but those in ``exclude`` (the crank's pivot when
    the crank shaft is sized: its journal is the shaft); ``specs`` by joint name override ``default``.

    InvalidInput names an unknown joint, a material without its limits or a sampling that is not one uniform
    cycle; Infeasible names the joint and the check no part can meet (see :mod:`.pins` and :mod:`.bearings`).
    """
    specs = specs or {}
    topo = analysis.linkage.mechanism.topology
    revolute = {j.name: j for j in topo.joints if j.kind == "revolute"}
    if unknown := sorted(set(specs) - set(revolute)):
        raise InvalidInput(f"joints {unknown} are not revolute joints of the linkage; they are "
                           f"{sorted(revolute)}", field="joints")
    period = cycle_time(analysis)
    out: dict[str, JointParts] = {}
    for name, joint in revolute.items():
        if name in exclude:
            continue
        spec = specs.get(name, default)
        out[name] = _size_joint(analysis, name, joint.bodies, spec, period, catalogue)
    return out


def _limits(name: str, spec: JointPartSpec, reaction: FloatArray, member_angle: FloatArray | None) -> PinLimits:
    if spec.limits is not None:
        return spec.limits
    spec.pin_material.validate(f"joints.{name}.pin_material")
    member = spec.member_strength if spec.member_strength is not None else spec.pin_material.ultimate_strength
    return roloff_limits(spec.pin_material.ultimate_strength, member, load_kind(reaction, member_angle))


def _size_joint(analysis: Analysis, name: str, links: tuple[str | None, str], spec: JointPartSpec,
                period: float, catalogue: tuple[RollingBearing, ...] | None) -> JointParts:
    reaction = np.asarray(analysis.kinetostatics.reactions[name], dtype=float)
    w = relative_speed(analysis, links)
    member_angle: FloatArray | None = None
    if spec.pin_fixed_in is not None:
        if spec.pin_fixed_in not in links and not (spec.pin_fixed_in == "frame" and links[0] is None):
            raise InvalidInput(f"joint {name}: its pin can be fixed in {[x or 'frame' for x in links]}, not "
                               f"{spec.pin_fixed_in!r}", field=f"joints.{name}.pin_fixed_in")
        angles = analysis.motion.link_angle
        member_angle = (np.zeros(w.size) if spec.pin_fixed_in == "frame"
                        else np.asarray(angles.get(spec.pin_fixed_in, np.zeros(w.size)), dtype=float))
    limits = _limits(name, spec, reaction, member_angle)
    pin = size_pin(name, reaction, spec.pin, limits, member_angle=member_angle)
    bushing: BushingResult | None = None
    rolling: RollingBearingResult | None = None
    notes: tuple[DesignWarning, ...] = ()
    if spec.bearing == "bushing":
        material = spec.bushing_material
        if isinstance(material, str):
            try:
                material = bushing_materials()[material]
            except KeyError:
                raise InvalidInput(f"joint {name}: unknown bushing material {material!r}; one of "
                                   f"{sorted(bushing_materials())}", field=f"joints.{name}.bushing_material") from None
        # The bushing's pressure and p·v limits are far below the pin's: the bore grows until a bushing of at
        # most 1.5 bores' length carries the load, and the pin with it.
        need = bushing_min_diameter(reaction, w, material)
        if need > pin.diameter:
            bore = standard_pin_diameter(need)
            if bore is None:
                raise Infeasible(f"joint {name}: a {material.name} bushing needs a bore of {need * 1e3:.0f} mm, "
                                 "beyond the largest pin", constraint="bushing_pressure", joint=name)
            pin = size_pin(name, reaction, spec.pin, limits, member_angle=member_angle, diameter=bore)
        bushing = size_bushing(f"joint {name}", reaction, w, pin.diameter, material, length=spec.bushing_length)
    elif spec.bearing == "rolling":
        rolling = select_rolling_bearing(f"joint {name}", reaction, w, period, min_bore=pin.diameter,
                                         required_life_hours=spec.life_hours, static_safety=spec.static_safety,
                                         types=spec.bearing_types, catalogue=catalogue)
        notes = rolling.warnings
        if rolling.bearing.bore > pin.diameter:
            pin = size_pin(name, reaction, spec.pin, limits, member_angle=member_angle,
                           diameter=rolling.bearing.bore)
    else:
        raise InvalidInput(f"joint {name}: a bearing is a bushing or rolling, got {spec.bearing!r}",
                           field=f"joints.{name}.bearing")
    # A given bushing length is checked, not sized: its checks may fail and say so.
    checks = pin.checks + (bushing.checks if bushing else ()) + (rolling.checks if rolling else ())
    return JointParts(name, links, pin, bushing, rolling, w, checks, notes)
