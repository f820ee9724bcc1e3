"""POST /v1/structure: mobility, redundant constraints and Assur groups of a mechanism given as links and pairs."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import Response


from ..execution import plans
from ..deps import AnswerSolverDep
from mechsynth_client.schemas.structure import StructureIn, StructureOut

router = APIRouter(tags=["structure"])


@router.post("/structure", response_model=StructureOut)
async def structure(body: StructureIn, request: Request, solvers: AnswerSolverDep) -> Response:
    """Pair classes, mobility by Somov-Malyshev (and Chebyshev when planar), redundant constraints, and for a
    planar linkage the primary mechanism and the Assur groups with their classes, in the order they are added."""
    return await solvers.answer_plan(plans.structure(body, solvers.limits), request)
