"""POST /v1/machines/optimise and /optimise-linkage: the function, prices and bounds in; the family, the optimum
and its certificate out."""

from __future__ import annotations

import math
from typing import Any

import synth

from api.translate.linkage import load_from, pair_frictions
from api.translate.machine import (
    machine_balancing_from,
    machine_design_out,
    machine_drive_from,
    machine_from,
    machine_geometry_from,
)
from api.translate.synthesis import _within_limits
from mechsynth_client.schemas.common import FourBarIn, PlanarLinkageIn, SliderCrankIn
from mechsynth_client.schemas.optimise import (
    BandIn,
    CrankRockerFunctionIn,
    FamilyMemberOut,
    FreeValueOut,
    GainOut,
    LinkageCertificateOut,
    LinkageMemberOut,
    LinkageOptimiseIn,
    LinkageOptimiseOut,
    MAX_SCAN,
    MachineOptimiseIn,
    MachineOptimiseOut,
    MachinePartsOut,
    OptimiseCertificateOut,
    PricesIn,
    RefinementOut,
    SliderCrankFunctionIn,
)


def _turns(req: LinkageOptimiseIn) -> bool:
    """The linkage's output turns (a link with two points) rather than slides (a block)."""
    mech = req.machine.mechanism
    assert mech.type == "linkage"
    out = mech.output or mech.links[-1].name
    return len(next(k for k in mech.links if k.name == out).joints) > 1


def _finite(v: float) -> float | None:
    return v if math.isfinite(v) else None


def crank_rocker_function_spec(function: CrankRockerFunctionIn, loads: tuple[synth.ProcessLoad, ...]
                               ) -> synth.CrankRockerSpec:
    """Engine synthesis spec (its dynamic objective unused); degrees become radians here."""
    bounds = _within_limits({n: r.pair() for n, r in function.bounds_m if r is not None},
                            ("crank", "coupler", "rocker", "ground"))
    return synth.CrankRockerSpec(
        swing=math.radians(function.swing_deg), time_ratio=function.time_ratio, scale_link=function.scale_link,
        scale_length=function.scale_length_m, bounds=bounds, max_length_ratio=function.max_length_ratio,
        min_transmission_angle=math.radians(function.min_transmission_angle_deg),
        slow_stroke={"ccw": 1, "cw": -1, None: 0}[function.slow_stroke],
        linear_density={k: v for k, v in dict(function.linear_density_kg_m).items() if v > 0}, loads=loads,
    )


def slider_crank_function_spec(function: SliderCrankFunctionIn, loads: tuple[synth.ProcessLoad, ...]
                               ) -> synth.SliderCrankSpec:
    """Engine synthesis spec (its dynamic objective unused); degrees become radians here."""
    given = {n: r.pair() for n, r in function.bounds_m if r is not None}
    bounds = {**_within_limits(given, ("crank", "rod")),
              **(_within_limits(given, ("offset",), lowest=0.0) if "offset" in given else {})}
    return synth.SliderCrankSpec(
        stroke=function.stroke_m, time_ratio=function.time_ratio, bounds=bounds,
        max_length_ratio=function.max_length_ratio,
        min_transmission_angle=math.radians(function.min_transmission_angle_deg),
        slow_stroke={"positive": 1, "negative": -1, None: 0}[function.slow_stroke],
        linear_density={k: v for k, v in dict(function.linear_density_kg_m).items() if v > 0},
        slider_mass=function.slider_mass_kg, loads=loads)


def function_spec(function: CrankRockerFunctionIn | SliderCrankFunctionIn, loads: tuple[synth.ProcessLoad, ...]
                  ) -> synth.CrankRockerSpec | synth.SliderCrankSpec:
    """Engine spec of the linkage's function, a crank-rocker's or a slider-crank's."""
    if isinstance(function, CrankRockerFunctionIn):
        return crank_rocker_function_spec(function, loads)
    return slider_crank_function_spec(function, loads)


def prices_from(prices: PricesIn) -> synth.Prices:
    """Engine prices."""
    return synth.Prices(prices.counterweight_per_kg, prices.balancer_per_kg, prices.flywheel_per_kg,
                        prices.gears_per_kg, prices.motor_per_kg, dict(prices.motors))


