"""POST /v1/machines/design: the whole machine, linkage to motor, in one request, checked by simulation."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import APIRouter, Query, Request
from fastapi.responses import Response

from ..execution import plans
from ..execution.optimise import answer_optimisation
from ..execution.optimise_linkage import answer_linkage_optimisation
from ..deps import AnswerSolverDep
from ..identity import current_user
from mechsynth_client.schemas.machine import MachineDesignOut, MachineIn
from mechsynth_client.schemas.optimise import (
    LinkageOptimiseIn,
    LinkageOptimiseOut,
    MachineOptimiseIn,
    MachineOptimiseOut,
)

router = APIRouter(prefix="/machines", tags=["machines"])

ReportFormat = Annotated[
    Literal["json", "png", "pdf"] | None,
    Query(description="`png`: a one-page summary; `pdf`: the multi-page design report."),
]

RESPONSES: dict[int | str, dict[str, Any]] = {
    200: {"content": {"image/png": {}, "application/pdf": {}},
          "description": "The design, its one-page summary (?format=png) or its report (?format=pdf)."}
}


@router.post("/design", response_model=MachineDesignOut, responses=RESPONSES, name="design_machine")
async def design(body: MachineIn, request: Request, solvers: AnswerSolverDep, format: ReportFormat = None) -> Response:
    """Design the whole machine in one request: analysis, balancing, the balanced linkage reduced to its crank,
    the motor from the mean power, ratio split and tooth numbers, the flywheel for the chosen motor on the chosen
    shaft, and every shaft's speed, power and peak and RMS torque; checked by simulating the assembled machine
    to its steady state. `alternatives: true` designs it with the other balancing modes too."""
    plan = plans.machine_design(body, solvers.limits)
    # the design a person just looked at, held: its record or summary of the same request is written from it
    user = current_user(request)
    key = ("" if user is None else str(user.id), plan.request_hash)
    return await solvers.answer_held(plan, request, format, key)


@router.post("/optimise", response_model=MachineOptimiseOut, name="optimise_machine",
             responses={200: {"content": {"application/pdf": {}},
                              "description": "The optimised machine, or its design record (?format=pdf)."}})
async def optimise(body: MachineOptimiseIn, request: Request, solvers: AnswerSolverDep,
                   format: Annotated[Literal["json", "pdf"] | None, Query(
                       description="`pdf`: the chosen machine's design record with a page for the "
                       "optimisation's certificate.")] = None) -> Response:
    """Optimise the machine as a whole: the linkage's family member (for its function: swing or stroke and time
    ratio), the counterweights, the flywheel and its shaft, the motor and the ratio together, for the least motor
    power, added mass, RMS shaking force or a weighted sum of these, each normalised by its value on the chain's
    machine; within the transmission-angle limit, the delta target, the motor's heating and breakdown checks and
    the optional shaking limits. The family is scanned kinematically at once, the whole chain runs on evenly
    spread members (side by side on the workers) and bounded Brent refines the best brackets. The answer holds
    the design as /v1/machines/design answers it, the gain over the chain in every objective, the certificate of
    how the family was covered and the Pareto set of two objectives over every member designed."""
    return await answer_optimisation(body, request, solvers, format)


@router.post("/optimise-linkage", response_model=LinkageOptimiseOut, name="optimise_linkage")
async def optimise_linkage(body: LinkageOptimiseIn, request: Request, solvers: AnswerSolverDep) -> Response:
    """Choose any linkage's free dimensions together with its machine: numbers of a general linkage (a frame
    point's coordinate, a link's length, a point of a link) free within bounds, the function as constraints on
    the analysed linkage (the output's stroke or swing within a band, the time ratio within a band, the least
    transmission angle of every dyad, assembly over the whole turn), for the least motor power, added mass,
    shaking force, machine mass, cost or a weighted sum. A scrambled Sobol sample of the box is checked
    kinematically, the members that meet the function run through the chain to their steady machine (side by
    side on the workers), the best are refined by COBYLA (the function as its constraints; one start per task)
    and the best member is designed whole; the certificate states the coverage and claims no gap. The work is
    estimated before it starts: 413 naming `samples` or `refine_runs` beyond the service's bound."""
    return await answer_linkage_optimisation(body, request, solvers)
