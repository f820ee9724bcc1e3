"""Schemas of /v1/balancing/*: counterweights that send straight back to /v1/analysis, with their checks."""

from __future__ import annotations

from typing import Annotated, Literal, get_args

from pydantic import BaseModel, ConfigDict, Field
from pydantic.config import JsonDict

from .common import (
    FOURBAR_EXAMPLE,
    MAX_MASS_KG,
    Coordinate,
    CounterweightIn,
    Length,
    LinkageRequest,
    StrictModel,
    SummaryOut,
    WarningOut,
)

BalanceMode = Literal["static", "full", "optimal"]
BALANCE_MODES: tuple[BalanceMode, ...] = get_args(BalanceMode)

SLIDER_CRANK_EXAMPLE: JsonDict = {
    "type": "slider_crank",
    "crank_length_m": 0.05,
    "rod_length_m": 0.2,
    "links": {
        "crank": {"mass_kg": 1.0, "com_m": [0.02, 0.0], "inertia_kgm2": 0.001},
        "rod": {"mass_kg": 0.8, "com_m": [0.06, 0.0], "inertia_kgm2": 0.003},
        "slider": {"mass_kg": 1.2},
    },
}


class BalanceIn(LinkageRequest):
    """A linkage and where counterweights may go: a four-bar (static, full, optimal), a slider-crank or a shaper
    (optimal)."""

    counterweight_links: list[str] | None = Field(
        None, min_length=1, max_length=5,
        description="Links that may carry a counterweight, links that turn about a pivot (never a slider, ram or "
        "block). Default: a four-bar's or a shaper's crank and rocker, a slider-crank's crank (its rod when "
        "named); a four-bar's textbook variant uses coupler and rocker.",
    )
    max_radius_m: dict[str, Length] = Field(
        default_factory=dict, description="Largest counterweight radius per link [m]; default the link's length "
        "(crank, rocker, rod; the shaper's lever O1-B), twice the coupler's (without a crank counterweight the "
        "coupler's must sit beyond B)."
    )
    angle_deg: dict[str, float] = Field(default_factory=dict, description="Fixed counterweight angle per link [deg].")
    radius_m: dict[str, Length] = Field(default_factory=dict, description="Fixed counterweight radius per link [m].")
    objective: Literal["min_mass", "min_inertia"] = Field("min_mass", description="Static mode only.")
    method: Literal["program", "fixed_points"] = Field(
        "program", description="Static mode only: 'program' solves for the least added mass (or inertia); "
        "'fixed_points' moves each link's centre of mass to a fixed point in closed form (crank to O, coupler to "
        "B and the rocker with it to Q; without a coupler counterweight, the coupler split into point masses at A "
        "and B), on the radii in radius_m or max_radius_m (default the crank's and rocker's lengths, twice the "
        "coupler's).")
    mass_budget_kg: float | None = Field(None, ge=0, le=MAX_MASS_KG, description="Largest total added mass [kg].")

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "counterweight_links": ["crank", "rocker"],
         "max_radius_m": {"crank": 0.1, "rocker": 0.25}},
    ]})


class FullBalanceIn(BalanceIn):
    """Full balancing: also counter-rotors geared to crank and rocker."""

    rotor_ratios: dict[str, Annotated[float, Field(gt=0, le=1e3)]] = Field(
        default_factory=dict, description="Counter-rotor speed over its link's, opposite sense; default 1 (1:1)."
    )

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "max_radius_m": {"crank": 0.1, "rocker": 0.25}},
    ]})


class WeightsIn(StrictModel):
    """Weights of the optimal mode's objective (RMS values unless `peak_`).

    Dimensionless by default (`weight_scale: "relative"`): each term is divided by its value before balancing,
    so `{"shaking_force": 1, "shaking_moment": 2}` weighs a 1 % change of the moment twice a 1 % change of the
    force. With `weight_scale: "absolute"` they are per N and per N·m.
    """

    shaking_force: float = Field(1.0, ge=0, description="Per (N RMS)² of shaking force, scaled by its value "
                                 "before balancing.")
    shaking_moment: float = Field(0.0, ge=0, description="Per (N·m RMS)² of shaking moment, scaled likewise.")
    driving_torque: float = Field(0.0, ge=0, description="Per (N·m RMS)² of driving torque, scaled likewise.")
    bearing_forces: float = Field(0.0, ge=0, description="Per (N RMS)² of joint reactions, summed over the joints.")
    peak_shaking_force: float = Field(0.0, ge=0, description="Per N of the largest shaking force over the cycle.")
    peak_shaking_moment: float = Field(0.0, ge=0, description="Per N·m of the largest shaking moment.")
    added_mass: float = Field(1e-6, ge=0, description="Per kg of added mass (and per kg·m² of added inertia over "
                              "its link's length²).")


