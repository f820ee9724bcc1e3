"""POST /v1/synthesis/*: crank-rocker, slider-crank and path synthesis specifications in, their answers with
the optimality certificate out."""

from __future__ import annotations

import math

import numpy as np

import synth

from api.translate.linkage import load_from, warnings_out
from mechsynth_client.schemas.analysis import TracePointIn
from mechsynth_client.schemas.common import (
    BRANCHES,
    FourBarIn,
    FourBarLinks,
    LinkIn,
    MAX_LENGTH_M,
    MIN_LENGTH_M,
    SliderCrankIn,
    SliderCrankLinks,
    one_of,
)
from mechsynth_client.schemas.synthesis import (
    CrankRockerCheckOut,
    CrankRockerIn,
    CrankRockerOut,
    OptimalityOut,
    PathCheckOut,
    PathFitOut,
    PathIn,
    PathOut,
    SliderCrankCheckOut,
    SliderCrankSynthesisIn,
    SliderCrankSynthesisOut,
    StrokesOut,
    TransmissionOut,
    _TimeRatio,
)


_OBJECTIVE_UNIT = {"transmission_angle": "deg", "peak_driving_torque": "N·m", "rms_shaking_force": "N"}


def _within_limits(bounds: dict[str, tuple[float, float]], names: tuple[str, ...],
                   lowest: float = MIN_LENGTH_M) -> dict[str, tuple[float, float]]:
    """The caller's ranges narrowed to what a `mechanism` may hold, so every answer is a valid request elsewhere."""
    out = {}
    for name in names:
        lo, hi = bounds.get(name, (lowest, MAX_LENGTH_M))
        out[name] = (max(lo, lowest), min(hi, MAX_LENGTH_M))
    return out


def time_ratio_q(request: _TimeRatio) -> float:
    """The time ratio Q."""
    if request.overlap_angle_deg is not None:
        return synth.time_ratio_of(math.radians(request.overlap_angle_deg))
    return 1.0 if request.time_ratio is None else request.time_ratio


def crank_rocker_spec(body: CrankRockerIn) -> synth.CrankRockerSpec:
    """Engine spec; degrees become radians here."""
    bounds = _within_limits({n: r.pair() for n, r in body.bounds_m if r is not None},
                            ("crank", "coupler", "rocker", "ground"))
    density = {} if body.linear_density_kg_m is None else dict(body.linear_density_kg_m)
    return synth.CrankRockerSpec(
        swing=math.radians(body.swing_deg), time_ratio=time_ratio_q(body), scale_link=body.scale_link,
        scale_length=body.scale_length_m, bounds=bounds, max_length_ratio=body.max_length_ratio,
        pivot_region=None if body.crank_pivot_region_m is None else body.crank_pivot_region_m.box(),
        min_transmission_angle=math.radians(body.min_transmission_angle_deg),
        slow_stroke={"ccw": 1, "cw": -1, None: 0}[body.slow_stroke], objective=body.objective,
        linear_density={k: v for k, v in density.items() if v > 0}, speed=body.omega_rad_s,
        loads=tuple(load_from(load, "rotation") for load in body.loads), samples=body.samples,
    )


def slider_crank_synthesis_spec(body: SliderCrankSynthesisIn) -> synth.SliderCrankSpec:
    """Engine spec; degrees become radians here."""
    given = {n: r.pair() for n, r in body.bounds_m if r is not None}
    # The offset needs no default range: the rod, bounded here, is longer than crank and offset together.
    bounds = {**_within_limits(given, ("crank", "rod")),
              **(_within_limits(given, ("offset",), lowest=0.0) if "offset" in given else {})}
    density = {} if body.linear_density_kg_m is None else dict(body.linear_density_kg_m)
    return synth.SliderCrankSpec(
        stroke=body.stroke_m, time_ratio=time_ratio_q(body), bounds=bounds, max_length_ratio=body.max_length_ratio,
        min_transmission_angle=math.radians(body.min_transmission_angle_deg),
        slow_stroke={"positive": 1, "negative": -1, None: 0}[body.slow_stroke], objective=body.objective,
        linear_density={k: v for k, v in density.items() if v > 0}, slider_mass=body.slider_mass_kg,
        speed=body.omega_rad_s, loads=tuple(load_from(load, "translation") for load in body.loads),
        samples=body.samples,
    )


def optimality_out(o: synth.Optimality, u: float, unit_scale: float) -> OptimalityOut:
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
    return OptimalityOut(statement=statement, parameter=u, family_evaluations=o.evaluations,
                         grid_points=o.grid_points, gap_bound=o.gap_bound * abs(unit_scale), kind=o.kind,
                         binding_constraint=o.binding, left_slope=fin(o.left_slope), right_slope=fin(o.right_slope),
                         conditions_met=o.conditions_met)


def transmission_out(c: synth.LinkageCheck) -> TransmissionOut:
    """Schema from an engine check."""
    return TransmissionOut(min_deg=math.degrees(c.min_transmission_angle),
                           min_at_crank_deg=math.degrees(c.min_transmission_crank_angle),
                           max_deg=math.degrees(c.max_transmission_angle),
                           max_at_crank_deg=math.degrees(c.max_transmission_crank_angle))


def strokes_out(c: synth.LinkageCheck, speed: float) -> StrokesOut:
    """Schema from an engine check at crank speed ``speed`` [rad/s]."""
    slow, fast = c.stroke_times(speed)
    return StrokesOut(time_ratio=c.time_ratio, overlap_angle_deg=math.degrees(synth.overlap_angle(c.time_ratio)),
                      slow_stroke_crank_deg=[math.degrees(a) for a in c.slow_stroke],
                      cycle_time_s=slow + fast, slow_stroke_time_s=slow, fast_stroke_time_s=fast)


