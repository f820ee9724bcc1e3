"""The design library: projects hold designs, a design is a line of immutable revisions of one endpoint's request.

A revision keeps the request (canonical JSON: keys sorted, no spaces), its content hash (sha256 of that text),
author, time and message, and the answer and design record made from exactly that request. Saving names the
revision it starts from (its parent); a save whose parent is no longer the design's latest revision would
silently overwrite someone's work, so it is refused (:class:`StaleParent`) unless it asks to branch.

The sign-off rules hold here, in one transaction each, on both engines, whatever two servers do at once:
a revision is checked and then approved by two different people, neither its author; only a revision whose
answer passed is signed, unless the signer states a deviation (its reason is kept and printed); a design has at
most one approved revision (approving supersedes the one before; approving an older revision than the approved
one is refused; a partial unique index backs this up); a checker or approver may return a revision with a
comment. An imported revision arrives ``imported``: its signatures were made elsewhere, so they are kept only as
a note, and its answer as one computed elsewhere. Nothing here knows who holds which role: the service checks
roles before it asks.
"""

from __future__ import annotations

import base64
import hashlib
import json
import time
from datetime import datetime, timezone
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import sqlalchemy as sa

from .db import Store
from .schema import designs, projects, revision_comments, revisions

#: The states of a revision: a draft is checked, then approved, then superseded by a later approval; a checker or
#: approver may return a draft or a checked one to its author; an import arrives unsigned as ``imported``.
STATES = ("draft", "checked", "approved", "superseded", "returned", "imported")
#: What an export document says it is; an import refuses any other.
EXPORT_FORMAT = "mechsynth-library/1"


class LibraryError(Exception):
    """Base of the library's refusals; ``detail`` says what to do."""


class NotFound(LibraryError):
    """No such project, design or revision."""


class StaleParent(LibraryError):
    """The save starts from a revision that is no longer the design's latest: it would overwrite ``head``."""

    def __init__(self, detail: str, head: int) -> None:
        super().__init__(detail)
        self.head = head

    def __reduce__(self) -> tuple[type[StaleParent], tuple[str, int]]:
        return type(self), (str(self), self.head)


class SignOffRefused(LibraryError):
    """The signer may not sign this revision (they wrote it, or signed it already in another role)."""


class WrongState(LibraryError):
    """The revision is not in the state the sign-off needs (a draft is checked, a checked one approved), or a
    later revision of the design is approved."""


class FailedChecks(LibraryError):
    """The revision's answer did not pass (``failed`` names the checks or the problem) and no deviation was
    given."""

    def __init__(self, detail: str, failed: list[str]) -> None:
        super().__init__(detail)
        self.failed = failed


class InvalidDocument(LibraryError):
    """A save or an import that cannot be stored as it is (a design of another endpoint, a hash that does not
    match its request); ``field`` names the part."""

    def __init__(self, detail: str, field: str) -> None:
        super().__init__(detail)
        self.field = field

    def __reduce__(self) -> tuple[type[InvalidDocument], tuple[str, str]]:
        # raised in a worker process (an import) and sent back to the web process whole
        return type(self), (str(self), self.field)


class ProjectExists(LibraryError):
    """An import into a project that already exists."""


def canonical_json(value: Any) -> str:
    """JSON with keys sorted and no spaces: the text a content hash is taken of."""
    return json.dumps(value, sort_keys=True, separators=(",", ":"), ensure_ascii=False, allow_nan=False)


def content_hash(request: Mapping[str, Any]) -> str:
    """sha256 of the request's canonical JSON, hex."""
    return hashlib.sha256(canonical_json(request).encode("utf-8")).hexdigest()


@dataclass(frozen=True, slots=True)
class Comment:
    """A comment on a revision: who [-], when [s since the epoch], what kind (``returned``, ``check``,
    ``approve``, ``deviation``, ``comment``) and its text [-]."""

    author: str
    created_at: float
    kind: str
    text: str


