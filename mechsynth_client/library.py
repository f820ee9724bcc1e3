"""The client's side of the design library: ``client.library.save(...)``, history, search, diff, restore,
sign-off, export and import, over the same models the service answers with.

>>> rev = client.library.save("press", "linkage", "/v1/balancing/static", BalanceIn(...), message="first",
...                           author="ann")
>>> client.library.diff("press", "linkage", 1, 2).request      # the inputs that changed, with units
"""

from __future__ import annotations

from datetime import datetime
from typing import Any, Literal, Protocol

import httpx
from pydantic import BaseModel

from .schemas.library import (
    DesignOut,
    DiffOut,
    LibraryExport,
    ProjectOut,
    RevisionDetailOut,
    RevisionOut,
)


class Sender(Protocol):
    """What the library needs of a client: one request, retried while busy, a problem raised as an error."""

    def _send(self, method: str, path: str, **kwargs: Any) -> httpx.Response: ...


def _body(request: BaseModel | dict[str, Any]) -> dict[str, Any]:
    if isinstance(request, BaseModel):
        dumped: dict[str, Any] = request.model_dump(mode="json", exclude_none=True)
        return dumped
    return request


def _sign_body(name: str | None, deviation: str | None, comment: str | None) -> dict[str, Any]:
    return {k: v for k, v in {"name": name, "deviation": deviation, "comment": comment}.items() if v is not None}


def _search_params(project: str | None, name: str | None, endpoint: str | None, author: str | None,
                   since: datetime | None, until: datetime | None, passed: bool | None, state: str | None,
                   latest: bool, offset: int, limit: int, deviation: bool | None = None) -> dict[str, Any]:
    params: dict[str, Any] = {"project": project, "name": name, "endpoint": endpoint, "author": author,
                              "since": since.isoformat() if since else None,
                              "until": until.isoformat() if until else None,
                              "passed": None if passed is None else str(passed).lower(), "state": state,
                              "latest": str(latest).lower(), "offset": offset, "limit": limit,
                              "deviation": None if deviation is None else str(deviation).lower()}
    return {k: v for k, v in params.items() if v is not None}


