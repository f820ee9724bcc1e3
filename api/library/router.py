"""/v1/library: projects, designs and their revisions. Saving validates a request with its endpoint's own schema,
computes its answer (and, for a machine design, its design record) on the workers and keeps them with the
revision; history, search, diff, restore, sign-off, and a project's export and import."""

from __future__ import annotations

import asyncio
import tempfile
import time
from datetime import datetime, timezone
from functools import partial
from typing import Annotated, Any, Literal

from fastapi import APIRouter, Depends, Header, Path, Query, Request
from fastapi.responses import Response

from mechsynth_client.schemas.library import (
    NAME_PATTERN,
    DesignOut,
    DiffOut,
    LibraryExport,
    CommentIn,
    ProjectOut,
    RestoreIn,
    ReturnIn,
    RevisionDetailOut,
    RevisionOut,
    RevisionState,
    SaveIn,
    SignIn,
)
from store import User
from synth.errors import InvalidInput
from store.library import Library

from ..deps import SettingsDep, SolverDep
from ..execution.plans import Limits
from ..identity import CurrentUserDep
from ..media import json_bytes, json_response
from ..storage import StoreDep
from .access import Forbidden, actor
from .diff import answer_changes, request_changes
from .sheet import draft_sheet, revision_sheet
from .tasks import (MACHINE, answer_revision, canonical_request, import_file, kept_sheet, machine_record,
                    sheet_of)

router = APIRouter(prefix="/library", tags=["library"])


def get_library(store: StoreDep) -> Library:
    """The library in the app's store."""
    return Library(store)


LibraryDep = Annotated[Library, Depends(get_library)]
ProjectName = Annotated[str, Path(pattern=NAME_PATTERN, description="The project's name.")]
DesignName = Annotated[str, Path(pattern=NAME_PATTERN, description="The design's name within its project.")]
Number = Annotated[int, Path(ge=1, le=1_000_000, description="The revision's number within its design.")]
UserHeader = Annotated[str | None, Header(alias="X-Synth-User", max_length=100,
                                          description="Who acts, when the service has no sign-in.")]


def _problems(*statuses: int) -> dict[int | str, dict[str, Any]]:
    text = {403: "The acting user may not do this: the author signs nothing of their own and the checker does not "
                 "approve what they checked; checking needs the checker role, approving the approver role, "
                 "returning either, saving the engineer role.",
            404: "No such project, design or revision (or record).",
            409: "The save starts from a revision that is no longer the design's latest (the answer names the one "
                 "it would overwrite: `head_revision`), the revision is not in the state the sign-off needs (or a "
                 "later revision is approved), its answer did not pass and no deviation was given "
                 "(`failed_checks` names them), or the imported project exists.",
            503: "The store cannot be reached; `reason` says why."}
    ref = {"application/problem+json": {"schema": {"$ref": "#/components/schemas/Problem"}}}
    return {s: {"description": text[s], "content": ref} for s in (*statuses, 503)}


async def _save(library: Library, solvers: SolverDep, settings: Any, project: str, design: str, endpoint: str,
                request: dict[str, Any], *, author: str, message: str, parent: int | None, branch: bool
                ) -> RevisionOut:
    canonical = canonical_request(endpoint, request)
    await asyncio.to_thread(library.check_parent, project, design, parent, branch)
    # the revision's date, which its design record carries: the record is a document of the revision
    created_at = time.time()
    sheet = None
    if endpoint == MACHINE:
        # the record is written once with the title block of the revision this save becomes (a draft)
        head = await asyncio.to_thread(library.head, project, design)
        sheet = await asyncio.to_thread(draft_sheet, library, project, design, (head or 0) + 1, author, message,
                                        created_at, canonical)
    answer, passed, record = await solvers.run(answer_revision, endpoint, Limits.from_settings(settings), canonical,
                                               sheet)
    info = await asyncio.to_thread(partial(library.save, project, design, endpoint, canonical, author=author,
                                           message=message, parent=parent, branch=branch, answer=answer,
                                           passed=passed, record_pdf=record, created_at=created_at))
    return RevisionOut.from_info(info)


@router.post("/projects/{project}/designs/{design}/revisions", status_code=201, response_model=RevisionOut,
             responses=_problems(403, 404, 409))
