"""/v1/balancing/*: counterweights for four-bars (static, full, optimal), rotors and slider-cranks."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import Response

import synth
from synth.exports import balance_export

from ..deps import SolverDep
from ..media import FIGURES, FormatQuery, file_headers, format_responses, render_for
from ..schemas.balancing import (
    BalanceIn,
    BalanceOut,
    FullBalanceIn,
    OptimalBalanceIn,
    OptimalBalanceOut,
    RotorIn,
    RotorOut,
    SliderCrankBalanceIn,
    SliderCrankBalanceOut,
)
from ..tasks import optimal_file

router = APIRouter(prefix="/balancing", tags=["balancing"])
FORMATS = (*FIGURES, "csv", "dxf")
RESPONSES = format_responses(FORMATS)


@router.post("/static", response_model=BalanceOut, responses=RESPONSES)
async def balance_static(body: BalanceIn, request: Request, solvers: SolverDep,
                         format: FormatQuery = None) -> Response:
    """Counterweights that make the shaking force identically zero, at least added mass (or inertia)."""
    render = render_for(request, format, FORMATS, BalanceOut.from_engine, balance_export)
    return await solvers.answer(
        render, synth.balance_static, body.to_linkage(), body.omega_rad_s, body.spec(), samples=body.samples,
        objective=body.objective, mass_budget=body.mass_budget_kg, time_limit_s=solvers.settings.solver_time_limit_s,
        method=body.method, headers=file_headers(render.fmt, "balance_static"),
    )


@router.post("/full", response_model=BalanceOut, responses=RESPONSES)
async def balance_full(body: FullBalanceIn, request: Request, solvers: SolverDep,
                       format: FormatQuery = None) -> Response:
    """Shaking force and moment identically zero: counterweights, a pendulum coupler and counter-rotors."""
    render = render_for(request, format, FORMATS, BalanceOut.from_engine, balance_export)
    return await solvers.answer(
        render, synth.balance_full, body.to_linkage(), body.omega_rad_s, body.spec(), samples=body.samples,
        ratios=body.rotor_ratios, time_limit_s=solvers.settings.solver_time_limit_s,
        headers=file_headers(render.fmt, "balance_full"),
    )


@router.post("/optimal", response_model=OptimalBalanceOut, responses=RESPONSES)
async def balance_optimal(body: OptimalBalanceIn, request: Request, solvers: SolverDep,
                          format: FormatQuery = None) -> Response:
    """The best weighted trade-off of shaking force, moment, driving torque and bearing forces within a mass
    budget (one SOCP), and the trade-off curve over `sweep`."""
    weight_sets = [w.to_engine() for w in [body.weights, *body.sweep]]
    render = render_for(request, format, FORMATS, OptimalBalanceOut.from_results, optimal_file)
    return await solvers.answer(
        render, synth.tradeoff, body.to_linkage(), body.omega_rad_s, body.spec(), weight_sets,
        mass_budget=body.mass_budget_kg, samples=body.samples, time_limit_s=solvers.settings.solver_time_limit_s,
        weight_scale=body.weight_scale, headers=file_headers(render.fmt, "balance_optimal"),
    )


@router.post("/rotor", response_model=RotorOut)
async def balance_rotor(body: RotorIn, solvers: SolverDep) -> RotorOut:
    """Correction masses for a rotor: one plane (static) or two planes (dynamic)."""
    rotor = body.to_engine()
    if body.mode == "static":
        result = await solvers.run(synth.balance_rotor_static, rotor, body.correction_radius_m,
                                   body.correction_plane_m)
    else:
        result = await solvers.run(synth.balance_rotor_dynamic, rotor, (body.planes_m[0], body.planes_m[1]),
                                   (body.radii_m[0], body.radii_m[1]))
    return RotorOut.from_engine(result, synth.check_rotor(rotor, result))


@router.post("/slider-crank", response_model=SliderCrankBalanceOut)
async def balance_slider_crank(body: SliderCrankBalanceIn, request: Request, solvers: SolverDep) -> Response:
    """Crank counterweight for the rotating masses, Lanchester pairs for the reciprocating ones."""
    linkage = body.to_linkage()
    return await solvers.answer(
        render_for(request, None, (), SliderCrankBalanceOut.from_engine, model_extra=(synth.check_linkage(linkage),)),
        synth.balance_slider_crank, linkage, body.omega_rad_s, counterweight_radius=body.counterweight_radius_m,
        balancer_radii=(body.balancer_radii_m[0], body.balancer_radii_m[1]), orders=body.orders,
        samples=body.samples,
    )
