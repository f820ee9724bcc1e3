"""POST /v1/machines/design: the whole machine, linkage to motor, in one request, checked by simulation."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import APIRouter, Query
from fastapi.responses import Response

import synth
from synth.machine.report import design_report_pdf, design_summary_png

from ..deps import SettingsDep, SolverGateDep
from ..media import json_response, png
from ..schemas.machine import MachineDesignOut, MachineIn

router = APIRouter(prefix="/machines", tags=["machines"])

ReportFormat = Annotated[
    Literal["json", "png", "pdf"] | None,
    Query(description="`png`: a one-page summary; `pdf`: the multi-page design report."),
]

RESPONSES: dict[int | str, dict[str, Any]] = {
    200: {"content": {"image/png": {}, "application/pdf": {}},
          "description": "The design, its one-page summary (?format=png) or its report (?format=pdf)."}
}


@router.post("/design", response_model=MachineDesignOut, responses=RESPONSES)
def design(body: MachineIn, settings: SettingsDep, gate: SolverGateDep, format: ReportFormat = None) -> Response:
    """Design the whole machine in one request: analysis, balancing, the balanced linkage reduced to its crank,
    the motor from the mean power, ratio split and tooth numbers, the flywheel for the chosen motor on the chosen
    shaft, and every shaft's speed, power and peak and RMS torque; checked by simulating the assembled machine
    to its steady state. `alternatives: true` designs it with the other balancing modes too."""
    spec = body.to_engine(settings.max_stages)
    result = gate.run(synth.design_machine, spec, time_limit_s=settings.solver_time_limit_s)
    others: tuple[synth.Alternative, ...] = ()
    if body.alternatives:
        others = gate.run(synth.alternatives, spec, time_limit_s=settings.solver_time_limit_s)
    if format == "png":
        return png(design_summary_png(result))
    if format == "pdf":
        return Response(content=design_report_pdf(result, others), media_type="application/pdf",
                        headers={"content-disposition": 'attachment; filename="machine-design.pdf"'})
    return json_response(MachineDesignOut.from_engine(result, others))
