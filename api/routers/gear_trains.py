"""POST /v1/gears/train: ratio, shaft senses and speeds, efficiency and pitch diameters of a given train."""

from __future__ import annotations

from fastapi import APIRouter

import synth

from ..schemas.train import TrainIn, TrainOut

router = APIRouter(prefix="/gears", tags=["gearing"])


@router.post("/train", response_model=TrainOut)
def train(body: TrainIn) -> TrainOut:
    """A given serial train of simple, compound and idler meshes and planetary (Willis) stages, from its tooth
    numbers: the ratio with its sign, every shaft's sense and speed, the efficiency and d = m·z of every wheel."""
    result = synth.gear_train(body.to_engine(), module=body.module_m, input_speed=body.input_speed_rad_s,
                              output_speed=body.output_speed_rad_s)
    return TrainOut.from_engine(result)
