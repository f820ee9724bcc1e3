"""Models shared by every endpoint: mechanisms with their links, loads, counterweights and summaries."""

from __future__ import annotations

import math
from types import UnionType
from typing import Annotated, Any, Literal, TypeVar, Union, get_args, get_origin

from pydantic import BaseModel, ConfigDict, Field, model_validator
from pydantic.config import JsonDict


# Bounds far outside any machine, so that arithmetic cannot overflow: a value beyond them is a typo.
MAX_LENGTH_M = 1e3
MAX_MASS_KG = 1e7
MAX_INERTIA_KGM2 = 1e9
Coordinate = Annotated[float, Field(ge=-MAX_LENGTH_M, le=MAX_LENGTH_M)]
Vec2 = Annotated[list[Coordinate], Field(min_length=2, max_length=2)]
MIN_LENGTH_M = 1e-6
# The engine's bound (synth.friction.MAX_COEFFICIENT): the schemas load without the engine.
MAX_FRICTION_COEFFICIENT = 3.0
Length = Annotated[float, Field(ge=MIN_LENGTH_M, le=MAX_LENGTH_M, description="[m]")]


def given(*names: str) -> JsonDict:
    """JSON Schema: every field of ``names`` is present and not null."""
    return {"required": list(names), "properties": {n: {"not": {"type": "null"}} for n in names}}


def exactly_one(*names: str) -> JsonDict:
    """JSON Schema: exactly one of the fields ``names`` is given (present and not null)."""
    return {"oneOf": [given(n) for n in names]}


def at_least_one(*names: str) -> JsonDict:
    """JSON Schema: one or more of the fields ``names`` is given."""
    return {"anyOf": [given(n) for n in names]}


def at_most_one(*names: str) -> JsonDict:
    """JSON Schema: no two of the fields ``names`` are given together."""
    return {"allOf": [{"not": given(a, b)} for i, a in enumerate(names) for b in names[i + 1:]]}


def service_limit(setting: str) -> JsonDict:
    """Schema mark of a count the service bounds by its setting ``setting`` (413 beyond): the OpenAPI document
    states the bound of the running service as the count's ``maximum`` or ``maxItems``."""
    return {"x-limit": setting}


Choice = TypeVar("Choice", bound=str | int)
Branch = Literal[1, -1]
BRANCHES: tuple[Branch, ...] = (1, -1)


def one_of(allowed: tuple[Choice, ...], value: str | int) -> Choice:
    """An engine value as the schema's closed type (the values of a Literal); anything else is an engine bug."""
    for option in allowed:
        if option == value:
            return option
    raise RuntimeError(f"engine answered {value!r}, not one of {allowed}")


def _integer_kind(annotation: Any) -> str | None:
    """``"int"`` for an integer field (optional or in a union), ``"list"`` for a list of integers, else None."""
    if get_origin(annotation) is Annotated:
        return _integer_kind(get_args(annotation)[0])
    if annotation is int or (get_origin(annotation) is Literal
                             and all(type(a) is int for a in get_args(annotation))):
        return "int"
    if get_origin(annotation) is list:
        return "list" if _integer_kind(get_args(annotation)[0]) == "int" else None
    if get_origin(annotation) in (Union, UnionType):
        kinds = {_integer_kind(a) for a in get_args(annotation)}
        return "int" if "int" in kinds else "list" if "list" in kinds else None
    return None


def _whole(value: Any) -> Any:
    """A float with no fractional part as the integer it is, anything else as it is."""
    if type(value) is float and value.is_integer() and abs(value) <= 2.0**63:
        return int(value)
    return value


_INTEGER_FIELDS: dict[type, dict[str, str]] = {}


