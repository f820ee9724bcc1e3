"""Schemas of /v1/synthesis/*: crank-rocker and slider-crank for a travel and a time ratio, path generation."""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from ._engine import np, synth
from .analysis import TracePointIn
from .common import (
    MAX_LENGTH_M,
    MIN_LENGTH_M,
    Coordinate,
    FourBarIn,
    FourBarLinks,
    Length,
    LinkIn,
    LoadIn,
    SliderCrankIn,
    SliderCrankLinks,
    BRANCHES,
    StrictModel,
    Vec2,
    WarningOut,
    one_of,
    warnings_out,
)

Objective = Literal["transmission_angle", "peak_driving_torque", "rms_shaking_force"]
_OBJECTIVE_UNIT = {"transmission_angle": "deg", "peak_driving_torque": "N·m", "rms_shaking_force": "N"}
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


def _within_limits(bounds: dict[str, tuple[float, float]], names: tuple[str, ...],
                   lowest: float = MIN_LENGTH_M) -> dict[str, tuple[float, float]]:
    """The caller's ranges narrowed to what a `mechanism` may hold, so every answer is a valid request elsewhere."""
    out = {}
    for name in names:
        lo, hi = bounds.get(name, (lowest, MAX_LENGTH_M))
        out[name] = (max(lo, lowest), min(hi, MAX_LENGTH_M))
    return out


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

    def q(self) -> float:
        """The time ratio Q."""
        if self.overlap_angle_deg is not None:
            return synth.time_ratio_of(math.radians(self.overlap_angle_deg))
        return 1.0 if self.time_ratio is None else self.time_ratio


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

    def to_spec(self) -> synth.CrankRockerSpec:
        """Engine spec; degrees become radians here."""
        bounds = _within_limits({n: r.pair() for n, r in self.bounds_m if r is not None},
                                ("crank", "coupler", "rocker", "ground"))
        density = {} if self.linear_density_kg_m is None else dict(self.linear_density_kg_m)
        return synth.CrankRockerSpec(
            swing=math.radians(self.swing_deg), time_ratio=self.q(), scale_link=self.scale_link,
            scale_length=self.scale_length_m, bounds=bounds, max_length_ratio=self.max_length_ratio,
            pivot_region=None if self.crank_pivot_region_m is None else self.crank_pivot_region_m.box(),
            min_transmission_angle=math.radians(self.min_transmission_angle_deg),
            slow_stroke={"ccw": 1, "cw": -1, None: 0}[self.slow_stroke], objective=self.objective,
            linear_density={k: v for k, v in density.items() if v > 0}, speed=self.omega_rad_s,
            loads=tuple(load.to_engine("rotation") for load in self.loads), samples=self.samples,
        )


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

    def to_spec(self) -> synth.SliderCrankSpec:
        """Engine spec; degrees become radians here."""
        given = {n: r.pair() for n, r in self.bounds_m if r is not None}
        # The offset needs no default range: the rod, bounded here, is longer than crank and offset together.
        bounds = {**_within_limits(given, ("crank", "rod")),
                  **(_within_limits(given, ("offset",), lowest=0.0) if "offset" in given else {})}
        density = {} if self.linear_density_kg_m is None else dict(self.linear_density_kg_m)
        return synth.SliderCrankSpec(
            stroke=self.stroke_m, time_ratio=self.q(), bounds=bounds, max_length_ratio=self.max_length_ratio,
            min_transmission_angle=math.radians(self.min_transmission_angle_deg),
            slow_stroke={"positive": 1, "negative": -1, None: 0}[self.slow_stroke], objective=self.objective,
            linear_density={k: v for k, v in density.items() if v > 0}, slider_mass=self.slider_mass_kg,
            speed=self.omega_rad_s, loads=tuple(load.to_engine("translation") for load in self.loads),
            samples=self.samples,
        )


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

    @classmethod
    def from_engine(cls, o: synth.Optimality, u: float, unit_scale: float) -> OptimalityOut:
        """Schema from the engine's certificate; ``unit_scale`` converts the objective to its reported unit."""
        def fin(v: float) -> float | None:
            return float(v * unit_scale) if math.isfinite(v) else None

        where = {"stationary": "a stationary point", "kink": "a kink where two limits meet",
                 "bound": f"the bound {o.binding!r}"}[o.kind]
        statement = (
            f"{o.grid_points} members spread over the whole family, then {o.evaluations - o.grid_points} more where a "
            f"Lipschitz bound left room for a better one; no member can beat the answer by more than "
            f"{o.gap_bound * abs(unit_scale):.3g}. The answer, polished within its bracket, sits at {where}; first-order "
            f"conditions {'hold' if o.conditions_met else 'do not hold'}."
        )
        return cls(statement=statement, parameter=u, family_evaluations=o.evaluations, grid_points=o.grid_points,
                   gap_bound=o.gap_bound * abs(unit_scale), kind=o.kind, binding_constraint=o.binding,
                   left_slope=fin(o.left_slope), right_slope=fin(o.right_slope), conditions_met=o.conditions_met)