class LibraryClient:
    """The design library of the service a client speaks to."""

    def __init__(self, client: Sender) -> None:
        self.client = client

    @staticmethod
    def _design(project: str, design: str) -> str:
        return f"/v1/library/projects/{project}/designs/{design}"

    def save(self, project: str, design: str, endpoint: str, request: BaseModel | dict[str, Any], *,
             message: str = "", parent: int | None = None, branch: bool = False,
             author: str | None = None) -> RevisionOut:
        """Save ``request`` (for ``endpoint``) as the next revision of ``project``/``design``, made from revision
        ``parent`` (None for a design's first); a stale parent raises a 409 problem unless ``branch``."""
        body = {"endpoint": endpoint, "request": _body(request), "message": message, "parent": parent,
                "branch": branch, "author": author}
        response = self.client._send("POST", f"{self._design(project, design)}/revisions", json=body)
        return RevisionOut.model_validate_json(response.content)

    def projects(self) -> list[ProjectOut]:
        """Every project, with its counts of designs and revisions."""
        return [ProjectOut.model_validate(p) for p in self.client._send("GET", "/v1/library/projects").json()]

    def search(self, *, project: str | None = None, name: str | None = None, endpoint: str | None = None,
               author: str | None = None, since: datetime | None = None, until: datetime | None = None,
               passed: bool | None = None, state: str | None = None, latest: bool = True, offset: int = 0,
               deviation: bool | None = None,
               limit: int = 100) -> list[RevisionOut]:
        """Revisions matching every filter given, newest first (each design's latest only, unless ``latest`` is
        false)."""
        params = _search_params(project, name, endpoint, author, since, until, passed, state, latest, offset, limit,
                                deviation)
        response = self.client._send("GET", "/v1/library/revisions", params=params)
        return [RevisionOut.model_validate(r) for r in response.json()]

    def history(self, project: str, design: str) -> DesignOut:
        """Every revision of a design, oldest first."""
        return DesignOut.model_validate_json(self.client._send("GET", self._design(project, design)).content)

    def revision(self, project: str, design: str, number: int) -> RevisionDetailOut:
        """A revision with its request and answer."""
        response = self.client._send("GET", f"{self._design(project, design)}/revisions/{number}")
        return RevisionDetailOut.model_validate_json(response.content)

    def record_pdf(self, project: str, design: str, number: int) -> bytes:
        """The design record (PDF) kept with a machine design's revision."""
        return self.client._send("GET", f"{self._design(project, design)}/revisions/{number}/record").content

    def diff(self, project: str, design: str, before: int, after: int) -> DiffOut:
        """The inputs and the figures of the answer that changed from revision ``before`` to ``after``."""
        response = self.client._send("GET", f"{self._design(project, design)}/diff",
                                     params={"from": before, "to": after})
        return DiffOut.model_validate_json(response.content)

    def restore(self, project: str, design: str, number: int, *, message: str = "",
                author: str | None = None) -> RevisionOut:
        """Make revision ``number``'s request the design's newest revision."""
        response = self.client._send("POST", f"{self._design(project, design)}/revisions/{number}/restore",
                                     json={"message": message, "author": author})
        return RevisionOut.model_validate_json(response.content)

    def _sign(self, action: Literal["check", "approve"], project: str, design: str, number: int,
              name: str | None, deviation: str | None, comment: str | None) -> RevisionOut:
        response = self.client._send("POST", f"{self._design(project, design)}/revisions/{number}/{action}",
                                     json=_sign_body(name, deviation, comment))
        return RevisionOut.model_validate_json(response.content)

    def check(self, project: str, design: str, number: int, *, name: str | None = None,
              deviation: str | None = None, comment: str | None = None) -> RevisionOut:
        """Sign a draft revision as its checker (never its author); one that failed a check needs
        ``deviation``, the reason it is passed on anyway."""
        return self._sign("check", project, design, number, name, deviation, comment)

    def approve(self, project: str, design: str, number: int, *, name: str | None = None,
                deviation: str | None = None, comment: str | None = None) -> RevisionOut:
        """Approve a checked revision (neither its author nor its checker); it is frozen from then on and the
        design's approved revision before it is superseded. One that failed a check needs ``deviation``."""
        return self._sign("approve", project, design, number, name, deviation, comment)

    def return_revision(self, project: str, design: str, number: int, comment: str, *,
                        name: str | None = None) -> RevisionOut:
        """Return a draft or checked revision to its author with ``comment``."""
        response = self.client._send("POST", f"{self._design(project, design)}/revisions/{number}/return",
                                     json={"comment": comment, "name": name})
        return RevisionOut.model_validate_json(response.content)

    def comment(self, project: str, design: str, number: int, text: str, *, name: str | None = None
                ) -> RevisionOut:
        """Keep a comment on a revision."""
        response = self.client._send("POST", f"{self._design(project, design)}/revisions/{number}/comments",
                                     json={"text": text, "name": name})
        return RevisionOut.model_validate_json(response.content)

    def export(self, project: str) -> LibraryExport:
        """The whole project as one document (every revision with its answer and record)."""
        response = self.client._send("GET", f"/v1/library/projects/{project}/export")
        return LibraryExport.model_validate_json(response.content)

    def import_project(self, document: LibraryExport) -> ProjectOut:
        """Import an exported project, hashes checked: every revision arrives ``imported``, unsigned."""
        response = self.client._send("POST", "/v1/library/import", json=document.model_dump(mode="json"))
        return ProjectOut.model_validate_json(response.content)


class AsyncSender(Protocol):
    """The same as :class:`Sender`, as a coroutine."""

    async def _send(self, method: str, path: str, **kwargs: Any) -> httpx.Response: ...


