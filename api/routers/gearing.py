"""Drive design: POST /v1/gears/split, /teeth, /drive, /rating; the stage-type table, motor catalogue and gear
materials."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import Response

import synth

from ..execution import plans
from ..deps import AnswerSolverDep
from api.translate.gearing import motor_out, stage_type_out
from api.translate.rating import gear_material_out
from mechsynth_client.schemas.gearing import (
    DriveIn,
    DriveOut,
    MotorOut,
    SplitIn,
    SplitOut,
    StageTypeOut,
    TeethIn,
    TeethOut,
)
from mechsynth_client.schemas.rating import GearMaterialOut, RatingIn, RatingOut

router = APIRouter(prefix="/gears", tags=["gearing"])


@router.post("/split", response_model=SplitOut)
async def gears_split(body: SplitIn, request: Request, solvers: AnswerSolverDep) -> Response:
    """Split the total ratio between the stages: minimum reduced inertia or gear volume (geometric programs,
    global optimum), or the two-stage handbook rule; optionally snapped to R20 ratios."""
    return await solvers.answer_plan(plans.gears_split(body, solvers.limits), request)


@router.post("/teeth", response_model=TeethOut)
async def gears_teeth(body: TeethIn, request: Request, solvers: AnswerSolverDep) -> Response:
    """Integer tooth numbers whose train ratio is closest to the target (or within a tolerance with the fewest
    teeth), by an exact exhaustive search; undercut, interference, hunting teeth and reverted layouts."""
    return await solvers.answer_plan(plans.gears_teeth(body, solvers.limits), request)


@router.post("/drive", response_model=DriveOut)
async def gears_drive(body: DriveIn, request: Request, solvers: AnswerSolverDep) -> Response:
    """Choose the motor from the catalogue, split the ratio and report every shaft's speed, power, torque and
    inertia reduced to the motor shaft."""
    return await solvers.answer_plan(plans.gears_drive(body, solvers.limits), request)


@router.post("/rating", response_model=RatingOut)
async def gears_rating(body: RatingIn, request: Request, solvers: AnswerSolverDep) -> Response:
    """Load capacity of an external spur or helical pair by ISO 6336 method B: contact and root stresses,
    their limits and the safety factors per wheel with every factor named; on a load spectrum, the life by
    Miner's rule."""
    return await solvers.answer_plan(plans.gears_rating(body, solvers.limits), request)


@router.get("/materials", response_model=list[GearMaterialOut])
def gears_materials() -> list[GearMaterialOut]:
    """The shipped gear material grades with their ISO 6336-5 allowable stress numbers."""
    return [gear_material_out(m) for m in synth.gear_materials().values()]


@router.get("/stage-types", response_model=list[StageTypeOut])
def gears_stage_types() -> list[StageTypeOut]:
    """The shipped stage-type table: admissible ratio ranges, efficiencies, sizing constants."""
    return [stage_type_out(t) for t in synth.stage_types().values()]


@router.get("/motors", response_model=list[MotorOut])
def gears_motors() -> list[MotorOut]:
    """The shipped motor catalogue, ascending in rated power."""
    return [motor_out(m) for m in synth.motor_catalogue()]
