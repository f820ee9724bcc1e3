"""Worker-side compositions of engine calls, and the exports' call shapes, for the routers.

Each is a plain module-level function of engine objects, so the whole of a request's work (analysis, solve,
warnings, figure or file) runs in the worker under the request's deadline.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import synth
from synth.machine import elastic_drive as ed
from synth.machine.simulate import MachineCycle
from synth.exports import analysis_export, balance_export, flywheel_export, mechanism_dxf, mechanism_svg
from synth.machine.record import DesignRecord
from synth.machine.report import design_report_pdf, design_summary_png
from synth.synthesis.plots import extremes_png, path_png

from api.translate.balancing import rotor_out as rotor_answer
from api.translate.flywheel import flywheel_out as flywheel_answer
from api.translate.machine import machine_design_out
from mechsynth_client.schemas.balancing import RotorOut
from mechsynth_client.schemas.flywheel import FlywheelOut
from mechsynth_client.schemas.machine import MachineDesignOut
from ..translate.machine_strength import with_strength_out

DesignAndAlternatives = tuple[synth.MachineDesign, tuple[synth.Alternative, ...]]
#: A flywheel with its warnings and, when asked, the elastic drive with that flywheel.
FlywheelAndWarnings = tuple[synth.FlywheelResult, list[synth.DesignWarning], ed.ElasticDrive | None]
#: Fields of the elastic drive's engine errors that are the request's ``elastic_drive`` block's.
_BLOCK_FIELDS = ("stiffness_Nm_rad", "machine_inertia_kgm2", "motor_side_inertia_kgm2", "damping_ratio", "start")


@dataclass(frozen=True, slots=True)
class ElasticLink:
    """The elastic link of a flywheel request: ``stiffness`` at the crank [N·m/rad], ``damping_ratio`` [-], the
    flywheel ``on_motor_shaft`` or on the crank, ``motor_side_inertia`` besides rotor and flywheel on the motor
    shaft [kg·m²], ``start`` the run-up too."""

    stiffness: float
    damping_ratio: float
    on_motor_shaft: bool
    motor_side_inertia: float
    start: bool


def analysis_file(an: synth.Analysis, fmt: str, phi: float) -> bytes:
    """An analysis as a figure, its curves as CSV or its mechanism drawing, with the drawing at ``phi`` [rad]."""
    return analysis_export(an, phi, fmt)


def mechanism_drawing(linkage: synth.Linkage, speed: float, samples: int, phi: Any, max_samples: int,
                      points: Any, at: float, fmt: str) -> bytes:
    """Analyse a linkage and draw it at crank angle ``at`` [rad] as DXF or SVG."""
    an = synth.analyse(linkage, speed, samples=samples, phi=phi, max_samples=max_samples, points=points)
    return (mechanism_dxf if fmt == "dxf" else mechanism_svg)(an, at)


def optimal_file(results: list[synth.BalanceResult], fmt: str) -> bytes:
    """The optimal design's figure (with the sweep's trade-off curve), curves or drawing."""
    return balance_export(results[0], fmt, sweep=results[1:])


def rotor_out(result: synth.RotorBalance, rotor: Any) -> RotorOut:
    """A rotor's corrections with the check of the request against them."""
    return rotor_answer(result, synth.check_rotor(rotor, result))


def flywheel_from_tables(cycle: synth.ReducedCycle, mean_speed: float, delta: float,
                         geometry: synth.GeometrySpec | None, **sizing: Any) -> FlywheelAndWarnings:
    """Size the flywheel of a tabulated cycle and check the answer for likely mistakes."""
    result = synth.size_flywheel(cycle, mean_speed, delta, geometry=geometry, **sizing)
    return result, synth.check_flywheel(result, geometry, None), None