class OptimalBalanceIn(BalanceIn):
    """Optimal balancing of a four-bar, slider-crank or shaper: a weighted trade-off within a mass budget,
    optionally swept over several weight sets."""

    weights: WeightsIn = Field(default_factory=WeightsIn, description="Weights of the design answered first.")
    sweep: list[WeightsIn] = Field(default_factory=list, max_length=50,
                                   description="More weight sets: the trade-off curve, each point re-analysed.")
    weight_scale: Literal["relative", "absolute"] = Field(
        "relative", description="relative: each term over its value before balancing (dimensionless weights); "
        "absolute: weights per N and per N·m.")

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "mass_budget_kg": 4.0,
         "weights": {"shaking_force": 1.0, "shaking_moment": 2.0},
         "sweep": [{"shaking_force": 1.0}, {"shaking_force": 0.0, "shaking_moment": 1.0}]},
        {"mechanism": SLIDER_CRANK_EXAMPLE, "speed_rpm": 1500, "counterweight_links": ["crank", "rod"],
         "weights": {"shaking_force": 1.0, "shaking_moment": 1.0}},
    ]})


class CounterweightPlacementOut(BaseModel):
    """A counterweight's place: radius and angle in its link frame, and the link's new centre of mass."""

    link: str = Field(description="Link that carries the counterweight, by name.")
    radius_m: float = Field(description="Distance of the counterweight's centre from the link frame's origin (the "
                            "link's first joint) [m].")
    angle_deg: float = Field(description="Direction of the counterweight's centre in the link frame, from the "
                             "link's x-axis (toward its second joint), counter-clockwise positive, in [-180, 180] "
                             "[deg]: ±180 is straight behind the joint.")
    link_com_m: list[float] = Field(description="The link's centre of mass with all its counterweights, [x, y] in "
                                    "the link frame [m].")
    link_mass_kg: float = Field(description="The link's mass with all its counterweights [kg].")


class CounterRotorOut(BaseModel):
    """A counter-rotating inertia geared to a link at -ratio times its speed."""

    link: str = Field(description="Link the rotor is geared to, by name (crank or rocker).")
    inertia_kgm2: float = Field(description="Rotor inertia about its own axis [kg·m²].")
    ratio: float = Field(description="Rotor speed over the link's speed, turning the opposite way [-].")


class BalanceChecksOut(BaseModel):
    """Re-analysis with the plain kinetostatic model (not the map the program was built on)."""

    residual_shaking_force_N: float = Field(description="Largest magnitude of the shaking force left over the "
                                            "samples after balancing [N].")
    residual_shaking_force_rel: float = Field(description="residual_shaking_force_N over the largest shaking force "
                                              "before balancing [-]; 0 when that was 0.")
    residual_shaking_moment_Nm: float = Field(description="Largest absolute shaking moment about the crank pivot O "
                                              "left over the samples after balancing, counter-rotors included "
                                              "[N·m].")
    residual_shaking_moment_rel: float = Field(description="residual_shaking_moment_Nm over the largest shaking "
                                               "moment before balancing [-]; 0 when that was 0.")


class BalanceOut(BaseModel):
    """Counterweights (send them back to /v1/analysis as they are), their cost and effect."""

    mode: BalanceMode = Field(description="The balancing mode that answered: static, full or optimal.")
    counterweights: list[CounterweightIn] = Field(description="The counterweights to add, each on its link in the "
                                                  "link frame, in the shape `/v1/analysis` takes them.")
    placements: list[CounterweightPlacementOut] = Field(description="Each counterweight's radius and angle, in the "
                                                        "order of `counterweights`, and its link's new mass and "
                                                        "centre of mass.")
    total_added_mass_kg: float = Field(description="Sum of the counterweights' masses [kg].")
    added_inertia_kgm2: float = Field(description="Counterweights' inertia about their joints plus counter-rotors.")
    summary_before: SummaryOut = Field(description="Shaking force, moment and driving torque of the linkage as "
                                       "given, before balancing.")
    summary_after: SummaryOut = Field(description="The same figures of the balanced linkage from a plain "
                                      "re-analysis (counter-rotors included).")
    checks: BalanceChecksOut = Field(description="What is left of the shaking force and moment, measured by the "
                                     "plain kinetostatic model.")
    coupler_inertia_kgm2: float | None = Field(None, description="Full mode: the coupler's inertia about its centre "
                                               "of mass that makes it a physical pendulum [kg·m²]; null otherwise.")
    counter_rotors: list[CounterRotorOut] | None = Field(None, description="Full mode: the counter-rotors geared to "
                                                         "crank and rocker; null otherwise.")
    objective: float | None = Field(None, description="The program's objective at the answer: static, the added "
                                    "mass [kg] (min_mass) or the added inertia about the joints [kg·m²] "
                                    "(min_inertia), each with 1e-9 of the other; full, the added mass plus 1e-3/"
                                    "crank length² times the added inertia; optimal, the weighted sum of the terms "
                                    "(relative weights divided by each term's value before balancing) re-evaluated "
                                    "on the balanced linkage, plus the added-mass term. Null for fixed_points.")
    weights: WeightsIn | None = Field(None, description="Optimal mode: this point's weights, as given.")
    weight_scale: str | None = Field(None, description="Optimal mode: relative or absolute.")
    warnings: list[WarningOut] = Field(default_factory=list, description="Likely mistakes in the request.")


