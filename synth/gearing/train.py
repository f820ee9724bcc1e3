"""A given gear train from its tooth numbers: the ratio, every shaft's speed and sense, the efficiency, d = m·z.

The train is serial: each element's input sits on the shaft the previous element drove. Elements are meshes
(simple, compound when the next driving wheel is another wheel on the same shaft, idler when it is the same
wheel) and planetary stages solved by Willis' equation (seed 004:570-613; section 9 of the seed digest).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

from ..errors import InvalidInput
from ..warnings import DesignWarning
from .stages import stage_types

Member = Literal["sun", "ring", "carrier"]

#: Largest number of elements in one train.
MAX_TRAIN_ELEMENTS = 64
#: Largest ratio magnitude (and inverse) of a train, so that its speeds stay finite.
RATIO_LIMIT = 1e100


@dataclass(frozen=True, slots=True)
class GearMesh:
    """One mesh: ``driving_teeth`` on the current shaft drive ``driven_teeth`` on the next.

    ``internal``: the driven (or driving) wheel is an annulus, so both turn the same way; ``idler``: the driving
    wheel is the previous mesh's driven wheel itself (its teeth must match); ``efficiency`` [-], default the
    table's closed spur pair.
    """

    driving_teeth: int
    driven_teeth: int
    internal: bool = False
    idler: bool = False
    efficiency: float | None = None


@dataclass(frozen=True, slots=True)
class PlanetaryStage:
    """A planetary (epicyclic) stage: sun, planets, ring, carrier; one of sun, ring, carrier held.

    Teeth of the sun ``sun_teeth``, of the planet meshing with it ``planet_teeth``, of the planet meshing with
    the ring ``planet_ring_teeth`` (a stepped planet; default the same wheel) and of the ring ``ring_teeth``.
    ``fixed``, ``input`` and ``output`` name the three members; ``efficiency`` [-], or else from
    ``basic_efficiency`` eta0 [-] of the gearing with the carrier held (default: two closed spur meshes, the
    table's spur efficiency squared) by the direction of the power in the relative motion
    (:meth:`stage_efficiency`). ``ring_internal`` False makes the "ring" an external second sun meshing with a
    stepped planet: a positive basic ratio, large ratios, and a stage that may self-lock.
    """

    sun_teeth: int
    planet_teeth: int
    ring_teeth: int
    fixed: Member = "ring"
    input: Member = "sun"
    output: Member = "carrier"
    planet_ring_teeth: int | None = None
    efficiency: float | None = None
    basic_efficiency: float | None = None
    ring_internal: bool = True

    def stage_efficiency(self) -> float:
        """Efficiency with power flowing from ``input`` to ``output`` [-]: given, or by the direction of the power
        through the relative (carrier-held) train (:func:`planetary_efficiency`); zero or below, the stage
        self-locks that way."""
        if self.efficiency is not None:
            return self.efficiency
        return planetary_efficiency(self.basic_ratio(), self.eta0(), self.fixed, self.input, self.output)

    def back_efficiency(self) -> float:
        """Efficiency with power flowing back, ``output`` driving ``input`` [-]: a given efficiency holds both
        ways; zero or below, the stage cannot be driven back (self-locking)."""
        if self.efficiency is not None:
            return self.efficiency
        return planetary_efficiency(self.basic_ratio(), self.eta0(), self.fixed, self.output, self.input)

    def eta0(self) -> float:
        """Efficiency of the gearing with the carrier held [-]: given, or two closed spur meshes."""
        if self.basic_efficiency is not None:
            return self.basic_efficiency
        return stage_types()["spur"].efficiency ** 2

    def basic_ratio(self) -> float:
        """Willis' ratio with the carrier held, (w_sun - w_c)/(w_ring - w_c) = -(z_p/z_s)·(z_r/z_p') [-] for an
        internal ring; +(z_p/z_s)·(z_r/z_p') when the "ring" is an external second sun (two external meshes)."""
        zp2 = self.planet_ring_teeth or self.planet_teeth
        sign = -1.0 if self.ring_internal else 1.0
        return sign * (self.planet_teeth / self.sun_teeth) * (self.ring_teeth / zp2)

    def ratio(self) -> float:
        """Input speed over output speed with ``fixed`` held [-], from w_s - i0·w_r + (i0 - 1)·w_c = 0."""
        i0 = self.basic_ratio()
        coef = {"sun": 1.0, "ring": -i0, "carrier": i0 - 1.0}
        return -coef[self.output] / coef[self.input]


def planetary_efficiency(i0: float, eta0: float, fixed: Member, driving: Member, driven: Member) -> float:
    """Efficiency of a three-shaft planetary stage with ``fixed`` held, ``driving`` driving ``driven`` [-].

    ``i0`` Willis' basic ratio (w_sun - w_c)/(w_ring - w_c) with either sign [-]; ``eta0`` the efficiency of the
    gearing with the carrier held [-]. In the carrier's frame the stage is an ordinary train whose meshes lose
    (1 - eta0) of the power they carry, in the direction that power really flows there: the sun drives the
    relative train when its relative power T_s·(w_s - w_c) of the loss-free stage is positive, the ring
    otherwise. The ring's torque is then T_r = -i0·eta0^x·T_s (x = +1 sun driving, -1 ring driving), the
    carrier's takes the rest, and the efficiency is the driven member's power over the driving member's.
    Sun driving, ring held: (1 + eta0·z_r/z_s)/(1 + z_r/z_s); carrier driving: (1 + z_r/z_s)/(1 + z_r/(z_s·eta0))
    (Willis, Kudryavtsev). Zero or below: the stage self-locks with power flowing this way.
    """
    ideal = {"sun": 1.0, "ring": -i0, "carrier": i0 - 1.0}
    speed = {fixed: 0.0, driving: 1.0, driven: -ideal[driving] / ideal[driven]}
    # the loss-free torques, scaled so the driving member takes in unit power
    sun_torque = 1.0 / ideal[driving]
    sun_drives = sun_torque * (speed["sun"] - speed["carrier"]) > 0
    k = i0 * (eta0 if sun_drives else 1.0 / eta0)
    lossy = {"sun": 1.0, "ring": -k, "carrier": k - 1.0}
    if abs(lossy[driving]) < 1e-12:
        # the driving member would carry no torque: the loss exactly cancels the stage's torque ratio
        raise InvalidInput("with this basic efficiency the driving member of the stage carries no torque: its "
                           "efficiency is undefined", field="basic_efficiency")
    return -lossy[driven] / lossy[driving] * speed[driven]


TrainElement = GearMesh | PlanetaryStage


@dataclass(frozen=True, slots=True)
class TrainWheel:
    """A wheel: its ``name`` ("1", "2", "2'"... or "sun 1", "planet 1", "ring 1"), ``teeth``, the ``shaft`` it
    is keyed to (None for planets), and its pitch diameter m·z [m] (None without a module)."""

    name: str
    teeth: int
    shaft: int | None
    pitch_diameter: float | None


@dataclass(frozen=True, slots=True)
class TrainShaft:
    """A shaft, 0 the input: ``ratio`` w_input/w_shaft with sign [-], ``direction`` +1 with the input, -1
    against, ``speed`` [rad/s] (None without a given speed), the ``wheels`` on it."""

    index: int
    ratio: float
    direction: int
    speed: float | None
    wheels: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class TrainResult:
    """The train's ratio w_in/w_out with sign [-], its efficiency [-], shafts and wheels.

    ``efficiency`` with power from input to output, ``back_efficiency`` with the output driving the input [-]
    (planetary stages differ by the direction of their relative power); ``locked`` the input cannot drive the
    train (efficiency zero or below), ``self_locking`` the output cannot drive it back.

    ``formula_ratio`` is the independent check: the seed's closed form (-1)^k·prod(z_driven/z_driving) for the
    meshes (k external meshes) times each planetary stage's Willis ratio, against the shaft-by-shaft
    propagation of pitch-line speeds that gives ``ratio``.
    """

    ratio: float
    efficiency: float
    shafts: tuple[TrainShaft, ...]
    wheels: tuple[TrainWheel, ...]
    external_meshes: int
    formula_ratio: float
    back_efficiency: float = 1.0
    locked: bool = False
    self_locking: bool = False
    warnings: tuple[DesignWarning, ...] = ()

    @property
    def formula_agrees(self) -> bool:
        """Whether the closed form and the propagation agree to 1e-9 (relative)."""
        return math.isclose(self.formula_ratio, self.ratio, rel_tol=1e-9)


def _validate(elements: Sequence[TrainElement], module: float | None) -> None:
    if not elements:
        raise InvalidInput("a train needs at least one mesh or planetary stage", field="elements")
    if len(elements) > MAX_TRAIN_ELEMENTS:
        raise InvalidInput(f"at most {MAX_TRAIN_ELEMENTS} elements", field="elements")
    if module is not None and not (math.isfinite(module) and module > 0):
        raise InvalidInput("module_m must be positive", field="module_m")
    previous: TrainElement | None = None
    for i, e in enumerate(elements):
        teeth = ([e.driving_teeth, e.driven_teeth] if isinstance(e, GearMesh)
                 else [e.sun_teeth, e.planet_teeth, e.ring_teeth, e.planet_ring_teeth or e.planet_teeth])
        if any(z < 1 for z in teeth):
            raise InvalidInput(f"tooth numbers must be positive, got {teeth}", field=f"elements[{i}]")
        if e.efficiency is not None and not 0 < e.efficiency <= 1:
            raise InvalidInput("efficiency must lie in (0, 1]", field=f"elements[{i}].efficiency")
        if isinstance(e, PlanetaryStage) and e.basic_efficiency is not None and not 0 < e.basic_efficiency <= 1:
            raise InvalidInput("basic_efficiency must lie in (0, 1]", field=f"elements[{i}].basic_efficiency")
        if isinstance(e, GearMesh) and e.idler:
            if not isinstance(previous, GearMesh):
                raise InvalidInput("an idler drives on from the previous mesh's driven wheel",
                                   field=f"elements[{i}].idler")
            if e.driving_teeth != previous.driven_teeth:
                raise InvalidInput(f"an idler is the previous driven wheel: it has {previous.driven_teeth} teeth, "
                                   f"not {e.driving_teeth}", field=f"elements[{i}].driving_teeth")
        if isinstance(e, PlanetaryStage):
            if len({e.fixed, e.input, e.output}) != 3:
                raise InvalidInput("fixed, input and output must be the three members sun, ring, carrier",
                                   field=f"elements[{i}]")
            zp2 = e.planet_ring_teeth or e.planet_teeth
            if not e.ring_internal:
                # two external meshes on one axis, one module: z_s + z_p = z_r + z_p'
                if e.planet_ring_teeth is None:
                    raise InvalidInput("an external second sun needs a stepped planet (planet_ring_teeth): with one "
                                       "planet wheel both suns would be equal and the stage locked",
                                       field=f"elements[{i}].planet_ring_teeth")
                if e.sun_teeth + e.planet_teeth != e.ring_teeth + zp2:
                    raise InvalidInput(f"two suns on one axis need z_s + z_p = z_r + z_p' "
                                       f"({e.sun_teeth + e.planet_teeth} against {e.ring_teeth + zp2})",
                                       field=f"elements[{i}].ring_teeth")
            elif e.planet_ring_teeth is None and e.ring_teeth != e.sun_teeth + 2 * e.planet_teeth:
                raise InvalidInput(f"sun, planet and ring on one axis need z_r = z_s + 2·z_p = "
                                   f"{e.sun_teeth + 2 * e.planet_teeth}, got {e.ring_teeth}",
                                   field=f"elements[{i}].ring_teeth")
            elif e.ring_teeth <= zp2:
                raise InvalidInput("the ring must have more teeth than the planet", field=f"elements[{i}].ring_teeth")
            if e.basic_ratio() == 1.0 or abs(e.ratio()) > 1e12 or e.ratio() == 0:
                raise InvalidInput("this choice of fixed, input and output locks or frees the stage",
                                   field=f"elements[{i}]")
        previous = e


def gear_train(elements: Sequence[TrainElement], *, module: float | None = None,
               input_speed: float | None = None, output_speed: float | None = None) -> TrainResult:
    """Ratio, shaft speeds and senses, efficiency and pitch diameters of a serial train.

    Parameters
    ----------
    elements : meshes and planetary stages, input side first.
    module : module of every wheel [m], for pitch diameters d = m·z; None leaves them out.
    input_speed, output_speed : the input's (or the output's) speed [rad/s]; at most one.

    Raises InvalidInput naming the element for impossible trains (an idler that is not the previous wheel, a
    planetary stage whose wheels do not share an axis or that is locked).
    """
    _validate(elements, module)
    if input_speed is not None and output_speed is not None:
        raise InvalidInput("give the input speed or the output speed, not both", field="output_speed_rad_s")
    for name, v in (("input_speed_rad_s", input_speed), ("output_speed_rad_s", output_speed)):
        if v is not None and not math.isfinite(v):
            raise InvalidInput(f"{name} must be finite", field=name)
    table = stage_types()
    speed = 1.0  # shaft speed over input speed, carried from shaft to shaft by the pitch-line speed
    shafts_rel = [1.0]
    wheels_on: list[list[str]] = [[]]
    wheels: list[tuple[str, int, int | None]] = []
    efficiency = 1.0
    back = 1.0
    warnings: list[DesignWarning] = []
    external = 0
    formula = 1.0
    number = 1
    for i, e in enumerate(elements):
        if isinstance(e, GearMesh):
            if e.idler:
                driving = wheels_on[-1][-1]
            else:
                on_shaft = [w for w in wheels_on[-1] if w.rstrip("'").isdigit()]
                if on_shaft:  # a compound wheel: the textbook's 2', 3'...
                    driving = on_shaft[0] + "'" * len(on_shaft)
                else:
                    driving, number = str(number), number + 1
                wheels.append((driving, e.driving_teeth, len(shafts_rel) - 1))
                wheels_on[-1].append(driving)
            # Equal pitch-line speeds: w_a·z_a = w_b·z_b, opposite senses on an external mesh.
            sense = 1.0 if e.internal else -1.0
            speed = sense * speed * e.driving_teeth / e.driven_teeth
            external += 0 if e.internal else 1
            formula *= e.driven_teeth / e.driving_teeth
            driven = str(number)
            number += 1
            shafts_rel.append(speed)
            wheels_on.append([driven])
            wheels.append((driven, e.driven_teeth, len(shafts_rel) - 1))
            eta = e.efficiency if e.efficiency is not None else table["spur"].efficiency
            efficiency *= eta
            back *= eta
        else:
            k = sum(1 for el in elements[:i + 1] if isinstance(el, PlanetaryStage))
            ratio = e.ratio()
            speed = speed / ratio
            formula *= ratio
            shafts_rel.append(speed)
            wheels_on[-1].append(f"{e.input} {k}")
            wheels_on.append([f"{e.output} {k}"])
            for member, z in (("sun", e.sun_teeth), ("ring", e.ring_teeth)):
                on = {str(e.input): len(shafts_rel) - 2, str(e.output): len(shafts_rel) - 1}.get(member)
                wheels.append((f"{member} {k}", z, on))
            wheels.append((f"planet {k}", e.planet_teeth, None))
            if e.planet_ring_teeth is not None:
                wheels.append((f"planet {k}'", e.planet_ring_teeth, None))
            try:
                forward, backward = e.stage_efficiency(), e.back_efficiency()
            except InvalidInput as exc:
                raise InvalidInput(str(exc), field=f"elements[{i}].basic_efficiency") from exc
            efficiency *= forward
            back *= backward
            warnings += _locking_warnings(i, k, e, forward, backward)
        if not RATIO_LIMIT ** -1 <= abs(speed) <= RATIO_LIMIT:
            raise InvalidInput(f"the train's ratio up to element {i} is {1 / speed:.3g}, beyond ±{RATIO_LIMIT:.0e} "
                               "either way: no real train", field=f"elements[{i}]")
    formula *= (-1) ** external
    w_in = input_speed if input_speed is not None else (output_speed / speed if output_speed is not None else None)
    shafts = tuple(
        TrainShaft(j, 1.0 / rel, 1 if rel > 0 else -1, None if w_in is None else w_in * rel, tuple(wheels_on[j]))
        for j, rel in enumerate(shafts_rel)
    )
    out_wheels = tuple(TrainWheel(n, z, s, None if module is None else module * z) for n, z, s in wheels)
    return TrainResult(1.0 / speed, efficiency, shafts, out_wheels, external, formula, back,
                       efficiency <= 0, back <= 0, tuple(warnings))


def _locking_warnings(i: int, k: int, e: PlanetaryStage, forward: float, backward: float) -> list[DesignWarning]:
    out = []
    if forward <= 0:
        out.append(DesignWarning(
            "self_locking", f"elements[{i}]", forward,
            f"planetary stage {k} self-locks with {e.input} driving {e.output} (efficiency {forward:.4g}): the "
            "input cannot turn it whatever the torque; swap input and output or choose other teeth"))
    if backward <= 0:
        out.append(DesignWarning(
            "self_locking_back", f"elements[{i}]", backward,
            f"planetary stage {k} self-locks with power flowing back, {e.output} driving {e.input} (efficiency "
            f"{backward:.4g}): the output cannot drive the input (it holds a load, and a drive that must "
            "run back or brake through it cannot)"))
    return out
