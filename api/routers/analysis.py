"""POST /v1/analysis: kinematics and kinetostatics of a linkage over one cycle; its drawing for CAD."""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Query, Request
from fastapi.responses import Response


from ..execution import plans
from ..deps import AnswerSolverDep, SolverDep
from ..media import ARRAYS, FIGURES, FormatQuery, format_responses, media
from api.translate.analysis import plot_angle
from api.translate.linkage import crank_angles, linkage_from
from mechsynth_client.schemas.analysis import AnalysisIn, AnalysisOut
from ..execution.tasks import mechanism_drawing

router = APIRouter(tags=["analysis"])
FORMATS = (*FIGURES, "csv", "dxf", *ARRAYS)
AngleQuery = Annotated[float | None, Query(ge=-1e6, le=1e6, description="Crank angle of the mechanism drawing [deg].")]


@router.post("/analysis", response_model=AnalysisOut, responses=format_responses(FORMATS))
async def analysis(
    body: AnalysisIn,
    request: Request,
    solvers: AnswerSolverDep,
    format: FormatQuery = None,
    angle_deg: AngleQuery = None,
) -> Response:
    """Positions, velocities, accelerations, joint reactions, driving torque, shaking force and moment,
    and the reduced model of a linkage over one crank revolution, with the virtual-power check.

    ``?format=png|svg|pdf``: driving torque, shaking moment, shaking force polar diagram and the mechanism at
    ``angle_deg``; ``csv``: every curve, one row per crank angle; ``dxf``: the mechanism drawing at ``angle_deg``;
    ``npz``: every number of the JSON answer as NumPy arrays keyed by their JSON path."""
    return await solvers.answer_plan(plans.analysis(body, solvers.limits, angle_deg), request, format)


@router.post("/analysis/drawing", response_class=Response, responses=format_responses(("dxf", "svg")))
async def analysis_drawing(
    body: AnalysisIn,
    solvers: SolverDep,
    format: Annotated[Literal["dxf", "svg"], Query(description="`dxf` for CAD, `svg` for the same drawing to view.")]
    = "dxf",
    angle_deg: AngleQuery = None,
) -> Response:
    """The mechanism at ``angle_deg`` drawn to scale in millimetres, for CAD (DXF) or a browser (SVG): frame
    pivots and guides, links, blocks, the crank circle, counterweights with their mass, radius and angle, centres
    of mass and the paths of the trace points over the cycle."""
    content = await solvers.run(mechanism_drawing, linkage_from(body), body.omega_rad_s, body.samples, crank_angles(body),
                                solvers.settings.max_samples, body.trace(), plot_angle(body, angle_deg), format)
    return media(content, format, "mechanism")
