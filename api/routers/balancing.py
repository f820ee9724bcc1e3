"""/v1/balancing/*: counterweights for four-bars (static, full, optimal), rotors and slider-cranks."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import Response

import synth
from synth.exports import balance_export

from ..deps import SettingsDep, SolverGateDep
from ..media import FIGURES, FormatQuery, format_responses, media, negotiate
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

router = APIRouter(prefix="/balancing", tags=["balancing"])
FORMATS = (*FIGURES, "csv", "dxf")
RESPONSES = format_responses(FORMATS)


def _answer(request: Request, fmt: str | None, result: synth.BalanceResult, out: BalanceOut) -> BalanceOut | Response:
    chosen = negotiate(request, fmt, FORMATS)
    return out if chosen == "json" else media(balance_export(result, chosen), chosen, f"balance_{result.mode}")


@router.post("/static", response_model=BalanceOut, responses=RESPONSES)
def balance_static(body: BalanceIn, request: Request, settings: SettingsDep, gate: SolverGateDep,
                   format: FormatQuery = None) -> BalanceOut | Response:
    """Counterweights that make the shaking force identically zero, at least added mass (or inertia)."""
    result = gate.run(
        synth.balance_static, body.to_linkage(), body.omega_rad_s, body.spec(), samples=body.samples,
        objective=body.objective, mass_budget=body.mass_budget_kg, time_limit_s=settings.solver_time_limit_s,
    )
    return _answer(request, format, result, BalanceOut.from_engine(result))


@router.post("/full", response_model=BalanceOut, responses=RESPONSES)
def balance_full(body: FullBalanceIn, request: Request, settings: SettingsDep, gate: SolverGateDep,
                 format: FormatQuery = None) -> BalanceOut | Response:
    """Shaking force and moment identically zero: counterweights, a pendulum coupler and counter-rotors."""
    result = gate.run(
        synth.balance_full, body.to_linkage(), body.omega_rad_s, body.spec(), samples=body.samples,
        ratios=body.rotor_ratios, time_limit_s=settings.solver_time_limit_s,
    )
    return _answer(request, format, result, BalanceOut.from_engine(result))


@router.post("/optimal", response_model=OptimalBalanceOut, responses=RESPONSES)
def balance_optimal(body: OptimalBalanceIn, request: Request, settings: SettingsDep, gate: SolverGateDep,
                    format: FormatQuery = None) -> OptimalBalanceOut | Response:
    """The best weighted trade-off of shaking force, moment, driving torque and bearing forces within a mass
    budget (one SOCP), and the trade-off curve over `sweep`."""
    weight_sets = [w.to_engine() for w in [body.weights, *body.sweep]]
    results = gate.run(
        synth.tradeoff, body.to_linkage(), body.omega_rad_s, body.spec(), weight_sets,
        mass_budget=body.mass_budget_kg, samples=body.samples, time_limit_s=settings.solver_time_limit_s,
    )
    fmt = negotiate(request, format, FORMATS)
    if fmt != "json":
        return media(balance_export(results[0], fmt, sweep=results[1:]), fmt, "balance_optimal")
    out = OptimalBalanceOut(**BalanceOut.from_engine(results[0]).model_dump(),
                            tradeoff=[BalanceOut.from_engine(r) for r in results[1:]])
    return out


@router.post("/rotor", response_model=RotorOut)
def balance_rotor(body: RotorIn) -> RotorOut:
    """Correction masses for a rotor: one plane (static) or two planes (dynamic)."""
    if body.mode == "static":
        result = synth.balance_rotor_static(body.to_engine(), body.correction_radius_m, body.correction_plane_m)
    else:
        result = synth.balance_rotor_dynamic(body.to_engine(), (body.planes_m[0], body.planes_m[1]),
                                             (body.radii_m[0], body.radii_m[1]))
    return RotorOut.from_engine(result, synth.check_rotor(body.to_engine(), result))


@router.post("/slider-crank", response_model=SliderCrankBalanceOut)
def balance_slider_crank(body: SliderCrankBalanceIn) -> SliderCrankBalanceOut:
    """Crank counterweight for the rotating masses, Lanchester pairs for the reciprocating ones."""
    linkage = body.to_linkage()
    result = synth.balance_slider_crank(
        linkage, body.omega_rad_s, counterweight_radius=body.counterweight_radius_m,
        balancer_radii=(body.balancer_radii_m[0], body.balancer_radii_m[1]), orders=body.orders,
        samples=body.samples,
    )
    return SliderCrankBalanceOut.from_engine(result, synth.check_linkage(linkage))
