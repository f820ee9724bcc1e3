"""Drive design: POST /v1/gears/split, /v1/gears/teeth, /v1/gears/drive; the stage-type table and motor catalogue."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import Response

import synth

from ..deps import SolverDep
from ..media import render_for
from ..schemas.gearing import (
    DriveIn,
    DriveOut,
    MotorOut,
    SplitIn,
    SplitOut,
    StageTypeOut,
    TeethIn,
    TeethOut,
)

router = APIRouter(prefix="/gears", tags=["gearing"])


@router.post("/split", response_model=SplitOut)
async def gears_split(body: SplitIn, request: Request, solvers: SolverDep) -> Response:
    """Split the total ratio between the stages: minimum reduced inertia or gear volume (geometric programs,
    global optimum), or the two-stage handbook rule; optionally snapped to R20 ratios."""
    stages = synth.make_stages(body.stage_specs(), max_stages=solvers.settings.max_stages)
    return await solvers.answer(
        render_for(request, None, (), SplitOut.from_engine, model_extra=(stages,)),
        synth.split_ratio, body.ratio(), stages, body.objective,
        inertia=body.inertia_model(body.motor_inertia_kgm2), input_torque=body.input_torque_Nm,
        handbook_factor=body.handbook_factor, snap_r20=body.snap_r20, snap_tolerance=body.snap_tolerance,
        time_limit_s=solvers.settings.solver_time_limit_s,
    )


@router.post("/teeth", response_model=TeethOut)
async def gears_teeth(body: TeethIn, request: Request, solvers: SolverDep) -> Response:
    """Integer tooth numbers whose train ratio is closest to the target (or within a tolerance with the fewest
    teeth), by an exact exhaustive search; undercut, interference, hunting teeth and reverted layouts."""
    stages = synth.make_stages(body.stage_specs(), max_stages=solvers.settings.max_stages)
    return await solvers.answer(render_for(request, None, (), TeethOut.from_engine),
                                synth.tooth_numbers, body.total_ratio, stages, body.rules(), body.tolerance,
                                planets=body.planets)


@router.post("/drive", response_model=DriveOut)
async def gears_drive(body: DriveIn, request: Request, solvers: SolverDep) -> Response:
    """Choose the motor from the catalogue, split the ratio and report every shaft's speed, power, torque and
    inertia reduced to the motor shaft."""
    stages = synth.make_stages(body.stage_specs(), max_stages=solvers.settings.max_stages)
    return await solvers.answer(
        render_for(request, None, (), DriveOut.from_engine, model_extra=(stages,)),
        synth.design_drive, body.output_power_W, body.output_speed(), stages,
        reserve_factor=body.reserve_factor, drive_efficiency=body.drive_efficiency,
        synchronous_speed=body.synchronous_speed(), motor=body.motor, objective=body.objective,
        torque_basis=body.torque_basis, inertia=body.inertia_model(), snap_r20=body.snap_r20,
        snap_tolerance=body.snap_tolerance, time_limit_s=solvers.settings.solver_time_limit_s,
        catalogue=body.catalogue(),
    )


@router.get("/stage-types", response_model=list[StageTypeOut])
def gears_stage_types() -> list[StageTypeOut]:
    """The shipped stage-type table: admissible ratio ranges, efficiencies, sizing constants."""
    return [StageTypeOut.from_engine(t) for t in synth.stage_types().values()]


@router.get("/motors", response_model=list[MotorOut])
def gears_motors() -> list[MotorOut]:
    """The shipped motor catalogue, ascending in rated power."""
    return [MotorOut.from_engine(m) for m in synth.motor_catalogue()]