def flywheel_for_linkage(linkage: synth.Linkage, mean_speed: float, samples: int, max_samples: int,
                         delta: float, geometry: synth.GeometrySpec | None,
                         friction: tuple[synth.PairFriction, ...] = (), elastic: ElasticLink | None = None,
                         **sizing: Any) -> FlywheelAndWarnings:
    """Analyse a linkage at its mean speed (with friction in its pairs, whose losses the reduced load torque then
    carries), size the flywheel on its reduced model and check the answer; with an ``elastic`` link, drive the
    same reduced machine through it with the sized flywheel on its side of the link."""
    analysis = synth.analyse(linkage, mean_speed, samples=samples, max_samples=max_samples, friction=friction)
    result = synth.size_flywheel(synth.cycle_from_reduced(analysis.reduced), mean_speed, delta, geometry=geometry,
                                 **sizing)
    drive = None
    if elastic is not None:
        drive = _elastic_drive(analysis, result, elastic, sizing["motor"], sizing.get("constant_inertia", 0.0))
    return result, synth.check_flywheel(result, geometry, analysis), drive


def _elastic_drive(analysis: synth.Analysis, result: synth.FlywheelResult, link: ElasticLink, motor: synth.Motor,
                   constant_inertia: float) -> ed.ElasticDrive:
    """The reduced machine driven through the link: the flywheel with the rotor (its inertia on the motor shaft the
    crank's over the ratio squared) or with the machine, whose constant inertia is always on the machine's side."""
    red = analysis.reduced
    cycle = MachineCycle(red.phi, red.inertia, red.inertia_slope, red.resisting_torque)
    flywheel = result.design.flywheel_inertia
    machine, motor_side = constant_inertia, link.motor_side_inertia
    if link.on_motor_shaft:
        motor_side += flywheel / motor.gear_ratio**2
    else:
        machine += flywheel
    try:
        return ed.elastic_drive(cycle, motor, link.stiffness, machine_inertia=machine, motor_side_inertia=motor_side,
                                damping_ratio=link.damping_ratio, start=link.start)
    except synth.InvalidInput as error:
        if error.field in _BLOCK_FIELDS:
            error.field = f"elastic_drive.{error.field}"
        raise


def flywheel_out(pair: FlywheelAndWarnings) -> FlywheelOut:
    """The flywheel's JSON answer with its warnings."""
    return flywheel_answer(*pair)


def flywheel_file(pair: FlywheelAndWarnings, fmt: str) -> bytes:
    """The flywheel's figure or curves."""
    return flywheel_export(pair[0], fmt)


def design_machine(spec: synth.MachineSpec, alternatives: bool, time_limit_s: float) -> DesignAndAlternatives:
    """The whole-machine design and, when asked, the same machine with the other balancing modes."""
    result = synth.design_machine(spec, time_limit_s=time_limit_s)
    others = synth.alternatives(spec, time_limit_s=time_limit_s) if alternatives else ()
    return result, others


def design_out(pair: DesignAndAlternatives, record: DesignRecord) -> MachineDesignOut:
    """The design's JSON answer, identified by its request's hash."""
    return with_strength_out(pair[0], machine_design_out(*pair, request_sha256=record.request_sha256))


def design_file(pair: DesignAndAlternatives, fmt: str, record: DesignRecord) -> bytes:
    """The design's one-page summary (png) or its design record (pdf)."""
    return design_summary_png(pair[0]) if fmt == "png" else design_report_pdf(*pair, record=record)


def crank_rocker_png(result: synth.CrankRockerResult, fmt: str) -> bytes:
    """Both dead-centre positions of a synthesised crank-rocker."""
    return extremes_png(result.linkage, result.check, "crank-rocker")


def slider_crank_png(result: synth.SliderCrankResult, fmt: str) -> bytes:
    """Both dead-centre positions of a synthesised offset slider-crank."""
    return extremes_png(result.linkage, result.check, "offset slider-crank")


def path_file(result: synth.PathResult, fmt: str, targets: Any) -> bytes:
    """The synthesised coupler curve through the target points."""
    return path_png(result, targets)
