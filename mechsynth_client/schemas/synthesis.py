"""Schemas of /v1/synthesis/*: crank-rocker and slider-crank for a travel and a time ratio, path generation."""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from .analysis import TracePointIn
from .common import Coordinate, FourBarIn, Length, LoadIn, SliderCrankIn, StrictModel, Vec2, WarningOut

Objective = Literal["transmission_angle", "peak_driving_torque", "rms_shaking_force"]
# What the crank-rocker and the slider-crank answers share, described once.
ObjectiveName = Annotated[str, Field(description="The objective the family was searched for.")]
ObjectiveValue = Annotated[float, Field(description="Its value at the answer, in objective_unit: the smallest "
                                        "transmission angle [deg] (maximised), the peak driving torque [N·m] or "
                                        "the RMS shaking force [N] (minimised).")]
ObjectiveUnit = Annotated[str, Field(description="Unit of objective_value: deg, N·m or N.")]
CrankSpeed = Annotated[float, Field(description="The request's crank speed [rad/s].")]

# The engine's path-generation bounds (synth.synthesis.MAX_POINTS, MAX_STARTS), spelled here so that the
# schema loads without the engine; a test keeps them equal.
MAX_PATH_POINTS = 40
MAX_PATH_STARTS = 256


class RangeIn(StrictModel):
    """A closed range of lengths [m]."""

    min_m: float = Field(0.0, ge=0, le=1e3, description="Shortest admissible value [m].")
    max_m: float = Field(gt=0, le=1e3, description="Longest admissible value [m].", examples=[0.5])

    def pair(self) -> tuple[float, float]:
        """(min, max) [m]."""
        return (self.min_m, self.max_m)


class RegionIn(StrictModel):
    """A rectangle [m]."""

    x_min_m: Coordinate = Field(description="Left edge [m].", examples=[-0.4])
    x_max_m: Coordinate = Field(description="Right edge [m].", examples=[0.0])
    y_min_m: Coordinate = Field(description="Lower edge [m].", examples=[-0.2])
    y_max_m: Coordinate = Field(description="Upper edge [m].", examples=[0.2])

    def box(self) -> tuple[float, float, float, float]:
        """(x_min, x_max, y_min, y_max) [m]."""
        return (self.x_min_m, self.x_max_m, self.y_min_m, self.y_max_m)


class _TimeRatio(StrictModel):
    time_ratio: float | None = Field(None, ge=1.0, le=100.0, description="Slow stroke time over fast stroke time (Q).")
    overlap_angle_deg: float | None = Field(
        None, ge=0.0, lt=180.0, description="Crank overlap angle theta = 180(Q-1)/(Q+1) [deg]; instead of time_ratio.")

    @model_validator(mode="after")
    def _one_of(self) -> _TimeRatio:
        if self.time_ratio is not None and self.overlap_angle_deg is not None:
            raise ValueError("give time_ratio or overlap_angle_deg, not both")
        return self


class _Dynamics(StrictModel):
    objective: Objective = Field(
        "transmission_angle",
        description="Largest minimum transmission angle, or least peak driving torque / RMS shaking force "
                    "(these need linear_density_kg_m).")
    speed_rpm: float = Field(60.0, ge=1e-3, le=1e5, description="Crank speed [rev/min] (strokes per minute).")
    loads: list[LoadIn] = Field(default_factory=list, max_length=8, description="Process loads on the output.")
    samples: int = Field(120, ge=12, le=720, description="Crank angles per member when the objective is dynamic.")
    min_transmission_angle_deg: float = Field(0.0, ge=0.0, le=89.0, description="Lowest admissible transmission angle.")
    max_length_ratio: float = Field(4.0, gt=1.0, le=100.0,
                                    description="No link longer than this many rocker lengths (strokes for a slider-crank).")

    @property
    def omega_rad_s(self) -> float:
        """Crank speed [rad/s]."""
        return self.speed_rpm * math.pi / 30.0


class CrankRockerBoundsIn(StrictModel):
    """Optional length ranges of the links [m]."""

    crank: RangeIn | None = Field(None, description="Range of the crank length [m].")
    coupler: RangeIn | None = Field(None, description="Range of the coupler length [m].")
    rocker: RangeIn | None = Field(None, description="Range of the rocker length [m].")
    ground: RangeIn | None = Field(None, description="Range of the ground length [m].")


