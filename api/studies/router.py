"""/v1/studies: design studies over any design endpoint, run in the background; progress, cancel, resume,
results (JSON pages or CSV) and the Pareto front (JSON or a scatter figure)."""

from __future__ import annotations

import asyncio
from typing import Annotated, Any, Literal

from fastapi import APIRouter, Depends, Query, Request
from fastapi.responses import Response, StreamingResponse

from ..auth.guard import NotOwner, Principal, principal
from ..deps import SolverDep
from ..media import FormatQuery, json_response, png, wants_png
from api.translate.studies import pareto_out, results_out, study_out
from mechsynth_client.schemas.studies import ParetoOut, ResultsOut, StudyIn, StudyOut
from ..problems import problem
from .runs import StudyFinished, StudyRuns, scatter_png

router = APIRouter(prefix="/studies", tags=["studies"])


def get_studies(request: Request) -> StudyRuns:
    """The app's design studies."""
    studies: StudyRuns = request.app.state.studies
    return studies


StudiesDep = Annotated[StudyRuns, Depends(get_studies)]
CallerDep = Annotated[Principal, Depends(principal)]


async def may_change(study_id: str, studies: StudiesDep, caller: CallerDep) -> None:
    """Only a study's owner or an admin may cancel or resume it (403 otherwise; with authentication off every
    caller is an admin)."""
    record = await asyncio.to_thread(studies.get, study_id)
    owner = record.spec.get("owner")
    if not caller.may_change(None if owner is None else str(owner)):
        raise NotOwner(f"study {study_id}", None if owner is None else str(owner), caller.name)


OwnerOnly = Annotated[None, Depends(may_change)]
NOT_FOUND: dict[int | str, dict[str, Any]] = {404: {
    "description": "No study has this id.",
    "content": {"application/problem+json": {"schema": {"$ref": "#/components/schemas/Problem"}}},
}}


@router.post("", status_code=202, response_model=StudyOut)
async def study(body: StudyIn, studies: StudiesDep, response: Response, caller: CallerDep) -> StudyOut:
    """Start a design study: every variant is a request to `endpoint` built from `base` with the parameters set;
    answers 202 at once with the study's id and its `Location`. Follow it with GET on that location. With
    authentication on, the study's owner is the signed-in user."""
    spec = body.model_dump(mode="json")
    if caller.name is not None:
        spec["owner"] = caller.name
    record = await asyncio.to_thread(studies.create, spec)
    out = study_out(record, await asyncio.to_thread(studies.position, record.id))
    response.headers["Location"] = out.links.self
    return out


@router.get("", response_model=list[StudyOut])
async def studies(
    studies: StudiesDep,
    offset: Annotated[int, Query(ge=0, le=100_000_000, description="Studies to skip.")] = 0,
    limit: Annotated[int, Query(ge=1, le=1000, description="Studies per page.")] = 100,
) -> list[StudyOut]:
    """The latest studies first, with their state and progress."""
    records = await asyncio.to_thread(studies.recent, limit, offset)
    places = await asyncio.to_thread(studies.positions)
    return [study_out(r, places.get(r.id)) for r in records]


@router.get("/{study_id}", response_model=StudyOut, responses=NOT_FOUND)
async def study_status(study_id: str, studies: StudiesDep) -> StudyOut:
    """State, variants done of the total, failed variants, running time and the estimated time to finish."""
    record = await asyncio.to_thread(studies.get, study_id)
    return study_out(record, await asyncio.to_thread(studies.position, study_id))


@router.delete("/{study_id}", response_model=StudyOut, responses=NOT_FOUND)
async def study_cancel(study_id: str, studies: StudiesDep, _: OwnerOnly) -> StudyOut:
    """Cancel a study: no new variant starts, running tasks are stopped, finished variants stay."""
    record = await asyncio.to_thread(studies.cancel, study_id)
    return study_out(record, await asyncio.to_thread(studies.position, study_id))


@router.post("/{study_id}/resume", status_code=202, response_model=StudyOut, responses={**NOT_FOUND, 409: {
    "description": "The study is done: every variant has its result, nothing is left to run.",
    "content": {"application/problem+json": {"schema": {"$ref": "#/components/schemas/Problem"}}}}})
async def study_resume(study_id: str, studies: StudiesDep, _: OwnerOnly) -> Any:
    """Run the variants of a cancelled, interrupted or failed study that have no result yet (a running or queued
    study is left as it is; a finished one answers 409)."""
    try:
        record = await asyncio.to_thread(studies.resume, study_id)
    except StudyFinished as exc:
        return problem(409, "study-finished", "Study finished", str(exc), study_id=study_id)
    return study_out(record, await asyncio.to_thread(studies.position, study_id))


@router.get("/{study_id}/results", response_model=ResultsOut,
            responses={200: {"content": {"text/csv": {}}, "description": "A page of variants, or all as CSV."},
                       **NOT_FOUND})
async def study_results(
    study_id: str, studies: StudiesDep,
    offset: Annotated[int, Query(ge=0, le=100_000_000, description="First variant of the page.")] = 0,
    limit: Annotated[int, Query(ge=1, le=10_000, description="Variants per page.")] = 1000,
    format: Annotated[Literal["json", "csv"] | None, Query(description="`csv`: every variant as CSV.")] = None,
) -> Response:
    """The variants in index order with their parameters and metrics, or their problem type and message."""
    if format == "csv":
        chunks = await asyncio.to_thread(studies.csv, study_id)
        return StreamingResponse(chunks, media_type="text/csv",
                                 headers={"Content-Disposition": f'attachment; filename="study-{study_id}.csv"'})
    record, rows = await asyncio.to_thread(studies.page, study_id, offset, limit)
    return json_response(results_out(record, rows, offset, limit))


@router.get("/{study_id}/pareto", response_model=ParetoOut,
            responses={200: {"content": {"image/png": {}}, "description": "The front, or with ?format=png a "
                                                                          "scatter of two metrics with it drawn."},
                       **NOT_FOUND})
async def study_pareto(
    study_id: str, request: Request, studies: StudiesDep, solvers: SolverDep, format: FormatQuery = None,
    x: Annotated[str | None, Query(max_length=200, description="Metric on the figure's x axis.")] = None,
    y: Annotated[str | None, Query(max_length=200, description="Metric on the figure's y axis.")] = None,
) -> Response:
    """The feasible variants no other feasible variant beats in every objective; `?format=png` draws every
    variant over metrics `x` and `y` (default: the first two objectives) with the front."""
    if wants_png(request, format):
        scatter = await asyncio.to_thread(studies.scatter, study_id, x, y)
        return png(await solvers.run(scatter_png, scatter))
    front = await asyncio.to_thread(studies.pareto, study_id)
    return json_response(pareto_out(front.record, front.candidates, front.rows))