class TransmissionOut(BaseModel):
    """Transmission angle extremes over the cycle with the crank angles where they occur [deg]."""

    min_deg: float = Field(description="Smallest transmission angle over the cycle [deg].")
    min_at_crank_deg: float = Field(description="Crank angle where it occurs, in [0, 360) [deg].")
    max_deg: float = Field(description="Largest transmission angle over the cycle [deg].")
    max_at_crank_deg: float = Field(description="Crank angle where it occurs, in [0, 360) [deg].")

    @classmethod
    def from_engine(cls, c: synth.LinkageCheck) -> TransmissionOut:
        """Schema from an engine check."""
        return cls(min_deg=math.degrees(c.min_transmission_angle),
                   min_at_crank_deg=math.degrees(c.min_transmission_crank_angle),
                   max_deg=math.degrees(c.max_transmission_angle),
                   max_at_crank_deg=math.degrees(c.max_transmission_crank_angle))


class StrokesOut(BaseModel):
    """The strokes as the analysis engine finds them."""

    time_ratio: float = Field(description="Slow stroke time over fast stroke time Q at constant crank speed [-].")
    overlap_angle_deg: float = Field(description="Crank overlap angle theta = 180·(Q - 1)/(Q + 1) [deg].")
    slow_stroke_crank_deg: list[float] = Field(description="Crank angles where the slow stroke starts and ends [deg].")
    cycle_time_s: float = Field(description="Time of one crank revolution at the request's speed [s].")
    slow_stroke_time_s: float = Field(description="Time of the slow (working) stroke [s].")
    fast_stroke_time_s: float = Field(description="Time of the fast (return) stroke [s].")

    @classmethod
    def from_engine(cls, c: synth.LinkageCheck, speed: float) -> StrokesOut:
        """Schema from an engine check at crank speed ``speed`` [rad/s]."""
        slow, fast = c.stroke_times(speed)
        return cls(time_ratio=c.time_ratio, overlap_angle_deg=math.degrees(synth.overlap_angle(c.time_ratio)),
                   slow_stroke_crank_deg=[math.degrees(a) for a in c.slow_stroke],
                   cycle_time_s=slow + fast, slow_stroke_time_s=slow, fast_stroke_time_s=fast)


class CrankRockerCheckOut(StrokesOut):
    """Swing, time ratio and transmission angles recomputed by the analysis engine."""

    swing_deg: float = Field(description="Rocker swing between its dead-centre positions [deg].")
    rocker_angle_deg: list[float] = Field(description="Rocker angle at the start and the end of the slow stroke [deg].")
    rocker_tip_chord_m: float = Field(description="Straight distance between the rocker tip's extreme positions [m].")
    transmission_angle: TransmissionOut = Field(description="Extremes of the angle between coupler and rocker.")


