"""Schemas of the design library (/v1/library): saving a request as a revision of a design in a project, listing
and searching, history, diffs, sign-off, export and import."""

from __future__ import annotations

from datetime import datetime, timezone
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field

from .common import FOURBAR_EXAMPLE, StrictModel

#: A project's or a design's name: letters, digits, dot, dash and underscore, as it appears in the paths.
NAME_PATTERN = r"^[A-Za-z0-9][A-Za-z0-9._-]{0,99}$"
Name = Annotated[str, Field(pattern=NAME_PATTERN, description="Letters, digits, '.', '-', '_'; at most 100.")]
Person = Annotated[str, Field(min_length=1, max_length=100, pattern=r"\S")]
RevisionState = Literal["draft", "checked", "approved", "superseded"]

SAVE_EXAMPLE: dict[str, Any] = {
    "endpoint": "/v1/balancing/static",
    "request": {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 36,
                "max_radius_m": {"crank": 0.1, "rocker": 0.25}},
    "message": "first balance of the press linkage",
    "parent": None,
    "author": "ann",
}


def _when(seconds: float) -> datetime:
    return datetime.fromtimestamp(seconds, tz=timezone.utc)


def _time(seconds: float | None) -> datetime | None:
    return None if seconds is None else _when(seconds)


class SaveIn(StrictModel):
    """A request to keep as the next revision of a design. The request is validated by its endpoint's own schema;
    an invalid one is refused (422) and nothing is stored."""

    model_config = ConfigDict(json_schema_extra={"examples": [SAVE_EXAMPLE]})

    endpoint: str = Field(min_length=4, max_length=100, pattern=r"^/v1/",
                          description="The endpoint the request is for, e.g. /v1/machines/design; a design holds "
                                      "requests of one endpoint.")
    request: dict[str, Any] = Field(description="The request body as the endpoint takes it.")
    message: str = Field("", max_length=2000, description="Why this revision was made.")
    parent: int | None = Field(None, ge=1, le=1_000_000,
                               description="The revision this one was made from: the design's latest, or null for "
                                           "its first. An older one is refused (409) unless `branch` is true.")
    branch: bool = Field(False, description="Keep this revision beside a later one made from the same parent.")
    author: Person | None = Field(None, description="Who saves it when the service has no sign-in (also the "
                                                    "X-Synth-User header); ignored for a signed-in user.")


class RestoreIn(StrictModel):
    """Restore an old revision as the design's newest."""

    model_config = ConfigDict(json_schema_extra={"examples": [{"message": "back to revision 1", "author": "ann"}]})

    message: str = Field("", max_length=2000, description="Why; default names the revision restored.")
    author: Person | None = Field(None, description="Who restores it (without sign-in; or X-Synth-User).")


class SignIn(StrictModel):
    """A sign-off of a revision."""

    model_config = ConfigDict(json_schema_extra={"examples": [{"name": "bob"}]})

    name: Person | None = Field(None, description="The signer when the service has no sign-in (or "
                                                  "X-Synth-User); never the revision's author.")


class Links(BaseModel):
    """Where to find the revision, its design and its record."""

    self: str
    design: str
    record: str | None = Field(description="The design record (PDF) kept with it, when there is one.")


class RevisionOut(BaseModel):
    """A revision: where it is kept, its hash, who made it and when, its state and sign-offs."""

    project: str
    design: str
    endpoint: str
    number: int = Field(description="1, 2, ... within the design.")
    parent: int | None = Field(description="The revision it was made from.")
    content_hash: str = Field(description="sha256 of the request's canonical JSON (keys sorted, no spaces), hex.")
    author: str
    created_at: datetime
    message: str
    passed: bool | None = Field(description="Every check of the answer passed (false: the engine refused it or a "
                                            "check failed); null without an answer (a study).")
    state: RevisionState = Field(description="draft -> checked -> approved; an approved revision is frozen and "
                                             "becomes superseded when a later one is approved.")
    checked_by: str | None
    checked_at: datetime | None
    approved_by: str | None
    approved_at: datetime | None
    superseded_by: int | None
    links: Links

    @classmethod
    def from_info(cls, i: Any) -> RevisionOut:
        """From the store's RevisionInfo."""
        base = f"/v1/library/projects/{i.project}/designs/{i.design}"
        return cls(project=i.project, design=i.design, endpoint=i.endpoint, number=i.number, parent=i.parent,
                   content_hash=i.content_hash, author=i.author, created_at=_when(i.created_at),
                   message=i.message, passed=i.passed, state=i.state, checked_by=i.checked_by,
                   checked_at=_time(i.checked_at), approved_by=i.approved_by, approved_at=_time(i.approved_at),
                   superseded_by=i.superseded_by,
                   links=Links(self=f"{base}/revisions/{i.number}", design=base,
                               record=f"{base}/revisions/{i.number}/record" if i.has_record else None))


