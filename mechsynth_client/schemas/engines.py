"""Schemas of POST /v1/balancing/engine: the shaking of an engine of several cylinders, order by order."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field

from .common import Coordinate, Length, StrictModel

Arrangement = Literal["inline2_360", "inline2_180", "inline3", "inline4", "inline5", "inline6", "v2_90",
                      "v8_crossplane", "boxer2", "flat4"]
Angle = Annotated[float, Field(ge=-720, le=720)]
Mass = Annotated[float, Field(ge=0, le=1e4)]


class CylinderIn(StrictModel):
    """One cylinder on the crankshaft."""

    crank_angle_deg: Angle = Field(examples=[180.0], description="Its throw's phase behind the first throw [deg]: it reaches its "
                                   "top dead centre that much later (in-line: the classic crank angles).")
    bank_angle_deg: Angle = Field(0.0, description="Its axis' angle from the vertical, in the crank's sense of "
                                  "rotation [deg]: 0 in line, ±45 for a 90° V.")
    axial_position_m: Coordinate = Field(0.0, description="Its plane's position along the crankshaft [m].")


class EngineIn(StrictModel):
    """An engine: the slider-crank of every cylinder (all alike) and where each sits on the crankshaft."""

    crank_radius_m: Length = Field(examples=[0.04], description="Crank radius r [m].")
    rod_length_m: Length = Field(examples=[0.14], description="Connecting-rod length l [m], longer than r.")
    reciprocating_mass_kg: Mass = Field(examples=[0.5], description="Reciprocating mass per cylinder (piston, pin, the rod's "
                                        "share at the small end) [kg].")
    rotating_mass_kg: Mass = Field(0.0, description="Rotating mass per cylinder at the crank pin (the rod's "
                                   "share at the big end, the pin, unbalanced web) [kg].")
    speed_rpm: float = Field(gt=0, le=1e5, examples=[3000.0], description="Crank speed [rev/min].")
    arrangement: Arrangement | None = Field(None, description="A classic arrangement instead of `cylinders`, its "
                                            "cylinders `pitch_m` apart.")
    pitch_m: Length = Field(0.1, description="With `arrangement`: distance between cylinder planes [m].")
    cylinders: list[CylinderIn] | None = Field(None, min_length=1, max_length=64,
                                               description="The cylinders, the first one's throw the reference.")
    firing_order: list[int] | None = Field(None, min_length=1, max_length=64, description="An in-line engine by "
                                           "its even firing order instead (cylinders 1..n from the first, "
                                           "`pitch_m` apart): each fires 720/n (four-stroke) or 360/n "
                                           "(two-stroke) degrees after the one before it.",
                                           examples=[[1, 2, 4, 5, 3]])
    strokes: Literal[2, 4] = Field(4, description="With `firing_order`: a four- or two-stroke cycle.")
    orders: int = Field(4, ge=1, le=24, description="Crank orders reported (FFT of the exact acceleration).")
    reference_z_m: Coordinate | None = Field(None, description="Axial position the moments are taken about [m]; "
                                             "left out: the cylinders' mean position.")

    model_config = ConfigDict(json_schema_extra={
        "allOf": [{"oneOf": [{"required": ["arrangement"]}, {"required": ["cylinders"]},
                             {"required": ["firing_order"]}]}],
        "examples": [
            {"crank_radius_m": 0.045, "rod_length_m": 0.15, "reciprocating_mass_kg": 0.5, "speed_rpm": 3000,
             "arrangement": "inline4", "pitch_m": 0.09},
            {"crank_radius_m": 0.045, "rod_length_m": 0.15, "reciprocating_mass_kg": 0.5, "rotating_mass_kg": 0.3,
             "speed_rpm": 3000, "cylinders": [{"crank_angle_deg": 0, "bank_angle_deg": -45},
                                              {"crank_angle_deg": 0, "bank_angle_deg": 45}]},
        ]})


class OrderOut(BaseModel):
    """One crank order of the shaking force [N] (or moment [N·m]): an ellipse, a forward and a backward circle."""

    order: int = Field(description="Crank order k: it turns at k times crank speed.")
    largest: float = Field(description="Largest magnitude over the revolution, |P| + |Q| [N or N·m].")
    smallest: float = Field(description="Smallest magnitude, ||P| - |Q|| (equal to `largest`: constant "
                            "magnitude, a pure circle) [N or N·m].")
    forward: float = Field(description="|P|: the circle turning with the crank at k·w [N or N·m].")
    backward: float = Field(description="|Q|: the circle turning against it at k·w [N or N·m].")
    balanced: bool = Field(description="Cancelled by the arrangement itself (largest ≤ 1e-9 of the engine's "
                           "scale).")
    forward_mass_radius: float = Field(description="Mass times radius [kg·m] (for a moment: times the axial "
                                       "spacing of the couple's two masses, kg·m²) on a shaft at +k·w that "
                                       "cancels the forward circle: the crank's counterweight for order 1.")
    forward_angle_deg: float = Field(description="Where that mass points at crank angle 0 [deg from vertical, "
                                     "in the sense of rotation].")
    backward_mass_radius: float = Field(description="The same on a shaft at -k·w for the backward circle (a "
                                        "balance shaft) [kg·m or kg·m²].")
    backward_angle_deg: float = Field(description="Where that mass points at crank angle 0 [deg].")


class EngineOut(BaseModel):
    """Shaking force and moment (about the transverse axes) by crank orders, what cancels each, and the checks."""

    cylinders: int = Field(description="Number of cylinders.")
    speed_rad_s: float = Field(description="Crank speed [rad/s].")
    reference_z_m: float = Field(description="Axial position the moments are taken about [m].")
    force_orders: list[OrderOut] = Field(description="The shaking force's orders 1..`orders` [N].")
    moment_orders: list[OrderOut] = Field(description="The shaking moment's orders about the transverse axes "
                                          "[N·m], its masses as couples.")
    largest_force_N: float = Field(description="Largest shaking force over the revolution [N].")
    largest_moment_Nm: float = Field(description="Largest transverse shaking moment over the revolution [N·m].")
    reconstruction_error_N: float = Field(description="Check: largest difference between the sampled force and "
                                          "the sum of its orders [N].")
    residual_force_N: float = Field(description="Check: the largest reported order of the force left once the "
                                    "named masses, evaluated from their own motion, are added (zero to rounding).")
    residual_moment_Nm: float = Field(description="Check: the same for the moment [N·m].")
    remaining_force_N: float = Field(description="Largest force left with every named mass: the orders beyond "
                                     "`orders` [N].")
    remaining_moment_Nm: float = Field(description="Largest moment left with every named couple [N·m].")
