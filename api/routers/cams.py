"""Disc cams: POST /v1/cams/analysis, POST /v1/cams/synthesis (the least cam), GET /v1/cams/laws."""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Query, Request
from fastapi.responses import Response

import synth.cams

from ..deps import AnswerSolverDep
from ..execution.plans import CAM_FORMATS as FORMATS
from ..execution.plans import cam_analysis_plan as analysis_plan
from ..execution.plans import cam_synthesis_plan as synthesis_plan
from ..media import format_responses
from api.translate.cams import motion_law_out
from mechsynth_client.schemas.cams import (
    CamAnalysisIn,
    CamAnalysisOut,
    CamSynthesisIn,
    CamSynthesisOut,
    MotionLawOut,
)

router = APIRouter(prefix="/cams", tags=["cams"])
CamFormat = Annotated[
    Literal["json", "png", "svg", "pdf", "csv", "dxf"] | None,
    Query(description="Answer format: `json` (default); `png` or `svg` for the figure (s, v, a, jerk and the "
                      "pressure angle over the turn, and the cam with its follower at drawing_angle_deg); `pdf` "
                      "for the design record (title block with the request's SHA-256, the cam's figures, the "
                      "checks, every input, then the figure); "
                      "`csv` for the point table, one row per cam angle with units in the column names; `dxf` "
                      "for the profile as a closed polyline within chord_tolerance_m, with the pitch curve and "
                      "the base circle, in millimetres. An `Accept` header chooses the same way."),
]


@router.post("/analysis", response_model=CamAnalysisOut, responses=format_responses(FORMATS))
async def cam_analysis(body: CamAnalysisIn, request: Request, solvers: AnswerSolverDep,
                       format: CamFormat = None) -> Response:
    """A disc cam over one turn: the follower's s, v, a and jerk (per radian and at speed), the pitch curve and
    profile, pressure angle and radius of curvature, and with `loads` the contact force, the spring (designed
    when not given) and the driving torque. Checks: pressure angle and curvature recomputed from the point table,
    the laws' derivatives by finite differences and their peaks against the textbooks, the torque by virtual
    power. Undercut (a roller larger than the least radius of curvature) and segments that do not close the turn
    answer 422 naming the field."""
    return await solvers.answer_plan(analysis_plan(body, solvers.limits), request, format)


@router.post("/synthesis", response_model=CamSynthesisOut, responses=format_responses(FORMATS))
async def cam_synthesis(body: CamSynthesisIn, request: Request, solvers: AnswerSolverDep,
                        format: CamFormat = None) -> Response:
    """The least base circle (and the best offset, given its range) for the largest pressure angles in rise and
    return and the least radius of curvature, by an exhaustive scan and bisection that certifies every smaller
    radius infeasible; the active constraint is named and the least cam analysed. Limits no radius within
    `base_radius_bounds_m` can meet answer 422 `infeasible` naming the constraint."""
    return await solvers.answer_plan(synthesis_plan(body, solvers.limits), request, format)


@router.get("/laws", response_model=list[MotionLawOut])
def cam_laws() -> list[MotionLawOut]:
    """The standard motion laws with their peak velocity, acceleration and jerk coefficients (peak = C h/beta^k),
    computed from the closed forms, beside the textbooks' acceleration coefficient."""
    return [motion_law_out(c) for c in synth.cams.standard_laws()]