class RevisionDetailOut(RevisionOut):
    """A revision with its request (canonical SI, as its endpoint validated it) and the answer made from it."""

    request: dict[str, Any]
    answer: dict[str, Any] | None = Field(description="The endpoint's answer to exactly this request, or "
                                                      "{\"problem\": ...} when the engine refused it; null for a "
                                                      "study.")


class DesignOut(BaseModel):
    """A design and its history, oldest revision first."""

    project: str
    design: str
    endpoint: str
    revisions: list[RevisionOut]


class ProjectOut(BaseModel):
    """A project and its counts."""

    name: str
    created_at: datetime
    created_by: str
    designs: int
    revisions: int

    @classmethod
    def from_project(cls, p: Any) -> ProjectOut:
        """From the store's Project."""
        return cls(name=p.name, created_at=_when(p.created_at), created_by=p.created_by, designs=p.designs,
                   revisions=p.revisions)


class FieldChange(BaseModel):
    """One input that differs between two revisions."""

    path: str = Field(description="Dotted JSON path; list items by index.")
    unit: str = Field(description="The unit its name carries (m, kg, rpm, ...); '-' dimensionless, '' none.")
    before: Any = Field(description="Its value in the first revision; null when absent.")
    after: Any = Field(description="Its value in the second revision; null when absent.")


class FigureChange(BaseModel):
    """One figure of the answer in both revisions."""

    path: str
    unit: str
    before: float | None
    after: float | None
    change: float | None = Field(description="after - before, in the figure's unit.")
    change_rel: float | None = Field(description="change / |before|; null when before is zero or absent.")


class DiffOut(BaseModel):
    """What changed from one revision to another: every input field that differs, with its unit, and every
    figure of the answer that moved."""

    project: str
    design: str
    before: int
    after: int
    request: list[FieldChange]
    answer: list[FigureChange]
    unchanged_figures: int = Field(description="Figures of the answer equal in both.")


class ExportRevision(StrictModel):
    """A revision as exported: everything the library keeps, the record in base64."""

    number: int = Field(ge=1, le=1_000_000)
    parent: int | None = Field(ge=1, le=1_000_000)
    request: dict[str, Any]
    content_hash: str = Field(pattern=r"^[0-9a-f]{64}$")
    author: Person
    created_at: float = Field(ge=0)
    message: str = Field(max_length=2000)
    answer: dict[str, Any] | None
    passed: bool | None
    state: RevisionState
    checked_by: str | None = Field(max_length=100)
    checked_at: float | None = Field(ge=0)
    approved_by: str | None = Field(max_length=100)
    approved_at: float | None = Field(ge=0)
    superseded_by: int | None = Field(ge=1, le=1_000_000)
    record_pdf_base64: str | None


class ExportDesign(StrictModel):
    """A design as exported."""

    name: Name
    endpoint: str = Field(min_length=4, max_length=100)
    created_at: float = Field(ge=0)
    created_by: Person
    revisions: list[ExportRevision] = Field(max_length=10_000)


class LibraryExport(StrictModel):
    """A project as one file: every design and revision with its answer and record; importing it on another
    service keeps every number, name, time, sign-off and content hash."""

    format: Literal["mechsynth-library/1"]
    project: Name
    created_at: float = Field(ge=0)
    created_by: Person
    exported_at: float = Field(ge=0)
    designs: list[ExportDesign] = Field(max_length=10_000)
