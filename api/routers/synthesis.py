"""/v1/synthesis/*: linkages from what the machine must do (swing or stroke and time ratio, or a path)."""

from __future__ import annotations


from fastapi import APIRouter, Request
from fastapi.responses import Response


from synth.synthesis.path import path_starts

from ..execution import plans
from ..execution.admission import together
from ..deps import AnswerSolverDep
from ..media import PNG_RESPONSES, FormatQuery
from mechsynth_client.schemas.synthesis import (
    CrankRockerIn,
    CrankRockerOut,
    PathIn,
    PathOut,
    SliderCrankSynthesisIn,
    SliderCrankSynthesisOut,
)

router = APIRouter(prefix="/synthesis", tags=["synthesis"])
FORMATS = ("png",)


@router.post("/crank-rocker", response_model=CrankRockerOut, responses=PNG_RESPONSES)
async def synthesise_crank_rocker(body: CrankRockerIn, request: Request, solvers: AnswerSolverDep,
                       format: FormatQuery = None) -> Response:
    """The crank-rocker with the requested rocker swing and time ratio that is best (largest minimum
    transmission angle, or least peak driving torque / RMS shaking force) over its whole one-parameter family,
    with the certificate of that, and the swing, time ratio and transmission angles recomputed by the engine.
    `?format=png` draws both dead-centre positions."""
    return await solvers.answer_plan(plans.synthesis_crank_rocker(body, solvers.limits), request, format)


@router.post("/slider-crank", response_model=SliderCrankSynthesisOut, responses=PNG_RESPONSES)
async def synthesise_slider_crank(body: SliderCrankSynthesisIn, request: Request, solvers: AnswerSolverDep,
                       format: FormatQuery = None) -> Response:
    """The offset slider-crank with the requested stroke and time ratio that is best over its whole
    one-parameter family, with its certificate and the engine's check. `?format=png` draws both dead centres."""
    return await solvers.answer_plan(plans.synthesis_slider_crank(body, solvers.limits), request, format)


@router.post("/path", response_model=PathOut, responses=PNG_RESPONSES)
async def synthesise_path(body: PathIn, request: Request, solvers: AnswerSolverDep, format: FormatQuery = None) -> Response:
    """A crank-rocker four-bar whose coupler point passes through (or nearest to) the target points: every
    seeded Sobol start screened by Levenberg-Marquardt, the best distinct designs polished by IPOPT, each
    fit with the starts that reached it and the residual at every point recomputed by the analysis engine, and the
    answer's Roberts-Chebyshev cognates. `?format=png` draws the coupler curve through the targets.

    The starts are independent: many of them are screened as one task per worker, side by side, and the answer is
    the same as one run of every start in order."""
    spec, chunks = plans.synthesis_path_chunks(body, solvers.limits, solvers.solvers.workers)
    if len(chunks) == 1:
        return await solvers.answer_plan(plans.synthesis_path(body, solvers.limits), request, format)
    parts = await together(solvers.run(path_starts, spec, chunk) for chunk in chunks)
    return await solvers.answer_plan(plans.synthesis_path_best(spec, parts), request, format)