def crank_rocker_out(r: synth.CrankRockerResult, speed: float) -> CrankRockerOut:
    """Schema from the engine result at crank speed ``speed`` [rad/s]."""
    fb, c = r.fourbar, r.check
    props = r.linkage.links
    links = FourBarLinks(**{n: LinkIn(mass_kg=p.mass, com_m=list(p.com), inertia_kgm2=p.inertia)
                            for n, p in props.items()})
    deg = r.objective == "transmission_angle"
    return CrankRockerOut(
        mechanism=FourBarIn(ground_length_m=fb.ground, crank_length_m=fb.crank, coupler_length_m=fb.coupler,
                            rocker_length_m=fb.rocker, branch=one_of(BRANCHES, fb.branch), links=links),
        grashof=fb.grashof, objective=r.objective,
        objective_value=math.degrees(r.objective_value) if deg else r.objective_value,
        objective_unit=_OBJECTIVE_UNIT[r.objective], crank_pivot_m=list(r.crank_pivot), crank_speed_rad_s=speed,
        check=CrankRockerCheckOut(
            **strokes_out(c, speed).model_dump(), swing_deg=math.degrees(c.travel),
            rocker_angle_deg=[math.degrees(a) for a in c.output_extremes],
            rocker_tip_chord_m=2.0 * fb.rocker * math.sin(0.5 * c.travel),
            transmission_angle=transmission_out(c)),
        optimality=optimality_out(r.optimality, r.parameter,
                                  math.degrees(1.0) if deg else -1.0),
        warnings=warnings_out(c.warnings),
    )


def slider_crank_synthesis_out(r: synth.SliderCrankResult, speed: float) -> SliderCrankSynthesisOut:
    """Schema from the engine result at crank speed ``speed`` [rad/s]."""
    sc, c = r.slider_crank, r.check
    links = SliderCrankLinks(**{n: LinkIn(mass_kg=p.mass, com_m=list(p.com), inertia_kgm2=p.inertia)
                                for n, p in r.linkage.links.items()})
    deg = r.objective == "transmission_angle"
    return SliderCrankSynthesisOut(
        mechanism=SliderCrankIn(crank_length_m=sc.crank, rod_length_m=sc.rod, offset_m=sc.offset,
                                branch=one_of(BRANCHES, sc.branch), links=links),
        objective=r.objective, objective_value=math.degrees(r.objective_value) if deg else r.objective_value,
        objective_unit=_OBJECTIVE_UNIT[r.objective], crank_speed_rad_s=speed,
        check=SliderCrankCheckOut(
            **strokes_out(c, speed).model_dump(), stroke_m=c.travel,
            slider_position_m=list(c.output_extremes), transmission_angle=transmission_out(c)),
        optimality=optimality_out(r.optimality, r.parameter, math.degrees(1.0) if deg else -1.0),
        warnings=warnings_out(c.warnings),
    )


def path_spec(path: PathIn, time_limit_s: float) -> synth.PathSpec:
    """Engine spec with the default limits filled in; degrees become radians here."""
    targets = np.array(path.points_m, dtype=float)
    bounds, box, cp_max = synth.default_path_limits(targets)
    bounds.update({n: r.pair() for n, r in path.bounds_m if r is not None})
    return synth.PathSpec(
        targets=targets,
        crank_angles=None if path.crank_angle_deg is None else np.radians(path.crank_angle_deg),
        bounds=_within_limits(bounds, ("crank", "coupler", "rocker", "ground")),
        pivot_box=box if path.pivot_box_m is None else path.pivot_box_m.box(),
        coupler_point_max=min(MAX_LENGTH_M, cp_max if path.coupler_point_max_m is None else path.coupler_point_max_m),
        branch=0 if path.branch is None else path.branch, starts=path.starts, seed=path.seed,
        time_limit=time_limit_s, min_transmission_angle=math.radians(path.min_transmission_angle_deg),
        rank_by=path.rank_by,
    )


def path_fit_out(f: synth.PathFit) -> PathFitOut:
    """Schema from an engine fit."""
    fb = f.fourbar
    lengths = (fb.ground, fb.crank, fb.coupler, fb.rocker)
    return PathFitOut(
        mechanism=FourBarIn(ground_length_m=fb.ground, crank_length_m=fb.crank, coupler_length_m=fb.coupler,
                            rocker_length_m=fb.rocker, branch=one_of(BRANCHES, fb.branch)),
        trace_point=TracePointIn(name="P", link="coupler", position_m=list(f.coupler_point)),
        crank_pivot_m=list(f.crank_pivot), ground_angle_deg=math.degrees(f.ground_angle),
        crank_angle_deg=np.degrees(f.crank_angles).tolist(), rms_residual_m=f.rms_residual,
        max_residual_m=float(f.residuals.max()), grashof=fb.grashof, link_ratio=max(lengths) / min(lengths),
        transmission_angle=None if f.check is None else transmission_out(f.check),
        starts=f.starts, source="cognate" if f.status == "cognate" else "starts",
    )


def path_out(r: synth.PathResult) -> PathOut:
    """Schema from the engine result."""
    fb, c = r.fourbar, r.check
    n = r.residuals.size
    rms_starts = np.sqrt(r.start_objectives / n)
    return PathOut(
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
        fits=[path_fit_out(f) for f in r.fits],
        cognates=[path_fit_out(f) for f in r.cognates],
        check=PathCheckOut(grashof=fb.grashof, swing_deg=math.degrees(c.travel), time_ratio=c.time_ratio,
                           transmission_angle=transmission_out(c)),
        warnings=warnings_out(c.warnings),
    )