@dataclass(frozen=True, slots=True)
class RevisionInfo:
    """A revision without its request and answer (for lists).

    Parameters
    ----------
    project, design, endpoint
        Where it is kept and the endpoint its request is for [-].
    number
        1, 2, ... within its design [-].
    parent
        The revision it was made from, None for a design's first [-].
    content_hash
        sha256 of the request's canonical JSON, hex [-].
    author, created_at, message
        Who saved it, when (seconds since the epoch) [s], and why [-].
    passed
        Every check of its answer passed; None without an answer (a study) or with an imported one [-].
    state
        ``draft``, ``checked``, ``approved``, ``superseded``, ``returned`` or ``imported`` [-].
    checked_by, checked_at, approved_by, approved_at
        The sign-offs, names and times [s].
    superseded_by
        The approved revision that superseded it [-].
    has_record
        A design record (PDF) is kept with it [-].
    deviation
        Why it was signed although its answer failed a check; None when it passed [-].
    imported_note
        For an imported revision: where it came from and what it claimed (state, signers, answer), none of it
        verified here; None for a revision saved here [-].
    comments
        Comments on it, oldest first (returns, sign-offs with a remark, deviations) [-].
    """

    project: str
    design: str
    endpoint: str
    number: int
    parent: int | None
    content_hash: str
    author: str
    created_at: float
    message: str
    passed: bool | None
    state: str
    checked_by: str | None
    checked_at: float | None
    approved_by: str | None
    approved_at: float | None
    superseded_by: int | None
    has_record: bool
    deviation: str | None = None
    imported_note: str | None = None
    comments: tuple[Comment, ...] = ()


@dataclass(frozen=True, slots=True)
class Revision:
    """A revision with its request (canonical SI, as the endpoint validated it) and answer."""

    info: RevisionInfo
    request: Mapping[str, Any]
    answer: Mapping[str, Any] | None


@dataclass(frozen=True, slots=True)
class Project:
    """A project: name, when and by whom it was made [s], its designs and revisions [-]."""

    name: str
    created_at: float
    created_by: str
    designs: int
    revisions: int


def _iso(seconds: float | None) -> str | None:
    if seconds is None:
        return None
    return datetime.fromtimestamp(seconds, tz=timezone.utc).strftime("%Y-%m-%d")


def title_block(info: RevisionInfo) -> dict[str, Any]:
    """What a design record's title block shows for a revision: project, record number (project/design),
    revision, title, the designed/checked/approved names with their dates (UTC, YYYY-MM-DD), the state and the
    content hash the record is of."""
    return {"project": info.project, "record_number": f"{info.project}/{info.design}", "revision": info.number,
            "title": info.design, "designed_by": info.author, "designed_on": _iso(info.created_at),
            "checked_by": info.checked_by, "checked_on": _iso(info.checked_at), "approved_by": info.approved_by,
            "approved_on": _iso(info.approved_at), "state": info.state, "content_hash": info.content_hash,
            "deviation": info.deviation}


_INFO = (projects.c.name, designs.c.name, designs.c.endpoint, revisions.c.number, revisions.c.parent,
         revisions.c.content_hash, revisions.c.author, revisions.c.created_at, revisions.c.message,
         revisions.c.passed, revisions.c.state, revisions.c.checked_by, revisions.c.checked_at,
         revisions.c.approved_by, revisions.c.approved_at, revisions.c.superseded_by,
         revisions.c.record_pdf.is_not(None), revisions.c.deviation, revisions.c.imported_note, revisions.c.id)
_JOINED = revisions.join(designs, designs.c.id == revisions.c.design_id).join(
    projects, projects.c.id == designs.c.project_id)


def _info(row: Sequence[Any], comments: Mapping[int, list[Comment]] | None = None) -> RevisionInfo:
    return RevisionInfo(row[0], row[1], row[2], int(row[3]), row[4], row[5], row[6], float(row[7]), row[8],
                        None if row[9] is None else bool(row[9]), row[10], row[11], row[12], row[13], row[14],
                        row[15], bool(row[16]), row[17], row[18], tuple((comments or {}).get(int(row[19]), ())))


