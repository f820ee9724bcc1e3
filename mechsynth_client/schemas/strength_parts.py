"""Schemas of the machine's parts sized for strength: every revolute joint's pin and bearing, the crank shaft,
its bearings and its hubs' keys. A block (:class:`PartsIn`) a strength or machine request carries, and its answer
(:class:`PartsOut`)."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field, model_validator

from .common import StrictModel, WarningOut
from .strength import MaterialIn

BushingMaterialName = Literal["sintered_bronze_oil", "cast_bronze_greased", "ptfe_composite_dry", "acetal_dry"]
BearingTypeName = Literal["deep_groove_ball", "cylindrical_roller", "needle_roller"]
NotchName = Literal["none", "shoulder_sharp", "shoulder_rounded", "keyseat_end_mill", "keyseat_sled_runner",
                    "retaining_ring_groove"]


class PinIn(StrictModel):
    """How a joint's pin is held (Roloff/Matek's clevis cases; docs/strength.md, Pins)."""

    shear_planes: Literal[1, 2] = Field(2, description="1: an overhung pin fixed in one member (single shear); "
                                        "2: a clevis (double shear).")
    fit: Literal["loose", "fixed_in_fork", "fixed_in_rod"] = Field(
        "loose", description="A clevis pin loose in rod and fork, or pressed into the fork or into the rod.")
    rod_thickness_mm: float | None = Field(None, gt=0, le=1000, description="Thickness t_S of the middle member "
                                           "(single shear: the member on the overhang) [mm]; null: rod_ratio·d.")
    fork_thickness_mm: float | None = Field(None, gt=0, le=1000, description="Thickness t_G of each fork cheek "
                                            "[mm]; null: fork_ratio·d.")
    rod_ratio: float = Field(1.0, gt=0, le=10, description="t_S/d when no thickness is given [-].")
    fork_ratio: float = Field(0.5, gt=0, le=10, description="t_G/d when no thickness is given [-].")
    application_factor: float = Field(1.0, ge=1, le=5, description="K_A on the reaction for shocks [-].")
    fixed_in: str | None = Field(None, min_length=1, max_length=40, description="The link the pin is pressed "
                                 "into (or `frame`): the kind of load is read in its frame; null: the pin turns.")


class BushingLimitsIn(StrictModel):
    """A bushing material of your own, with every limit."""

    name: str = Field("user", min_length=1, max_length=80, description="Your bushing material's name.")
    pressure_limit_MPa: float = Field(gt=0, examples=[10], le=1000, description="Largest mean pressure F/(d·b) [MPa].")
    speed_limit_m_s: float = Field(gt=0, examples=[6], le=100, description="Largest sliding speed [m/s].")
    pv_limit_MPa_m_s: float = Field(gt=0, examples=[1.75], le=1000, description="Largest cycle-mean p·v [MPa·m/s].")


class JointBearingIn(StrictModel):
    """A plain bushing on the pin, or a rolling bearing from the catalogue by its ISO 281 life."""

    kind: Literal["bushing", "rolling"] = Field("bushing", description="Plain bushing (p, v, p·v) or rolling "
                                                "bearing (basic rating life).")
    bushing_material: BushingMaterialName = Field("sintered_bronze_oil", description="A shipped bushing material "
                                                  "(indicative limits).")
    bushing_limits: BushingLimitsIn | None = Field(None, description="Your bushing material instead.")
    bushing_length_mm: float | None = Field(None, gt=0, le=1000, description="A given bushing length, checked; "
                                            "null: the least length within 1.5 bores.")
    life_hours: float = Field(20000.0, gt=0, le=1e7, description="Required basic rating life L10h [h].")
    static_safety: float = Field(1.0, ge=0.5, le=10, description="Required C0/P0 [-].")
    types: list[BearingTypeName] | None = Field(None, min_length=1, max_length=3, description="Rolling bearing "
                                                "types allowed; null: all.")


class JointPartsIn(StrictModel):
    """One joint built otherwise than the block's defaults."""

    joint: str = Field(min_length=1, max_length=40, description="The revolute joint, by name.", examples=["A"])
    pin: PinIn | None = Field(None, description="This joint's pin; default the block's.")
    bearing: JointBearingIn | None = Field(None, description="This joint's bearing; default the block's.")
    pin_material: MaterialIn | None = Field(None, description="This joint's pin material; default the block's.")