class OptimalBalanceOut(BalanceOut):
    """The optimal design for `weights`, and the trade-off curve over `sweep`."""

    tradeoff: list[BalanceOut] = Field(default_factory=list, description="One design per weight set of `sweep`, "
                                       "in its order, each re-analysed and with its `weights`; empty without a "
                                       "sweep.")


class RotorMassIn(StrictModel):
    """An unbalanced point mass of a rotor."""

    mass_kg: float = Field(ge=0, le=MAX_MASS_KG, description="Unbalanced mass [kg].", examples=[1.0])
    radius_m: float = Field(ge=0, le=1e3, description="Its distance from the axis [m].", examples=[0.1])
    angle_deg: float = Field(description="Its angle about the axis in the rotor frame [deg].", examples=[20.0])
    axial_position_m: Coordinate = Field(0.0, description="Its position along the axis [m].")


class RotorIn(StrictModel):
    """Point masses of a rotor and where the corrections go: one plane (static) or two (dynamic)."""

    masses: list[RotorMassIn] = Field(min_length=1, max_length=1000, description="The rotor's unbalanced masses.")
    mode: Literal["static", "dynamic"] = Field("dynamic", description="static: one correction plane, the "
                                               "resultant force only; dynamic: two planes, force and couple.")
    correction_radius_m: Length = Field(0.1, description="Static mode: radius of the correction mass [m].")
    correction_plane_m: Coordinate = Field(0.0, description="Static mode: axial position of the correction plane [m].")
    planes_m: list[Coordinate] = Field(default_factory=lambda: [0.0, 1.0], min_length=2, max_length=2,
                                       description="Dynamic mode: axial positions of the two correction planes [m].")
    radii_m: list[Length] = Field(default_factory=lambda: [0.1, 0.1], min_length=2, max_length=2,
                                  description="Dynamic mode: radius of the correction mass in each plane [m].")

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"masses": [{"mass_kg": 1.0, "radius_m": 0.1, "angle_deg": 20, "axial_position_m": 0.2},
                    {"mass_kg": 2.0, "radius_m": 0.05, "angle_deg": 115, "axial_position_m": 0.5}],
         "mode": "dynamic", "planes_m": [0.0, 1.0], "radii_m": [0.1, 0.1]},
    ]})


class CorrectionOut(BaseModel):
    """A correction mass and where it goes."""

    mass_kg: float = Field(description="Correction mass [kg].")
    radius_m: float = Field(description="Its distance from the axis [m], as requested for its plane.")
    angle_deg: float = Field(description="Its angle about the axis in the rotor frame, in [0, 360) [deg]: opposite "
                             "the unbalance it cancels.")
    axial_position_m: float = Field(description="Axial position of its correction plane [m].")


class RotorOut(BaseModel):
    """Corrections and the check: what is left of the static and the couple unbalance with them added."""

    corrections: list[CorrectionOut] = Field(description="One correction mass per plane: one (static mode) or two "
                                             "(dynamic mode, in the order of `planes_m`).")
    unbalance_before_kgm: float = Field(description="Magnitude of the rotor's static unbalance |sum m·r| before "
                                        "correction [kg·m].")
    moment_unbalance_before_kgm2: float = Field(description="Magnitude of its moment of unbalance |sum m·r·z| "
                                                "about the axial origin before correction [kg·m²].")
    residual_unbalance_kgm: float = Field(description="|sum m·r| with the corrections added [kg·m]; zero to "
                                          "rounding.")
    residual_moment_unbalance_kgm2: float = Field(description="|sum m·r·z| with the corrections added [kg·m²]; "
                                                  "zero to rounding in dynamic mode, what a single plane leaves in "
                                                  "static mode.")
    warnings: list[WarningOut] = Field(default_factory=list, description="Likely mistakes in the request.")