class StrictModel(BaseModel):
    """Base of every schema: unknown fields and NaN/infinity are rejected at the edge.

    Types are strict (a string is no number, a boolean no integer), but an integer field takes a whole number
    written with a fraction (``36.0``): JSON Schema's ``integer`` is any number without a fractional part, and
    the service accepts what its schema does.
    """

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False, strict=True)

    @model_validator(mode="before")
    @classmethod
    def _whole_numbers(cls, data: Any) -> Any:
        if not isinstance(data, dict):
            return data
        fields = _INTEGER_FIELDS.get(cls)
        if fields is None:
            fields = {(f.alias or name): kind for name, f in cls.model_fields.items()
                      if (kind := _integer_kind(f.annotation)) is not None}
            _INTEGER_FIELDS[cls] = fields
        if not any(key in data for key in fields):
            return data
        out = dict(data)
        for key, kind in fields.items():
            if key in out:
                value = out[key]
                out[key] = [_whole(v) for v in value] if kind == "list" and isinstance(value, list) else _whole(value)
        return out


class LinkIn(StrictModel):
    """Mass properties of one link in its own frame (origin at its first joint, x toward the second)."""

    mass_kg: float = Field(0.0, ge=0, le=MAX_MASS_KG, description="Link mass [kg].")
    com_m: Vec2 = Field(default_factory=lambda: [0.0, 0.0], description="Centre of mass in the link frame [m].")
    inertia_kgm2: float = Field(0.0, ge=0, le=MAX_INERTIA_KGM2,
                                description="Moment of inertia about the centre of mass [kg·m²].")


class FourBarLinks(StrictModel):
    """Links of a four-bar; a link left out is massless."""

    crank: LinkIn = Field(default_factory=LinkIn, description="Crank O-A; frame origin at O.")
    coupler: LinkIn = Field(default_factory=LinkIn, description="Coupler A-B; frame origin at A.")
    rocker: LinkIn = Field(default_factory=LinkIn, description="Rocker Q-B; frame origin at Q.")


class SliderCrankLinks(StrictModel):
    """Links of a slider-crank; a link left out is massless."""

    crank: LinkIn = Field(default_factory=LinkIn, description="Crank; frame origin at its pivot.")
    rod: LinkIn = Field(default_factory=LinkIn, description="Connecting rod; frame origin at the crank pin.")
    slider: LinkIn = Field(default_factory=LinkIn, description="Slider (piston, crosshead); frame origin at its pin.")


class SlottedLeverLinks(StrictModel):
    """Links of a shaper: crank, block in the lever slot, lever, block at the lever tip, ram."""

    crank: LinkIn = Field(default_factory=LinkIn, description="Crank; frame origin at its pivot O.")
    slider: LinkIn = Field(default_factory=LinkIn, description="Block on the crank pin, sliding in the lever slot.")
    rocker: LinkIn = Field(default_factory=LinkIn, description="Slotted lever; frame origin at its pivot O1.")
    ram_slider: LinkIn = Field(default_factory=LinkIn, description="Block at the lever tip, sliding in the ram.")
    ram: LinkIn = Field(default_factory=LinkIn, description="Ram (tool carrier) on its horizontal guide.")


class FourBarIn(StrictModel):
    """Four-bar O-A-B-Q: crank pivot O at the origin, rocker pivot Q at (ground_length_m, 0)."""

    type: Literal["fourbar"] = Field("fourbar", description="Mechanism family: a four-bar linkage.")
    ground_length_m: Length = Field(description="Frame O-Q between the crank and rocker pivots [m].", examples=[0.3])
    crank_length_m: Length = Field(description="Crank O-A [m].", examples=[0.1])
    coupler_length_m: Length = Field(description="Coupler A-B [m].", examples=[0.35])
    rocker_length_m: Length = Field(description="Rocker Q-B [m].", examples=[0.25])
    branch: Literal[1, -1] = Field(1, description="+1: B to the left of the directed line A->Q; -1: to the right.")
    links: FourBarLinks = Field(default_factory=FourBarLinks,
                                description="Mass properties per link; a link left out is massless.")