class CrankRockerDensityIn(StrictModel):
    """Mass per unit length of each link [kg/m] (uniform bars)."""

    crank: float = Field(0.0, ge=0, le=1e5, description="Mass per metre of the crank [kg/m].")
    coupler: float = Field(0.0, ge=0, le=1e5, description="Mass per metre of the coupler [kg/m].")
    rocker: float = Field(0.0, ge=0, le=1e5, description="Mass per metre of the rocker [kg/m].")


class CrankRockerIn(_TimeRatio, _Dynamics):
    """A crank-rocker for a rocker swing and a time ratio, best in its whole one-parameter family."""

    swing_deg: float = Field(gt=0.0, lt=180.0, description="Rocker swing psi [deg].", examples=[40.0])
    scale_link: Literal["rocker", "ground", "crank"] = Field("rocker", description="The link whose length is given.")
    scale_length_m: Length = Field(description="Its length [m].", examples=[0.3])
    bounds_m: CrankRockerBoundsIn = Field(default_factory=CrankRockerBoundsIn,
                                          description="Length ranges of the links [m].")
    crank_pivot_region_m: RegionIn | None = Field(
        None, description="Where the crank pivot may go, with the rocker pivot at the origin and the rocker's "
                          "mid-swing position along +x.")
    slow_stroke: Literal["ccw", "cw"] | None = Field(
        None, description="Rocker turning counter-clockwise or clockwise in the slow stroke (crank counter-clockwise).")
    linear_density_kg_m: CrankRockerDensityIn | None = Field(None, description="Mass per metre of each link, "
                                                             "for the dynamic objectives [kg/m].")

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"swing_deg": 40, "time_ratio": 1.1, "scale_link": "rocker", "scale_length_m": 0.15, "speed_rpm": 180},
        {"swing_deg": 60, "time_ratio": 1.15, "scale_length_m": 0.25, "speed_rpm": 240,
         "objective": "peak_driving_torque", "linear_density_kg_m": {"crank": 2, "coupler": 2, "rocker": 3},
         "loads": [{"type": "window", "torque_Nm": 4.0}], "min_transmission_angle_deg": 35},
    ]})


class SliderCrankBoundsIn(StrictModel):
    """Optional length ranges [m]; the offset's range is for its magnitude."""

    crank: RangeIn | None = Field(None, description="Range of the crank length [m].")
    rod: RangeIn | None = Field(None, description="Range of the rod length [m].")
    offset: RangeIn | None = Field(None, description="Range of the offset of the slider line [m].")


class SliderCrankDensityIn(StrictModel):
    """Mass per unit length of crank and rod [kg/m] (uniform bars)."""

    crank: float = Field(0.0, ge=0, le=1e5, description="Mass per metre of the crank [kg/m].")
    rod: float = Field(0.0, ge=0, le=1e5, description="Mass per metre of the rod [kg/m].")


class SliderCrankSynthesisIn(_TimeRatio, _Dynamics):
    """An offset slider-crank for a stroke and a time ratio, best in its whole one-parameter family."""

    stroke_m: Length = Field(description="Slider stroke H [m].", examples=[0.1])
    bounds_m: SliderCrankBoundsIn = Field(default_factory=SliderCrankBoundsIn,
                                          description="Ranges of the crank, rod and offset [m].")
    slow_stroke: Literal["positive", "negative"] | None = Field(
        None, description="Slider moving along +x or -x in the slow stroke (crank counter-clockwise).")
    linear_density_kg_m: SliderCrankDensityIn | None = Field(None, description="Mass per metre of crank and rod, "
                                                             "for the dynamic objectives [kg/m].")
    slider_mass_kg: float = Field(0.0, ge=0, le=1e7, description="Slider mass, for the dynamic objectives [kg].")

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"stroke_m": 0.1, "time_ratio": 1.3, "slow_stroke": "positive", "speed_rpm": 120},
        {"stroke_m": 0.2, "time_ratio": 1.0, "objective": "rms_shaking_force", "speed_rpm": 600,
         "linear_density_kg_m": {"crank": 3, "rod": 2}, "slider_mass_kg": 1.5, "min_transmission_angle_deg": 60},
    ]})


