"""Worker side of a save: a design's request validated by its endpoint's own schema, and the answer (with the
design record, for machine designs) made from exactly that request."""

from __future__ import annotations

import io
import json
from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import orjson
from pydantic import ValidationError
from pypdf import PdfReader

from mechsynth_client.schemas.library import LibraryExport
from mechsynth_client.schemas.studies import StudyIn
from store import Store
from store.library import Library, Project
from synth.errors import InvalidInput, SynthError
from synth.machine.record import (
    SHEET_KEY,
    TITLE_BLOCK,
    ChangeNote,
    DesignRecord,
    RevisionRow,
    TitleBlock,
    sheet_metadata,
)

from ..execution.plans import PLANS, Limits
from ..studies.tasks import validate_request

STUDIES = "/v1/studies"
#: The endpoint whose revisions keep their design record (PDF).
MACHINE = "/v1/machines/design"
#: Endpoints whose requests the library keeps: every design endpoint, and studies.
ENDPOINTS = (*sorted(PLANS), STUDIES)


def canonical_request(endpoint: str, request: dict[str, Any]) -> dict[str, Any]:
    """The request as its endpoint's schema reads it (defaults filled, SI, JSON-compatible); an invalid one is
    :class:`InvalidInput` naming the field under ``request``."""
    if endpoint == STUDIES:
        try:
            return StudyIn.model_validate_json(json.dumps(request)).model_dump(mode="json")
        except ValidationError as exc:
            err = exc.errors()[0]
            name = ".".join(str(p) for p in ("request", *err.get("loc", ())))
            raise InvalidInput(f"{name}: {err.get('msg', 'invalid')}", field=name) from None
    if endpoint not in PLANS:
        raise InvalidInput(f"{endpoint!r} is not an endpoint the library keeps designs of; one of "
                           f"{list(ENDPOINTS)}", field="endpoint")
    dumped: dict[str, Any] = validate_request(endpoint, request, field="request").model_dump(mode="json")
    if endpoint == MACHINE:
        # the library writes a record's title block from the revision itself: it is no part of the design, so the
        # content hash is the record's "request SHA-256"
        dumped.pop(TITLE_BLOCK, None)
    return dumped


def record_title_block(block: Mapping[str, Any]) -> dict[str, str]:
    """A revision's title block (:func:`store.library.title_block`) as a machine design request's ``title_block``:
    the record number, revision, names and dates as text, blank where nobody has signed."""
    text = {k: "" if block.get(k) is None else str(block[k]) for k in (
        "project", "revision", "title", "designed_by", "designed_on", "checked_by", "checked_on", "approved_by",
        "approved_on", "state")}
    return {**text, "number": str(block["record_number"])}


def sheet_record(record: DesignRecord, sheet: Mapping[str, Any]) -> DesignRecord:
    """``record`` with a library's sheet (:mod:`api.library.sheet`): its title block, date, revision table and
    change note."""
    note = sheet.get("change_note")
    return replace(record, created=str(sheet["created"]), title_block=TitleBlock.of(sheet["title_block"]),
                   revisions=tuple(RevisionRow(**r) for r in sheet.get("revisions", ())),
                   change_note=None if note is None else ChangeNote(
                       str(note["against"]), tuple((str(a), str(b), str(c), str(d)) for a, b, c, d in note["rows"])))


def sheet_of(sheet: Mapping[str, Any]) -> str:
    """What a record written with ``sheet`` keeps in its metadata (compared with :func:`kept_sheet`)."""
    return sheet_metadata(sheet_record(DesignRecord("", "", ""), sheet))


def kept_sheet(pdf: bytes) -> str | None:
    """The sheet a kept design record was written with (its PDF's metadata), None when it does not say."""
    info = PdfReader(io.BytesIO(pdf)).metadata
    written = None if info is None else info.get(SHEET_KEY)
    return written if isinstance(written, str) else None


def _plan(limits: Limits, request: dict[str, Any], sheet: Mapping[str, Any]) -> Any:
    # the wire's title block is the request's; the deviation, date and tables are the library's own
    wire = {k: v for k, v in sheet["title_block"].items() if k != "deviation"}
    plan = PLANS[MACHINE][1](validate_request(MACHINE, {**request, TITLE_BLOCK: wire}), limits)
    record = sheet_record(plan.render.export_extra[0], sheet)
    return plan, replace(plan.render, model_extra=(record,), export_extra=(record,))


def machine_record(limits: Limits, request: dict[str, Any], sheet: dict[str, Any]) -> bytes:
    """The design record of a machine design's canonical request with a library's ``sheet`` (title block,
    date, revision table, change note): the same design, as the revision stands now."""
    plan, render = _plan(limits, request, sheet)
    pdf: bytes = replace(render, fmt="pdf")(plan.fn(*plan.args, **plan.kwargs))[0]
    return pdf


def answer_revision(endpoint: str, limits: Limits, request: dict[str, Any], sheet: dict[str, Any] | None = None
                    ) -> tuple[dict[str, Any] | None, bool | None, bytes | None]:
    """The answer to a canonical request, whether it passed, and its design record (PDF) for a machine design,
    with the library's ``sheet``; an engine problem is the answer (``{"problem": ...}``, not passed). A study
    has no answer here."""
    if endpoint == STUDIES:
        return None, None, None
    if endpoint == MACHINE and sheet:
        plan, render = _plan(limits, request, sheet)
    else:
        plan = PLANS[endpoint][1](validate_request(endpoint, request), limits)
        render = plan.render
    try:
        result = plan.fn(*plan.args, **plan.kwargs)
        content, _ = render(result)
    except SynthError as exc:
        return {"problem": {"type": f"/problems/{exc.slug}", "title": exc.title, "detail": str(exc)}}, False, None
    answer: dict[str, Any] = orjson.loads(content)
    record = replace(render, fmt="pdf")(result)[0] if endpoint == MACHINE else None
    passed = answer.get("passed")
    return answer, passed if isinstance(passed, bool) else True, record


def import_file(path: str, store_url: str, importer: str) -> Project:
    """Worker side of an import: the export read from the file its body was spooled to, checked against the
    export's schema (422 naming the first field that fails) and stored, so the web process never holds the
    document (a 100 MB export parses to far more than 100 MB of objects)."""
    with open(path, "rb") as spooled:
        raw = spooled.read()
    try:
        document = orjson.loads(raw)
    except orjson.JSONDecodeError as exc:
        raise InvalidInput(f"the body is not JSON: {exc}", field="body") from None
    del raw
    try:
        export = LibraryExport.model_validate(document)
    except ValidationError as exc:
        first = exc.errors(include_url=False)[0]
        where = ".".join(str(p) for p in first["loc"]) or "body"
        raise InvalidInput(f"{where}: {first['msg']}", field=where) from None
    del document
    store = Store(store_url)
    try:
        return Library(store).import_project(export.model_dump(mode="json"), importer=importer)
    finally:
        store.dispose()