class SliderCrankIn(StrictModel):
    """Offset slider-crank: crank pivot at the origin, slider on the horizontal line y = offset_m."""

    type: Literal["slider_crank"] = Field("slider_crank", description="Mechanism family: a (possibly offset) "
                                          "slider-crank, as in presses, compressors and engines.")
    crank_length_m: Length = Field(description="Crank radius [m].", examples=[0.05])
    rod_length_m: Length = Field(description="Connecting rod length, crank pin to slider pin [m].", examples=[0.2])
    offset_m: Coordinate = Field(0.0, description="Height of the slider line above the crank pivot [m]; 0: in-line.")
    branch: Literal[1, -1] = Field(1, description="+1: slider on the +x side of the crank pin; -1: on the -x side.")
    links: SliderCrankLinks = Field(default_factory=SliderCrankLinks,
                                    description="Mass properties per link; a link left out is massless.")


class SlottedLeverIn(StrictModel):
    """Shaper: rocker pivot O1 at (0, -ground_length_m) below the crank pivot, ram guide ram_height_m above O1."""

    type: Literal["slotted_lever"] = Field("slotted_lever", description="Mechanism family: the shaper's "
                                           "crank and slotted lever driving a ram.")
    crank_length_m: Length = Field(description="Crank O-A [m].", examples=[0.1])
    ground_length_m: float = Field(ge=MIN_LENGTH_M, le=MAX_LENGTH_M, examples=[0.3],
                                   description="Distance O-O1 between crank and lever pivots [m].")
    rocker_length_m: float = Field(ge=MIN_LENGTH_M, le=MAX_LENGTH_M, examples=[0.6],
                                   description="Lever length O1-B [m].")
    ram_height_m: float = Field(ge=MIN_LENGTH_M, le=MAX_LENGTH_M, examples=[0.7],
                                description="Height of the ram guide above O1 [m].")
    links: SlottedLeverLinks = Field(default_factory=SlottedLeverLinks,
                                     description="Mass properties per link; a link left out is massless.")


MAX_LINKAGE_LINKS = 24
Name = Annotated[str, Field(min_length=1, max_length=64)]


class LinkageLinkIn(LinkIn):
    """A moving link of a general linkage: its points in its own frame, and its mass properties there."""

    name: Name = Field(description="Link name, unique; `frame` is the fixed link.", examples=["rod"])
    joints: list[Name] = Field(min_length=1, max_length=2, description="One or two point names: the first is "
                               "the link frame's origin; the second lies on its x-axis at `length_m`. A block "
                               "(slider) has one, and its x-axis runs along its slide.", examples=[["C", "D"]])
    length_m: float = Field(0.0, ge=0, le=MAX_LENGTH_M, description="Distance from the first point to the second "
                            "[m]; needed when the link has two.", examples=[0.5])
    points_m: dict[Name, Vec2] = Field(default_factory=dict, max_length=16, description="Further named points in "
                                       "the link frame [m] (a ternary link's third joint, a coupler point).",
                                       examples=[{"C": [0.4, 0.0]}])


class LinkageJointIn(StrictModel):
    """A lower pair between two links: a revolute at a point both carry, or a prismatic pair (a slide axis fixed in
    one link along which a point of the other runs, the two turning together)."""

    name: Name = Field(description="Joint name, unique; a revolute's point by default.", examples=["D"])
    kind: Literal["revolute", "prismatic"] = Field(description="`revolute` (turning pair) or `prismatic` (sliding "
                                                   "pair).")
    links: list[Name] = Field(min_length=2, max_length=2, description="The two links it joins (`frame` for the "
                              "fixed one); its reaction is reported as the force the first exerts on the second.",
                              examples=[["rod", "ram"]])
    point: Name | None = Field(None, description="Revolute: the point both links carry (default the joint's name). "
                               "Prismatic: the point of the sliding link that runs on the axis (default its "
                               "origin).")
    axis_link: Name | None = Field(None, description="Prismatic: the link that carries the slide axis (default the "
                                   "first of `links`).")
    axis_deg: float = Field(0.0, ge=-3600, le=3600, description="Prismatic: the slide axis's direction in the axis "
                            "link's frame [deg] (in the frame: from the x-axis, counter-clockwise).")
    through: Name | None = Field(None, description="Prismatic: a point of the axis link on the slide axis (default "
                                 "its origin; a frame point for a fixed guide).")
    slider_axis_deg: float = Field(0.0, ge=-3600, le=3600, description="Prismatic: the slide axis's direction in "
                                   "the sliding link's frame [deg]; 0 for a block whose x-axis runs along it.")


