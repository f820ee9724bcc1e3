"""POST /v1/flywheel: flywheel sizing for a target coefficient of speed fluctuation; GET /v1/machine-types."""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Query, Request
from fastapi.responses import Response

import synth

from ..execution import plans
from ..deps import AnswerSolverDep
from ..media import ARRAYS, FIGURES, format_responses
from api.translate.flywheel import machine_type_out
from mechsynth_client.schemas.flywheel import FlywheelIn, FlywheelOut, MachineTypeOut

router = APIRouter(tags=["flywheel"])
FORMATS = (*FIGURES, "csv", *ARRAYS)
# Only what this endpoint serves: a flywheel has no mechanism to draw, so no DXF.
FlywheelFormat = Annotated[
    Literal["json", "png", "svg", "pdf", "csv", "npz"] | None,
    Query(description="Answer format: `json` (default); `png`, `svg` or `pdf` for the energy-mass diagram and "
                      "the speed over the cycle; `csv` for the cycle and every method's speed, one row per crank "
                      "angle; `npz` for every number of the JSON answer as a NumPy archive, one array per JSON "
                      "path. An `Accept` header (image/png, image/svg+xml, application/pdf, text/csv, "
                      "application/x-npz) chooses the same way."),
]


@router.get("/machine-types", response_model=list[MachineTypeOut])
def machine_types() -> list[MachineTypeOut]:
    """The seeds' table of admissible delta per machine type; a request naming one gets its tightest value."""
    return [machine_type_out(row) for row in synth.machine_types()]


@router.post("/flywheel", response_model=FlywheelOut, responses=format_responses(FORMATS))
async def flywheel(body: FlywheelIn, request: Request, solvers: AnswerSolverDep,
                   format: FlywheelFormat = None) -> Response:
    """Smallest flywheel for a target delta by the exact (Wittenbauer), Mertsalov and energy methods, and with
    a motor characteristic as a collocation NLP; each checked by integrating the equation of motion. With
    ``?format=png|svg|pdf`` the energy-mass diagram with its tangents (the excess-work curve for a constant
    reduced inertia) and the speed over the cycle; ``csv`` the cycle and every method's speed per crank angle;
    ``npz`` the JSON answer's numbers as NumPy arrays keyed by their JSON path."""
    return await solvers.answer_plan(plans.flywheel(body, solvers.limits), request, format)
