"""/v1/balancing/*: counterweights (four-bars static, full, optimal; slider-cranks and shapers optimal), rotors and
slider-cranks' Lanchester balancing."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import Response


from ..execution import plans
from ..deps import AnswerSolverDep
from ..media import FIGURES, FormatQuery, format_responses
from mechsynth_client.schemas.engines import EngineIn, EngineOut
from mechsynth_client.schemas.balancing import (
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


@router.post("/static", response_model=BalanceOut, responses=RESPONSES)
async def balance_static(body: BalanceIn, request: Request, solvers: AnswerSolverDep,
                         format: FormatQuery = None) -> Response:
    """Counterweights that make the shaking force identically zero, at least added mass (or inertia)."""
    return await solvers.answer_plan(plans.balance_static(body, solvers.limits), request, format)


@router.post("/full", response_model=BalanceOut, responses=RESPONSES)
async def balance_full(body: FullBalanceIn, request: Request, solvers: AnswerSolverDep,
                       format: FormatQuery = None) -> Response:
    """Shaking force and moment identically zero: counterweights, a pendulum coupler and counter-rotors."""
    return await solvers.answer_plan(plans.balance_full(body, solvers.limits), request, format)


@router.post("/optimal", response_model=OptimalBalanceOut, responses=RESPONSES)
async def balance_optimal(body: OptimalBalanceIn, request: Request, solvers: AnswerSolverDep,
                          format: FormatQuery = None) -> Response:
    """The best weighted trade-off of shaking force, moment, driving torque and bearing forces within a mass
    budget (one SOCP), and the trade-off curve over `sweep`: four-bars, slider-cranks and shapers."""
    return await solvers.answer_plan(plans.balance_optimal(body, solvers.limits), request, format)


@router.post("/rotor", response_model=RotorOut)
async def balance_rotor(body: RotorIn, request: Request, solvers: AnswerSolverDep) -> Response:
    """Correction masses for a rotor: one plane (static) or two planes (dynamic)."""
    return await solvers.answer_plan(plans.balance_rotor(body, solvers.limits), request)


@router.post("/slider-crank", response_model=SliderCrankBalanceOut, responses=format_responses(FIGURES))
async def balance_slider_crank(body: SliderCrankBalanceIn, request: Request, solvers: AnswerSolverDep,
                               format: FormatQuery = None) -> Response:
    """Crank counterweight for the rotating masses, Lanchester pairs on the slide axis for the reciprocating
    ones, in-line or offset."""
    return await solvers.answer_plan(plans.balance_slider_crank(body, solvers.limits), request, format)


@router.post("/engine", response_model=EngineOut)
async def balance_engine(body: EngineIn, request: Request, solvers: AnswerSolverDep) -> Response:
    """Shaking force and moment (about the transverse axes) of an engine of several cylinders, in line or in V,
    by crank orders from the exact slider-crank acceleration; which orders the arrangement cancels, and the
    counterweight and balance-shaft masses (shafts at ±k·w) that cancel the rest, with their check."""
    return await solvers.answer_plan(plans.balance_engine(body, solvers.limits), request)
