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
RevisionState = Literal["draft", "checked", "approved", "superseded", "returned", "imported"]

SAVE_EXAMPLE: dict[str, Any] = {
    "endpoint": "/v1/balancing/static",
    "request": {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 36,
                "max_radius_m": {"crank": 0.1, "rocker": 0.25}},
    "message": "first balance of the press linkage",
    "parent": None,
    "author": "ann",
}


#: 9999-12-31T23:59:59 UTC [s since 1970]: the last instant a date can name, so an export's times stay dates.
LAST_SECOND = 253_402_300_799.0
#: An instant of an export [s since 1970, UTC].
Instant = Annotated[float, Field(ge=0, le=LAST_SECOND, examples=[1.7e9])]


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
                                                  "X-Synth-User); never the revision's author, nor its checker "
                                                  "when approving.")
    deviation: str | None = Field(None, max_length=2000,
                                  description="Why a revision whose answer failed a check is signed anyway: kept "
                                              "with it, printed in the record's title block and checks page. "
                                              "Without it such a revision is refused (409 naming the failed "
                                              "checks).")
    comment: str | None = Field(None, max_length=2000, description="A remark kept with the revision.")


class ReturnIn(StrictModel):
    """A revision returned to its author by its checker or approver, with why."""

    model_config = ConfigDict(json_schema_extra={"examples": [{"comment": "the flywheel sits on the wrong shaft"}]})

    comment: str = Field(min_length=1, max_length=2000, pattern=r"\S", description="Why it is returned.")
    name: Person | None = Field(None, description="Who returns it when the service has no sign-in.")


class CommentIn(StrictModel):
    """A comment on a revision."""

    model_config = ConfigDict(json_schema_extra={"examples": [{"text": "checked against the 2019 drawing"}]})

    text: str = Field(min_length=1, max_length=2000, pattern=r"\S", description="The comment.")
    name: Person | None = Field(None, description="Who writes it when the service has no sign-in.")


class CommentOut(BaseModel):
    """A comment on a revision."""

    author: str = Field(description="Who wrote it.")
    created_at: datetime = Field(description="When (UTC).")
    kind: Literal["returned", "check", "approve", "deviation", "comment"] = Field(
        description="returned: why it was returned; check/approve: a signer's remark; deviation: the reason a "
                    "failing revision was signed; comment: anything else.")
    text: str = Field(description="What it says.")


class Links(BaseModel):
    """Where to find the revision, its design and its record."""

    self: str = Field(description="This revision's address on the service.")
    design: str = Field(description="The design's history on the service.")
    record: str | None = Field(description="The design record (PDF) kept with it, when there is one.")


class RevisionOut(BaseModel):
    """A revision: where it is kept, its hash, who made it and when, its state and sign-offs."""

    project: str = Field(description="The project the design belongs to.")
    design: str = Field(description="The design's name within its project.")
    endpoint: str = Field(description="The service operation the request is for (/v1/...).")
    number: int = Field(description="1, 2, ... within the design.")
    parent: int | None = Field(description="The revision it was made from.")
    content_hash: str = Field(description="sha256 of the request's canonical JSON (keys sorted, no spaces), hex.")
    author: str = Field(description="Who saved it.")
    created_at: datetime = Field(description="When it was saved (UTC).")
    message: str = Field(description="Why it was made.")
    passed: bool | None = Field(description="Every check of the answer passed (false: the engine refused it or a "
                                            "check failed); null without an answer (a study).")
    state: RevisionState = Field(description="draft -> checked -> approved; an approved revision is frozen and "
                                             "becomes superseded when a later one is approved; returned: sent "
                                             "back to its author with a comment; imported: from another "
                                             "service's export, unsigned here.")
    checked_by: str | None = Field(description="Who checked it; null while unchecked.")
    checked_at: datetime | None = Field(description="When it was checked (UTC).")
    approved_by: str | None = Field(description="Who approved it; null while unapproved.")
    approved_at: datetime | None = Field(description="When it was approved (UTC).")
    superseded_by: int | None = Field(description="The approved revision that replaced it, when one did.")
    deviation: str | None = Field(None, description="Why it was signed although its answer failed a check.")
    imported_note: str | None = Field(None, description="For an imported revision: where it came from and what "
                                                        "it claimed (state, signers, answer), not verified here.")
    answer_origin: Literal["computed", "imported", "none"] = Field(
        "computed", description="computed: its answer was computed by this service from its request; imported: "
                                "the answer came in a file (restore the revision to compute it here); none: no "
                                "answer (a study).")
    comments: list[CommentOut] = Field(default_factory=list, description="Comments, oldest first.")
    links: Links = Field(description="Addresses of the revision, its design and its record.")

    @classmethod
    def from_info(cls, i: Any) -> RevisionOut:
        """From the store's RevisionInfo."""
        base = f"/v1/library/projects/{i.project}/designs/{i.design}"
        return cls(project=i.project, design=i.design, endpoint=i.endpoint, number=i.number, parent=i.parent,
                   content_hash=i.content_hash, author=i.author, created_at=_when(i.created_at),
                   message=i.message, passed=i.passed, state=i.state, checked_by=i.checked_by,
                   checked_at=_time(i.checked_at), approved_by=i.approved_by, approved_at=_time(i.approved_at),
                   superseded_by=i.superseded_by, deviation=i.deviation, imported_note=i.imported_note,
                   answer_origin="imported" if i.imported_note else "none" if i.passed is None and
                   i.endpoint == "/v1/studies" else "computed",
                   comments=[CommentOut(author=c.author, created_at=_when(c.created_at), kind=c.kind, text=c.text)
                             for c in i.comments],
                   links=Links(self=f"{base}/revisions/{i.number}", design=base,
                               record=f"{base}/revisions/{i.number}/record" if i.has_record else None))