class OptimalityOut(BaseModel):
    """Why the answer is the global optimum of its one-parameter family."""

    statement: str = Field(description="The certificate in words: how the family was searched and why no member "
                           "beats the answer by more than gap_bound.")
    parameter: float = Field(description="Family parameter u of the answer.")
    family_evaluations: int = Field(description="Family members evaluated in all: grid, refinement and polish.")
    grid_points: int = Field(description="Members of the first grid spread over the whole family.")
    gap_bound: float = Field(description="Largest possible improvement anywhere in the family, in the objective's unit.")
    kind: str = Field(description="stationary, kink (of a max-min objective) or bound (a constraint is active).")
    binding_constraint: str | None = Field(description="The constraint active at the answer when kind is bound; "
                                           "null otherwise.")
    left_slope: float | None = Field(description="One-sided derivative of the objective in the family parameter u "
                                     "from below, in the objective's unit per unit u; null when not finite.")
    right_slope: float | None = Field(description="One-sided derivative from above, in the same unit; null when not "
                                      "finite.")
    conditions_met: bool = Field(description="The first-order optimality conditions of `kind` hold at the answer.")


class TransmissionOut(BaseModel):
    """Transmission angle extremes over the cycle with the crank angles where they occur [deg]."""

    min_deg: float = Field(description="Smallest transmission angle over the cycle [deg].")
    min_at_crank_deg: float = Field(description="Crank angle where it occurs, in [0, 360) [deg].")
    max_deg: float = Field(description="Largest transmission angle over the cycle [deg].")
    max_at_crank_deg: float = Field(description="Crank angle where it occurs, in [0, 360) [deg].")


class StrokesOut(BaseModel):
    """The strokes as the analysis engine finds them."""

    time_ratio: float = Field(description="Slow stroke time over fast stroke time Q at constant crank speed [-].")
    overlap_angle_deg: float = Field(description="Crank overlap angle theta = 180·(Q - 1)/(Q + 1) [deg].")
    slow_stroke_crank_deg: list[float] = Field(description="Crank angles where the slow stroke starts and ends [deg].")
    cycle_time_s: float = Field(description="Time of one crank revolution at the request's speed [s].")
    slow_stroke_time_s: float = Field(description="Time of the slow (working) stroke [s].")
    fast_stroke_time_s: float = Field(description="Time of the fast (return) stroke [s].")


class CrankRockerCheckOut(StrokesOut):
    """Swing, time ratio and transmission angles recomputed by the analysis engine."""

    swing_deg: float = Field(description="Rocker swing between its dead-centre positions [deg].")
    rocker_angle_deg: list[float] = Field(description="Rocker angle at the start and the end of the slow stroke [deg].")
    rocker_tip_chord_m: float = Field(description="Straight distance between the rocker tip's extreme positions [m].")
    transmission_angle: TransmissionOut = Field(description="Extremes of the angle between coupler and rocker.")


class CrankRockerOut(BaseModel):
    """The optimal crank-rocker as a `mechanism` every other endpoint takes, with its check and certificate."""

    mechanism: FourBarIn = Field(description="The crank-rocker, with link masses when densities were given: send "
                                 "it to any mechanism endpoint as it is.")
    grashof: str = Field(description="Grashof class of the answer's four-bar.")
    objective: ObjectiveName
    objective_value: ObjectiveValue
    objective_unit: ObjectiveUnit
    crank_pivot_m: list[float] = Field(description="Crank pivot with the rocker pivot at the origin and the rocker's "
                                                   "mid-swing along +x [m].")
    crank_speed_rad_s: CrankSpeed
    check: CrankRockerCheckOut = Field(description="The answer re-analysed by the kinematics engine: swing, time "
                                       "ratio, stroke times and transmission angles.")
    optimality: OptimalityOut = Field(description="Why the answer is the best of its family.")
    warnings: list[WarningOut] = Field(description="The analysis' own notes on the answer: a transmission angle "
                                       "under 40° (`transmission_angle_low`, with the crank angles), a link ratio "
                                       "beyond 10 (`link_ratio_large`). Set `min_transmission_angle_deg`, "
                                       "`max_length_ratio` or `bounds_m` to keep them out.")


