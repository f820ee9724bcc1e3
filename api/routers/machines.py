"""POST /v1/machines/design: the whole machine, linkage to motor, in one request, checked by simulation."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import APIRouter, Query
from fastapi.responses import Response

from ..deps import SolverDep
from ..media import Render
from ..schemas.machine import MachineDesignOut, MachineIn
from ..tasks import design_file, design_machine, design_out

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
async def design(body: MachineIn, solvers: SolverDep, format: ReportFormat = None) -> Response:
    """Design the whole machine in one request: analysis, balancing, the balanced linkage reduced to its crank,
    the motor from the mean power, ratio split and tooth numbers, the flywheel for the chosen motor on the chosen
    shaft, and every shaft's speed, power and peak and RMS torque; checked by simulating the assembled machine
    to its steady state. `alternatives: true` designs it with the other balancing modes too."""
    spec = body.to_engine(solvers.settings.max_stages)
    render = Render(design_out, design_file, format or "json")
    headers = {"content-disposition": 'attachment; filename="machine-design.pdf"'} if format == "pdf" else None
    return await solvers.answer(render, design_machine, spec, body.alternatives,
                                solvers.settings.solver_time_limit_s, headers=headers)
