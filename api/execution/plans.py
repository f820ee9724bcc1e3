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
from ..translate.machine_strength import with_strength
from ..translate.strength import sizing_call, sizing_out
from mechsynth_client.schemas.strength import StrengthSizingIn
from mechsynth_client.schemas.analysis import AnalysisIn, AnalysisOut, plot_angle
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
    the file of a CSV or DXF answer."""

    render: Render
    fn: Callable[..., Any]
    args: tuple[Any, ...] = ()
    kwargs: dict[str, Any] = field(default_factory=dict)
    offered: tuple[str, ...] = ()
    stem: str = "answer"


def analysis(b: AnalysisIn, lim: Limits, angle_deg: float | None = None) -> Plan:
    """POST /v1/analysis."""
    return Plan(Render(AnalysisOut.from_engine, analysis_file, model_extra=(b.geometry_request(),),
                       export_extra=(plot_angle(b, angle_deg),)),
                synth.analyse, (b.to_linkage(), b.omega_rad_s),
                dict(samples=b.samples, phi=b.phi(), crank_acceleration=b.crank_acceleration_rad_s2,
                     max_samples=lim.max_samples, points=b.trace(), counter_rotors=b.rotors(),
                     friction=b.frictions()),
                (*CURVES, *ARRAYS), "analysis")


def balance_static(b: BalanceIn, lim: Limits) -> Plan:
    """POST /v1/balancing/static."""
    return Plan(Render(BalanceOut.from_engine, balance_export), synth.balance_static,
                (b.to_linkage(), b.omega_rad_s, b.spec()),
                dict(samples=b.samples, objective=b.objective, mass_budget=b.mass_budget_kg,
                     time_limit_s=lim.solver_time_limit_s, method=b.method),
                CURVES, "balance_static")


def balance_full(b: FullBalanceIn, lim: Limits) -> Plan:
    """POST /v1/balancing/full."""
    return Plan(Render(BalanceOut.from_engine, balance_export), synth.balance_full,
                (b.to_linkage(), b.omega_rad_s, b.spec()),
                dict(samples=b.samples, ratios=b.rotor_ratios, time_limit_s=lim.solver_time_limit_s),
                CURVES, "balance_full")


def balance_optimal(b: OptimalBalanceIn, lim: Limits) -> Plan:
    """POST /v1/balancing/optimal: the request's weights first, then the sweep's."""
    weight_sets = [w.to_engine() for w in [b.weights, *b.sweep]]
    return Plan(Render(OptimalBalanceOut.from_results, optimal_file), synth.tradeoff,
                (b.to_linkage(), b.omega_rad_s, b.spec(), weight_sets),
                dict(mass_budget=b.mass_budget_kg, samples=b.samples, time_limit_s=lim.solver_time_limit_s,
                     weight_scale=b.weight_scale),
                CURVES, "balance_optimal")


def balance_rotor(b: RotorIn, lim: Limits) -> Plan:
    """POST /v1/balancing/rotor."""
    rotor = b.to_engine()
    render = Render(rotor_out, model_extra=(rotor,))
    if b.mode == "static":
        return Plan(render, synth.balance_rotor_static, (rotor, b.correction_radius_m, b.correction_plane_m))
    return Plan(render, synth.balance_rotor_dynamic,
                (rotor, (b.planes_m[0], b.planes_m[1]), (b.radii_m[0], b.radii_m[1])))


def balance_engine(b: EngineIn, lim: Limits) -> Plan:
    """POST /v1/balancing/engine."""
    return Plan(Render(EngineOut.from_engine), synth.engine_shaking, (b.to_engine(),))


def balance_slider_crank(b: SliderCrankBalanceIn, lim: Limits) -> Plan:
    """POST /v1/balancing/slider-crank."""
    linkage = b.to_linkage()
    return Plan(Render(SliderCrankBalanceOut.from_engine, slider_crank_balance_export,
                       model_extra=(synth.check_linkage(linkage),)),
                synth.balance_slider_crank, (linkage, b.omega_rad_s),
                dict(counterweight_radius=b.counterweight_radius_m,
                     balancer_radii=(b.balancer_radii_m[0], b.balancer_radii_m[1]), orders=b.orders,
                     samples=b.samples),
                FIGURES, "balance_slider_crank")


def flywheel(b: FlywheelIn, lim: Limits) -> Plan:
    """POST /v1/flywheel: from tables, or from a linkage analysed at its mean speed."""
    mean_speed, delta = b.mean_speed(), b.target_delta()
    geometry = None if b.geometry is None else b.geometry.to_engine()
    sizing: dict[str, Any] = dict(constant_inertia=b.constant_inertia_kgm2,
                                  motor=None if b.motor is None else b.motor.to_engine(),
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
        sizing["elastic"] = ElasticLink(e.link_stiffness(), e.damping_ratio, e.flywheel_on == "motor_shaft",
                                        e.motor_side_inertia_kgm2, e.start)
    if b.uses_tables():
        assert b.tables is not None
        return Plan(render, flywheel_from_tables,
                    (b.tables.to_cycle(b.cycle_deg, lim.max_samples), mean_speed, delta, geometry), sizing,
                    offered, "flywheel")
    return Plan(render, flywheel_for_linkage,
                (b.to_linkage(), mean_speed, b.samples, lim.max_samples, delta, geometry),
                dict(sizing, friction=b.frictions()), offered, "flywheel")


def gears_split(b: SplitIn, lim: Limits) -> Plan:
    """POST /v1/gears/split."""
    stages = synth.make_stages(b.stage_specs(), max_stages=lim.max_stages)
    return Plan(Render(SplitOut.from_engine, model_extra=(stages,)), synth.split_ratio,
                (b.ratio(), stages, b.objective),
                dict(inertia=b.inertia_model(b.motor_inertia_kgm2), input_torque=b.input_torque_Nm,
                     handbook_factor=b.handbook_factor, snap_r20=b.snap_r20, snap_tolerance=b.snap_tolerance,
                     time_limit_s=lim.solver_time_limit_s))


def gears_teeth(b: TeethIn, lim: Limits) -> Plan:
    """POST /v1/gears/teeth."""
    stages = synth.make_stages(b.stage_specs(), max_stages=lim.max_stages)
    return Plan(Render(TeethOut.from_engine), synth.tooth_numbers, (b.total_ratio, stages, b.rules(), b.tolerance),
                dict(planets=b.planets))


def gears_drive(b: DriveIn, lim: Limits) -> Plan:
    """POST /v1/gears/drive."""
    stages = synth.make_stages(b.stage_specs(), max_stages=lim.max_stages)
    return Plan(Render(DriveOut.from_engine, model_extra=(stages,)), synth.design_drive,
                (b.output_power_W, b.output_speed(), stages),
                dict(reserve_factor=b.reserve_factor, drive_efficiency=b.drive_efficiency,
                     synchronous_speed=b.synchronous_speed(), motor=b.motor, objective=b.objective,
                     torque_basis=b.torque_basis, inertia=b.inertia_model(), snap_r20=b.snap_r20,
                     snap_tolerance=b.snap_tolerance, time_limit_s=lim.solver_time_limit_s,
                     catalogue=b.catalogue(), strength=None if b.strength is None else b.strength.to_engine()))


def gears_rating(b: RatingIn, lim: Limits) -> Plan:
    """POST /v1/gears/rating: at a nominal torque, or on a load spectrum (Miner)."""
    if b.load_spectrum is not None:
        return Plan(Render(RatingOut.from_engine), synth.rate_spectrum,
                    (b.to_engine(), b.spectrum(), b.speed(), b.duty()))
    assert b.pinion_torque_Nm is not None
    return Plan(Render(RatingOut.from_engine), synth.rate_pair,
                (b.to_engine(), b.pinion_torque_Nm, b.speed(), b.duty()))


def gears_train(b: TrainIn, lim: Limits) -> Plan:
    """POST /v1/gears/train."""
    return Plan(Render(TrainOut.from_engine), synth.gear_train, (b.to_engine(),),
                dict(module=b.module_m, input_speed=b.input_speed_rad_s, output_speed=b.output_speed_rad_s))


def structure(b: StructureIn, lim: Limits) -> Plan:
    """POST /v1/structure."""
    if b.mechanism is not None:
        return Plan(Render(StructureOut.from_engine), synth.linkage_structure, (b.mechanism.to_mechanism(),), {})
    assert b.links is not None and b.pairs is not None
    return Plan(Render(StructureOut.from_engine), synth.analyse_structure,
                (b.links, [p.to_engine() for p in b.pairs]),
                dict(frame=b.frame, planar=b.planar, input_links=b.input_links, known_mobility=b.known_mobility))


def synthesis_crank_rocker(b: CrankRockerIn, lim: Limits) -> Plan:
    """POST /v1/synthesis/crank-rocker."""
    return Plan(Render(CrankRockerOut.from_engine, crank_rocker_png, model_extra=(b.omega_rad_s,)),
                synth.synthesise_crank_rocker, (b.to_spec(),), offered=("png",))


def synthesis_slider_crank(b: SliderCrankSynthesisIn, lim: Limits) -> Plan:
    """POST /v1/synthesis/slider-crank."""
    return Plan(Render(SliderCrankSynthesisOut.from_engine, slider_crank_png, model_extra=(b.omega_rad_s,)),
                synth.synthesise_slider_crank, (b.to_spec(),), offered=("png",))


def synthesis_path(b: PathIn, lim: Limits) -> Plan:
    """POST /v1/synthesis/path, all starts in one task (a design study's variant)."""
    spec = b.to_spec(lim.solver_time_limit_s)
    return Plan(Render(PathOut.from_engine, path_file, export_extra=(spec.targets,)), synth.synthesise_path,
                (spec,), offered=("png",))


PATH_CHUNK_STARTS = 64


def synthesis_path_chunks(b: PathIn, lim: Limits, workers: int) -> tuple[PathSpec, list[tuple[int, ...]]]:
    """POST /v1/synthesis/path, first step: the starts dealt into chunks of at least :data:`PATH_CHUNK_STARTS`,
    at most one per worker, each a task of :func:`synth.synthesis.path.path_starts` (the screening steps all of a
    chunk's starts at once, so a smaller chunk saves little and costs a round trip)."""
    wall = estimate_s("/v1/synthesis/path", b) / max(1, workers)
    if wall > lim.max_work_s:
        raise synth.TooLarge("path synthesis estimated time [s]", int(lim.max_work_s), int(wall),
                             f"{b.starts} starts through {len(b.points_m)} points take about {wall:.3g} s on the "
                             f"{workers} workers, beyond the bound of {lim.max_work_s:g} s: ask for "
                             "fewer starts or points", field="starts")
    spec = b.to_spec(lim.solver_time_limit_s)
    return spec, start_chunks(spec, min(workers, max(1, b.starts // PATH_CHUNK_STARTS)))


def synthesis_path_best(spec: PathSpec, parts: Sequence[PathStarts]) -> Plan:
    """POST /v1/synthesis/path, last step: the best of the chunks' starts, placed and checked, then rendered."""
    return Plan(Render(PathOut.from_engine, path_file, export_extra=(spec.targets,)), best_path,
                (spec, tuple(parts)), offered=("png",))


def machine_design(b: MachineIn, lim: Limits) -> Plan:
    """POST /v1/machines/design: the design and, when asked, its alternatives; a summary PNG or the PDF design
    record, titled and identified by the request's hash."""
    record = DesignRecord.of(b.model_dump(mode="json"), name=b.name, version=SERVICE_VERSION)
    spec = with_strength(b.to_engine(lim.max_stages), b.strength)
    return Plan(Render(design_out, design_file, model_extra=(record,), export_extra=(record,)), design_machine,
                (spec, b.alternatives, lim.solver_time_limit_s), offered=("png", "pdf"),
                stem="machine-design")


def machine_optimise(b: MachineOptimiseIn, lim: Limits) -> Plan:
    """POST /v1/machines/optimise as one task: every stage of the optimisation one after another (a study's
    variant); the endpoint itself spreads the candidates' chains over the workers and ends with
    :func:`machine_optimise_conclusion`, which gives the same answer."""
    return Plan(Render(MachineOptimiseOut.from_engine), synth.optimise_machine, (b.to_engine(lim.max_stages),),
                dict(time_limit_s=lim.solver_time_limit_s))


def machine_optimise_conclusion(fn: Callable[..., Any], *args: Any, record: DesignRecord | None = None) -> Plan:
    """The last task of POST /v1/machines/optimise: ``fn(*args[:-1], time_limit_s=args[-1])`` concludes and its answer is rendered in the worker: the JSON, or with ``record`` the design record of the
    chosen machine with the certificate's page (pdf)."""
    *head, time_limit_s = args
    if record is None:
        return Plan(Render(MachineOptimiseOut.from_engine), fn, tuple(head), dict(time_limit_s=time_limit_s))
    return Plan(Render(MachineOptimiseOut.from_engine, optimisation_file, export_extra=(record,)), fn, tuple(head),
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
    frame, isolators = b.to_frame()
    return Plan(Render(IsolationOut.from_engine, isolation_figure), fd.isolate_linkage,
                (b.to_linkage(), b.omega_rad_s, frame, isolators),
                dict(samples=b.samples, max_samples=lim.max_samples, counter_rotors=b.rotors(),
                     run_up=b.run_up_engine()),
                FIGURES, "isolation")


def isolation_design(b: IsolationDesignIn, lim: Limits) -> Plan:
    """POST /v1/machines/isolation/design."""
    _uniform(b)
    return Plan(Render(IsolationDesignOut.from_engine, design_figure), fdd.design_linkage_isolation,
                (b.to_linkage(), b.omega_rad_s, b.frame.to_engine(), b.to_spec()),
                dict(samples=b.samples, max_samples=lim.max_samples, counter_rotors=b.rotors()),
                FIGURES, "isolation-design")


def elastic_drive(b: ElasticDriveIn, lim: Limits) -> Plan:
    """POST /v1/machines/elastic-drive."""
    _uniform(b)
    return Plan(Render(ElasticDriveOut.from_engine, elastic_drive_figure), ed.elastic_drive_for_linkage,
                (b.to_linkage(), b.omega_rad_s, b.motor.to_engine()),
                dict(stiffness=b.stiffness_Nm_rad, elements=b.to_elements(), samples=b.samples,
                     max_samples=lim.max_samples, counter_rotors=b.rotors(), friction=b.frictions(),
                     machine_inertia=b.machine_inertia_kgm2, motor_side_inertia=b.motor_side_inertia_kgm2,
                     damping_ratio=b.damping_ratio, start=b.start),
                FIGURES, "elastic-drive")


def regulation(b: RegulationIn, lim: Limits) -> Plan:
    """POST /v1/machines/regulation."""
    _uniform(b)
    controller, tuning = (None, None) if b.regulator is None else b.regulator.to_engine()
    return Plan(Render(RegulationOut.from_engine, regulation_figure), rg.regulate_linkage,
                (b.to_linkage(), b.omega_rad_s, b.motor.to_engine(), b.load_step_Nm),
                dict(constant_inertia=b.constant_inertia_kgm2, delta=b.delta, band_fraction=b.settling_band,
                     controller=controller, tuning=tuning,
                     samples=b.samples, max_samples=lim.max_samples, counter_rotors=b.rotors(),
                     friction=b.frictions()),
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
    return Plan(Render(CamAnalysisOut.from_engine, synth.cams.cam_export,
                       export_extra=(math.radians(b.drawing_angle_deg), b.chord_tolerance_m,
                                     cam_record_title(b, "disc cam"))),
                synth.cams.analyse_cam, (b.spec(),), dict(max_samples=lim.max_samples), CAM_FORMATS, "cam")


def cam_synthesis_plan(b: CamSynthesisIn, lim: Limits) -> Plan:
    """POST /v1/cams/synthesis."""
    return Plan(Render(CamSynthesisOut.from_engine, cam_synthesis_export,
                       export_extra=(math.radians(b.drawing_angle_deg), b.chord_tolerance_m,
                                     cam_record_title(b, "least disc cam"))),
                synth.cams.synthesise_cam, (b.to_spec(), b.limits()), dict(max_samples=lim.max_samples), CAM_FORMATS,
                "least-cam")


def machine_optimise_linkage(b: LinkageOptimiseIn, lim: Limits) -> Plan:
    """POST /v1/machines/optimise-linkage as one task: every stage one after another (a study's variant, a kept
    design); the endpoint itself runs the same stages as tasks side by side and gives the same answer."""
    return Plan(Render(LinkageOptimiseOut.from_engine, model_extra=(b.model_dump(mode="json"),)), optimise_linkage,
                (b.to_engine(lim.max_stages),), dict(time_limit_s=lim.solver_time_limit_s))


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

