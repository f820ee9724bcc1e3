"""POST /v1/machines/isolation: the machine on its foundation, with the isolators' design and the elastic drive and
speed regulation beside it."""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Query, Request
from fastapi.responses import Response

from synth.errors import InvalidInput
from synth.machine import foundation as fd
from synth.machine.foundation_plots import isolation_figure

from ..deps import SolverDep
from ..execution.plans import Limits, Plan
from ..media import FIGURES, Render, format_responses
from mechsynth_client.schemas.foundation import IsolationIn, IsolationOut

router = APIRouter(prefix="/machines", tags=["machines"])

FigureFormat = Annotated[
    Literal["json", "png", "svg", "pdf"] | None,
    Query(description="Answer format: `json` (default); `png`, `svg` or `pdf` for the figure. An `Accept` header "
                      "(image/png, image/svg+xml, application/pdf) chooses the same way."),
]


def isolation_plan(b: IsolationIn, lim: Limits) -> Plan:
    """POST /v1/machines/isolation."""
    frame, isolators = b.to_frame()
    return Plan(Render(IsolationOut.from_engine, isolation_figure), fd.isolate_linkage,
                (b.to_linkage(), b.omega_rad_s, frame, isolators),
                dict(samples=b.samples, max_samples=lim.max_samples, counter_rotors=b.rotors()),
                FIGURES, "isolation")


@router.post("/isolation", response_model=IsolationOut, responses=format_responses(FIGURES),
             name="isolate_machine")
async def isolation(body: IsolationIn, request: Request, solvers: SolverDep, format: FigureFormat = None) -> Response:
    """The machine's frame on isolators, driven by the linkage's shaking force and moment over the steady cycle
    at the crank speed: natural frequencies and mode shapes, the steady motion solved exactly per harmonic, the
    force each isolator and all together pass to the foundation (as the foundation feels it), the
    transmissibility per harmonic and the frame's peak movement; checked by integrating the same equations in
    time. `?format=png|svg|pdf`: force to the foundation against the shaking force, the frame's orbit and the
    transmissibility per harmonic."""
    if body.crank_angle_deg is not None:
        raise InvalidInput("the foundation takes uniformly spaced samples over one revolution: give samples, "
                              "not crank_angle_deg", field="crank_angle_deg")
    return await solvers.answer_plan(isolation_plan(body, solvers.limits), request, format)
