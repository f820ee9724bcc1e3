"""What each design endpoint runs: a validated request turned into one engine call and the way its answer is written.

A :class:`Plan` is plain data: the engine function and its arguments, and the :class:`~api.media.Render` that turns
the result into JSON or an export in the worker. The routers answer a request with its plan, and a design study
runs the same plans for its variants, so a study row is exactly what the endpoint would answer.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from importlib import metadata
from typing import Any

from pydantic import BaseModel

import synth
import synth.cams
import synth.strength
from synth.exports import balance_export, slider_crank_balance_export
from synth.machine import elastic_drive as ed
from synth.machine import foundation as fd
from synth.machine import foundation_design as fdd
from synth.machine import regulation as rg
from synth.machine.foundation_plots import design_figure, elastic_drive_figure, isolation_figure, regulation_figure
from synth.machine.record import DesignRecord, input_rows
from synth.machine.optimise_linkage import optimise_linkage
from synth.synthesis.path import PathSpec, PathStarts, best_path, start_chunks

from ..media import ARRAYS, FIGURES, Render
from api.translate.analysis import analysis_out, plot_angle, rotors_from
from api.translate.balancing import (
    balance_out,
    balance_spec,
    optimal_balance_out,
    rotor_from,
    slider_crank_balance_out,
    weights_from,
)
from api.translate.cams import cam_analysis_out, cam_analysis_spec, cam_spec, cam_synthesis_out, limits_from
from api.translate.engines import engine_from, engine_out
from api.translate.flywheel import cycle_from, geometry_from, link_stiffness, mean_speed_of, target_delta, uses_tables
from api.translate.foundation import (
    elastic_drive_out,
    elements_from,
    frame_and_isolators_from,
    frame_from,
    isolation_design_out,
    isolation_design_spec,
    isolation_out,
    regulation_out,
    regulator_from,
    run_up_from,
)
from api.translate.gearing import (
    drive_catalogue,
    drive_out,
    inertia_model,
    split_out,
    split_ratio,
    stage_specs,
    teeth_out,
    teeth_rules,
)
from api.translate.linkage import crank_angles, linkage_from, pair_frictions, planar_linkage_from
from api.translate.machine import machine_from
from api.translate.machine_strength import with_strength
from api.translate.motor import motor_from
from api.translate.optimise import (
    linkage_optimise_from,
    linkage_optimise_out,
    machine_optimise_from,
    machine_optimise_out,
)
from api.translate.rating import duty_from, rating_from, rating_out, spectrum_from, strength_from
from api.translate.strength import sizing_call, sizing_out
from api.translate.structure import pair_from, structure_out
from api.translate.synthesis import (
    crank_rocker_out,
    crank_rocker_spec,
    path_out,
    path_spec,
    slider_crank_synthesis_out,
    slider_crank_synthesis_spec,
)
from api.translate.train import train_from, train_out
from mechsynth_client.schemas.analysis import AnalysisIn, AnalysisOut
from mechsynth_client.schemas.strength import StrengthSizingIn
from mechsynth_client.schemas.balancing import (
    BalanceIn,
    BalanceOut,
    FullBalanceIn,
    OptimalBalanceIn,
    OptimalBalanceOut,
    RotorIn,
    SliderCrankBalanceIn,
    SliderCrankBalanceOut,
)
from mechsynth_client.schemas.cams import CamAnalysisIn, CamAnalysisOut, CamSynthesisIn, CamSynthesisOut
from mechsynth_client.schemas.flywheel import FlywheelIn
from mechsynth_client.schemas.engines import EngineIn, EngineOut
from mechsynth_client.schemas.gearing import DriveIn, DriveOut, SplitIn, SplitOut, TeethIn, TeethOut
from mechsynth_client.schemas.rating import RatingIn, RatingOut
from mechsynth_client.schemas.machine import MachineIn
from mechsynth_client.schemas.optimise import MachineOptimiseIn, MachineOptimiseOut
from mechsynth_client.schemas.optimise import LinkageOptimiseIn, LinkageOptimiseOut
from mechsynth_client.schemas.structure import StructureIn, StructureOut
from mechsynth_client.schemas.synthesis import (
    CrankRockerIn,
    CrankRockerOut,
    PathIn,
    PathOut,
    SliderCrankSynthesisIn,
    SliderCrankSynthesisOut,
)
from mechsynth_client.schemas.train import TrainIn, TrainOut
from mechsynth_client.schemas.foundation import (
    ElasticDriveIn,
    ElasticDriveOut,
    IsolationDesignIn,
    IsolationDesignOut,
    IsolationIn,
    IsolationOut,
    RegulationIn,
    RegulationOut,
)
from ..settings import Settings
from .work import estimate_s
from .tasks import (
    ElasticLink,
    analysis_file,
    crank_rocker_png,
    design_file,
    design_machine,
    design_out,
    flywheel_file,
    flywheel_for_linkage,
    flywheel_from_tables,
    flywheel_out,
    optimal_file,
    path_file,
    rotor_out,
    slider_crank_png,
)

CURVES = (*FIGURES, "csv", "dxf")
#: The installed service's version, printed in every design record.
SERVICE_VERSION = metadata.version("mechsynth")


@dataclass(frozen=True, slots=True)
class Limits:
    """The service limits every plan runs under, a single request's and a study variant's alike."""

    max_samples: int
    max_stages: int
    solver_time_limit_s: float
    #: A request's estimated time on the workers it is dealt to [s]; beyond it TooLarge before any work starts.
    max_work_s: float = float("inf")

    @classmethod
    def from_settings(cls, settings: Settings) -> Limits:
        """The limits of a service instance."""
        return cls(settings.max_samples, settings.max_stages, settings.solver_time_limit_s,
                   settings.max_request_work_s)


@dataclass(frozen=True, slots=True)
class Plan:
    """One engine call and how its answer is written; ``offered`` are the formats besides JSON, ``stem`` names
    the file of a CSV or DXF answer, ``request_hash`` the canonical request's where the result is held for the
    documents of the same request."""

    render: Render
    fn: Callable[..., Any]
    args: tuple[Any, ...] = ()
    kwargs: dict[str, Any] = field(default_factory=dict)
    offered: tuple[str, ...] = ()
    stem: str = "answer"
    request_hash: str = ""


def analysis(b: AnalysisIn, lim: Limits, angle_deg: float | None = None) -> Plan:
    """POST /v1/analysis."""
    return Plan(Render(analysis_out, analysis_file, model_extra=(b.geometry_request(),),
                       export_extra=(plot_angle(b, angle_deg),)),
                synth.analyse, (linkage_from(b), b.omega_rad_s),
                dict(samples=b.samples, phi=crank_angles(b), crank_acceleration=b.crank_acceleration_rad_s2,
                     max_samples=lim.max_samples, points=b.trace(), counter_rotors=rotors_from(b),
                     friction=pair_frictions(b.friction)),
                (*CURVES, *ARRAYS), "analysis")


def balance_static(b: BalanceIn, lim: Limits) -> Plan:
    """POST /v1/balancing/static."""
    return Plan(Render(balance_out, balance_export), synth.balance_static,
                (linkage_from(b), b.omega_rad_s, balance_spec(b)),
                dict(samples=b.samples, objective=b.objective, mass_budget=b.mass_budget_kg,
                     time_limit_s=lim.solver_time_limit_s, method=b.method),
                CURVES, "balance_static")


def balance_full(b: FullBalanceIn, lim: Limits) -> Plan:
    """POST /v1/balancing/full."""
    return Plan(Render(balance_out, balance_export), synth.balance_full,
                (linkage_from(b), b.omega_rad_s, balance_spec(b)),
                dict(samples=b.samples, ratios=b.rotor_ratios, time_limit_s=lim.solver_time_limit_s),
                CURVES, "balance_full")


def balance_optimal(b: OptimalBalanceIn, lim: Limits) -> Plan:
    """POST /v1/balancing/optimal: the request's weights first, then the sweep's."""
    weight_sets = [weights_from(w) for w in [b.weights, *b.sweep]]
    return Plan(Render(optimal_balance_out, optimal_file), synth.tradeoff,
                (linkage_from(b), b.omega_rad_s, balance_spec(b), weight_sets),
                dict(mass_budget=b.mass_budget_kg, samples=b.samples, time_limit_s=lim.solver_time_limit_s,
                     weight_scale=b.weight_scale),
                CURVES, "balance_optimal")


def balance_rotor(b: RotorIn, lim: Limits) -> Plan:
    """POST /v1/balancing/rotor."""
    rotor = rotor_from(b)
    render = Render(rotor_out, model_extra=(rotor,))
    if b.mode == "static":
        return Plan(render, synth.balance_rotor_static, (rotor, b.correction_radius_m, b.correction_plane_m))
    return Plan(render, synth.balance_rotor_dynamic,
                (rotor, (b.planes_m[0], b.planes_m[1]), (b.radii_m[0], b.radii_m[1])))


def balance_engine(b: EngineIn, lim: Limits) -> Plan:
    """POST /v1/balancing/engine."""
    return Plan(Render(engine_out), synth.engine_shaking, (engine_from(b),))


def balance_slider_crank(b: SliderCrankBalanceIn, lim: Limits) -> Plan:
    """POST /v1/balancing/slider-crank."""
    linkage = linkage_from(b)
    return Plan(Render(slider_crank_balance_out, slider_crank_balance_export,
                       model_extra=(synth.check_linkage(linkage),)),
                synth.balance_slider_crank, (linkage, b.omega_rad_s),
                dict(counterweight_radius=b.counterweight_radius_m,
                     balancer_radii=(b.balancer_radii_m[0], b.balancer_radii_m[1]), orders=b.orders,
                     samples=b.samples),
                FIGURES, "balance_slider_crank")


def flywheel(b: FlywheelIn, lim: Limits) -> Plan:
    """POST /v1/flywheel: from tables, or from a linkage analysed at its mean speed."""
    mean_speed, delta = mean_speed_of(b), target_delta(b)
    geometry = None if b.geometry is None else geometry_from(b.geometry)
    sizing: dict[str, Any] = dict(constant_inertia=b.constant_inertia_kgm2,
                                  motor=None if b.motor is None else motor_from(b.motor),
                                  time_limit_s=lim.solver_time_limit_s)
    render = Render(flywheel_out, flywheel_file)
    offered = (*FIGURES, "csv", *ARRAYS)
    if b.elastic_drive is not None:
        if b.motor is None:
            raise synth.InvalidInput("the elastic drive joins a motor's rotor to the machine: give the motor",
                                     field="elastic_drive")
        if b.mechanism is None:
            raise synth.InvalidInput("the elastic drive takes a linkage (its reduced inertia's slope comes from the "
                                     "analysis), not tables", field="elastic_drive")
        e = b.elastic_drive
        sizing["elastic"] = ElasticLink(link_stiffness(e), e.damping_ratio, e.flywheel_on == "motor_shaft",
                                        e.motor_side_inertia_kgm2, e.start)
    if uses_tables(b):
        assert b.tables is not None
        return Plan(render, flywheel_from_tables,
                    (cycle_from(b.tables, b.cycle_deg, lim.max_samples), mean_speed, delta, geometry), sizing,
                    offered, "flywheel")
    return Plan(render, flywheel_for_linkage,
                (linkage_from(b), mean_speed, b.samples, lim.max_samples, delta, geometry),
                dict(sizing, friction=pair_frictions(b.friction)), offered, "flywheel")


def gears_split(b: SplitIn, lim: Limits) -> Plan:
    """POST /v1/gears/split."""
    stages = synth.make_stages(stage_specs(b.stages), max_stages=lim.max_stages)
    return Plan(Render(split_out, model_extra=(stages,)), synth.split_ratio,
                (split_ratio(b), stages, b.objective),
                dict(inertia=inertia_model(b, b.motor_inertia_kgm2), input_torque=b.input_torque_Nm,
                     handbook_factor=b.handbook_factor, snap_r20=b.snap_r20, snap_tolerance=b.snap_tolerance,
                     time_limit_s=lim.solver_time_limit_s))


def gears_teeth(b: TeethIn, lim: Limits) -> Plan:
    """POST /v1/gears/teeth."""
    stages = synth.make_stages(stage_specs(b.stages), max_stages=lim.max_stages)
    return Plan(Render(teeth_out), synth.tooth_numbers, (b.total_ratio, stages, teeth_rules(b), b.tolerance),
                dict(planets=b.planets))


def gears_drive(b: DriveIn, lim: Limits) -> Plan:
    """POST /v1/gears/drive."""
    stages = synth.make_stages(stage_specs(b.stages), max_stages=lim.max_stages)
    return Plan(Render(drive_out, model_extra=(stages,)), synth.design_drive,
                (b.output_power_W, b.output_speed(), stages),
                dict(reserve_factor=b.reserve_factor, drive_efficiency=b.drive_efficiency,
                     synchronous_speed=b.synchronous_speed(), motor=b.motor, objective=b.objective,
                     torque_basis=b.torque_basis, inertia=inertia_model(b), snap_r20=b.snap_r20,
                     snap_tolerance=b.snap_tolerance, time_limit_s=lim.solver_time_limit_s,
                     catalogue=drive_catalogue(b), strength=None if b.strength is None else strength_from(b.strength)))


def gears_rating(b: RatingIn, lim: Limits) -> Plan:
    """POST /v1/gears/rating: at a nominal torque, or on a load spectrum (Miner)."""
    if b.load_spectrum is not None:
        return Plan(Render(rating_out), synth.rate_spectrum,
                    (rating_from(b), spectrum_from(b), b.speed(), duty_from(b)))
    assert b.pinion_torque_Nm is not None
    return Plan(Render(rating_out), synth.rate_pair,
                (rating_from(b), b.pinion_torque_Nm, b.speed(), duty_from(b)))


def gears_train(b: TrainIn, lim: Limits) -> Plan:
    """POST /v1/gears/train."""
    return Plan(Render(train_out), synth.gear_train, (train_from(b),),
                dict(module=b.module_m, input_speed=b.input_speed_rad_s, output_speed=b.output_speed_rad_s))


def structure(b: StructureIn, lim: Limits) -> Plan:
    """POST /v1/structure."""
    if b.mechanism is not None:
        return Plan(Render(structure_out), synth.linkage_structure, (planar_linkage_from(b.mechanism),), {})
    assert b.links is not None and b.pairs is not None
    return Plan(Render(structure_out), synth.analyse_structure,
                (b.links, [pair_from(p) for p in b.pairs]),
                dict(frame=b.frame, planar=b.planar, input_links=b.input_links, known_mobility=b.known_mobility))


def synthesis_crank_rocker(b: CrankRockerIn, lim: Limits) -> Plan:
    """POST /v1/synthesis/crank-rocker."""
    return Plan(Render(crank_rocker_out, crank_rocker_png, model_extra=(b.omega_rad_s,)),
                synth.synthesise_crank_rocker, (crank_rocker_spec(b),), offered=("png",))


def synthesis_slider_crank(b: SliderCrankSynthesisIn, lim: Limits) -> Plan:
    """POST /v1/synthesis/slider-crank."""
    return Plan(Render(slider_crank_synthesis_out, slider_crank_png, model_extra=(b.omega_rad_s,)),
                synth.synthesise_slider_crank, (slider_crank_synthesis_spec(b),), offered=("png",))


def synthesis_path(b: PathIn, lim: Limits) -> Plan:
    """POST /v1/synthesis/path, all starts in one task (a design study's variant)."""
    spec = path_spec(b, lim.solver_time_limit_s)
    return Plan(Render(path_out, path_file, export_extra=(spec.targets,)), synth.synthesise_path,
                (spec,), offered=("png",))


#: Through 10 points on two workers, 64 starts dealt in two chunks answered in 32-33 ms against 38-44 ms as one
#: task; 32 starts took 16-37 ms either way, as the second worker's core happened to be free or busy.
PATH_CHUNK_STARTS = 32


def synthesis_path_chunks(b: PathIn, lim: Limits, workers: int) -> tuple[PathSpec, list[tuple[int, ...]]]:
    """POST /v1/synthesis/path, first step: the starts dealt into chunks of at least :data:`PATH_CHUNK_STARTS`,
    at most one per worker, each a task of :func:`synth.synthesis.path.path_starts` (a start's screening takes about
    a fifth of a millisecond, so a smaller chunk saves less than its round trip and the extra task that
    concludes it cost)."""
    wall = estimate_s("/v1/synthesis/path", b) / max(1, workers)
    if wall > lim.max_work_s:
        raise synth.TooLarge("path synthesis estimated time [s]", int(lim.max_work_s), int(wall),
                             f"{b.starts} starts through {len(b.points_m)} points take about {wall:.3g} s on the "
                             f"{workers} workers, beyond the bound of {lim.max_work_s:g} s: ask for "
                             "fewer starts or points", field="starts")
    spec = path_spec(b, lim.solver_time_limit_s)
    return spec, start_chunks(spec, min(workers, max(1, b.starts // PATH_CHUNK_STARTS)))


def synthesis_path_best(spec: PathSpec, parts: Sequence[PathStarts]) -> Plan:
    """POST /v1/synthesis/path, last step: the best of the chunks' starts, placed and checked, then rendered."""
    return Plan(Render(path_out, path_file, export_extra=(spec.targets,)), best_path,
                (spec, tuple(parts)), offered=("png",))


def machine_design(b: MachineIn, lim: Limits) -> Plan:
    """POST /v1/machines/design: the design and, when asked, its alternatives; a summary PNG or the PDF design
    record, titled and identified by the request's hash."""
    record = DesignRecord.of(b.model_dump(mode="json"), name=b.name, version=SERVICE_VERSION)
    spec = with_strength(machine_from(b, lim.max_stages), b.strength)
    return Plan(Render(design_out, design_file, model_extra=(record,), export_extra=(record,)), design_machine,
                (spec, b.alternatives, lim.solver_time_limit_s), offered=("png", "pdf"),
                stem="machine-design", request_hash=record.request_sha256)


def machine_optimise(b: MachineOptimiseIn, lim: Limits) -> Plan:
    """POST /v1/machines/optimise as one task: every stage of the optimisation one after another (a study's
    variant); the endpoint itself spreads the candidates' chains over the workers and ends with
    :func:`machine_optimise_conclusion`, which gives the same answer."""
    return Plan(Render(machine_optimise_out), synth.optimise_machine, (machine_optimise_from(b, lim.max_stages),),
                dict(time_limit_s=lim.solver_time_limit_s))


def machine_optimise_conclusion(fn: Callable[..., Any], *args: Any, record: DesignRecord | None = None) -> Plan:
    """The last task of POST /v1/machines/optimise: ``fn(*args[:-1], time_limit_s=args[-1])`` concludes and its answer is rendered in the worker: the JSON, or with ``record`` the design record of the
    chosen machine with the certificate's page (pdf)."""
    *head, time_limit_s = args
    if record is None:
        return Plan(Render(machine_optimise_out), fn, tuple(head), dict(time_limit_s=time_limit_s))
    return Plan(Render(machine_optimise_out, optimisation_file, export_extra=(record,)), fn, tuple(head),
                dict(time_limit_s=time_limit_s), offered=("pdf",), stem="machine-optimisation")


def optimisation_file(result: synth.MachineOptimum, fmt: str, record: DesignRecord) -> bytes:
    """The optimised machine's design record with the optimisation's certificate page."""
    from synth.machine.optimise_record import optimisation_record_pdf

    return optimisation_record_pdf(result, record)


def _uniform(b: IsolationIn | IsolationDesignIn | ElasticDriveIn | RegulationIn) -> None:
    """The foundation's harmonics and the drives' periodic states take the whole cycle at uniform samples."""
    if b.crank_angle_deg is not None:
        raise synth.InvalidInput("the foundation takes uniformly spaced samples over one revolution: give samples, "
                                 "not crank_angle_deg", field="crank_angle_deg")


def isolation(b: IsolationIn, lim: Limits) -> Plan:
    """POST /v1/machines/isolation."""
    _uniform(b)
    frame, isolators = frame_and_isolators_from(b)
    return Plan(Render(isolation_out, isolation_figure), fd.isolate_linkage,
                (linkage_from(b), b.omega_rad_s, frame, isolators),
                dict(samples=b.samples, max_samples=lim.max_samples, counter_rotors=rotors_from(b),
                     run_up=run_up_from(b)),
                FIGURES, "isolation")


def isolation_design(b: IsolationDesignIn, lim: Limits) -> Plan:
    """POST /v1/machines/isolation/design."""
    _uniform(b)
    return Plan(Render(isolation_design_out, design_figure), fdd.design_linkage_isolation,
                (linkage_from(b), b.omega_rad_s, frame_from(b.frame), isolation_design_spec(b)),
                dict(samples=b.samples, max_samples=lim.max_samples, counter_rotors=rotors_from(b)),
                FIGURES, "isolation-design")


def elastic_drive(b: ElasticDriveIn, lim: Limits) -> Plan:
    """POST /v1/machines/elastic-drive."""
    _uniform(b)
    return Plan(Render(elastic_drive_out, elastic_drive_figure), ed.elastic_drive_for_linkage,
                (linkage_from(b), b.omega_rad_s, motor_from(b.motor)),
                dict(stiffness=b.stiffness_Nm_rad, elements=elements_from(b), samples=b.samples,
                     max_samples=lim.max_samples, counter_rotors=rotors_from(b), friction=pair_frictions(b.friction),
                     machine_inertia=b.machine_inertia_kgm2, motor_side_inertia=b.motor_side_inertia_kgm2,
                     damping_ratio=b.damping_ratio, start=b.start),
                FIGURES, "elastic-drive")


def regulation(b: RegulationIn, lim: Limits) -> Plan:
    """POST /v1/machines/regulation."""
    _uniform(b)
    controller, tuning = (None, None) if b.regulator is None else regulator_from(b.regulator)
    return Plan(Render(regulation_out, regulation_figure), rg.regulate_linkage,
                (linkage_from(b), b.omega_rad_s, motor_from(b.motor), b.load_step_Nm),
                dict(constant_inertia=b.constant_inertia_kgm2, delta=b.delta, band_fraction=b.settling_band,
                     controller=controller, tuning=tuning,
                     samples=b.samples, max_samples=lim.max_samples, counter_rotors=rotors_from(b),
                     friction=pair_frictions(b.friction)),
                FIGURES, "regulation")


CAM_FORMATS = (*FIGURES, "csv", "dxf")


def cam_record_title(body: CamAnalysisIn | CamSynthesisIn, name: str) -> synth.cams.RecordTitle:
    """The design record's title block for a request: now, this service, the request's hash and its inputs."""
    record = DesignRecord.of(body.model_dump(mode="json", exclude_none=True), name=name, version=SERVICE_VERSION)
    return synth.cams.RecordTitle(record.name, record.created, record.version, record.request_sha256,
                                  tuple(input_rows(record.request)))


def cam_synthesis_export(result: synth.cams.CamSynthesis, fmt: str, at: float, tolerance: float,
                     title: synth.cams.RecordTitle) -> bytes:
    """The least cam's figure, point table, drawing or design record (with the search's certificate)."""
    lc = result.least
    least = (f"base radius {lc.base_radius * 1e3:.6g} mm at offset {lc.offset * 1e3:.5g} mm; active limit: "
             f"{lc.active}", lc.statement)
    return synth.cams.cam_export(result.analysis, fmt, at, tolerance,
                                 replace(title, least=least))


def cam_analysis_plan(b: CamAnalysisIn, lim: Limits) -> Plan:
    """POST /v1/cams/analysis."""
    return Plan(Render(cam_analysis_out, synth.cams.cam_export,
                       export_extra=(math.radians(b.drawing_angle_deg), b.chord_tolerance_m,
                                     cam_record_title(b, "disc cam"))),
                synth.cams.analyse_cam, (cam_analysis_spec(b),), dict(max_samples=lim.max_samples), CAM_FORMATS, "cam")


def cam_synthesis_plan(b: CamSynthesisIn, lim: Limits) -> Plan:
    """POST /v1/cams/synthesis."""
    return Plan(Render(cam_synthesis_out, cam_synthesis_export,
                       export_extra=(math.radians(b.drawing_angle_deg), b.chord_tolerance_m,
                                     cam_record_title(b, "least disc cam"))),
                synth.cams.synthesise_cam, (cam_spec(b), limits_from(b)), dict(max_samples=lim.max_samples), CAM_FORMATS,
                "least-cam")


def machine_optimise_linkage(b: LinkageOptimiseIn, lim: Limits) -> Plan:
    """POST /v1/machines/optimise-linkage as one task: every stage one after another (a study's variant, a kept
    design); the endpoint itself runs the same stages as tasks side by side and gives the same answer."""
    return Plan(Render(linkage_optimise_out, model_extra=(b.model_dump(mode="json"),)), optimise_linkage,
                (linkage_optimise_from(b, lim.max_stages),), dict(time_limit_s=lim.solver_time_limit_s))


def strength_plan(b: StrengthSizingIn, lim: Limits) -> Plan:
    """POST /v1/strength."""
    linkage, speed, specs, limits = sizing_call(b)
    return Plan(Render(sizing_out), synth.strength.size_links, (linkage, speed, specs, limits),
                dict(samples=b.samples, crank_acceleration=b.crank_acceleration_rad_s2,
                     max_samples=lim.max_samples), (), "strength")


# The design endpoints by path: request schema and plan. A study may vary any of them.
PLANS: dict[str, tuple[type[BaseModel], Callable[[Any, Limits], Plan]]] = {
    "/v1/analysis": (AnalysisIn, analysis),
    "/v1/balancing/static": (BalanceIn, balance_static),
    "/v1/balancing/full": (FullBalanceIn, balance_full),
    "/v1/balancing/optimal": (OptimalBalanceIn, balance_optimal),
    "/v1/balancing/rotor": (RotorIn, balance_rotor),
    "/v1/balancing/slider-crank": (SliderCrankBalanceIn, balance_slider_crank),
    "/v1/flywheel": (FlywheelIn, flywheel),
    "/v1/gears/split": (SplitIn, gears_split),
    "/v1/gears/teeth": (TeethIn, gears_teeth),
    "/v1/gears/drive": (DriveIn, gears_drive),
    "/v1/gears/rating": (RatingIn, gears_rating),
    "/v1/gears/train": (TrainIn, gears_train),
    "/v1/structure": (StructureIn, structure),
    "/v1/synthesis/crank-rocker": (CrankRockerIn, synthesis_crank_rocker),
    "/v1/synthesis/slider-crank": (SliderCrankSynthesisIn, synthesis_slider_crank),
    "/v1/synthesis/path": (PathIn, synthesis_path),
    "/v1/machines/design": (MachineIn, machine_design),
    "/v1/machines/optimise": (MachineOptimiseIn, machine_optimise),
    "/v1/balancing/engine": (EngineIn, balance_engine),
    "/v1/machines/isolation": (IsolationIn, isolation),
    "/v1/machines/isolation/design": (IsolationDesignIn, isolation_design),
    "/v1/machines/elastic-drive": (ElasticDriveIn, elastic_drive),
    "/v1/machines/regulation": (RegulationIn, regulation),
    "/v1/cams/analysis": (CamAnalysisIn, cam_analysis_plan),
    "/v1/cams/synthesis": (CamSynthesisIn, cam_synthesis_plan),
    "/v1/machines/optimise-linkage": (LinkageOptimiseIn, machine_optimise_linkage),
    "/v1/strength": (StrengthSizingIn, strength_plan),
}