class SliderCrankCheckOut(StrokesOut):
    """Stroke, time ratio and transmission angles recomputed by the analysis engine."""

    stroke_m: float = Field(description="Slider stroke between the dead centres [m].")
    slider_position_m: list[float] = Field(description="Slider x at the start and the end of the slow stroke [m].")
    transmission_angle: TransmissionOut = Field(description="Extremes of the angle between the rod and the normal "
                                                "to the guide (90° less the rod's inclination to the guide).")


class SliderCrankSynthesisOut(BaseModel):
    """The optimal offset slider-crank as a `mechanism` every other endpoint takes, with check and certificate."""

    mechanism: SliderCrankIn = Field(description="The slider-crank, with link masses when densities were given: "
                                     "send it to any mechanism endpoint as it is.")
    objective: ObjectiveName
    objective_value: ObjectiveValue
    objective_unit: ObjectiveUnit
    crank_speed_rad_s: CrankSpeed
    check: SliderCrankCheckOut = Field(description="The answer re-analysed by the kinematics engine: stroke, time "
                                       "ratio, stroke times and transmission angles.")
    optimality: OptimalityOut = Field(description="Why the answer is the best of its family.")
    warnings: list[WarningOut] = Field(description="The analysis' own notes on the answer: a transmission angle "
                                       "under 40° (`transmission_angle_low`, with the crank angles), a link ratio "
                                       "beyond 10 (`link_ratio_large`). Set `min_transmission_angle_deg`, "
                                       "`max_length_ratio` or `bounds_m` to keep them out.")


class PathBoundsIn(StrictModel):
    """Length ranges of the links [m]; a link left out gets D/50 to 4·D, D the targets' extent."""

    crank: RangeIn | None = Field(None, description="Range of the crank length [m].")
    coupler: RangeIn | None = Field(None, description="Range of the coupler length [m].")
    rocker: RangeIn | None = Field(None, description="Range of the rocker length [m].")
    ground: RangeIn | None = Field(None, description="Range of the ground length [m].")


class PathIn(StrictModel):
    """Target points for a four-bar's coupler point, in the order the crank (turning counter-clockwise) passes them."""

    points_m: list[Vec2] = Field(min_length=3, max_length=MAX_PATH_POINTS, description="Target points of the "
                                 "coupler point [m], in order along the path.",
                                 examples=[[[0.1, 0.3], [0.2, 0.35], [0.3, 0.33], [0.35, 0.25]]])
    crank_angle_deg: list[Annotated[float, Field(ge=-3600.0, le=3600.0)]] | None = Field(
        None, description="Crank angle at each point [deg], fixed up to a common shift (timed path generation).")
    bounds_m: PathBoundsIn = Field(default_factory=PathBoundsIn, description="Length ranges of the links [m].")
    pivot_box_m: RegionIn | None = Field(None, description="Where both ground pivots may go; default: within 2·D "
                                                           "of the targets' bounding box.")
    coupler_point_max_m: float | None = Field(None, gt=0, le=1e3,
                                              description="Bound on each coupler-point coordinate; default 4·D.")
    branch: Literal[1, -1] | None = Field(None, description="Assembly branch; null tries both.")
    starts: int = Field(32, ge=1, le=MAX_PATH_STARTS, description="Multistart points (scrambled Sobol).")
    seed: int = Field(0, ge=0, le=2**31 - 1, description="Seed of the Sobol scrambling: same seed, same answer.")
    min_transmission_angle_deg: float = Field(0.0, ge=0.0, le=89.0, description="Lowest admissible transmission angle.")
    rank_by: Literal["residual", "transmission_angle", "link_ratio", "starts"] = Field(
        "residual", description="How fits equally near the points are ordered (the first is the answer): least "
        "residual (where residuals differ by round-off only, most starts reaching it), largest least transmission "
        "angle (its deviation from 90° taken both ways), least ratio of the longest link to the shortest, or most "
        "starts reaching it.")

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"points_m": [[0.1512, 0.1621], [0.1698, 0.2037], [0.1319, 0.2318], [0.0685, 0.2331], [0.0075, 0.204],
                      [-0.0316, 0.1556], [-0.0404, 0.1063], [-0.02, 0.0745], [0.0236, 0.0747], [0.0853, 0.1112]],
         "starts": 16, "seed": 1},
    ]})

