"""POST /v1/flywheel: flywheel sizing for a target coefficient of speed fluctuation; GET /v1/machine-types."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import Response

import synth
from synth.exports import flywheel_export

from ..deps import SettingsDep, SolverGateDep
from ..media import FIGURES, FormatQuery, format_responses, json_response, media, negotiate
from ..schemas.flywheel import FlywheelIn, FlywheelOut, MachineTypeOut

router = APIRouter(tags=["flywheel"])
FORMATS = (*FIGURES, "csv")


@router.get("/machine-types", response_model=list[MachineTypeOut])
def machine_types() -> list[MachineTypeOut]:
    """The seeds' table of admissible delta per machine type; a request naming one gets its tightest value."""
    return [MachineTypeOut.from_engine(row) for row in synth.machine_types()]


@router.post("/flywheel", response_model=FlywheelOut, responses=format_responses(FORMATS))
def flywheel(
    body: FlywheelIn, request: Request, settings: SettingsDep, gate: SolverGateDep, format: FormatQuery = None
) -> Response:
    """Smallest flywheel for a target delta by the exact (Wittenbauer), Mertsalov and energy methods, and with
    a motor characteristic as a collocation NLP; each checked by integrating the equation of motion. With
    ``?format=png|svg|pdf`` the energy-mass diagram with its tangents (the excess-work curve for a constant
    reduced inertia) and the speed over the cycle; ``csv`` the cycle and every method's speed per crank angle."""
    mean_speed, delta = body.mean_speed(), body.target_delta()
    analysis = None
    if body.uses_tables():
        assert body.tables is not None
        cycle = body.tables.to_cycle(body.cycle_deg, settings.max_samples)
    else:
        analysis = synth.analyse(body.to_linkage(), mean_speed, samples=body.samples, max_samples=settings.max_samples)
        cycle = synth.cycle_from_reduced(analysis.reduced)
    result = gate.run(
        synth.size_flywheel,
        cycle,
        mean_speed,
        delta,
        constant_inertia=body.constant_inertia_kgm2,
        motor=None if body.motor is None else body.motor.to_engine(),
        geometry=None if body.geometry is None else body.geometry.to_engine(),
        time_limit_s=settings.solver_time_limit_s,
    )
    fmt = negotiate(request, format, FORMATS)
    if fmt != "json":
        return media(flywheel_export(result, fmt), fmt, "flywheel")
    warnings = synth.check_flywheel(result, None if body.geometry is None else body.geometry.to_engine(), analysis)
    return json_response(FlywheelOut.from_engine(result, warnings))
