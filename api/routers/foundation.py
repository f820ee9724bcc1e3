"""POST /v1/machines/isolation: the machine on its foundation, with the isolators' design and the elastic drive and
speed regulation beside it."""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Query, Request
from fastapi.responses import Response

from ..deps import AnswerSolverDep
from ..execution import plans
from ..media import FIGURES, format_responses
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


@router.post("/isolation", response_model=IsolationOut, responses=format_responses(FIGURES),
             name="isolate_machine")
async def isolation(body: IsolationIn, request: Request, solvers: AnswerSolverDep, format: FigureFormat = None) -> Response:
    """The machine's frame on isolators, driven by the linkage's shaking force and moment over the steady cycle
    at the crank speed: natural frequencies and mode shapes, the steady motion solved exactly per harmonic, the
    force each isolator and all together pass to the foundation (as the foundation feels it), the
    transmissibility per harmonic and the frame's peak movement; checked by integrating the same equations in
    time. `?format=png|svg|pdf`: force to the foundation against the shaking force, the frame's orbit and the
    transmissibility per harmonic."""
    return await solvers.answer_plan(plans.isolation(body, solvers.limits), request, format)


@router.post("/isolation/design", response_model=IsolationDesignOut, responses=format_responses(FIGURES),
             name="design_isolation")
async def isolation_design(body: IsolationDesignIn, request: Request, solvers: AnswerSolverDep,
                           format: FigureFormat = None) -> Response:
    """Choose one isolator type for the given positions (vertical stiffness, horizontal as a ratio of it, damping
    ratio) and optionally an inertia block: the least frame amplitude with the peak force to the foundation
    under a limit, or the least peak force with the amplitude under a limit, within the stiffness bounds and the
    static deflection limit. Every candidate of a log-spaced grid is solved at once per harmonic, the best feasible
    refined by SLSQP; the design is re-solved with its time-integration check. A limit nothing within the bounds
    meets answers 422 naming the constraint. `?format=png|svg|pdf`: the figure of the frame on the chosen
    isolators."""
    return await solvers.answer_plan(plans.isolation_design(body, solvers.limits), request, format)


@router.post("/elastic-drive", response_model=ElasticDriveOut, responses=format_responses(FIGURES),
             name="elastic_drive")
async def elastic_drive(body: ElasticDriveIn, request: Request, solvers: AnswerSolverDep,
                        format: FigureFormat = None) -> Response:
    """The machine driven through an elastic link: motor rotor and machine as two masses on a torsional spring
    (given, or from shafts and couplings reduced to the crank by their speed ratio squared), the machine's
    reduced inertia and load torque over the cycle, the motor's characteristic. Answers the free-free natural
    frequency, the torque in the link over the steady cycle against the rigid model's (the dynamic factor), the
    load harmonics near the natural frequency (as warnings) and the run-up from rest with the link; checked by
    the two-mass matrix's eigenvalues and the energy balance. `?format=png|svg|pdf`: the torques and the
    run-up."""
    return await solvers.answer_plan(plans.elastic_drive(body, solvers.limits), request, format)


@router.post("/regulation", response_model=RegulationOut, responses=format_responses(FIGURES), name="regulation")
async def regulation(body: RegulationIn, request: Request, solvers: AnswerSolverDep, format: FigureFormat = None) -> Response:
    """The machine's speed after a step in the process load: self-regulation through the motor's characteristic
    (time constant, speed drop, time to settle in the delta band, with their closed forms for a constant
    inertia), or a PI controller on a frequency converter tuned for a settling time and overshoot (or given
    gains; an unstable regulator answers 422). `?format=png|svg|pdf`: speed and torques over time."""
    return await solvers.answer_plan(plans.regulation(body, solvers.limits), request, format)
