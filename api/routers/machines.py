"""POST /v1/machines/design: the whole machine, linkage to motor, in one request, checked by simulation."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import APIRouter, Query, Request
from fastapi.responses import Response

from ..execution import plans
from ..deps import SolverDep
from mechsynth_client.schemas.machine import MachineDesignOut, MachineIn

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
async def design(body: MachineIn, request: Request, solvers: SolverDep, format: ReportFormat = None) -> Response:
    """Design the whole machine in one request: analysis, balancing, the balanced linkage reduced to its crank,
    the motor from the mean power, ratio split and tooth numbers, the flywheel for the chosen motor on the chosen
    shaft, and every shaft's speed, power and peak and RMS torque; checked by simulating the assembled machine
    to its steady state. `alternatives: true` designs it with the other balancing modes too."""
    return await solvers.answer_plan(plans.machine_design(body, solvers.limits), request, format)