async def save_revision(project: ProjectName, design: DesignName, body: SaveIn, library: LibraryDep,
                        solvers: SolverDep, settings: SettingsDep, user: CurrentUserDep, response: Response,
                        x_synth_user: UserHeader = None) -> RevisionOut:
    """Save a request as the next revision of a design (the project and the design are made on their first save).
    The request is validated by its endpoint's schema (422 names the field; nothing is stored), its answer is
    computed and kept with it, and for a machine design its design record (PDF) too. `parent` is the revision it
    was made from: when that is no longer the design's latest the save is refused (409, naming the revision it
    would overwrite) unless `branch` is true."""
    author = actor(user, body.author or x_synth_user, "author", "engineer")
    out = await _save(library, solvers, settings, project, design, body.endpoint, body.request, author=author,
                      message=body.message, parent=body.parent, branch=body.branch)
    response.headers["Location"] = out.links.self
    return out


@router.get("/projects", response_model=list[ProjectOut], responses=_problems())
async def list_projects(library: LibraryDep) -> list[ProjectOut]:
    """Every project by name, with its counts of designs and revisions."""
    return [ProjectOut.from_project(p) for p in await asyncio.to_thread(library.projects)]


# The library keeps times as seconds since 1970 (UTC); a query's date outside 1970..9999 is refused, never turned
# into a local time the platform cannot represent.
_EPOCH = datetime(1970, 1, 1, tzinfo=timezone.utc)


def _seconds(when: datetime | None, field: str) -> float | None:
    """A query's date as seconds since 1970 (a date without a zone is UTC); 422 naming ``field`` outside
    1970-01-01..9999-12-31."""
    if when is None:
        return None
    aware = when if when.tzinfo is not None else when.replace(tzinfo=timezone.utc)
    try:
        seconds = (aware - _EPOCH).total_seconds()
    except (OverflowError, ValueError) as exc:
        raise InvalidInput(f"{field}={when.isoformat()} cannot be compared with the library's times",
                           field=field) from exc
    if not 0.0 <= seconds <= 253402300799.0:
        raise InvalidInput(f"{field}={when.isoformat()} is outside 1970-01-01..9999-12-31, the library's times",
                           field=field)
    return seconds


@router.get("/revisions", response_model=list[RevisionOut], responses=_problems())
async def search_revisions(
    library: LibraryDep,
    project: Annotated[str | None, Query(pattern=NAME_PATTERN, description="Only this project.")] = None,
    name: Annotated[str | None, Query(max_length=100, description="A part of the design's name (any case).")] = None,
    endpoint: Annotated[str | None, Query(max_length=100, description="Only designs of this endpoint (their "
                                                                      "type), e.g. /v1/machines/design.")] = None,
    author: Annotated[str | None, Query(max_length=100, description="Only revisions by this author.")] = None,
    since: Annotated[datetime | None, Query(description="Saved at or after (ISO 8601).")] = None,
    until: Annotated[datetime | None, Query(description="Saved at or before (ISO 8601).")] = None,
    passed: Annotated[bool | None, Query(description="true: every check passed; false: failed or refused.")] = None,
    state: Annotated[RevisionState | None, Query(description="Only revisions in this state.")] = None,
    deviation: Annotated[bool | None, Query(description="true: only revisions signed with a deviation (released "
                                                        "although they fail a check); false: only without.")] = None,
    latest: Annotated[bool, Query(description="Only each design's latest revision (false: every revision).")] = True,
    offset: Annotated[int, Query(ge=0, le=100_000_000)] = 0,
    limit: Annotated[int, Query(ge=1, le=1000)] = 100,
) -> list[RevisionOut]:
    """Search the library: revisions matching every filter given, newest first."""
    found = await asyncio.to_thread(partial(
        library.search, project=project, name=name, endpoint=endpoint, author=author,
        since=_seconds(since, "since"), until=_seconds(until, "until"),
        passed=passed, state=state, deviation=deviation, latest=latest, limit=limit, offset=offset))
    return [RevisionOut.from_info(i) for i in found]


@router.get("/projects/{project}/designs/{design}", response_model=DesignOut, responses=_problems(404))
async def design_history(project: ProjectName, design: DesignName, library: LibraryDep) -> DesignOut:
    """A design's history: every revision, oldest first, with its parent, author, message, state and sign-offs."""
    history = await asyncio.to_thread(library.history, project, design)
    return DesignOut(project=project, design=design, endpoint=history[0].endpoint,
                     revisions=[RevisionOut.from_info(i) for i in history])


@router.get("/projects/{project}/designs/{design}/revisions/{number}", response_model=RevisionDetailOut,
            responses=_problems(404))
async def get_revision(project: ProjectName, design: DesignName, number: Number,
                       library: LibraryDep) -> Response:
    """A revision with its request (canonical SI) and the answer computed from exactly that request."""
    r = await asyncio.to_thread(library.revision, project, design, number)
    out = RevisionDetailOut(**RevisionOut.from_info(r.info).model_dump(), request=dict(r.request),
                            answer=None if r.answer is None else dict(r.answer))
    return json_response(out)


