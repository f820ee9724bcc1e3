"""Disc cams: POST /v1/cams/analysis, POST /v1/cams/synthesis (the least cam), GET /v1/cams/laws."""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Annotated, Literal

from fastapi import APIRouter, Query, Request
from fastapi.responses import Response

import synth.cams

from ..deps import SolverDep
from synth.machine.record import DesignRecord, input_rows

from ..execution.plans import SERVICE_VERSION, Limits, Plan
from ..media import FIGURES, Render, format_responses
from mechsynth_client.schemas.cams import (
    CamAnalysisIn,
    CamAnalysisOut,
    CamSynthesisIn,
    CamSynthesisOut,
    MotionLawOut,
)

router = APIRouter(prefix="/cams", tags=["cams"])
FORMATS = (*FIGURES, "csv", "dxf")
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


def record_title(body: CamAnalysisIn | CamSynthesisIn, name: str) -> synth.cams.RecordTitle:
    """The design record's title block for a request: now, this service, the request's hash and its inputs."""
    record = DesignRecord.of(body.model_dump(mode="json", exclude_none=True), name=name, version=SERVICE_VERSION)
    return synth.cams.RecordTitle(record.name, record.created, record.version, record.request_sha256,
                                  tuple(input_rows(record.request)))


def synthesis_export(result: synth.cams.CamSynthesis, fmt: str, at: float, tolerance: float,
                     title: synth.cams.RecordTitle) -> bytes:
    """The least cam's figure, point table, drawing or design record (with the search's certificate)."""
    lc = result.least
    least = (f"base radius {lc.base_radius * 1e3:.6g} mm at offset {lc.offset * 1e3:.5g} mm; active limit: "
             f"{lc.active}", lc.statement)
    return synth.cams.cam_export(result.analysis, fmt, at, tolerance,
                                 replace(title, least=least))


def analysis_plan(b: CamAnalysisIn, lim: Limits) -> Plan:
    """POST /v1/cams/analysis."""
    return Plan(Render(CamAnalysisOut.from_engine, synth.cams.cam_export,
                       export_extra=(math.radians(b.drawing_angle_deg), b.chord_tolerance_m,
                                     record_title(b, "disc cam"))),
                synth.cams.analyse_cam, (b.spec(),), dict(max_samples=lim.max_samples), FORMATS, "cam")


def synthesis_plan(b: CamSynthesisIn, lim: Limits) -> Plan:
    """POST /v1/cams/synthesis."""
    return Plan(Render(CamSynthesisOut.from_engine, synthesis_export,
                       export_extra=(math.radians(b.drawing_angle_deg), b.chord_tolerance_m,
                                     record_title(b, "least disc cam"))),
                synth.cams.synthesise_cam, (b.to_spec(), b.limits()), dict(max_samples=lim.max_samples), FORMATS,
                "least-cam")


@router.post("/analysis", response_model=CamAnalysisOut, responses=format_responses(FORMATS))
async def cam_analysis(body: CamAnalysisIn, request: Request, solvers: SolverDep,
                       format: CamFormat = None) -> Response:
    """A disc cam over one turn: the follower's s, v, a and jerk (per radian and at speed), the pitch curve and
    profile, pressure angle and radius of curvature, and with `loads` the contact force, the spring (designed
    when not given) and the driving torque. Checks: pressure angle and curvature recomputed from the point table,
    the laws' derivatives by finite differences and their peaks against the textbooks, the torque by virtual
    power. Undercut (a roller larger than the least radius of curvature) and segments that do not close the turn
    answer 422 naming the field."""
    return await solvers.answer_plan(analysis_plan(body, solvers.limits), request, format)


@router.post("/synthesis", response_model=CamSynthesisOut, responses=format_responses(FORMATS))
async def cam_synthesis(body: CamSynthesisIn, request: Request, solvers: SolverDep,
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
    return [MotionLawOut.from_engine(c) for c in synth.cams.standard_laws()]
