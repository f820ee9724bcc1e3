"""POST /v1/analysis: kinematics and kinetostatics of a linkage over one cycle."""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Query, Request
from fastapi.responses import Response

import synth
from synth.exports import analysis_export, mechanism_dxf, mechanism_svg

from ..deps import SettingsDep
from ..media import FIGURES, FormatQuery, format_responses, json_response, media, negotiate
from ..schemas.analysis import AnalysisIn, AnalysisOut, plot_angle

router = APIRouter(tags=["analysis"])
FORMATS = (*FIGURES, "csv", "dxf")
AngleQuery = Annotated[float | None, Query(ge=-1e6, le=1e6, description="Crank angle of the mechanism drawing [deg].")]


@router.post("/analysis", response_model=AnalysisOut, responses=format_responses(FORMATS))
def analysis(
    body: AnalysisIn,
    request: Request,
    settings: SettingsDep,
    format: FormatQuery = None,
    angle_deg: AngleQuery = None,
) -> Response:
    """Positions, velocities, accelerations, joint reactions, driving torque, shaking force and moment,
    and the reduced model of a linkage over one crank revolution, with the virtual-power check.

    ``?format=png|svg|pdf``: driving torque, shaking moment, shaking force polar diagram and the mechanism at
    ``angle_deg``; ``csv``: every curve, one row per crank angle; ``dxf``: the mechanism drawing at ``angle_deg``."""
    result = synth.analyse(
        body.to_linkage(),
        body.omega_rad_s,
        samples=body.samples,
        phi=body.phi(),
        crank_acceleration=body.crank_acceleration_rad_s2,
        max_samples=settings.max_samples,
        points=body.trace(),
    )
    fmt = negotiate(request, format, FORMATS)
    if fmt != "json":
        return media(analysis_export(result, plot_angle(body, angle_deg), fmt), fmt, "analysis")
    return json_response(AnalysisOut.from_engine(result))


@router.post("/analysis/drawing", response_class=Response, responses=format_responses(("dxf", "svg")))
def drawing(
    body: AnalysisIn,
    settings: SettingsDep,
    format: Annotated[Literal["dxf", "svg"], Query(description="`dxf` for CAD, `svg` for the same drawing to view.")]
    = "dxf",
    angle_deg: AngleQuery = None,
) -> Response:
    """The mechanism at ``angle_deg`` drawn to scale in millimetres, for CAD (DXF) or a browser (SVG): frame
    pivots and guides, links, blocks, the crank circle, counterweights with their mass, radius and angle, centres
    of mass and the paths of the trace points over the cycle."""
    result = synth.analyse(body.to_linkage(), body.omega_rad_s, samples=body.samples, phi=body.phi(),
                           max_samples=settings.max_samples, points=body.trace())
    draw = mechanism_dxf if format == "dxf" else mechanism_svg
    return media(draw(result, plot_angle(body, angle_deg)), format, "mechanism")