class RollingBearingIn(StrictModel):
    """One entry of your bearing catalogue."""

    designation: str = Field(min_length=1, max_length=40, description="The catalogue designation.")
    type: BearingTypeName = Field(description="Bearing type.")
    bore_mm: float = Field(gt=0, le=2000, examples=[20], description="Bore [mm].")
    outer_mm: float = Field(gt=0, le=3000, examples=[47], description="Outer diameter [mm].")
    width_mm: float = Field(gt=0, le=1000, examples=[14], description="Width [mm].")
    dynamic_rating_kN: float = Field(gt=0, examples=[13.5], le=1e5, description="Basic dynamic load rating C [kN].")
    static_rating_kN: float = Field(gt=0, examples=[6.55], le=1e5, description="Basic static load rating C0 [kN].")


class HubKeyIn(StrictModel):
    """A hub keyed to the crank shaft by a DIN 6885-1 parallel key."""

    hub: Literal["crank", "drive", "coupling", "flywheel", "counterweight"] = Field(
        description="The hub: its torque is the driving torque (crank, drive, coupling), the flywheel's swing "
        "about the mean, or none (a counterweight).")
    hub_length_mm: float = Field(gt=0, examples=[60], le=2000, description="The hub's length, which bounds the key [mm].")
    allowed_pressure_MPa: float = Field(gt=0, examples=[120], le=2000, description="Allowed pressure on the weaker of hub, key "
                                        "and shaft [MPa].")
    form: Literal["A", "B"] = Field("A", description="A: round ends (bearing length l - b); B: square ends.")
    count: Literal[1, 2] = Field(1, description="One key, or two at 180° carrying 1.5 times one.")
    application_factor: float = Field(1.0, ge=1, le=5, description="K_A on the torque [-].")


class CrankShaftIn(StrictModel):
    """The crank shaft between its bearings A (at 0) and B, sized by DE-Goodman (Shigley)."""

    span_mm: float = Field(gt=0, examples=[100], le=5000, description="Bearing A to bearing B [mm].")
    crank_position_mm: float = Field(ge=-5000, examples=[150], le=5000, description="The crank along the shaft from A [mm] "
                                     "(negative: overhung beyond A).")
    drive_position_mm: float = Field(ge=-5000, examples=[50], le=5000, description="The coupling or drive gear from A [mm].")
    drive: Literal["coupling", "gear"] = Field("coupling", description="How the torque comes in.")
    pitch_radius_mm: float | None = Field(None, gt=0, le=5000, description="The drive gear's pitch radius [mm].")
    mesh_angle_deg: float = Field(0.0, ge=-360, le=360, description="Direction from the shaft to the mating "
                                  "gear [deg].")
    pressure_angle_deg: float = Field(20.0, gt=0, lt=45, description="Normal pressure angle [deg].")
    helix_angle_deg: float = Field(0.0, ge=0, lt=45, description="Helix angle [deg].")
    flywheel_position_mm: float | None = Field(None, ge=-5000, le=5000, description="A flywheel on this shaft "
                                               "[mm]; null: none.")
    flywheel_mass_kg: float = Field(0.0, ge=0, le=1e5, description="Its mass, for its weight [kg].")
    material: MaterialIn = Field(default_factory=lambda: MaterialIn(grade="42CrMo4+QT"),
                                 description="The shaft's material.")
    design_factor: float = Field(2.0, ge=1, le=20, description="Required DE-Goodman and yield factors [-].")
    surface: Literal["ground", "machined", "hot_rolled", "forged"] = Field("machined", description="Marin's ka.")
    reliability: float = Field(0.99, ge=0.5, lt=1, description="Marin's ke, one of Shigley Table 6-5's.")
    bearing_notch: NotchName = Field("shoulder_rounded", description="The notch at the bearing seats "
                                     "(Shigley Table 7-1).")
    bearing_life_hours: float = Field(40000.0, gt=0, le=1e7, description="Its two bearings' required L10h [h].")
    keys: list[HubKeyIn] = Field(default_factory=list, max_length=5, description="Its hubs' keys.")

    @model_validator(mode="after")
    def _gear_needs_radius(self) -> CrankShaftIn:
        if self.drive == "gear" and self.pitch_radius_mm is None:
            raise ValueError("a gear drive needs its pitch_radius_mm")
        return self