class PlanarLinkageIn(StrictModel):
    """Any crank-driven planar linkage of revolute and prismatic pairs, split into the crank and dyads (RRR, RRP,
    RPR, PRP, RPP) solved in closed form: six-bar presses, Watt and Stephenson chains, quick-return mechanisms."""

    type: Literal["linkage"] = Field("linkage", description="Mechanism family: a general linkage given by its "
                                     "links and joints.")
    frame_points_m: dict[Name, Vec2] = Field(max_length=32, description="Fixed points by name [m]; the crank pivot "
                                             "is at [0, 0].", examples=[{"O": [0, 0], "Q": [0.3, 0]}])
    links: list[LinkageLinkIn] = Field(min_length=1, max_length=MAX_LINKAGE_LINKS, description="The moving links, "
                                       "each with its points and mass properties in its own frame.")
    joints: list[LinkageJointIn] = Field(min_length=1, max_length=2 * MAX_LINKAGE_LINKS,
                                         description="The pairs; one degree of freedom: 3·links - 2·joints = 1.")
    crank: Name = Field(description="The driven link: it turns about its first point, the frame point at the "
                        "origin; the crank angle is the angle of its x-axis.", examples=["crank"])
    output: Name | None = Field(None, description="The working member (default the last link), joined to the "
                                "frame: its load is a torque if it turns, a force along the slide if it slides.")
    branches: dict[Name, Literal[1, -1]] = Field(default_factory=dict, max_length=MAX_LINKAGE_LINKS,
                                                 description="Assembly branch per dyad, keyed by its inner joint; "
                                                 "+1 (default) or -1 (see docs/linkages.md).")
    assembly_m: dict[Name, Vec2] = Field(default_factory=dict, max_length=4 * MAX_LINKAGE_LINKS,
                                         description="Points as drawn at crank angle 0 [m]: where a group of class "
                                         "III or above (placed numerically) starts, and so the branch it keeps; "
                                         "without them the first start that closes its loops is taken.",
                                         examples=[{"B": [0.28, 0.12], "C": [0.47, 0.15]}])


MechanismIn = Annotated[Union[FourBarIn, SliderCrankIn, SlottedLeverIn, PlanarLinkageIn], Field(discriminator="type")]


class GravityIn(StrictModel):
    """Uniform gravity; leave ``gravity`` out (null) to switch it off."""

    g_m_s2: float = Field(9.81, ge=0, le=1e4, description="Acceleration of gravity [m/s²].")
    direction_deg: float = Field(-90.0, description="Direction of g in the plane, -90 = straight down.")


class CounterweightIn(StrictModel):
    """A counterweight on a link: point mass at a position in the link frame, with optional own inertia."""

    link: str = Field(description="Link that carries it, by name (crank, coupler, rocker, rod, ...).",
                      examples=["crank"])
    mass_kg: float = Field(ge=0, le=MAX_MASS_KG, description="Counterweight mass [kg].", examples=[2.5])
    position_m: Vec2 = Field(description="Its centre in the link frame [m]: behind the pivot has a negative x.",
                             examples=[[-0.06, 0.0]])
    inertia_kgm2: float = Field(0.0, ge=0, le=MAX_INERTIA_KGM2, description="Own inertia about its centre [kg·m²].")