@router.get("/projects/{project}/designs/{design}/revisions/{number}/record",
            responses={200: {"content": {"application/pdf": {}},
                             "description": "The design record made from exactly this revision when it was saved."},
                       **_problems(404)})
async def get_record(project: ProjectName, design: DesignName, number: Number, library: LibraryDep,
                     solvers: SolverDep, settings: SettingsDep) -> Response:
    """The design record (PDF) kept with a machine design's revision, as the revision stands: its title block
    (project, record number, revision, state, who designed, checked and approved it and when, a deviation), dated
    when the revision was saved, with the revision table and the change note against the previous approved
    revision on its first pages. A record kept from before a sign-off (or a comment) is written again once (the
    same request, so the same figures and the same request SHA-256, which is the revision's content hash) and
    kept in its place: two downloads of a revision that did not move are the same bytes."""
    pdf = await asyncio.to_thread(library.record_pdf, project, design, number)
    revision = await asyncio.to_thread(library.revision, project, design, number)
    if revision.info.endpoint == MACHINE:
        sheet = await asyncio.to_thread(revision_sheet, library, project, design, number)
        if await asyncio.to_thread(kept_sheet, pdf) != sheet_of(sheet):
            pdf = await solvers.run(machine_record, Limits.from_settings(settings), dict(revision.request), sheet)
            await asyncio.to_thread(library.sign_record, project, design, number, pdf)
    return Response(pdf, media_type="application/pdf", headers={
        "content-disposition": f'attachment; filename="{project}-{design}-r{number}.pdf"'})


@router.get("/projects/{project}/designs/{design}/diff", response_model=DiffOut, responses=_problems(404))
async def diff_revisions(
    project: ProjectName, design: DesignName, library: LibraryDep,
    before: Annotated[int, Query(alias="from", ge=1, le=1_000_000, description="The older revision.")],
    after: Annotated[int, Query(alias="to", ge=1, le=1_000_000, description="The newer revision.")],
    order: Annotated[Literal["relative", "path"], Query(
        description="relative: the figures that appeared or vanished first, then the largest relative change; "
                    "path: in the answer's own order.")] = "relative",
    noise: Annotated[bool, Query(
        description="Also list the figures that moved by less than the answers' own tolerance (the largest "
                    "disagreement their checks report in the figure's unit, at least a billionth of the largest "
                    "figure in it); left out by default and counted in noise_figures.")] = False,
) -> DiffOut:
    """What changed between two revisions: every input field that differs, with the unit its name carries, and
    every figure of the answer that moved beyond the answers' own tolerance, with its change (after - before) and
    relative change, the largest relative change first."""
    old = await asyncio.to_thread(library.revision, project, design, before)
    new = await asyncio.to_thread(library.revision, project, design, after)
    figures, same, quiet = answer_changes(old.answer, new.answer, order=order, noise=noise)
    return DiffOut(project=project, design=design, before=before, after=after,
                   request=request_changes(old.request, new.request), answer=figures, unchanged_figures=same,
                   noise_figures=quiet)


@router.post("/projects/{project}/designs/{design}/revisions/{number}/restore", status_code=201,
             response_model=RevisionOut, responses=_problems(403, 404, 409))
async def restore_revision(project: ProjectName, design: DesignName, number: Number, body: RestoreIn,
                           library: LibraryDep, solvers: SolverDep, settings: SettingsDep, user: CurrentUserDep,
                           response: Response, x_synth_user: UserHeader = None) -> RevisionOut:
    """Make an old revision's request the design's newest revision (a new number; the old one is unchanged)."""
    author = actor(user, body.author or x_synth_user, "author", "engineer")
    old = await asyncio.to_thread(library.revision, project, design, number)
    head = await asyncio.to_thread(library.head, project, design)
    out = await _save(library, solvers, settings, project, design, old.info.endpoint, dict(old.request),
                      author=author, message=body.message or f"restored revision {number}", parent=head,
                      branch=False)
    response.headers["Location"] = out.links.self
    return out


async def _sign(library: Library, project: str, design: str, number: int, role: Literal["checker", "approver"],
                user: User | None, body: SignIn, header: str | None) -> RevisionOut:
    signer = actor(user, body.name or header, "name", role)
    return RevisionOut.from_info(await asyncio.to_thread(partial(
        library.sign, project, design, number, role=role, name=signer, deviation=body.deviation,
        comment=body.comment)))


@router.post("/projects/{project}/designs/{design}/revisions/{number}/check", response_model=RevisionOut,
             responses=_problems(403, 404, 409))