class PartsIn(StrictModel):
    """Every revolute joint's pin and bearing, and optionally the crank shaft with its bearings and keys."""

    pin_material: MaterialIn = Field(default_factory=lambda: MaterialIn(grade="C45E+QT"),
                                     description="Every pin's material unless a joint says otherwise.")
    member_strength_MPa: float | None = Field(None, gt=0, le=1e4, description="Ultimate strength of the weakest "
                                              "member a pin bears on [MPa]; null: the pin's.")
    pin: PinIn = Field(default_factory=PinIn, description="Every pin's arrangement unless a joint says otherwise.")
    bearing: JointBearingIn = Field(default_factory=JointBearingIn, description="Every joint's bearing unless a "
                                    "joint says otherwise.")
    joints: list[JointPartsIn] | None = Field(None, max_length=40, description="Joints built otherwise.")
    bearing_catalogue: list[RollingBearingIn] | None = Field(None, min_length=1, max_length=500, description=(
        "Your rolling bearings, replacing the shipped indicative catalogue."))
    crank_shaft: CrankShaftIn | None = Field(None, description="Size the crank shaft too.")


class PartCheckOut(BaseModel):
    """One check of a part: the value the cycle gives against its limit."""

    part: str = Field(description="The joint, shaft, bearing or hub.")
    name: str = Field(description="The check, e.g. pin_bending, bushing_pv, bearing_life, shaft_fatigue_safety.")
    value: float | None = Field(description="The cycle's value, in `unit`; null: unbounded (a bearing that is "
                                "never loaded lives for ever).")
    limit: float = Field(description="Its limit, in `unit`.")
    unit: str = Field(description="MPa, m/s, MPa·m/s, h, mm or 1.")
    at_least: bool = Field(description="The value must reach the limit (a life, a safety factor), not stay under.")
    passed: bool = Field(description="The value on the right side of its limit.")
    meaning: str = Field(description="What it checks, in words.")


class PinOut(BaseModel):
    """A joint's pin at its chosen diameter."""

    diameter_mm: float = Field(description="Chosen: ISO 2340, or the bearing's bore [mm].")
    diameter_required_mm: float = Field(description="Least diameter every check allows [mm].")
    governing: str = Field(description="The check that set the least diameter.")
    force_max_N: float = Field(description="Largest reaction times K_A [N].")
    load_kind: Literal["static", "pulsating", "alternating"] = Field(description="Sets the allowable stresses.")
    max_shear_MPa: float = Field(description="Largest stress over the cycle [MPa].")
    max_bending_MPa: float = Field(description="Largest bending stress over the cycle [MPa].")
    max_rod_pressure_MPa: float = Field(description="Largest bearing pressure in the rod over the cycle [MPa].")
    max_fork_pressure_MPa: float = Field(description="Largest bearing pressure in each fork cheek over the cycle [MPa].")


class BushingOut(BaseModel):
    """A plain bushing on the pin."""

    material: str = Field(description="The bushing's material.")
    bore_mm: float = Field(description="Bore [mm].")
    length_mm: float = Field(description="Length [mm].")
    max_pressure_MPa: float = Field(description="Largest pressure over the cycle [MPa].")
    max_sliding_speed_m_s: float = Field(description="Largest sliding speed [m/s].")
    mean_pv_MPa_m_s: float = Field(description="The cycle's mean p·v [MPa·m/s].")


