"""Schemas of POST /v1/gears/train: a given train of meshes and planetary stages, from its tooth numbers."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Discriminator, Field, Tag

from .common import Length, StrictModel, WarningOut

Teeth = Annotated[int, Field(ge=1, le=10_000)]
Speed = Annotated[float, Field(ge=-1e6, le=1e6)]
MemberName = Literal["sun", "ring", "carrier"]


class TrainMeshIn(StrictModel):
    """A mesh: the driving wheel on the current shaft drives the driven wheel on the next shaft."""

    type: Literal["mesh"] = Field("mesh", description="A pair of meshing wheels.")
    driving_teeth: Teeth = Field(description="Teeth of the driving wheel.", examples=[20])
    driven_teeth: Teeth = Field(description="Teeth of the driven wheel.", examples=[60])
    internal: bool = Field(False, description="One wheel is an annulus: both turn the same way.")
    idler: bool = Field(False, description="The driving wheel is the previous mesh's driven wheel itself.")
    efficiency: float | None = Field(None, gt=0, le=1, description="Default: a closed spur pair's (table).")


class TrainPlanetaryIn(StrictModel):
    """A planetary stage: sun, planets, ring and carrier, one of sun, ring or carrier held (Willis)."""

    type: Literal["planetary"] = Field(description="A planetary stage of sun, planets, ring and carrier.")
    sun_teeth: Teeth = Field(description="Teeth of the sun wheel.", examples=[20])
    planet_teeth: Teeth = Field(description="Teeth of each planet (meshing with the sun).", examples=[30])
    ring_teeth: Teeth = Field(description="Teeth of the ring (annulus).", examples=[80])
    planet_ring_teeth: Teeth | None = Field(None, description="Stepped planet: the teeth meshing with the ring.")
    fixed: MemberName = Field("ring", description="The member held still.")
    input: MemberName = Field("sun", description="The member driven by the previous shaft.")
    output: MemberName = Field("carrier", description="The member that drives the next shaft.")
    efficiency: float | None = Field(None, gt=0, le=1, description="The stage's efficiency; default from "
                                    "basic_efficiency by the loss in the motion relative to the carrier.")
    basic_efficiency: float | None = Field(None, gt=0, le=1, description="Efficiency with the carrier held (both "
                                           "meshes); default the table's closed spur pair, squared.")
    ring_internal: bool = Field(True, description="false: the ring is an external second sun meshing with a "
                                "stepped planet (z_s + z_p = z_r + planet_ring_teeth): a positive basic ratio, "
                                "large ratios, and a stage that may self-lock.")


def _element_type(value: object) -> str:
    """A mesh unless it says otherwise: most trains are meshes only."""
    found = value.get("type", "mesh") if isinstance(value, dict) else getattr(value, "type", "mesh")
    return str(found)


TrainElementIn = Annotated[
    Annotated[TrainMeshIn, Tag("mesh")] | Annotated[TrainPlanetaryIn, Tag("planetary")],
    Discriminator(_element_type),
]


class TrainIn(StrictModel):
    """A serial gear train, input side first: each element starts on the shaft the previous one drove."""

    elements: list[TrainElementIn] = Field(min_length=1, max_length=64, description="Meshes and planetary stages, "
                                           "input side first.")
    module_m: Length | None = Field(None, description="Module of every wheel [m]: pitch diameters d = m·z.")
    input_speed_rad_s: Speed | None = Field(None, description="Input shaft speed [rad/s].")
    output_speed_rad_s: Speed | None = Field(None, description="Output shaft speed [rad/s] (instead of the input's).")

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"elements": [{"driving_teeth": 20, "driven_teeth": 30}, {"driving_teeth": 18, "driven_teeth": 36},
                      {"driving_teeth": 25, "driven_teeth": 100, "internal": True}],
         "module_m": 0.004, "input_speed_rad_s": 200.0},
        {"elements": [{"type": "planetary", "sun_teeth": 20, "planet_teeth": 31, "ring_teeth": 82}],
         "input_speed_rad_s": 150.0},
    ]})


class TrainShaftOut(BaseModel):
    """A shaft, 0 the input."""

    index: int = Field(description="Shaft number along the train, 0 the input shaft.")
    ratio: float = Field(description="Input speed over this shaft's speed, with sign [-].")
    direction: int = Field(description="+1 turning with the input, -1 against it.")
    speed_rad_s: float | None = Field(description="Shaft speed [rad/s], negative when it turns against the input; "
                                      "null without a given input or output speed.")
    speed_rpm: float | None = Field(description="The same speed [rev/min]; null without a given speed.")
    wheels: list[str] = Field(description="Names of the wheels keyed to this shaft.")


class TrainWheelOut(BaseModel):
    """A wheel and its pitch diameter d = m·z."""

    name: str = Field(description='Wheel name: "1", "2", "2\'"... along the train, or "sun 1", "planet 1", "ring 1" '
                      'of a planetary stage.')
    teeth: int = Field(description="Number of teeth.")
    shaft: int | None = Field(description="The shaft it is keyed to; null for planets and held members.")
    pitch_diameter_m: float | None = Field(description="Pitch diameter d = m·z [m]; null without `module_m`.")


class TrainChecksOut(BaseModel):
    """The seed's closed form (-1)^k·prod(z_driven/z_driving) times the Willis ratios, against the propagation."""

    formula_ratio: float = Field(description="The train's ratio by the closed form (-1)^k·prod(z_driven/z_driving) "
                                 "times each planetary stage's Willis ratio [-].")
    agrees: bool = Field(description="The closed form and the mesh-by-mesh propagation agree to 1e-9, relative.")


class TrainOut(BaseModel):
    """Ratio, senses, speeds and efficiency of the train."""

    ratio: float = Field(description="Input speed over output speed, negative when the output turns the other way.")
    output_direction: int = Field(description="+1: the output turns with the input; -1: against it.")
    efficiency: float = Field(description="Product of the elements' efficiencies with power flowing from input "
                              "to output [-]; a planetary stage's by the direction of the power through its "
                              "carrier-held train. Zero or below: the input cannot drive the train (it locks).")
    back_efficiency: float = Field(description="The same with the output driving the input (power flowing back) "
                                   "[-]; zero or below: the train is self-locking.")
    locked: bool = Field(description="The input cannot drive the train: `efficiency` is zero or below.")
    self_locking: bool = Field(description="The output cannot drive the input: `back_efficiency` is zero or below.")
    external_meshes: int = Field(description="Number k of external meshes, the exponent of (-1)^k.")
    shafts: list[TrainShaftOut] = Field(description="Every shaft, input first, output last.")
    wheels: list[TrainWheelOut] = Field(description="Every wheel with its teeth, shaft and pitch diameter.")
    checks: TrainChecksOut = Field(description="The closed-form ratio against the propagation.")
    warnings: list[WarningOut] = Field(description="A planetary stage that self-locks either way "
                                       "(`self_locking`, `self_locking_back`).")
