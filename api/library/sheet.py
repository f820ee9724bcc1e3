"""What a design record says of its revision beyond the design itself: the title block, the revision's date (when
it was saved, never when the record is downloaded), the revision table (every revision of the design up to this
one, with its state, signers, deviation and comments) and the change note (each input that differs from the
previous approved revision, with its unit). Read from the store in the service; the worker writes it."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from datetime import datetime, timezone
from typing import Any

from store.library import Comment, Library, NotFound, RevisionInfo, title_block

from .diff import request_changes
from .tasks import record_title_block


def _stamp(seconds: float) -> str:
    return datetime.fromtimestamp(seconds, tz=timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC")


def _day(seconds: float | None) -> str:
    return "" if seconds is None else datetime.fromtimestamp(seconds, tz=timezone.utc).strftime("%Y-%m-%d")


def _value(v: Any) -> str:
    if v is None:
        return "—"
    if isinstance(v, float):
        return f"{v:.6g}"
    return str(v)


def comment_text(comments: Sequence[Comment]) -> str:
    """A revision's comments in one cell: ``kind by who on day: text``, oldest first."""
    kinds = {"returned": "returned", "check": "checker's remark", "approve": "approver's remark",
             "deviation": "deviation", "comment": "comment"}
    return "; ".join(f"{kinds.get(c.kind, c.kind)} by {c.author} on {_day(c.created_at)}: {c.text}"
                     for c in comments)


def _row(r: RevisionInfo) -> dict[str, str]:
    return {"number": str(r.number), "date": _day(r.created_at), "author": r.author, "message": r.message,
            "state": r.state, "checked": f"{r.checked_by} {_day(r.checked_at)}" if r.checked_by else "",
            "approved": f"{r.approved_by} {_day(r.approved_at)}" if r.approved_by else "",
            "deviation": r.deviation or "", "comments": comment_text(r.comments)}


def _change_note(library: Library, project: str, design: str, number: int, earlier: Sequence[RevisionInfo],
                 request: Mapping[str, Any]) -> dict[str, Any]:
    approved = [r for r in earlier if r.number < number and r.approved_by is not None]
    if not approved:
        return {"against": "", "rows": []}
    previous = max(approved, key=lambda r: r.number)
    before = library.revision(project, design, previous.number).request
    rows = [[c.path, c.unit, _value(c.before), _value(c.after)] for c in request_changes(before, request)]
    return {"against": f"revision {previous.number} (approved by {previous.approved_by} on "
                       f"{_day(previous.approved_at)})", "rows": rows}


def revision_sheet(library: Library, project: str, design: str, number: int) -> dict[str, Any]:
    """The sheet of a kept revision as it stands now (store reads: call it in a thread)."""
    history = library.history(project, design)
    up_to = [r for r in history if r.number <= number]
    this = next((r for r in up_to if r.number == number), None)
    if this is None:
        raise NotFound(f"{project}/{design} has no revision {number}")
    request = library.revision(project, design, number).request
    block = {**record_title_block(title_block(this)), "deviation": this.deviation or ""}
    return {"title_block": block, "created": _stamp(this.created_at), "revisions": [_row(r) for r in up_to],
            "change_note": _change_note(library, project, design, number, up_to, request)}


def draft_sheet(library: Library, project: str, design: str, number: int, author: str, message: str,
                created_at: float, request: Mapping[str, Any]) -> dict[str, Any]:
    """The sheet of the revision a save is about to make: number ``number``, a draft dated ``created_at``."""
    try:
        earlier = library.history(project, design)
    except NotFound:
        earlier = []
    block = record_title_block({"project": project, "record_number": f"{project}/{design}", "revision": number,
                                "title": design, "designed_by": author, "designed_on": _day(created_at),
                                "state": "draft"})
    pending = {"number": str(number), "date": _day(created_at), "author": author, "message": message,
               "state": "draft", "checked": "", "approved": "", "deviation": "", "comments": ""}
    return {"title_block": {**block, "deviation": ""}, "created": _stamp(created_at),
            "revisions": [*(_row(r) for r in earlier), pending],
            "change_note": _change_note(library, project, design, number, earlier, request)}