class AsyncLibraryClient:
    """:class:`LibraryClient`'s methods as coroutines, for :class:`~mechsynth_client.client.AsyncSynthClient`."""

    def __init__(self, client: AsyncSender) -> None:
        self.client = client

    async def save(self, project: str, design: str, endpoint: str, request: BaseModel | dict[str, Any], *,
                   message: str = "", parent: int | None = None, branch: bool = False,
                   author: str | None = None) -> RevisionOut:
        """See :meth:`LibraryClient.save`."""
        body = {"endpoint": endpoint, "request": _body(request), "message": message, "parent": parent,
                "branch": branch, "author": author}
        response = await self.client._send("POST", f"{LibraryClient._design(project, design)}/revisions", json=body)
        return RevisionOut.model_validate_json(response.content)

    async def projects(self) -> list[ProjectOut]:
        """See :meth:`LibraryClient.projects`."""
        response = await self.client._send("GET", "/v1/library/projects")
        return [ProjectOut.model_validate(p) for p in response.json()]

    async def search(self, *, project: str | None = None, name: str | None = None, endpoint: str | None = None,
                     author: str | None = None, since: datetime | None = None, until: datetime | None = None,
                     passed: bool | None = None, state: str | None = None, latest: bool = True, offset: int = 0,
               deviation: bool | None = None,
                     limit: int = 100) -> list[RevisionOut]:
        """See :meth:`LibraryClient.search`."""
        params = _search_params(project, name, endpoint, author, since, until, passed, state, latest, offset, limit,
                                deviation)
        response = await self.client._send("GET", "/v1/library/revisions", params=params)
        return [RevisionOut.model_validate(r) for r in response.json()]

    async def record_pdf(self, project: str, design: str, number: int) -> bytes:
        """See :meth:`LibraryClient.record_pdf`."""
        path = f"{LibraryClient._design(project, design)}/revisions/{number}/record"
        return (await self.client._send("GET", path)).content

    async def restore(self, project: str, design: str, number: int, *, message: str = "",
                      author: str | None = None) -> RevisionOut:
        """See :meth:`LibraryClient.restore`."""
        response = await self.client._send(
            "POST", f"{LibraryClient._design(project, design)}/revisions/{number}/restore",
            json={"message": message, "author": author})
        return RevisionOut.model_validate_json(response.content)

    async def history(self, project: str, design: str) -> DesignOut:
        """See :meth:`LibraryClient.history`."""
        response = await self.client._send("GET", LibraryClient._design(project, design))
        return DesignOut.model_validate_json(response.content)

    async def revision(self, project: str, design: str, number: int) -> RevisionDetailOut:
        """See :meth:`LibraryClient.revision`."""
        response = await self.client._send("GET", f"{LibraryClient._design(project, design)}/revisions/{number}")
        return RevisionDetailOut.model_validate_json(response.content)

    async def diff(self, project: str, design: str, before: int, after: int) -> DiffOut:
        """See :meth:`LibraryClient.diff`."""
        response = await self.client._send("GET", f"{LibraryClient._design(project, design)}/diff",
                                           params={"from": before, "to": after})
        return DiffOut.model_validate_json(response.content)

    async def check(self, project: str, design: str, number: int, *, name: str | None = None,
                    deviation: str | None = None, comment: str | None = None) -> RevisionOut:
        """See :meth:`LibraryClient.check`."""
        response = await self.client._send(
            "POST", f"{LibraryClient._design(project, design)}/revisions/{number}/check",
            json=_sign_body(name, deviation, comment))
        return RevisionOut.model_validate_json(response.content)

    async def approve(self, project: str, design: str, number: int, *, name: str | None = None,
                      deviation: str | None = None, comment: str | None = None) -> RevisionOut:
        """See :meth:`LibraryClient.approve`."""
        response = await self.client._send(
            "POST", f"{LibraryClient._design(project, design)}/revisions/{number}/approve",
            json=_sign_body(name, deviation, comment))
        return RevisionOut.model_validate_json(response.content)

    async def return_revision(self, project: str, design: str, number: int, comment: str, *,
                              name: str | None = None) -> RevisionOut:
        """See :meth:`LibraryClient.return_revision`."""
        response = await self.client._send(
            "POST", f"{LibraryClient._design(project, design)}/revisions/{number}/return",
            json={"comment": comment, "name": name})
        return RevisionOut.model_validate_json(response.content)

    async def comment(self, project: str, design: str, number: int, text: str, *, name: str | None = None
                      ) -> RevisionOut:
        """See :meth:`LibraryClient.comment`."""
        response = await self.client._send(
            "POST", f"{LibraryClient._design(project, design)}/revisions/{number}/comments",
            json={"text": text, "name": name})
        return RevisionOut.model_validate_json(response.content)

    async def export(self, project: str) -> LibraryExport:
        """See :meth:`LibraryClient.export`."""
        response = await self.client._send("GET", f"/v1/library/projects/{project}/export")
        return LibraryExport.model_validate_json(response.content)

    async def import_project(self, document: LibraryExport) -> ProjectOut:
        """See :meth:`LibraryClient.import_project`."""
        response = await self.client._send("POST", "/v1/library/import", json=document.model_dump(mode="json"))
        return ProjectOut.model_validate_json(response.content)