class SliderCrankBalanceIn(LinkageRequest):
    """A slider-crank, in-line or offset (desaxé): crank counterweight and Lanchester balancer."""

    counterweight_radius_m: Length | None = Field(None, description="Default: the crank length.")
    balancer_radii_m: list[Length] = Field(default_factory=lambda: [0.05, 0.05], min_length=2, max_length=2,
                                          description="Radius of the 1st- and 2nd-order balancer masses [m].")
    orders: Literal[1, 2] = Field(2, description="Highest order of the reciprocating force the Lanchester "
                                  "balancer cancels: 1 (first order) or 2 (first and second).")

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"mechanism": SLIDER_CRANK_EXAMPLE, "speed_rpm": 1500, "balancer_radii_m": [0.04, 0.03]},
        {"mechanism": {**SLIDER_CRANK_EXAMPLE, "offset_m": 0.02}, "speed_rpm": 1500},
    ]})


class LanchesterOut(BaseModel):
    """A pair of shafts at ±order times crank speed, each carrying mass_kg at radius_m."""

    order: int = Field(description="Crank order the pair cancels: 1 (shafts at ±1 times crank speed) or 2 (±2).")
    mass_kg: float = Field(description="Mass on each of the pair's two shafts [kg].")
    radius_m: float = Field(description="Radius of each mass on its shaft [m].")
    amplitude_N: float = Field(description="Amplitude of the slider's inertia force of this order it cancels [N].")
    phase_deg: float = Field(description="Angle [deg], in [0, 360), of the mass on the pair's clockwise shaft "
                                         "(the one at -order times crank speed) at crank angle 0, measured "
                                         "counter-clockwise from +x (the slide direction); the mass on the "
                                         "counter-clockwise shaft is its mirror image in the slide axis, at "
                                         "-phase_deg. Both point along +x when order × crank angle equals "
                                         "phase_deg, and the pair's force then cancels this order's slider force "
                                         "(180 for the first order in-line; an offset turns it by about "
                                         "offset/rod length rad).")


class SliderCrankBalanceOut(BaseModel):
    """Masses split to crank pin and slider, the crank counterweight, the balancer, and the residual force."""

    rotating_mass_kg: float = Field(description="The rod's static share at the crank pin A, m_rod·(1 - x_S/l) "
                                    "[kg], balanced by the crank counterweight with the crank's own mass.")
    reciprocating_mass_kg: float = Field(description="The slider's mass plus the rod's static share at the slider "
                                         "pin B, m_rod·x_S/l [kg].")
    crank_counterweight: CounterweightIn = Field(description="The crank counterweight, in the shape "
                                                 "`/v1/analysis` takes it.")
    lanchester: list[LanchesterOut] = Field(description="One Lanchester pair per cancelled order, order 1 first.")
    balancer_line_y_m: float = Field(description="Height of the line the balancer shafts sit on, in mirror image "
                                     "two by two: the slide axis, y = offset_m [m]. Each pair's force acts along "
                                     "it, wherever along it the shafts are.")
    first_order_amplitude_N: float = Field(description="Amplitude of the first crank-order harmonic of the "
                                           "reciprocating mass's inertia force along the slide, -m_B·a_B, from an "
                                           "FFT of the exact motion [N].")
    second_order_amplitude_N: float = Field(description="Amplitude of its second-order harmonic [N].")
    summary_before: SummaryOut = Field(description="Shaking force, moment and driving torque before balancing.")
    residual_shaking_force_N: float = Field(description="Largest magnitude over the samples of the shaking force "
                                            "left: the plain engine's with the crank counterweight, plus the "
                                            "balancer shafts' inertia forces [N].")
    residual_shaking_force_rel: float = Field(description="residual_shaking_force_N over the largest shaking force "
                                              "before balancing [-]; 0 when that was 0.")
    residual_by_order_N: list[float] = Field(
        description="Largest shaking force of each crank order left after balancing [N]; item 0 is order 1."
    )
    residual_shaking_moment_Nm: float = Field(description="Largest absolute shaking moment about the crank pivot "
                                              "O left: the plain engine's with the crank counterweight, plus the "
                                              "balancer masses' moment [N·m]. The pairs are sized for the force; "
                                              "on the slide axis their force is in line with the slider's, so "
                                              "what is left is mostly the driving torque's reaction and the "
                                              "rod's.")
    residual_shaking_moment_rel: float = Field(description="residual_shaking_moment_Nm over the largest shaking "
                                               "moment before balancing [-]; 0 when that was 0.")
    balancer_moment_Nm: float = Field(description="Largest absolute moment about O of the balancers' forces alone "
                                      "[N·m]: offset_m times their force, since they act on the slide axis; 0 "
                                      "in-line.")
    warnings: list[WarningOut] = Field(default_factory=list, description="Likely mistakes in the request.")