class _LoadBase(StrictModel):
    force_N: float | list[float] | None = Field(None, description="Force on a sliding output (slider, ram) [N].")
    torque_Nm: float | list[float] | None = Field(None, description="Torque on a turning output (rocker) [N·m].")
    point_m: Vec2 = Field(
        default_factory=lambda: [0.0, 0.0], description="Where a force acts, in the output link's frame [m]."
    )
    stroke: Literal[-1, 0, 1] = Field(0, description="Act only while the output moves in + (1) or - (-1); 0: both.")
    direction: Literal["against_motion", "output", "frame"] = Field(
        "against_motion", description="against_motion: a resistance, turning with the output's velocity (the "
        "magnitude resists); output: signed and fixed along the output, + along the slide axis or "
        "counter-clockwise (a spring preload, a constant thrust); frame: a force of fixed direction in the frame "
        "at frame_angle_deg, signed, on a sliding or a turning output at point_m (a weight: force_N m·g at -90).")
    frame_angle_deg: float = Field(0.0, ge=-360.0, le=360.0, description="direction frame: the force's direction, "
                                   "counter-clockwise from +x [deg].")


class WindowLoadIn(_LoadBase):
    """Constant load while the crank angle is inside [start_deg, end_deg] (wrapping past 360), against the output velocity."""

    type: Literal["window"] = Field("window", description="A constant load over a window of crank angles.")
    start_deg: float = Field(0.0, description="Crank angle where the load starts acting [deg].")
    end_deg: float = Field(360.0, description="Crank angle where it stops [deg]; below start_deg the window "
                           "wraps past 360 (-60 to 60 is the 120° around 0).")


class CrankTableLoadIn(_LoadBase):
    """Load magnitude tabulated over crank angle (periodic linear interpolation), against the output velocity."""

    type: Literal["crank_table"] = Field("crank_table", description="A load tabulated over the crank angle.")
    crank_angle_deg: list[float] = Field(min_length=2, examples=[[0, 90, 180, 270]], description="Crank angles of "
                                         "the table rows [deg]; the magnitudes are force_N or torque_Nm, one per row.")


class PositionTableLoadIn(_LoadBase):
    """Load magnitude tabulated over the output position: slide displacement [m] or output angle [deg]."""

    type: Literal["position_table"] = Field("position_table", description="A load tabulated over the output "
                                            "position (an indicator diagram, say).")
    position_m: list[float] | None = Field(None, min_length=2, description="Output slide position along its guide [m].")
    position_deg: list[float] | None = Field(None, min_length=2, description="Output link angle [deg].")


LoadIn = Annotated[Union[WindowLoadIn, CrankTableLoadIn, PositionTableLoadIn], Field(discriminator="type")]


class LinkTorqueIn(StrictModel):
    """A constant external torque on a link [N·m], counter-clockwise positive."""

    link: str = Field(description="Link the torque acts on, by name.", examples=["rocker"])
    torque_Nm: float = Field(description="Torque from outside on the link [N·m], counter-clockwise positive.",
                             examples=[-20.0])


class PairFrictionIn(StrictModel):
    """Friction in one pair: Coulomb (a coefficient; for a revolute pair with its journal radius, the friction
    circle f·r) and an optional viscous term."""

    coefficient: float = Field(ge=0, le=MAX_FRICTION_COEFFICIENT,
                               description="Sliding (kinetic) coefficient of friction f [-]; above 1 is "
                               "accepted with a warning (steel on steel 0.15-0.2, seed 000:557-569).",
                               examples=[0.15])
    static_coefficient: float | None = Field(None, ge=0, le=MAX_FRICTION_COEFFICIENT,
                                             description="Coefficient for breaking away from rest f0 >= f [-]; "
                                             "default f.", examples=[0.17])
    journal_radius_m: float = Field(0.0, ge=0, le=MAX_LENGTH_M,
                                    description="Revolute pair: pin (journal) radius r [m]; the reaction is "
                                    "tangent to the friction circle of radius f·r. Zero (default) or left out "
                                    "for a slide.", examples=[0.02])
    viscous: float = Field(0.0, ge=0, le=1e9, description="Viscous coefficient c: friction c·w_rel [N·m·s/rad] in "
                           "a revolute pair, c·v_rel [N·s/m] in a slide.")
    rolling_resistance_m: float = Field(0.0, ge=0, le=MAX_LENGTH_M,
                                        description="A slide run on rollers: coefficient of rolling friction k "
                                        "[m], the resisting moment k·N at the contact (hardened steel on steel "
                                        "about 1e-5 m); the slide then feels (k/rho)·N and `coefficient` is only "
                                        "the adhesion (pure rolling needs f > k/rho).", examples=[1e-5])
    roller_radius_m: float = Field(0.0, ge=0, le=MAX_LENGTH_M,
                                   description="With `rolling_resistance_m`: the roller's radius rho [m].",
                                   examples=[0.01])


