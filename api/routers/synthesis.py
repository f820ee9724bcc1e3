"""/v1/synthesis/*: linkages from what the machine must do (swing or stroke and time ratio, or a path)."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import Response

import synth
from synth.synthesis.plots import extremes_png, path_png

from ..deps import SettingsDep, SolverGateDep
from ..media import PNG_RESPONSES, FormatQuery, png, wants_png
from ..schemas.synthesis import (
    CrankRockerIn,
    CrankRockerOut,
    PathIn,
    PathOut,
    SliderCrankSynthesisIn,
    SliderCrankSynthesisOut,
)

router = APIRouter(prefix="/synthesis", tags=["synthesis"])


@router.post("/crank-rocker", response_model=CrankRockerOut, responses=PNG_RESPONSES)
def crank_rocker(body: CrankRockerIn, request: Request, gate: SolverGateDep,
                 format: FormatQuery = None) -> CrankRockerOut | Response:
    """The crank-rocker with the requested rocker swing and time ratio that is best (largest minimum
    transmission angle, or least peak driving torque / RMS shaking force) over its whole one-parameter family,
    with the certificate of that, and the swing, time ratio and transmission angles recomputed by the engine.
    `?format=png` draws both dead-centre positions."""
    result = gate.run(synth.synthesise_crank_rocker, body.to_spec())
    if wants_png(request, format):
        return png(extremes_png(result.linkage, result.check, "crank-rocker"))
    return CrankRockerOut.from_engine(result, body.omega_rad_s)


@router.post("/slider-crank", response_model=SliderCrankSynthesisOut, responses=PNG_RESPONSES)
def slider_crank(body: SliderCrankSynthesisIn, request: Request, gate: SolverGateDep,
                 format: FormatQuery = None) -> SliderCrankSynthesisOut | Response:
    """The offset slider-crank with the requested stroke and time ratio that is best over its whole
    one-parameter family, with its certificate and the engine's check. `?format=png` draws both dead centres."""
    result = gate.run(synth.synthesise_slider_crank, body.to_spec())
    if wants_png(request, format):
        return png(extremes_png(result.linkage, result.check, "offset slider-crank"))
    return SliderCrankSynthesisOut.from_engine(result, body.omega_rad_s)


@router.post("/path", response_model=PathOut, responses=PNG_RESPONSES)
def path(body: PathIn, request: Request, settings: SettingsDep, gate: SolverGateDep,
         format: FormatQuery = None) -> PathOut | Response:
    """A crank-rocker four-bar whose coupler point passes through (or nearest to) the target points: multistart
    IPOPT from seeded Sobol starts, the best of all starts with the residual at every point recomputed by the
    analysis engine. `?format=png` draws the coupler curve through the targets."""
    spec = body.to_spec(settings.solver_time_limit_s)
    result = gate.run(synth.synthesise_path, spec)
    if wants_png(request, format):
        return png(path_png(result, spec.targets))
    return PathOut.from_engine(result)