async def check_revision(project: ProjectName, design: DesignName, number: Number, body: SignIn,
                         library: LibraryDep, user: CurrentUserDep, x_synth_user: UserHeader = None) -> RevisionOut:
    """Sign a draft revision as its checker (the checker role; never its author): it becomes checked. A revision
    whose answer did not pass is refused (409 naming the failed checks) unless `deviation` says why it is
    passed on anyway."""
    return await _sign(library, project, design, number, "checker", user, body, x_synth_user)


@router.post("/projects/{project}/designs/{design}/revisions/{number}/approve", response_model=RevisionOut,
             responses=_problems(403, 404, 409))
async def approve_revision(project: ProjectName, design: DesignName, number: Number, body: SignIn,
                           library: LibraryDep, user: CurrentUserDep, x_synth_user: UserHeader = None
                           ) -> RevisionOut:
    """Approve a checked revision (the approver role; neither its author nor its checker): it becomes approved
    and frozen, and the design's approved revision becomes superseded (one approved revision per design; an
    older revision than the approved one is refused, 409). A revision whose answer did not pass needs
    `deviation`, the reason it is released anyway: kept, printed in the record and found by search."""
    return await _sign(library, project, design, number, "approver", user, body, x_synth_user)


@router.post("/projects/{project}/designs/{design}/revisions/{number}/return", response_model=RevisionOut,
             responses=_problems(403, 404, 409))
async def return_revision(project: ProjectName, design: DesignName, number: Number, body: ReturnIn,
                          library: LibraryDep, user: CurrentUserDep, x_synth_user: UserHeader = None
                          ) -> RevisionOut:
    """Return a draft or checked revision to its author with a comment (the checker or approver role; not its
    author): it becomes returned and is signed no more; the comment is kept, listed in its history and printed
    in its record. The author saves a new revision from it."""
    name = actor(user, body.name or x_synth_user, "name", "checker", "approver")
    return RevisionOut.from_info(await asyncio.to_thread(partial(
        library.return_revision, project, design, number, name=name, comment=body.comment)))


@router.post("/projects/{project}/designs/{design}/revisions/{number}/comments", response_model=RevisionOut,
             responses=_problems(403, 404))
async def comment_revision(project: ProjectName, design: DesignName, number: Number, body: CommentIn,
                           library: LibraryDep, user: CurrentUserDep, x_synth_user: UserHeader = None
                           ) -> RevisionOut:
    """Keep a comment on a revision in any state (the engineer, checker or approver role); it signs nothing."""
    name = actor(user, body.name or x_synth_user, "name", "engineer", "checker", "approver")
    return RevisionOut.from_info(await asyncio.to_thread(partial(
        library.comment, project, design, number, name=name, text=body.text)))


@router.get("/projects/{project}/export", response_model=LibraryExport, responses=_problems(404))
async def export_project(project: ProjectName, library: LibraryDep) -> Response:
    """The whole project as one JSON file: every design and revision with its request, hash, answer, sign-offs
    and design record (base64). POST it to /v1/library/import on another service to restore it there."""
    document = await asyncio.to_thread(library.export, project)
    return Response(json_bytes(LibraryExport.model_validate(document)), media_type="application/json", headers={
        "content-disposition": f'attachment; filename="{project}.library.json"'})


@router.post("/import", status_code=201, response_model=ProjectOut, responses=_problems(403, 409),
             openapi_extra={"requestBody": {"required": True, "content": {"application/json": {
                 "schema": {"$ref": "#/components/schemas/LibraryExport"}}}}})
async def import_project(request: Request, library: LibraryDep, solvers: SolverDep,
                         user: CurrentUserDep) -> ProjectOut:
    """Import an exported project's history: numbers, authors, times, messages, requests (every content hash
    checked against its request first: 422 names one that does not match). A file cannot sign: every revision
    arrives `imported` and unsigned, what it claimed (state, signers, pass, deviation, comments) kept only in its
    `imported_note`, its answer marked as computed elsewhere, its record left behind. Restore a revision to
    compute it here and sign it here."""
    if user is not None and not (user.has("admin") or user.has("engineer")):
        raise Forbidden(f"{user.name} may not import projects: importing needs the engineer role")
    importer = user.name if user is not None else "a caller of an open service"
    # the body arrives spooled to a file (the service's body limit streams it there, bounded by
    # SYNTH_MAX_IMPORT_BYTES): a worker parses, checks and stores it, and the web process stays small
    spooled: str | None = request.scope.get("state", {}).get("body_file")
    if spooled is not None:
        return ProjectOut.from_project(await solvers.run(import_file, spooled, library.store.url, importer))
    with tempfile.NamedTemporaryFile(prefix="synth-body-", suffix=".json") as copy:
        copy.write(await request.body())
        copy.flush()
        return ProjectOut.from_project(await solvers.run(import_file, copy.name, library.store.url, importer))