class RevisionDetailOut(RevisionOut):
    """A revision with its request (canonical SI, as its endpoint validated it) and the answer made from it."""

    request: dict[str, Any] = Field(description="The canonical SI request the content hash is taken of.")
    answer: dict[str, Any] | None = Field(description="The endpoint's answer to exactly this request, or "
                                                      "{\"problem\": ...} when the engine refused it; null for a "
                                                      "study.")


class DesignOut(BaseModel):
    """A design and its history, oldest revision first."""

    project: str = Field(description="The project the design belongs to.")
    design: str = Field(description="The design's name within its project.")
    endpoint: str = Field(description="The service operation its requests are for.")
    revisions: list[RevisionOut] = Field(description="Every revision, oldest first.")


class ProjectOut(BaseModel):
    """A project and its counts."""

    name: str = Field(description="The project's name.")
    created_at: datetime = Field(description="When its first design was saved (UTC).")
    created_by: str = Field(description="Who saved it.")
    designs: int = Field(description="Designs in the project.")
    revisions: int = Field(description="Revisions of all its designs together.")

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

    path: str = Field(description="Dotted JSON path of the figure in the answer; list items by index.")
    unit: str = Field(description="The unit its name carries; '-' dimensionless, '' none.")
    before: float | None = Field(description="Its value in the first revision; null when absent.")
    after: float | None = Field(description="Its value in the second revision; null when absent.")
    change: float | None = Field(description="after - before, in the figure's unit.")
    change_rel: float | None = Field(description="change / |before|; null when before is zero or absent.")


class DiffOut(BaseModel):
    """What changed from one revision to another: every input field that differs, with its unit, and every
    figure of the answer that moved."""

    project: str = Field(description="The project the design belongs to.")
    design: str = Field(description="The design's name within its project.")
    before: int = Field(description="The first revision compared.")
    after: int = Field(description="The second revision compared.")
    request: list[FieldChange] = Field(description="Fields of the request that differ, with their units.")
    answer: list[FigureChange] = Field(description="Figures of the answer that differ, with the change.")
    unchanged_figures: int = Field(description="Figures of the answer equal in both.")
    noise_figures: int = Field(0, description="Figures that moved by less than the answers' own tolerance: left out "
                                              "of `answer` unless asked for with noise=true.")


class ExportComment(StrictModel):
    """A comment as exported."""

    author: str = Field(max_length=100, description="Who wrote it.")
    created_at: Instant = Field(description="When [s since 1970, UTC].")
    kind: str = Field(max_length=16, description="returned, check, approve, deviation or comment.")
    text: str = Field(max_length=2000, description="What it says.")


class ExportRevision(StrictModel):
    """A revision as exported: everything the library keeps, the record in base64."""

    number: int = Field(ge=1, le=1_000_000, examples=[1], description="1, 2, ... within the design.")
    parent: int | None = Field(ge=1, le=1_000_000, examples=[None], description="The revision it was made from.")
    request: dict[str, Any] = Field(description="The canonical SI request.")
    content_hash: str = Field(pattern=r"^[0-9a-f]{64}$", description="sha256 of the request's canonical JSON, hex.")
    author: Person = Field(description="Who saved it.")
    created_at: Instant = Field(description="When it was saved [s since 1970, UTC].")
    message: str = Field(max_length=2000, description="Why it was made.")
    answer: dict[str, Any] | None = Field(description="The endpoint's answer to the request, when kept.")
    passed: bool | None = Field(description="Every check of the answer passed.")
    state: RevisionState = Field(description="draft, checked, approved or superseded.")
    checked_by: str | None = Field(max_length=100, description="Who checked it.")
    checked_at: Instant | None = Field(examples=[1.7e9], description="When it was checked [s since 1970, UTC].")
    approved_by: str | None = Field(max_length=100, description="Who approved it.")
    approved_at: Instant | None = Field(examples=[1.7e9], description="When it was approved [s since 1970, UTC].")
    superseded_by: int | None = Field(ge=1, le=1_000_000, examples=[None], description="The approved revision that replaced it.")
    deviation: str | None = Field(None, max_length=2000, description="Why it was signed although it failed a check.")
    imported_note: str | None = Field(None, max_length=4000, description="Set when it was imported here before.")
    comments: list[ExportComment] = Field(default_factory=list, max_length=1000, description="Its comments.")
    record_pdf_base64: str | None = Field(description="The design record kept with it (PDF, base64), when there is one.")


class ExportDesign(StrictModel):
    """A design as exported."""

    name: Name = Field(description="The design's name within its project.")
    endpoint: str = Field(min_length=4, max_length=100, description="The service operation its requests are for.")
    created_at: Instant = Field(description="When it was first saved [s since 1970, UTC].")
    created_by: Person = Field(description="Who first saved it.")
    revisions: list[ExportRevision] = Field(max_length=10_000, description="Every revision, oldest first.")


class LibraryExport(StrictModel):
    """A project as one file: every design and revision with its answer and record. Importing it on another
    service keeps every number, name, time, message and content hash; its states, signatures and answers arrive
    as claims (each revision `imported`, unsigned, with a note of what it said), never as sign-offs."""

    format: Literal["mechsynth-library/1"] = Field(description="The export format and its version.")
    project: Name = Field(description="The project exported.")
    created_at: Instant = Field(description="When the project was made [s since 1970, UTC].")
    created_by: Person = Field(description="Who made it.")
    exported_at: Instant = Field(description="When it was exported [s since 1970, UTC].")
    designs: list[ExportDesign] = Field(max_length=10_000, description="Every design with its revisions.")
