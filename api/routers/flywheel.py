"""POST /v1/flywheel: flywheel sizing for a target coefficient of speed fluctuation; GET /v1/machine-types."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter, Request
from fastapi.responses import Response

import synth

from ..deps import SolverDep
from ..media import FIGURES, FormatQuery, file_headers, format_responses, render_for
from ..schemas.flywheel import FlywheelIn, FlywheelOut, MachineTypeOut
from ..tasks import flywheel_file, flywheel_for_linkage, flywheel_from_tables, flywheel_out

router = APIRouter(tags=["flywheel"])
FORMATS = (*FIGURES, "csv")


@router.get("/machine-types", response_model=list[MachineTypeOut])
def machine_types() -> list[MachineTypeOut]:
    """The seeds' table of admissible delta per machine type; a request naming one gets its tightest value."""
    return [MachineTypeOut.from_engine(row) for row in synth.machine_types()]


@router.post("/flywheel", response_model=FlywheelOut, responses=format_responses(FORMATS))
async def flywheel(body: FlywheelIn, request: Request, solvers: SolverDep, format: FormatQuery = None) -> Response:
    """Smallest flywheel for a target delta by the exact (Wittenbauer), Mertsalov and energy methods, and with
    a motor characteristic as a collocation NLP; each checked by integrating the equation of motion. With
    ``?format=png|svg|pdf`` the energy-mass diagram with its tangents (the excess-work curve for a constant
    reduced inertia) and the speed over the cycle; ``csv`` the cycle and every method's speed per crank angle."""
    settings = solvers.settings
    mean_speed, delta = body.mean_speed(), body.target_delta()
    geometry = None if body.geometry is None else body.geometry.to_engine()
    sizing: dict[str, Any] = dict(
        constant_inertia=body.constant_inertia_kgm2,
        motor=None if body.motor is None else body.motor.to_engine(),
        time_limit_s=settings.solver_time_limit_s,
    )
    render = render_for(request, format, FORMATS, flywheel_out, flywheel_file)
    headers = file_headers(render.fmt, "flywheel")
    if body.uses_tables():
        assert body.tables is not None
        cycle = body.tables.to_cycle(body.cycle_deg, settings.max_samples)
        return await solvers.answer(render, flywheel_from_tables, cycle, mean_speed, delta, geometry,
                                    headers=headers, **sizing)
    return await solvers.answer(render, flywheel_for_linkage, body.to_linkage(), mean_speed, body.samples,
                                settings.max_samples, delta, geometry, headers=headers, **sizing)