def _infos(db: sa.Connection, rows: Sequence[Sequence[Any]]) -> list[RevisionInfo]:
    """The revisions of ``rows`` (selected with ``_INFO`` first) with their comments."""
    ids = [int(r[19]) for r in rows]
    found: dict[int, list[Comment]] = {}
    for k in range(0, len(ids), 500):
        for c in db.execute(sa.select(revision_comments.c.revision_id, revision_comments.c.author,
                                      revision_comments.c.created_at, revision_comments.c.kind,
                                      revision_comments.c.text)
                            .where(revision_comments.c.revision_id.in_(ids[k:k + 500]))
                            .order_by(revision_comments.c.created_at, revision_comments.c.id)):
            found.setdefault(int(c[0]), []).append(Comment(c[1], float(c[2]), c[3], c[4]))
    return [_info(r, found) for r in rows]


def failed_checks(answer: Mapping[str, Any] | None) -> list[str]:
    """What did not pass in a stored answer: the engine's problem, or the names of its failed checks."""
    if not answer:
        return []
    problem = answer.get("problem")
    if isinstance(problem, Mapping):
        return [f"{problem.get('title', 'refused')}: {problem.get('detail', '')}".strip()]
    checks = answer.get("checks")
    names = [str(c.get("label") or c.get("name") or "check") + (f" ({c['detail']})" if c.get("detail") else "")
             for c in checks
             if isinstance(c, Mapping) and c.get("passed") is False] if isinstance(checks, list) else []
    return names or (["the answer says it did not pass"] if answer.get("passed") is False else [])


def _wrong_state(where: str, number: int, state: str, role: str, needed: str) -> str:
    why = {"approved": " (an approved revision is frozen: save a new revision to change it)",
           "superseded": " (an approved revision is frozen: save a new revision to change it)",
           "returned": " (it was returned to its author: the author saves a new revision from it)",
           "imported": " (it was signed, if at all, on another service: restore it to make a revision of this "
                       "library, computed here, and sign that)"}
    return f"revision {number} of {where} is {state}; the {role} signs a {needed} revision{why.get(state, '')}"


