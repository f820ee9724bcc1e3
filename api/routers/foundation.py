"""POST /v1/machines/isolation: the machine on its foundation, with the isolators' design and the elastic drive and
speed regulation beside it."""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Query, Request
from fastapi.responses import Response

from synth.errors import InvalidInput
from synth.machine import foundation as fd
from synth.machine import foundation_design as fdd
from synth.machine import elastic_drive as ed
from synth.machine import regulation as rg
from synth.machine.foundation_plots import design_figure, elastic_drive_figure, isolation_figure, regulation_figure

from ..deps import SolverDep
from ..execution.plans import Limits, Plan
from ..media import FIGURES, Render, format_responses
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

router = APIRouter(prefix="/machines", tags=["machines"])

FigureFormat = Annotated[
    Literal["json", "png", "svg", "pdf"] | None,
    Query(description="Answer format: `json` (default); `png`, `svg` or `pdf` for the figure. An `Accept` header "
                      "(image/png, image/svg+xml, application/pdf) chooses the same way."),
]


def isolation_plan(b: IsolationIn, lim: Limits) -> Plan:
    """POST /v1/machines/isolation."""
    frame, isolators = b.to_frame()
    return Plan(Render(IsolationOut.from_engine, isolation_figure), fd.isolate_linkage,
                (b.to_linkage(), b.omega_rad_s, frame, isolators),
                dict(samples=b.samples, max_samples=lim.max_samples, counter_rotors=b.rotors(),
                     run_up=b.run_up_engine()),
                FIGURES, "isolation")


def isolation_design_plan(b: IsolationDesignIn, lim: Limits) -> Plan:
    """POST /v1/machines/isolation/design."""
    return Plan(Render(IsolationDesignOut.from_engine, design_figure), fdd.design_linkage_isolation,
                (b.to_linkage(), b.omega_rad_s, b.frame.to_engine(), b.to_spec()),
                dict(samples=b.samples, max_samples=lim.max_samples, counter_rotors=b.rotors()),
                FIGURES, "isolation-design")


def elastic_drive_plan(b: ElasticDriveIn, lim: Limits) -> Plan:
    """POST /v1/machines/elastic-drive."""
    return Plan(Render(ElasticDriveOut.from_engine, elastic_drive_figure), ed.elastic_drive_for_linkage,
                (b.to_linkage(), b.omega_rad_s, b.motor.to_engine()),
                dict(stiffness=b.stiffness_Nm_rad, elements=b.to_elements(), samples=b.samples,
                     max_samples=lim.max_samples, counter_rotors=b.rotors(), friction=b.frictions(),
                     machine_inertia=b.machine_inertia_kgm2, motor_side_inertia=b.motor_side_inertia_kgm2,
                     damping_ratio=b.damping_ratio, start=b.start),
                FIGURES, "elastic-drive")


def regulation_plan(b: RegulationIn, lim: Limits) -> Plan:
    """POST /v1/machines/regulation."""
    controller, tuning = (None, None) if b.regulator is None else b.regulator.to_engine()
    return Plan(Render(RegulationOut.from_engine, regulation_figure), rg.regulate_linkage,
                (b.to_linkage(), b.omega_rad_s, b.motor.to_engine(), b.load_step_Nm),
                dict(constant_inertia=b.constant_inertia_kgm2, delta=b.delta, controller=controller, tuning=tuning,
                     samples=b.samples, max_samples=lim.max_samples, counter_rotors=b.rotors(),
                     friction=b.frictions()),
                FIGURES, "regulation")


def _uniform(b: IsolationIn | IsolationDesignIn | ElasticDriveIn | RegulationIn) -> None:
    if b.crank_angle_deg is not None:
        raise InvalidInput("the foundation takes uniformly spaced samples over one revolution: give samples, "
                           "not crank_angle_deg", field="crank_angle_deg")


@router.post("/isolation", response_model=IsolationOut, responses=format_responses(FIGURES),
             name="isolate_machine")
async def isolation(body: IsolationIn, request: Request, solvers: SolverDep, format: FigureFormat = None) -> Response:
    """The machine's frame on isolators, driven by the linkage's shaking force and moment over the steady cycle
    at the crank speed: natural frequencies and mode shapes, the steady motion solved exactly per harmonic, the
    force each isolator and all together pass to the foundation (as the foundation feels it), the
    transmissibility per harmonic and the frame's peak movement; checked by integrating the same equations in
    time. `?format=png|svg|pdf`: force to the foundation against the shaking force, the frame's orbit and the
    transmissibility per harmonic."""
    _uniform(body)
    return await solvers.answer_plan(isolation_plan(body, solvers.limits), request, format)


@router.post("/isolation/design", response_model=IsolationDesignOut, responses=format_responses(FIGURES),
             name="design_isolation")
async def isolation_design(body: IsolationDesignIn, request: Request, solvers: SolverDep,
                           format: FigureFormat = None) -> Response:
    """Choose one isolator type for the given positions (vertical stiffness, horizontal as a ratio of it, damping
    ratio) and optionally an inertia block: the least frame amplitude with the peak force to the foundation
    under a limit, or the least peak force with the amplitude under a limit, within the stiffness bounds and the
    static deflection limit. Every candidate of a log-spaced grid is solved at once per harmonic, the best feasible
    refined by SLSQP; the design is re-solved with its time-integration check. A limit nothing within the bounds
    meets answers 422 naming the constraint. `?format=png|svg|pdf`: the figure of the frame on the chosen
    isolators."""
    _uniform(body)
    return await solvers.answer_plan(isolation_design_plan(body, solvers.limits), request, format)


@router.post("/elastic-drive", response_model=ElasticDriveOut, responses=format_responses(FIGURES),
             name="elastic_drive")
async def elastic_drive(body: ElasticDriveIn, request: Request, solvers: SolverDep,
                        format: FigureFormat = None) -> Response:
    """The machine driven through an elastic link: motor rotor and machine as two masses on a torsional spring
    (given, or from shafts and couplings reduced to the crank by their speed ratio squared), the machine's
    reduced inertia and load torque over the cycle, the motor's characteristic. Answers the free-free natural
    frequency, the torque in the link over the steady cycle against the rigid model's (the dynamic factor), the
    load harmonics near the natural frequency (as warnings) and the run-up from rest with the link; checked by
    the two-mass matrix's eigenvalues and the energy balance. `?format=png|svg|pdf`: the torques and the
    run-up."""
    _uniform(body)
    return await solvers.answer_plan(elastic_drive_plan(body, solvers.limits), request, format)


@router.post("/regulation", response_model=RegulationOut, responses=format_responses(FIGURES), name="regulation")
async def regulation(body: RegulationIn, request: Request, solvers: SolverDep, format: FigureFormat = None) -> Response:
    """The machine's speed after a step in the process load: self-regulation through the motor's characteristic
    (time constant, speed drop, time to settle in the delta band, with their closed forms for a constant
    inertia), or a PI controller on a frequency converter tuned for a settling time and overshoot (or given
    gains; an unstable regulator answers 422). `?format=png|svg|pdf`: speed and torques over time."""
    _uniform(body)
    return await solvers.answer_plan(regulation_plan(body, solvers.limits), request, format)
