"""POST /v1/strength: a linkage's bars sized for the cycle's forces, their masses fed back to a fixed point."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import Response

from ..deps import AnswerSolverDep
from ..execution.plans import strength_plan
from mechsynth_client.schemas.strength import StrengthSizingIn, StrengthSizingOut

router = APIRouter(tags=["strength"])


@router.post("/strength", response_model=StrengthSizingOut)
async def strength(body: StrengthSizingIn, request: Request, solvers: AnswerSolverDep) -> Response:
    """Each bar of the linkage as a beam under its joint reactions, torques and its own weight and inertia at
    every crank angle: the least section of its shape meeting the static (von Mises), fatigue (modified Goodman
    with Marin factors) and buckling (Euler/Johnson, in and out of the plane) checks; the sized masses go back
    into the analysis until no section changes. 422 `infeasible` names the link, the check and the crank angle
    where even the largest section fails."""
    return await solvers.answer_plan(strength_plan(body, solvers.limits), request, None)