class Library:
    """The design library in ``store``."""

    def __init__(self, store: Store) -> None:
        self.store = store

    # --- saving ----------------------------------------------------------------------------------------------

    def head(self, project: str, design: str) -> int | None:
        """The latest revision number of a design, None when the design does not exist yet."""
        with self.store.read() as db:
            return self._head(db, project, design)

    @staticmethod
    def _head(db: sa.Connection, project: str, design: str) -> int | None:
        number: int | None = db.scalar(sa.select(sa.func.max(revisions.c.number)).select_from(_JOINED)
                                       .where(projects.c.name == project, designs.c.name == design))
        return number

    def check_parent(self, project: str, design: str, parent: int | None, branch: bool) -> None:
        """Refuse a save from ``parent`` before its answer is computed: :class:`StaleParent` when it would
        overwrite a later revision, :class:`NotFound` when a branch's parent does not exist."""
        with self.store.read() as db:
            self._check_parent(db, project, design, parent, branch, self._head(db, project, design))

    def _check_parent(self, db: sa.Connection, project: str, design: str, parent: int | None, branch: bool,
                      head: int | None) -> None:
        where = f"{project}/{design}"
        if branch:
            if parent is None or head is None or not 1 <= parent <= head:
                raise NotFound(f"{where} has no revision {parent} to branch from")
            return
        if parent != head:
            if head is None:
                raise NotFound(f"{where} has no revision {parent}: a design's first save has no parent")
            raise StaleParent(f"{where} is at revision {head}, not {parent}: this save would overwrite revision "
                              f"{head}. Start from revision {head} (see the diff from {parent}), or save with "
                              f"branch: true to keep both", head=head)

    def save(self, project: str, design: str, endpoint: str, request: Mapping[str, Any], *, author: str,
             message: str, parent: int | None, branch: bool = False, answer: Mapping[str, Any] | None = None,
             passed: bool | None = None, record_pdf: bytes | None = None,
             created_at: float | None = None) -> RevisionInfo:
        """Store a new revision of ``project``/``design`` (both made on their first save) from ``parent``, dated
        ``created_at`` [s since the epoch] (default now: the date its design record was written with).

        :class:`StaleParent` when ``parent`` is not the latest revision and ``branch`` is false,
        :class:`InvalidDocument` when the design holds requests of another endpoint.
        """
        text = canonical_json(request)
        for attempt in range(2):
            try:
                number = self._insert(project, design, endpoint, text, author=author, message=message, parent=parent,
                                      branch=branch, answer=answer, passed=passed, record_pdf=record_pdf,
                                      created_at=created_at)
                break
            except sa.exc.IntegrityError:
                head = self.head(project, design)
                if attempt == 0 and (head is None or head == parent):
                    continue    # another save made the same new project or design first: this one goes on top
                # another save of the same design committed first: this one starts from a stale parent
                raise StaleParent(f"{project}/{design} moved to revision {head} while this save was made: it "
                                  f"would overwrite revision {head}", head=head or 0) from None
        return self.info(project, design, number)

    def _insert(self, project: str, design: str, endpoint: str, text: str, *, author: str, message: str,
                parent: int | None, branch: bool, answer: Mapping[str, Any] | None, passed: bool | None,
                record_pdf: bytes | None, created_at: float | None) -> int:
        now = time.time() if created_at is None else created_at
        with self.store.write() as db:
            project_id = db.scalar(sa.select(projects.c.id).where(projects.c.name == project))
            if project_id is None:
                project_id = db.execute(projects.insert().values(name=project, created_at=now,
                                                                 created_by=author)
                                        .returning(projects.c.id)).scalar_one()
            found = db.execute(sa.select(designs.c.id, designs.c.endpoint)
                               .where(designs.c.project_id == project_id, designs.c.name == design)).one_or_none()
            if found is None:
                self._check_parent(db, project, design, parent, branch, None)
                design_id = db.execute(designs.insert().values(project_id=project_id, name=design,
                                                               endpoint=endpoint, created_at=now,
                                                               created_by=author)
                                       .returning(designs.c.id)).scalar_one()
                head = None
            else:
                design_id, kept = found
                if kept != endpoint:
                    raise InvalidDocument(f"{project}/{design} holds {kept} requests, not {endpoint}: save "
                                          "this one as another design", field="endpoint")
                head = db.scalar(sa.select(sa.func.max(revisions.c.number))
                                 .where(revisions.c.design_id == design_id))
                self._check_parent(db, project, design, parent, branch, head)
            number = (head or 0) + 1
            db.execute(revisions.insert().values(
                design_id=design_id, number=number, parent=parent, request=text,
                content_hash=hashlib.sha256(text.encode("utf-8")).hexdigest(), author=author, created_at=now,
                message=message, answer=None if answer is None else canonical_json(answer), passed=passed,
                record_pdf=record_pdf, state="draft"))
        return number

    # --- reading ---------------------------------------------------------------------------------------------

    def info(self, project: str, design: str, number: int) -> RevisionInfo:
        """A revision's summary; :class:`NotFound` when there is none."""
        with self.store.read() as db:
            row = db.execute(sa.select(*_INFO).select_from(_JOINED).where(
                projects.c.name == project, designs.c.name == design, revisions.c.number == number)).one_or_none()
            if row is None:
                raise NotFound(f"{project}/{design} has no revision {number}")
            return _infos(db, [row])[0]

    def revision(self, project: str, design: str, number: int) -> Revision:
        """A revision with its request and answer; :class:`NotFound` when there is none."""
        with self.store.read() as db:
            row = db.execute(sa.select(*_INFO, revisions.c.request, revisions.c.answer).select_from(_JOINED).where(
                projects.c.name == project, designs.c.name == design, revisions.c.number == number)).one_or_none()
            if row is None:
                raise NotFound(f"{project}/{design} has no revision {number}")
            info = _infos(db, [row])[0]
        return Revision(info, json.loads(row[-2]), None if row[-1] is None else json.loads(row[-1]))

    def record_pdf(self, project: str, design: str, number: int) -> bytes:
        """The design record kept with a revision; :class:`NotFound` when the revision or its record is missing."""
        with self.store.read() as db:
            row = db.execute(sa.select(revisions.c.record_pdf).select_from(_JOINED).where(
                projects.c.name == project, designs.c.name == design, revisions.c.number == number)).one_or_none()
        if row is None:
            raise NotFound(f"{project}/{design} has no revision {number}")
        if row[0] is None:
            raise NotFound(f"revision {number} of {project}/{design} has no design record: records are kept for "
                           "machine designs")
        return bytes(row[0])

    def sign_record(self, project: str, design: str, number: int, pdf: bytes) -> None:
        """Keep ``pdf`` as a revision's design record: the same design with the title block as signed now (the
        record of a revision is only ever rewritten for its title block)."""
        with self.store.write() as db:
            design_id = db.scalar(sa.select(designs.c.id).join(projects, projects.c.id == designs.c.project_id)
                                  .where(projects.c.name == project, designs.c.name == design))
            db.execute(revisions.update().where(revisions.c.design_id == design_id, revisions.c.number == number,
                                                revisions.c.record_pdf.is_not(None)).values(record_pdf=pdf))

    def history(self, project: str, design: str) -> list[RevisionInfo]:
        """Every revision of a design, oldest first; :class:`NotFound` when the design does not exist."""
        with self.store.read() as db:
            rows = db.execute(sa.select(*_INFO).select_from(_JOINED).where(
                projects.c.name == project, designs.c.name == design).order_by(revisions.c.number)).all()
            if not rows:
                raise NotFound(f"no design {design!r} in project {project!r}")
            return _infos(db, rows)

    def projects(self) -> list[Project]:
        """Every project by name, with its counts of designs and revisions."""
        counts = (sa.select(projects.c.name, projects.c.created_at, projects.c.created_by,
                            sa.func.count(sa.distinct(designs.c.id)), sa.func.count(revisions.c.id))
                  .select_from(projects.outerjoin(designs, designs.c.project_id == projects.c.id)
                               .outerjoin(revisions, revisions.c.design_id == designs.c.id))
                  .group_by(projects.c.id, projects.c.name, projects.c.created_at, projects.c.created_by)
                  .order_by(projects.c.name))
        with self.store.read() as db:
            return [Project(r[0], float(r[1]), r[2], int(r[3]), int(r[4])) for r in db.execute(counts)]

    def search(self, *, project: str | None = None, name: str | None = None, endpoint: str | None = None,
               author: str | None = None, since: float | None = None, until: float | None = None,
               passed: bool | None = None, state: str | None = None, deviation: bool | None = None,
               latest: bool = True, limit: int = 100, offset: int = 0) -> list[RevisionInfo]:
        """Revisions matching every filter given, newest first: ``name`` a part of the design's name (any case),
        ``since``/``until`` bounds on the save time [s]; ``deviation`` signed with (true) or without (false) a
        deviation; ``latest`` only each design's latest revision."""
        query = sa.select(*_INFO).select_from(_JOINED)
        if project is not None:
            query = query.where(projects.c.name == project)
        if name:
            query = query.where(sa.func.lower(designs.c.name).contains(name.lower(), autoescape=True))
        if endpoint is not None:
            query = query.where(designs.c.endpoint == endpoint)
        if author is not None:
            query = query.where(revisions.c.author == author)
        if since is not None:
            query = query.where(revisions.c.created_at >= since)
        if until is not None:
            query = query.where(revisions.c.created_at <= until)
        if passed is not None:
            query = query.where(revisions.c.passed.is_(passed))
        if state is not None:
            query = query.where(revisions.c.state == state)
        if deviation is not None:
            query = query.where(revisions.c.deviation.is_not(None) if deviation else revisions.c.deviation.is_(None))
        if latest:
            later = revisions.alias("later")
            query = query.where(~sa.exists().where(later.c.design_id == revisions.c.design_id,
                                                   later.c.number > revisions.c.number))
        query = query.order_by(revisions.c.created_at.desc(), revisions.c.id.desc()).limit(limit).offset(offset)
        with self.store.read() as db:
            return _infos(db, db.execute(query).all())

    # --- signing ---------------------------------------------------------------------------------------------

    def sign(self, project: str, design: str, number: int, *, role: str, name: str, deviation: str | None = None,
             comment: str | None = None) -> RevisionInfo:
        """Sign a revision as ``checker`` (a draft becomes checked) or ``approver`` (a checked one becomes approved
        and supersedes the design's approved revision), in one transaction that holds the design.

        Refused when the signer wrote it or signed it in the other role (:class:`SignOffRefused`), when it is not
        in the state the role signs or a later revision is approved (:class:`WrongState`), and when its answer
        did not pass and no ``deviation`` (the reason it is signed anyway) is given (:class:`FailedChecks`).
        ``comment`` is kept with the revision."""
        if role not in ("checker", "approver"):
            raise ValueError(f"unknown sign-off role {role!r}")
        needed, becomes = ("draft", "checked") if role == "checker" else ("checked", "approved")
        reason = (deviation or "").strip() or None
        where = f"{project}/{design}"
        now = time.time()
        try:
            with self.store.write() as db:
                design_id, row = self._locked(db, project, design, number)
                if name == row["author"]:
                    raise SignOffRefused(f"{name} wrote revision {number} of {where}: another person signs it as "
                                         f"{role}")
                if role == "approver" and name == row["checked_by"]:
                    raise SignOffRefused(f"{name} checked revision {number} of {where}: a third person approves it "
                                         "(author, checker and approver are three different people)")
                if row["state"] != needed:
                    raise WrongState(_wrong_state(where, number, row["state"], role, needed))
                if row["passed"] is False and reason is None:
                    failed = failed_checks(None if row["answer"] is None else json.loads(row["answer"]))
                    raise FailedChecks(f"revision {number} of {where} did not pass ({'; '.join(failed)}): it is not "
                                       f"signed unless the {role} states a deviation, the reason it is released "
                                       "anyway", failed=failed)
                later = db.scalar(sa.select(sa.func.max(revisions.c.number)).where(
                    revisions.c.design_id == design_id, revisions.c.state == "approved"))
                if role == "approver" and later is not None and later > number:
                    raise WrongState(f"revision {later} of {where} is approved, a later one than {number}: an older "
                                     f"revision is not approved over it. Restore revision {number} (a new revision "
                                     "with its request) and sign that")
                who, when = ((revisions.c.checked_by, revisions.c.checked_at) if role == "checker"
                             else (revisions.c.approved_by, revisions.c.approved_at))
                if becomes == "approved":
                    db.execute(revisions.update().where(revisions.c.design_id == design_id,
                                                        revisions.c.state == "approved")
                               .values(state="superseded", superseded_by=number))
                values: dict[Any, Any] = {revisions.c.state: becomes, who: name, when: now}
                if reason is not None and row["passed"] is False:
                    values[revisions.c.deviation] = reason
                    self._comment(db, row["id"], name, now, "deviation", reason)
                db.execute(revisions.update().where(revisions.c.id == row["id"]).values(values))
                if comment and comment.strip():
                    self._comment(db, row["id"], name, now, "check" if role == "checker" else "approve", comment)
        except sa.exc.IntegrityError:
            # the unique index on approved revisions: another server approved one of this design meanwhile
            raise WrongState(f"another revision of {where} was approved at the same moment; look at its history "
                             "and sign again") from None
        return self.info(project, design, number)

    def return_revision(self, project: str, design: str, number: int, *, name: str, comment: str) -> RevisionInfo:
        """Return a draft or checked revision to its author with ``comment`` (kept): it becomes ``returned`` and
        is signed no more; the author saves a new revision from it."""
        text = comment.strip()
        if not text:
            raise InvalidDocument("say why the revision is returned: a comment is required", field="comment")
        where = f"{project}/{design}"
        now = time.time()
        with self.store.write() as db:
            _, row = self._locked(db, project, design, number)
            if name == row["author"]:
                raise SignOffRefused(f"{name} wrote revision {number} of {where}: its checker or approver returns "
                                     "it (the author saves a new revision instead)")
            if row["state"] not in ("draft", "checked"):
                raise WrongState(_wrong_state(where, number, row["state"], "returner", "draft or checked"))
            db.execute(revisions.update().where(revisions.c.id == row["id"]).values(state="returned"))
            self._comment(db, row["id"], name, now, "returned", text)
        return self.info(project, design, number)

    def comment(self, project: str, design: str, number: int, *, name: str, text: str) -> RevisionInfo:
        """Keep a comment on a revision (any state; a comment signs nothing)."""
        if not text.strip():
            raise InvalidDocument("a comment has text", field="text")
        with self.store.write() as db:
            _, row = self._locked(db, project, design, number)
            self._comment(db, row["id"], name, time.time(), "comment", text.strip())
        return self.info(project, design, number)

    @staticmethod
    def _comment(db: sa.Connection, revision_id: int, author: str, when: float, kind: str, text: str) -> None:
        db.execute(revision_comments.insert().values(revision_id=revision_id, author=author, created_at=when,
                                                     kind=kind, text=text.strip()))

    @staticmethod
    def _locked(db: sa.Connection, project: str, design: str, number: int) -> tuple[int, Mapping[str, Any]]:
        """The design's id, held until the transaction ends (PostgreSQL: a row lock; SQLite's writer holds the
        whole file), and the revision's row; :class:`NotFound` when either is missing."""
        design_id = db.scalar(sa.select(designs.c.id).join(projects, projects.c.id == designs.c.project_id)
                              .where(projects.c.name == project, designs.c.name == design)
                              .with_for_update(of=designs))
        row = None if design_id is None else db.execute(
            sa.select(revisions.c.id, revisions.c.author, revisions.c.state, revisions.c.passed,
                      revisions.c.answer, revisions.c.checked_by)
            .where(revisions.c.design_id == design_id, revisions.c.number == number)).mappings().one_or_none()
        if design_id is None or row is None:
            raise NotFound(f"{project}/{design} has no revision {number}")
        return int(design_id), dict(row)

    # --- export and import -----------------------------------------------------------------------------------

    def export(self, project: str) -> dict[str, Any]:
        """Every design and revision of a project, with answers and records (base64), as one JSON document that
        :meth:`import_project` takes on another store; :class:`NotFound` when there is no such project."""
        with self.store.read() as db:
            found = db.execute(sa.select(projects.c.id, projects.c.created_at, projects.c.created_by)
                               .where(projects.c.name == project)).one_or_none()
            if found is None:
                raise NotFound(f"no project {project!r}")
            project_id, created_at, created_by = found
            out_designs = []
            for d in db.execute(sa.select(designs.c.id, designs.c.name, designs.c.endpoint, designs.c.created_at,
                                          designs.c.created_by).where(designs.c.project_id == project_id)
                                .order_by(designs.c.name)).all():
                rows = db.execute(sa.select(revisions).where(revisions.c.design_id == d[0])
                                  .order_by(revisions.c.number)).mappings().all()
                comments: dict[int, list[Comment]] = {}
                for c in db.execute(sa.select(revision_comments).join(
                        revisions, revisions.c.id == revision_comments.c.revision_id)
                        .where(revisions.c.design_id == d[0])
                        .order_by(revision_comments.c.created_at, revision_comments.c.id)).mappings():
                    comments.setdefault(int(c["revision_id"]), []).append(
                        Comment(c["author"], float(c["created_at"]), c["kind"], c["text"]))
                out_designs.append({
                    "name": d[1], "endpoint": d[2], "created_at": d[3], "created_by": d[4],
                    "revisions": [{
                        "number": r["number"], "parent": r["parent"], "request": json.loads(r["request"]),
                        "content_hash": r["content_hash"], "author": r["author"], "created_at": r["created_at"],
                        "message": r["message"], "answer": None if r["answer"] is None else json.loads(r["answer"]),
                        "passed": r["passed"], "state": r["state"], "checked_by": r["checked_by"],
                        "checked_at": r["checked_at"], "approved_by": r["approved_by"],
                        "approved_at": r["approved_at"], "superseded_by": r["superseded_by"],
                        "deviation": r["deviation"], "imported_note": r["imported_note"],
                        "comments": [{"author": c.author, "created_at": c.created_at, "kind": c.kind,
                                      "text": c.text} for c in comments.get(int(r["id"]), [])],
                        "record_pdf_base64": None if r["record_pdf"] is None
                        else base64.b64encode(r["record_pdf"]).decode("ascii"),
                    } for r in rows]})
        return {"format": EXPORT_FORMAT, "project": project, "created_at": created_at, "created_by": created_by,
                "exported_at": time.time(), "designs": out_designs}

    def import_project(self, document: Mapping[str, Any], *, importer: str) -> Project:
        """Store an exported project's history: numbers, authors, times, messages, requests and their hashes
        (every hash checked against its request first: :class:`InvalidDocument` names one that does not match);
        :class:`ProjectExists` when the project is here already.

        Nothing in a file can sign here: every revision arrives ``imported``, unsigned, with what it claimed (its
        state, who checked and approved it, whether it passed, its deviation and comments) kept only as a note
        saying nobody here verified it; its answer is kept as one computed elsewhere (``passed`` unknown), and its
        design record, whose title block carries those claims, is left behind. Restoring an imported revision
        makes a revision of this library, its answer and record computed here, to be signed here.
        """
        if document.get("format") != EXPORT_FORMAT:
            raise InvalidDocument(f"not a library export: format must be {EXPORT_FORMAT!r}", field="format")
        name = document["project"]
        for d, design in enumerate(document["designs"]):
            for k, r in enumerate(design["revisions"]):
                if content_hash(r["request"]) != r["content_hash"]:
                    raise InvalidDocument(f"revision {r['number']} of {name}/{design['name']}: its request does not "
                                          "hash to its content_hash; the document was changed after export",
                                          field=f"designs.{d}.revisions.{k}.content_hash")
        now = time.time()
        try:
            with self.store.write() as db:
                project_id = db.execute(projects.insert().values(
                    name=name, created_at=document["created_at"], created_by=document["created_by"])
                    .returning(projects.c.id)).scalar_one()
                for design in document["designs"]:
                    design_id = db.execute(designs.insert().values(
                        project_id=project_id, name=design["name"], endpoint=design["endpoint"],
                        created_at=design["created_at"], created_by=design["created_by"])
                        .returning(designs.c.id)).scalar_one()
                    if design["revisions"]:
                        db.execute(revisions.insert(), [{
                            "design_id": design_id, "number": r["number"], "parent": r["parent"],
                            "request": canonical_json(r["request"]), "content_hash": r["content_hash"],
                            "author": r["author"], "created_at": r["created_at"], "message": r["message"],
                            "answer": None if r["answer"] is None else canonical_json(r["answer"]),
                            "passed": None, "state": "imported", "record_pdf": None,
                            "imported_note": imported_note(document, r, importer, now),
                        } for r in design["revisions"]])
        except sa.exc.IntegrityError:
            raise ProjectExists(f"project {name!r} exists in this library already; import it under another "
                                "name or remove it first") from None
        return next(p for p in self.projects() if p.name == name)