FrictionIn = Annotated[dict[str, PairFrictionIn], Field(
    max_length=20, description="Friction per pair, keyed by the pair's (joint's) name as the answer's "
    "`joint_reactions_N` names them (O, A, B, Q, guide, ...); pairs left out are frictionless.",
    examples=[{"O": {"coefficient": 0.1, "journal_radius_m": 0.02}, "guide": {"coefficient": 0.15}}])]


class LinkageFields(StrictModel):
    """A linkage with its loads and counterweights, where a subclass may leave the mechanism and its speed out."""

    mechanism: MechanismIn | None = Field(None, description="The linkage, chosen by `type`: fourbar, "
                                          "slider_crank, slotted_lever or a general linkage.")
    speed_rpm: float | None = Field(None, ge=1e-6, le=1e6, description="Crank speed [rev/min].")
    crank_acceleration_rad_s2: float = Field(
        0.0, ge=-1e9, le=1e9, description="Crank angular acceleration, the same at every angle [rad/s²]."
    )
    samples: int = Field(360, ge=3, json_schema_extra=service_limit("max_samples"),
                         description="Uniformly spaced crank angles over one revolution.")
    crank_angle_deg: list[float] | None = Field(
        None, min_length=1, json_schema_extra=service_limit("max_samples"),
        description="Explicit crank angles [deg]; overrides samples."
    )
    gravity: GravityIn | None = Field(None, description="Gravity; null (default) switches it off.")
    loads: list[LoadIn] = Field(default_factory=list, description="Process loads on the output member.")
    torques: list[LinkTorqueIn] = Field(default_factory=list, description="Constant external torques on links.")
    counterweights: list[CounterweightIn] = Field(
        default_factory=list, description="Counterweights already fitted (a balancing answer's, as they are)."
    )


class LinkageRequest(LinkageFields):
    """A linkage at a crank speed: what every mechanism endpoint takes."""

    mechanism: MechanismIn = Field(description="The linkage, chosen by `type`: fourbar, slider_crank, "
                                   "slotted_lever or a general linkage of links and joints.")
    speed_rpm: float = Field(60.0, ge=1e-6, le=1e6, description="Crank speed [rev/min].")

    @property
    def omega_rad_s(self) -> float:
        """Crank speed [rad/s]."""
        return self.speed_rpm * math.pi / 30.0


class WarningOut(BaseModel):
    """A likely mistake in the request or a weak point of the result: the answer stands, but look again."""

    code: str = Field(description="Stable identifier of the check, e.g. `length_likely_mm`, `transmission_angle_low`.")
    field: str | None = Field(None, description="The request field it concerns, as this API spells it.")
    value: float | None = Field(None, description="The number that triggered it, in `unit`.")
    unit: str = Field("", description="Unit of `value` (angles in degrees).")
    message: str = Field(description="What was found and what to check, in words.")
    crank_angle_ranges_deg: list[list[float]] | None = Field(
        None, description="Crank-angle ranges [start, end] where it holds [deg].")
    stage: str | None = Field(None, description="In a machine design, the stage that found it: analysis, "
                              "balancing, drive, teeth, flywheel, motor or simulation; null elsewhere.")