def machine_optimise_from(body: MachineOptimiseIn, max_stages: int) -> synth.OptimiseSpec:
    """Engine optimisation (degrees and rpm become radians and rad/s here)."""
    if (body.delta is None) == (body.machine_type is None):
        raise synth.InvalidInput("give delta or machine_type (one of them)", field="delta")
    if (body.objective is None) == (body.weights is None):
        raise synth.InvalidInput("give objective or weights (one of them)", field="objective")
    delta = body.delta if body.delta is not None else synth.admissible_delta(str(body.machine_type))
    motion = "rotation" if isinstance(body.function, CrankRockerFunctionIn) else "translation"
    loads = tuple(load_from(load, motion) for load in body.loads)
    weights = {body.objective: 1.0} if body.objective is not None else dict(body.weights or {})
    return synth.OptimiseSpec(
        function=function_spec(body.function, loads), speed=body.speed_rpm * math.pi / 30.0,
        drive=machine_drive_from(body.drive, max_stages), delta=delta,
        balancing=machine_balancing_from(body.balancing),
        flywheel=synth.FlywheelChoice(body.flywheel.placement, machine_geometry_from(body.flywheel.geometry)),
        samples=body.samples, speed_tolerance=body.speed_tolerance, weights={str(k): v for k, v in weights.items()},
        max_rms_shaking_force=body.max_rms_shaking_force_N, max_rms_shaking_moment=body.max_rms_shaking_moment_Nm,
        pareto=(body.pareto[0], body.pareto[1]), scan=body.scan_members,
        search_cells=MAX_SCAN if body.search_cells == "all" else body.search_cells,
        friction=pair_frictions(body.friction), brake_torque=body.brake_torque_Nm,
        start_under_load=body.start_under_load, max_startup_time=body.max_startup_time_s,
        max_rundown_time=body.max_rundown_time_s, prices=prices_from(body.prices))


def mechanism_json(linkage: synth.Linkage) -> dict[str, Any]:
    """A family member as the `mechanism` of a /v1/machines/design request (lengths [m], link masses)."""
    mech = linkage.mechanism
    links = {name: {"mass_kg": p.mass, "com_m": [p.com[0], p.com[1]], "inertia_kgm2": p.inertia}
             for name, p in linkage.links.items()}
    if isinstance(mech, synth.FourBar):
        return {"type": "fourbar", "ground_length_m": mech.ground, "crank_length_m": mech.crank,
                "coupler_length_m": mech.coupler, "rocker_length_m": mech.rocker, "branch": mech.branch,
                "links": links}
    assert isinstance(mech, synth.SliderCrank)
    return {"type": "slider_crank", "crank_length_m": mech.crank, "rod_length_m": mech.rod,
            "offset_m": mech.offset, "branch": mech.branch, "links": links}


def mechanism_out(linkage: synth.Linkage) -> FourBarIn | SliderCrankIn:
    """A family member as the `mechanism` model of a /v1/machines/design request."""
    body = mechanism_json(linkage)
    return FourBarIn.model_validate(body) if body["type"] == "fourbar" else SliderCrankIn.model_validate(body)


def member_linkage(spec: Any, u: float) -> Any:
    """The family member at ``u`` of an optimisation spec (engine objects)."""
    from synth.machine.optimise import member_linkage as engine_member

    return engine_member(spec, u)


def family_member_out(m: Any, linkage: synth.Linkage | None = None) -> FamilyMemberOut:
    """Schema from an engine member score and its linkage."""
    v = m.values
    return FamilyMemberOut(parameter=m.parameter, stage=m.stage, feasible=m.feasible, reason=m.reason,
                           motor_power_W=None if v is None else v[0], added_mass_kg=None if v is None else v[1],
                           rms_shaking_force_N=None if v is None else v[2],
                           rms_shaking_moment_Nm=m.rms_shaking_moment,
                           machine_mass_kg=None if v is None else _finite(v[3]),
                           cost=None if v is None else _finite(v[4]),
                           machine_mass_bound_kg=None if m.lower_values is None else _finite(m.lower_values[3]),
                           motor=None if m.choice is None else m.choice[0],
                           mechanism=None if linkage is None else mechanism_out(linkage))


def machine_parts_out(p: Any, prices: Any) -> MachinePartsOut:
    """Schema from the engine's parts and prices."""
    return MachinePartsOut(counterweights_kg=p.counterweights, balancers_kg=p.balancers, flywheel_kg=p.flywheel,
                           gears_kg=p.gears or 0.0, motor_kg=p.motor, motor=p.motor_name, machine_mass_kg=p.mass,
                           motor_price=p.motor_price(prices), cost=p.cost(prices))


def optimise_certificate_out(c: Any) -> OptimiseCertificateOut:
    """Schema from the engine's certificate."""
    s = c.scan
    refinements = [RefinementOut(
        lo=r.lo, hi=r.hi, start=r.start, status=r.status, bound=_finite(r.bound), plateaus=r.plateaus,
        evaluations=r.evaluations, best_parameter=r.best_parameter, motor=None if r.choice is None else r.choice[0],
        teeth=None if r.choice is None else [list(p) for p in r.choice[1]]) for r in c.refinements]
    return OptimiseCertificateOut(
        statement=c.statement, parameter_range=list(s.parameter_range), kinematic_members=s.grid_points,
        kinematic_feasible=s.feasible_points, feasible_runs=[list(r) for r in s.runs],
        members_designed=c.members_designed, feasible_designed=c.feasible_designed, scan_members=len(s.candidates),
        refinements=refinements, cells_found=len(c.refinements),
        cells_searched=sum(r.status == "searched" for r in c.refinements),
        cells_pruned=sum(r.status == "pruned" for r in c.refinements),
        cells_unsearched=sum(r.status == "unsearched" for r in c.refinements),
        gap_bound=c.gap_bound, binding_constraints=list(c.binding))