def imported_note(document: Mapping[str, Any], r: Mapping[str, Any], importer: str, now: float) -> str:
    """What an imported revision claimed, as text that says nobody here verified it."""
    def on(seconds: Any) -> str:
        return f" on {_iso(float(seconds))}" if isinstance(seconds, (int, float)) else ""

    claims = [f"exported from project {document['project']!r} as {r.get('state') or 'unknown'}"]
    if r.get("checked_by"):
        claims.append(f"checked by {r['checked_by']}{on(r.get('checked_at'))}")
    if r.get("approved_by"):
        claims.append(f"approved by {r['approved_by']}{on(r.get('approved_at'))}")
    if r.get("passed") is not None:
        claims.append("its answer said it " + ("passed" if r["passed"] else "failed"))
    if r.get("deviation"):
        claims.append(f"deviation: {r['deviation']}")
    if r.get("imported_note"):
        claims.append(f"it had been imported before: {r['imported_note']}")
    for c in r.get("comments") or ():
        claims.append(f"{c.get('kind', 'comment')} by {c.get('author', '?')}{on(c.get('created_at'))}: "
                      f"{c.get('text', '')}")
    return (f"Imported by {importer} on {_iso(now)}; claims not verified by this service (signatures and answer "
            f"made elsewhere): " + "; ".join(claims))[:4000]