class ValidityCheckOut(BaseModel):
    """A condition the answer's model needs, held against its limit; a failed one comes with a warning of the
    same code."""

    name: str = Field(description="The condition, e.g. `motor_stalls`, `follower_contact`, `pressure_angle`.")
    value: float = Field(description="What the answer gives, in `unit`.")
    limit: float = Field(description="What the model needs, in the same unit.")
    passed: bool = Field(description="The condition holds: the answer is inside its model.")
    detail: str = Field(description="What is compared, in words.")
    unit: str = Field("", description="Unit of `value` and `limit` (angles in degrees); empty for a ratio.")



class SummaryOut(BaseModel):
    """RMS over the samples and peak absolute values of the frame loads and the driving torque."""

    rms_shaking_force_N: float = Field(description="RMS over the crank-angle samples of the shaking force's "
                                       "magnitude |F| [N] (the force the linkage exerts on the frame).")
    max_shaking_force_N: float = Field(description="Largest magnitude of the shaking force over the samples [N].")
    rms_shaking_moment_Nm: float = Field(description="RMS over the samples of the shaking moment about the crank "
                                         "pivot O [N·m].")
    max_shaking_moment_Nm: float = Field(description="Largest absolute shaking moment about O over the samples [N·m].")
    rms_driving_torque_Nm: float = Field(description="RMS over the samples of the driving torque on the crank [N·m].")
    max_driving_torque_Nm: float = Field(description="Largest absolute driving torque on the crank over the samples "
                                         "[N·m].")
    max_bearing_force_N: float = Field(description="Largest magnitude of any revolute joint's reaction over the "
                                       "samples [N].")


FOURBAR_EXAMPLE: JsonDict = {
    "type": "fourbar",
    "ground_length_m": 0.30,
    "crank_length_m": 0.10,
    "coupler_length_m": 0.25,
    "rocker_length_m": 0.25,
    "branch": 1,
    "links": {
        "crank": {"mass_kg": 1.0, "com_m": [0.05, 0.0], "inertia_kgm2": 0.001},
        "coupler": {"mass_kg": 2.0, "com_m": [0.125, 0.0], "inertia_kgm2": 0.02},
        "rocker": {"mass_kg": 1.5, "com_m": [0.125, 0.0], "inertia_kgm2": 0.008},
    },
}

#: A six-bar press: a crank-rocker (O-A-B-Q) whose rocker drives a ram on a vertical guide through a rod C-D.
SIX_BAR_PRESS_EXAMPLE: JsonDict = {
    "type": "linkage",
    "frame_points_m": {"O": [0.0, 0.0], "Q": [0.3, 0.0], "G": [0.45, 0.0]},
    "links": [
        {"name": "crank", "joints": ["O", "A"], "length_m": 0.1, "mass_kg": 1.0, "com_m": [0.05, 0.0],
         "inertia_kgm2": 0.001},
        {"name": "coupler", "joints": ["A", "B"], "length_m": 0.35, "mass_kg": 2.0, "com_m": [0.175, 0.0],
         "inertia_kgm2": 0.02},
        {"name": "rocker", "joints": ["Q", "B"], "length_m": 0.25, "points_m": {"C": [0.4, 0.0]}, "mass_kg": 3.0,
         "com_m": [0.2, 0.0], "inertia_kgm2": 0.04},
        {"name": "rod", "joints": ["C", "D"], "length_m": 0.5, "mass_kg": 2.5, "com_m": [0.25, 0.0],
         "inertia_kgm2": 0.05},
        {"name": "ram", "joints": ["D"], "mass_kg": 8.0},
    ],
    "joints": [
        {"name": "O", "kind": "revolute", "links": ["frame", "crank"]},
        {"name": "A", "kind": "revolute", "links": ["crank", "coupler"]},
        {"name": "B", "kind": "revolute", "links": ["coupler", "rocker"]},
        {"name": "Q", "kind": "revolute", "links": ["frame", "rocker"]},
        {"name": "C", "kind": "revolute", "links": ["rocker", "rod"]},
        {"name": "D", "kind": "revolute", "links": ["rod", "ram"]},
        {"name": "guide", "kind": "prismatic", "links": ["frame", "ram"], "through": "G", "axis_deg": 90.0},
    ],
    "crank": "crank",
    "output": "ram",
}
