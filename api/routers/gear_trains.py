"""POST /v1/gears/train: ratio, shaft senses and speeds, efficiency and pitch diameters of a given train."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import Response


from ..execution import plans
from ..deps import AnswerSolverDep
from mechsynth_client.schemas.train import TrainIn, TrainOut

router = APIRouter(prefix="/gears", tags=["gearing"])


@router.post("/train", response_model=TrainOut)
async def gears_train(body: TrainIn, request: Request, solvers: AnswerSolverDep) -> Response:
    """A given serial train of simple, compound and idler meshes and planetary (Willis) stages, from its tooth
    numbers: the ratio with its sign, every shaft's sense and speed, the efficiency and d = m·z of every wheel."""
    return await solvers.answer_plan(plans.gears_train(body, solvers.limits), request)