class RollingBearingOut(BaseModel):
    """A catalogue rolling bearing and its basic rating life over the cycle."""

    designation: str = Field(description="The catalogue designation.")
    type: str = Field(description="Bearing type.")
    bore_mm: float = Field(description="Bore [mm].")
    outer_mm: float = Field(description="Outer diameter [mm].")
    width_mm: float = Field(description="Width [mm].")
    dynamic_rating_kN: float = Field(description="Basic dynamic load rating C [kN].")
    static_rating_kN: float = Field(description="Basic static load rating C0 [kN].")
    mean_load_N: float = Field(description="The cycle's mean load P, weighted by revolutions [N].")
    peak_load_N: float = Field(description="Largest radial load over the cycle [N].")
    revolutions_per_cycle: float = Field(description="Revolutions the rings sweep per cycle [-].")
    oscillating: bool = Field(description="The joint only swings (does not turn).")
    swing_deg: float = Field(description="Full swing of an oscillating joint [deg] (360 or more when it turns).")
    life_million_revolutions: float | None = Field(description="L10 [million revolutions]; null: unloaded.")
    life_hours: float | None = Field(description="L10h [h]; null: unloaded or not turning.")
    static_safety: float | None = Field(description="C0/P0 [-]; null: unloaded.")


class JointPartsOut(BaseModel):
    """One revolute joint with its pin and its bearing."""

    joint: str = Field(description="The joint, by name.")
    links: list[str] = Field(description="The two links it joins (`frame` for the frame).")
    pin: PinOut = Field(description="The pin.")
    bushing: BushingOut | None = Field(description="Its plain bushing; null with a rolling bearing.")
    rolling: RollingBearingOut | None = Field(description="Its rolling bearing; null with a bushing.")
    max_relative_speed_rad_s: float = Field(description="Largest relative angular speed of its links [rad/s].")
    passed: bool = Field(description="Every check met.")


class ShaftSectionOut(BaseModel):
    """One checked section of the shaft."""

    name: str = Field(description="Name.")
    position_mm: float = Field(description="From bearing A [mm].")
    kf: float = Field(description="Fatigue notch factor in bending [-].")
    kfs: float = Field(description="Fatigue notch factor in torsion [-].")
    max_moment_Nm: float = Field(description="Largest bending moment over the cycle [N·m].")
    max_torque_Nm: float = Field(description="Largest torque over the cycle [N·m].")
    diameter_required_mm: float = Field(description="Least diameter it needs [mm].")
    fatigue_safety: float | None = Field(description="DE-Goodman at the chosen diameter; null when unloaded.")
    yield_safety: float | None = Field(description="First-cycle yield factor of safety [-]; null when unloaded.")


class KeyOut(BaseModel):
    """A hub's DIN 6885-1 key."""

    hub: str = Field(description="The hub.")
    designation: str = Field(description="e.g. `DIN 6885 A 14x9x56`.")
    b_mm: float = Field(description="Key width b [mm].")
    h_mm: float = Field(description="Key height h [mm].")
    t1_mm: float = Field(description="Keyway depth in the shaft t1 [mm].")
    t2_mm: float = Field(description="Keyway depth in the hub t2 [mm].")
    length_mm: float = Field(description="Length [mm].")
    max_pressure_MPa: float = Field(description="Largest pressure over the cycle [MPa].")
    max_shear_MPa: float = Field(description="Largest stress over the cycle [MPa].")


class CrankShaftOut(BaseModel):
    """The crank shaft, its bearings and its keys."""

    diameter_mm: float = Field(description="Chosen standard diameter [mm].")
    diameter_required_mm: float = Field(description="Least diameter it needs [mm].")
    endurance_limit_MPa: float = Field(description="Marin's endurance limit Se at the chosen diameter [MPa].")
    fatigue_safety: float | None = Field(description="Least DE-Goodman factor of safety [-]; null when unloaded.")
    yield_safety: float | None = Field(description="First-cycle yield factor of safety [-]; null when unloaded.")
    method: str = Field(description="The method and its source.")
    sections: list[ShaftSectionOut] = Field(description="Every checked section.")
    bearings: list[RollingBearingOut] = Field(description="Bearing A, then B.")
    keys: list[KeyOut] = Field(description="Its hubs' keys.")


class PartsOut(BaseModel):
    """The joints' and the crank shaft's parts, every check and every warning."""

    joints: list[JointPartsOut] = Field(description="Every revolute joint's parts.")
    crank_shaft: CrankShaftOut | None = Field(description="The crank shaft; null when not sized.")
    passed: bool = Field(description="Every check met.")
    checks: list[PartCheckOut] = Field(description="Every check of every part.")
    warnings: list[WarningOut] = Field(description="Named notes on where the models stretch.")