def _links(lengths: dict[str, float], density: dict[str, float]) -> dict[str, LinkIn]:
    out = {}
    for name, rho in density.items():
        if rho > 0:
            m, length = rho * lengths[name], lengths[name]
            out[name] = LinkIn(mass_kg=m, com_m=[0.5 * length, 0.0], inertia_kgm2=m * length**2 / 12.0)
    return out


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

    @classmethod
    def from_engine(cls, r: synth.CrankRockerResult, speed: float) -> CrankRockerOut:
        """Schema from the engine result at crank speed ``speed`` [rad/s]."""
        fb, c = r.fourbar, r.check
        props = r.linkage.links
        links = FourBarLinks(**{n: LinkIn(mass_kg=p.mass, com_m=list(p.com), inertia_kgm2=p.inertia)
                                for n, p in props.items()})
        deg = r.objective == "transmission_angle"
        return cls(
            mechanism=FourBarIn(ground_length_m=fb.ground, crank_length_m=fb.crank, coupler_length_m=fb.coupler,
                                rocker_length_m=fb.rocker, branch=one_of(BRANCHES, fb.branch), links=links),
            grashof=fb.grashof, objective=r.objective,
            objective_value=math.degrees(r.objective_value) if deg else r.objective_value,
            objective_unit=_OBJECTIVE_UNIT[r.objective], crank_pivot_m=list(r.crank_pivot), crank_speed_rad_s=speed,
            check=CrankRockerCheckOut(
                **StrokesOut.from_engine(c, speed).model_dump(), swing_deg=math.degrees(c.travel),
                rocker_angle_deg=[math.degrees(a) for a in c.output_extremes],
                rocker_tip_chord_m=2.0 * fb.rocker * math.sin(0.5 * c.travel),
                transmission_angle=TransmissionOut.from_engine(c)),
            optimality=OptimalityOut.from_engine(r.optimality, r.parameter,
                                                 math.degrees(1.0) if deg else -1.0),
            warnings=warnings_out(c.warnings),
        )


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

    @classmethod
    def from_engine(cls, r: synth.SliderCrankResult, speed: float) -> SliderCrankSynthesisOut:
        """Schema from the engine result at crank speed ``speed`` [rad/s]."""
        sc, c = r.slider_crank, r.check
        links = SliderCrankLinks(**{n: LinkIn(mass_kg=p.mass, com_m=list(p.com), inertia_kgm2=p.inertia)
                                    for n, p in r.linkage.links.items()})
        deg = r.objective == "transmission_angle"
        return cls(
            mechanism=SliderCrankIn(crank_length_m=sc.crank, rod_length_m=sc.rod, offset_m=sc.offset,
                                    branch=one_of(BRANCHES, sc.branch), links=links),
            objective=r.objective, objective_value=math.degrees(r.objective_value) if deg else r.objective_value,
            objective_unit=_OBJECTIVE_UNIT[r.objective], crank_speed_rad_s=speed,
            check=SliderCrankCheckOut(
                **StrokesOut.from_engine(c, speed).model_dump(), stroke_m=c.travel,
                slider_position_m=list(c.output_extremes), transmission_angle=TransmissionOut.from_engine(c)),
            optimality=OptimalityOut.from_engine(r.optimality, r.parameter, math.degrees(1.0) if deg else -1.0),
            warnings=warnings_out(c.warnings),
        )


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
        "residual, largest least transmission angle (its deviation from 90° taken both ways), least ratio of the "
        "longest link to the shortest, or most starts reaching it.")

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"points_m": [[0.1512, 0.1621], [0.1698, 0.2037], [0.1319, 0.2318], [0.0685, 0.2331], [0.0075, 0.204],
                      [-0.0316, 0.1556], [-0.0404, 0.1063], [-0.02, 0.0745], [0.0236, 0.0747], [0.0853, 0.1112]],
         "starts": 16, "seed": 1},
    ]})

    def to_spec(self, time_limit_s: float) -> synth.PathSpec:
        """Engine spec with the default limits filled in; degrees become radians here."""
        targets = np.array(self.points_m, dtype=float)
        bounds, box, cp_max = synth.default_path_limits(targets)
        bounds.update({n: r.pair() for n, r in self.bounds_m if r is not None})
        return synth.PathSpec(
            targets=targets,
            crank_angles=None if self.crank_angle_deg is None else np.radians(self.crank_angle_deg),
            bounds=_within_limits(bounds, ("crank", "coupler", "rocker", "ground")),
            pivot_box=box if self.pivot_box_m is None else self.pivot_box_m.box(),
            coupler_point_max=min(MAX_LENGTH_M, cp_max if self.coupler_point_max_m is None else self.coupler_point_max_m),
            branch=0 if self.branch is None else self.branch, starts=self.starts, seed=self.seed,
            time_limit=time_limit_s, min_transmission_angle=math.radians(self.min_transmission_angle_deg),
            rank_by=self.rank_by,
        )


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

    @classmethod
    def from_engine(cls, f: synth.PathFit) -> PathFitOut:
        """Schema from an engine fit."""
        fb = f.fourbar
        lengths = (fb.ground, fb.crank, fb.coupler, fb.rocker)
        return cls(
            mechanism=FourBarIn(ground_length_m=fb.ground, crank_length_m=fb.crank, coupler_length_m=fb.coupler,
                                rocker_length_m=fb.rocker, branch=one_of(BRANCHES, fb.branch)),
            trace_point=TracePointIn(name="P", link="coupler", position_m=list(f.coupler_point)),
            crank_pivot_m=list(f.crank_pivot), ground_angle_deg=math.degrees(f.ground_angle),
            crank_angle_deg=np.degrees(f.crank_angles).tolist(), rms_residual_m=f.rms_residual,
            max_residual_m=float(f.residuals.max()), grashof=fb.grashof, link_ratio=max(lengths) / min(lengths),
            transmission_angle=None if f.check is None else TransmissionOut.from_engine(f.check),
            starts=f.starts, source="cognate" if f.status == "cognate" else "starts",
        )


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

    @classmethod
    def from_engine(cls, r: synth.PathResult) -> PathOut:
        """Schema from the engine result."""
        fb, c = r.fourbar, r.check
        n = r.residuals.size
        rms_starts = np.sqrt(r.start_objectives / n)
        return cls(
            mechanism=FourBarIn(ground_length_m=fb.ground, crank_length_m=fb.crank, coupler_length_m=fb.coupler,
                                rocker_length_m=fb.rocker, branch=one_of(BRANCHES, fb.branch)),
            trace_point=TracePointIn(name="P", link="coupler", position_m=list(r.coupler_point)),
            crank_pivot_m=list(r.crank_pivot), ground_angle_deg=math.degrees(r.ground_angle),
            crank_angle_deg=np.degrees(r.crank_angles).tolist(), residuals_m=r.residuals.tolist(),
            max_residual_m=float(r.residuals.max()), rms_residual_m=float(np.sqrt(np.mean(r.residuals**2))),
            starts=int(r.start_objectives.size), starts_converged=int(np.isfinite(r.start_objectives).sum()),
            starts_at_best=r.starts_at_best,
            start_rms_residuals_m=[float(v) if math.isfinite(v) else None for v in rms_starts],
            solver_status=r.status,
            fits=[PathFitOut.from_engine(f) for f in r.fits],
            cognates=[PathFitOut.from_engine(f) for f in r.cognates],
            check=PathCheckOut(grashof=fb.grashof, swing_deg=math.degrees(c.travel), time_ratio=c.time_ratio,
                               transmission_angle=TransmissionOut.from_engine(c)),
            warnings=warnings_out(c.warnings),
        )