def machine_optimise_out(r: synth.MachineOptimum) -> MachineOptimiseOut:
    """Schema from the engine's optimum."""
    return MachineOptimiseOut(
        design=machine_design_out(r.design),
        mechanism=mechanism_out(r.design.spec.linkage), parameter=r.parameter, weights=dict(r.spec.weights),
        score=r.score, chain_score=r.chain_score, chain_parameter=r.certificate.scan.chain_parameter,
        chain_mechanism=mechanism_out(r.chain_linkage),
        chain_reason=r.chain_reason,
        gains=[GainOut(objective=g.objective, unit=g.unit, chain=_finite(g.chain), optimum=g.optimum,
                       gain=_finite(g.gain), relative_gain=_finite(g.relative)) for g in r.gains],
        certificate=optimise_certificate_out(r.certificate),
        pareto_objectives=list(r.pareto_objectives),
        pareto=[family_member_out(m) for m in r.pareto],
        members=[family_member_out(m, member_linkage(r.spec, m.parameter))
                 for m in sorted(r.members, key=lambda m: m.parameter)],
        parts=None if r.parts is None else machine_parts_out(r.parts, r.spec.prices),
    )


def band_pair(band: BandIn, field: str, scale: float = 1.0) -> tuple[float, float]:
    """(min, max) times ``scale``; InvalidInput naming ``field`` when min > max."""
    if band.min > band.max:
        raise synth.InvalidInput("a band needs min <= max", field=f"{field}.min")
    return (band.min * scale, band.max * scale)


def linkage_optimise_from(body: LinkageOptimiseIn, max_stages: int) -> Any:
    """Engine spec (degrees become radians here)."""
    from synth.machine.optimise_linkage import FreeDimension, LinkageFunction, LinkageOptimiseSpec

    if (body.objective is None) == (body.weights is None):
        raise synth.InvalidInput("give objective or weights (one of them)", field="objective")
    if body.machine.mechanism.type != "linkage":
        raise synth.InvalidInput("free dimensions need a general linkage (type linkage)",
                                 field="machine.mechanism.type")
    if body.stroke_m is not None and body.swing_deg is not None:
        raise synth.InvalidInput("give stroke_m (a sliding output) or swing_deg (a turning one), not both",
                                 field="swing_deg")
    travel = (band_pair(body.stroke_m, "stroke_m") if body.stroke_m is not None
              else band_pair(body.swing_deg, "swing_deg", math.pi / 180) if body.swing_deg is not None else None)
    weights = {body.objective: 1.0} if body.objective is not None else dict(body.weights or {})
    return LinkageOptimiseSpec(
        machine=machine_from(body.machine, max_stages),
        free=tuple(FreeDimension(d.path, d.min, d.max) for d in body.free),
        function=LinkageFunction(
            travel, None if body.time_ratio is None else band_pair(body.time_ratio, "time_ratio"),
            math.radians(body.min_transmission_angle_deg)),
        weights={str(k): v for k, v in weights.items()}, samples=body.samples, refined=body.refined,
        refine_runs=body.refine_runs, prices=prices_from(body.prices))


def linkage_optimise_out(r: Any, body: dict[str, Any]) -> LinkageOptimiseOut:
    """Schema from the engine's optimum and the request (as JSON)."""
    req = LinkageOptimiseIn.model_validate(body)
    turning = req.swing_deg is not None or (req.stroke_m is None and _turns(req))
    k = 180 / math.pi if turning else 1.0
    names = ("motor_power", "added_mass", "rms_shaking_force", "machine_mass", "cost")

    def member(m: Any) -> LinkageMemberOut:
        kin = m.kinematics
        ok = math.isfinite(kin.travel)
        return LinkageMemberOut(
            x=list(m.x), stage=m.stage, feasible=m.feasible, reason=m.reason,
            stroke_or_swing=kin.travel * k if ok else None, time_ratio=_finite(kin.time_ratio) if ok else None,
            min_transmission_angle_deg=math.degrees(kin.min_transmission_angle) if ok else None,
            values=None if m.values is None else {n: _finite(v) for n, v in zip(names, m.values, strict=True)})

    c = r.certificate
    return LinkageOptimiseOut(
        design=machine_design_out(r.design),
        mechanism=PlanarLinkageIn.model_validate(req.mechanism_with(r.x)),
        free=[FreeValueOut(path=d.path, value_m=float(v)) for d, v in zip(req.free, r.x, strict=True)],
        stroke_or_swing=r.kinematics.travel * k, time_ratio=r.kinematics.time_ratio,
        time_ratio_range=list(r.kinematics.time_ratio_span),
        min_transmission_angle_deg=math.degrees(r.kinematics.min_transmission_angle),
        values=dict(zip(names, r.values, strict=True)), score=r.score,
        parts=machine_parts_out(r.parts, r.spec.prices),
        certificate=LinkageCertificateOut(statement=c.statement, sampled=c.sampled,
                                          kinematic_feasible=c.kinematic_feasible, designed=c.designed,
                                          feasible=c.feasible, refined=c.refined, refine_runs=c.refine_runs,
                                          gap_bound=c.gap_bound),
        members=[member(m) for m in r.members])