class PathFitOut(BaseModel):
    """One four-bar through (or near) the points: a distinct design the starts reached, or a cognate of the
    answer built in closed form."""

    mechanism: FourBarIn = Field(description="The four-bar in its own frame (crank pivot at the origin, rocker "
                                 "pivot on +x), massless: send it to any mechanism endpoint.")
    trace_point: TracePointIn = Field(description="The coupler point as a trace point for /v1/analysis.")
    crank_pivot_m: list[float] = Field(description="Its driving pivot in the targets' frame [m].")
    ground_angle_deg: float = Field(description="Direction of its ground line in the targets' frame [deg].")
    crank_angle_deg: list[float] = Field(description="Its driver's angle at each target, in its own frame [deg].")
    rms_residual_m: float = Field(description="RMS distance from the targets, recomputed by the analysis engine [m].")
    max_residual_m: float = Field(description="Largest distance from a target, recomputed by the analysis engine [m].")
    grashof: str = Field(description="Grashof class.")
    link_ratio: float = Field(description="Longest link over the shortest, the ground included [-].")
    transmission_angle: TransmissionOut | None = Field(description="Extremes of the angle between coupler and "
                                                       "rocker over the cycle, for a crank-rocker.")
    starts: int = Field(description="Starts whose screening ended in this design's basin (0: a cognate no start "
                        "reached).")
    source: Literal["starts", "cognate"] = Field(description="Reached by the starts and polished by IPOPT, or a "
                                                 "Roberts-Chebyshev cognate of the answer in closed form.")



class PathCheckOut(BaseModel):
    """Rocker swing, time ratio and transmission angles of the answer, from the analysis engine."""

    grashof: str = Field(description="Grashof class of the answer.")
    swing_deg: float = Field(description="Rocker swing between its dead-centre positions [deg].")
    time_ratio: float = Field(description="Crank angle of the slow stroke over that of the fast one [-].")
    transmission_angle: TransmissionOut = Field(description="Extremes of the angle between coupler and rocker.")


class PathOut(BaseModel):
    """The best four-bar of all starts: its `mechanism`, the coupler point as a trace point for /v1/analysis,
    where it sits among the targets, and the residual at every target recomputed by the analysis engine."""

    mechanism: FourBarIn = Field(description="The four-bar in its own frame (crank pivot at the origin, rocker "
                                 "pivot on +x), massless: send it to any mechanism endpoint.")
    trace_point: TracePointIn = Field(description="The coupler point as a trace point for /v1/analysis.")
    crank_pivot_m: list[float] = Field(description="Crank pivot O in the targets' frame [m].")
    ground_angle_deg: float = Field(description="Direction of O->Q in the targets' frame [deg].")
    crank_angle_deg: list[float] = Field(description="Crank angle at each target, in the mechanism's frame [deg].")
    residuals_m: list[float] = Field(description="Distance from each target to the coupler point at its crank "
                                     "angle, recomputed by the analysis engine, in target order [m].")
    max_residual_m: float = Field(description="Largest of residuals_m [m].")
    rms_residual_m: float = Field(description="RMS of residuals_m [m].")
    starts: int = Field(description="Multistart points run.")
    starts_converged: int = Field(description="Starts whose screening ended at a finite residual.")
    starts_at_best: int = Field(description="Starts whose screening ended in the answer's basin.")
    start_rms_residuals_m: list[float | None] = Field(description="RMS residual where each start's screening "
                                                      "ended; null: it broke down.")
    solver_status: str = Field(description="IPOPT's status for the answer's polish.")
    fits: list[PathFitOut] = Field(description="Every distinct design polished from the starts, the answer first: "
                                   "those as near the points as the best ordered by rank_by, then the rest by "
                                   "residual.")
    cognates: list[PathFitOut] = Field(description="The answer's Roberts-Chebyshev cognates that pass every point "
                                       "on one assembly (the crank-driven one always does), with the engine's "
                                       "residuals.")
    check: PathCheckOut = Field(description="Swing, time ratio and transmission angles of the answer, from the "
                                "analysis engine.")
    warnings: list[WarningOut] = Field(description="The analysis' own notes on the answer: a transmission angle "
                                       "under 40° (`transmission_angle_low`, with the crank angles), a link ratio "
                                       "beyond 10 (`link_ratio_large`). Set `min_transmission_angle_deg` or "
                                       "`bounds_m` to keep them out.")
