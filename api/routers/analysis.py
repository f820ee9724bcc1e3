"""POST /v1/analysis: kinematics and kinetostatics of a linkage over one cycle."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Query, Request
from fastapi.responses import Response

import synth
from synth.plots import analysis_png

from ..deps import SolverDep
from ..media import PNG_RESPONSES, FormatQuery, render_for
from ..schemas.analysis import AnalysisIn, AnalysisOut, plot_angle

router = APIRouter(tags=["analysis"])


@router.post("/analysis", response_model=AnalysisOut, responses=PNG_RESPONSES)
async def analysis(
    body: AnalysisIn,
    request: Request,
    solvers: SolverDep,
    format: FormatQuery = None,
    angle_deg: Annotated[float | None, Query(description="Crank angle of the mechanism drawing [deg].")] = None,
) -> Response:
    """Positions, velocities, accelerations, joint reactions, driving torque, shaking force and moment,
    and the reduced model of a linkage over one crank revolution, with the virtual-power check."""
    return await solvers.answer(
        render_for(request, format, AnalysisOut.from_engine, analysis_png,
                   figure_extra=(plot_angle(body, angle_deg),)),
        synth.analyse,
        body.to_linkage(),
        body.omega_rad_s,
        samples=body.samples,
        phi=body.phi(),
        crank_acceleration=body.crank_acceleration_rad_s2,
        max_samples=solvers.settings.max_samples,
        points=body.trace(),
        counter_rotors=body.rotors(),
    )
