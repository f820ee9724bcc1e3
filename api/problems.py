"""The one place that maps engine errors and bad requests to RFC 9457 problem responses."""

from __future__ import annotations

import asyncio
import logging
import math
import os
import sys
import tempfile
import uuid
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.routing import Match
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from synth.errors import (
    Infeasible,
    InvalidInput,
    NotAssemblable,
    SolverFailed,
    SolverTimeout,
    SynthError,
    TooLarge,
    WorkerLost,
)

from store import StoreUnavailable
from store.library import (
    FailedChecks,
    InvalidDocument,
    LibraryError,
    NotFound,
    ProjectExists,
    SignOffRefused,
    StaleParent,
    WrongState,
)

from . import validation
from .settings import Settings
from .execution.admission import Overloaded
from .library.access import Forbidden

log = logging.getLogger("api")

PROBLEM_JSON = "application/problem+json"
_STATUS: dict[type[SynthError], int] = {
    InvalidInput: 422,
    NotAssemblable: 422,
    Infeasible: 422,
    SolverFailed: 422,
    TooLarge: 413,
    SolverTimeout: 504,
    WorkerLost: 502,
}
# Every problem a POST operation can answer, documented in the OpenAPI document with the one Problem schema.
PROBLEM_STATUSES: dict[int, str] = {
    400: "The body is empty, not valid JSON (the detail says where), not UTF-8, nested deeper than the JSON reader "
         "allows, or not a JSON object: send a JSON object with content-type application/json.",
    408: "The client did not send its body within the body timeout.",
    413: "The body, or a count in it (samples, stages, sweep points), is beyond the service's limits.",
    415: "The body was sent with a content type other than JSON: send it as application/json.",
    422: "Input that cannot be satisfied: a field out of range, a linkage that cannot assemble, an infeasible "
         "target, a solver that failed.",
    502: "The worker process running the request died; the service goes on with a new worker.",
    503: "Every worker is busy and the queue is full; retry after the Retry-After header's seconds.",
    504: "The request's work did not finish within its deadline; the answer says how far it got.",
}
PROBLEM_SCHEMA: dict[str, Any] = {
    "title": "Problem",
    "type": "object",
    "description": "RFC 9457 problem details, with fields that help act on the problem (field, angles, "
                   "constraint, solver status, limit).",
    "properties": {
        "type": {"type": "string", "description": "Relative URI naming the kind of problem."},
        "title": {"type": "string", "description": "Short summary of the kind of problem, the same for every "
                                                   "occurrence of it."},
        "status": {"type": "integer", "description": "HTTP status code of this answer."},
        "detail": {"type": "string", "description": "What went wrong with this request, in words."},
        "field": {"type": ["string", "null"], "description": "Dotted name of the offending input field, as the "
                                                             "JSON body spells it; for an answer that would hold a "
                                                             "number beyond any physical range or not finite, the "
                                                             "answer's field."},
        "stage": {"type": "string", "description": "The stage of a machine design that failed: analysis, "
                                                   "balancing, drive, teeth, flywheel, motor or simulation; of a "
                                                   "request past its deadline, queued or running."},
        "stage_index": {"type": "integer", "minimum": 0, "description": "The gear stage (0: motor side) that "
                                                                      "has no admissible design."},
        "constraint": {"type": "string", "description": "The limit that made the target infeasible."},
        "solver_status": {"type": "string", "description": "The solver's own status."},
        "limit": {"type": "integer", "description": "The size limit that was exceeded."},
        "got": {"type": "integer", "description": "The size asked for."},
        "limit_s": {"type": "number", "description": "The time limit that was exceeded [s]."},
        "errors": {"type": "array", "description": "Every validation error: field, message, type.",
                   "items": {"type": "object", "properties": {"field": {"type": "string"},
                                                              "message": {"type": "string"},
                                                              "type": {"type": "string"}},
                             "required": ["field", "message", "type"]}},
        "code": {"type": "string", "description": "The likely-mistake check that refused the input, e.g. "
                                                  "length_likely_mm."},
    },
    "required": ["type", "title", "status", "detail"],
    "additionalProperties": True,
}


def _finite(value: Any) -> Any:
    """Problem extras as finite JSON: non-finite numbers become null, numpy scalars and arrays plain values."""
    if isinstance(value, dict):
        return {str(k): _finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(v) for v in value]
    if isinstance(value, np.ndarray):
        return _finite(value.tolist())
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def problem(status: int, slug: str, title: str, detail: str, headers: Mapping[str, str] | None = None,
            **extras: Any) -> JSONResponse:
    """A problem+json response; ``type`` is a relative URI naming the kind of problem."""
    body = {"type": f"/problems/{slug}", "title": title, "status": status, "detail": detail, **_finite(extras)}
    return JSONResponse(body, status_code=status, media_type=PROBLEM_JSON, headers=headers)


def problem_response(exc: SynthError) -> JSONResponse:
    """Map an engine error to its status code and problem body."""
    status = next((_STATUS[c] for c in type(exc).__mro__ if c in _STATUS), 422)
    extras = exc.extras()
    if exc.stage is not None:
        extras["stage"] = exc.stage
    return problem(status, exc.slug, exc.title, str(exc), **extras)


async def _synth_handler(_: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, SynthError)
    return problem_response(exc)


#: What every answer to a body that is not a JSON object says to do.
SEND_JSON = "send JSON with content-type application/json"


def _body_problem(request: Request, body: Any) -> JSONResponse:
    """The body is missing, not JSON, or JSON that is not an object: say what to send."""
    ctype = request.headers.get("content-type", "")
    if body is None or body in (b"", ""):
        detail = f"the body is empty: {SEND_JSON}"
    elif ctype and "json" not in ctype:
        return problem(415, "unsupported-media-type", "Unsupported media type",
                       f"the body was sent as {ctype}, not as JSON: {SEND_JSON}", content_type=ctype)
    elif "json" not in ctype:
        detail = f"the body was sent with no content type, not as JSON: {SEND_JSON}"
    else:
        detail = f"the body is JSON but not an object of the request's fields ({{...}}): {SEND_JSON}"
    return problem(400, "json-body-expected", "JSON body expected", detail, content_type=ctype or None)


def _allowed(request: Request, body: Any, parent: list[str | int]) -> list[str]:
    """The fields the request schema allows at ``parent``; none when the operation has no JSON body schema."""
    # the path as the OpenAPI document lists it: the design endpoints have no path parameters
    doc = request.app.openapi()
    schema = validation.request_schema(doc, request.url.path, request.method)
    return [] if schema is None else validation.allowed_fields(schema, doc, body, parent)


async def _validation_handler(request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, RequestValidationError)
    raw = list(exc.errors())
    bad_json = next((e for e in raw if e.get("type") == "json_invalid"), None)
    if bad_json is not None:
        position = bad_json.get("loc", ("body", 0))[-1]
        return problem(400, "malformed-json", "Malformed JSON",
                       f"the body is not valid JSON ({bad_json.get('msg', '')} at character {position}): {SEND_JSON}",
                       position=position)
    body = exc.body
    in_body = [e for e in raw if tuple(e.get("loc", ()))[:1] == ("body",)]
    if not isinstance(body, Mapping) and in_body and all(len(tuple(e.get("loc", ()))) == 1 for e in in_body):
        return _body_problem(request, body)
    errors: list[dict[str, Any]] = []
    hint: dict[str, Any] = {}
    for e in raw:
        loc = tuple(e.get("loc", ()))
        path = validation.json_path(loc, body) if loc[:1] == ("body",) else [p for p in loc[1:]]
        field, message = validation.dotted(path), str(e.get("msg", ""))
        item: dict[str, Any] = {"field": field, "message": message, "type": e.get("type", "")}
        if e.get("type") == "extra_forbidden" and path and isinstance(path[-1], str):
            allowed = _allowed(request, body, path[:-1])
            close = validation.did_you_mean(path[-1], allowed)
            where = validation.dotted(path[:-1]) or "the body"
            message = f"{path[-1]!r} is not a field of {where}" + (f"; did you mean {close[0]!r}?" if close else "")
            if allowed:
                message += ("" if close else ".") + f" The fields there are: {', '.join(allowed)}"
            item.update(message=message, did_you_mean=close, valid=allowed)
            hint = {"did_you_mean": close, "valid": allowed}
        if item not in errors:
            errors.append(item)
    # of a union's several errors, the one that went furthest into the body is the one the client made
    first = max(errors, key=lambda e: len(str(e["field"]))) if errors else {"field": "", "message": "invalid request"}
    detail = f"{first['field']}: {first['message']}" if first["field"] else str(first["message"])
    return problem(422, "invalid-input", "Invalid input", detail, field=first["field"], errors=errors, **hint)


def _unreadable(exc: BaseException | None) -> JSONResponse | None:
    """The body could not be read as JSON text at all: say why (FastAPI's own answer names no reason)."""
    if isinstance(exc, UnicodeDecodeError):
        return problem(400, "body-not-utf8", "Body not UTF-8",
                       f"the body is not UTF-8 text: byte 0x{exc.object[exc.start]:02x} at position {exc.start} "
                       f"cannot start or continue a character: {SEND_JSON}", position=exc.start)
    if isinstance(exc, RecursionError):
        return problem(400, "json-too-deep", "JSON nested too deeply",
                       f"the body's arrays and objects are nested deeper than the JSON reader allows (about "
                       f"{sys.getrecursionlimit()} levels; a request needs fewer than ten): {SEND_JSON}")
    return None


_METHODS = ("GET", "HEAD", "POST", "PUT", "PATCH", "DELETE")


def _allow(request: Request) -> str:
    """Every method the request's path answers to, over all the routes that match it."""
    routes = request.app.router.routes
    return ", ".join(m for m in _METHODS
                     if any(r.matches({**request.scope, "method": m})[0] == Match.FULL for r in routes))


async def _http_handler(request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, StarletteHTTPException)
    if exc.status_code == 400 and (answer := _unreadable(exc.__cause__)) is not None:
        return answer
    headers = dict(exc.headers or {})
    if exc.status_code == 405:
        # Starlette names the methods of the first route on the path only; a path may have several routes.
        headers["Allow"] = _allow(request) or headers.get("Allow", "")
    return problem(exc.status_code, "http-error", str(exc.detail), str(exc.detail), headers=headers)


async def _overloaded_handler(_: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, Overloaded)
    return problem(503, "overloaded", "Service busy", str(exc), headers={"Retry-After": str(exc.retry_after_s)},
                   capacity=exc.capacity, retry_after_s=exc.retry_after_s)


async def _store_handler(_: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, StoreUnavailable)
    return problem(503, "store-unavailable", "Store unavailable", str(exc), headers={"Retry-After": "10"},
                   reason=exc.reason)


_LIBRARY: dict[type[LibraryError], tuple[int, str, str]] = {
    NotFound: (404, "not-found", "Not found"),
    StaleParent: (409, "stale-parent", "Stale parent revision"),
    WrongState: (409, "wrong-state", "Revision in the wrong state"),
    FailedChecks: (409, "failed-checks", "The revision did not pass"),
    ProjectExists: (409, "project-exists", "Project exists"),
    SignOffRefused: (403, "sign-off-refused", "Sign-off refused"),
    InvalidDocument: (422, "invalid-input", "Invalid input"),
}


async def _library_handler(_: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, LibraryError)
    status, slug, title = next(_LIBRARY[c] for c in type(exc).__mro__ if c in _LIBRARY)
    extras: dict[str, Any] = {}
    if isinstance(exc, StaleParent):
        extras["head_revision"] = exc.head
    if isinstance(exc, InvalidDocument):
        extras["field"] = exc.field
    if isinstance(exc, FailedChecks):
        extras["failed_checks"] = exc.failed
    return problem(status, slug, title, str(exc), **extras)


async def _forbidden_handler(_: Request, exc: Exception) -> JSONResponse:
    return problem(403, "forbidden", "Forbidden", str(exc))


async def _unexpected_handler(request: Request, exc: Exception) -> JSONResponse:
    request_id = uuid.uuid4().hex[:16]
    # a worker's error carries the worker's traceback as text (the one here ends where the web process got it)
    remote = getattr(exc, "worker_traceback", None)
    log.error("unexpected error, request %s: %s %s%s", request_id, request.method, request.url.path,
              f"\nin the worker:\n{remote}" if remote else "", exc_info=exc)
    return problem(500, "internal-error", "Internal error",
                   f"the service failed unexpectedly; the error was logged with the request id {request_id}",
                   request_id=request_id)


class BodyLimit:
    """ASGI middleware that reads the whole body before the app sees it: 413 past ``max_bytes`` (declared or
    streamed in chunks), 408 when the client takes longer than ``timeout_s`` to send it."""

    def __init__(self, app: ASGIApp, max_bytes: int, timeout_s: float,
                 larger: Mapping[str, int] | None = None) -> None:
        self.app = app
        self.max_bytes = max_bytes
        self.timeout_s = timeout_s
        # paths whose bodies are whole files (a library export), with their own bound, spooled to a file
        self.larger = dict(larger or {})

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        limit = self.larger.get(scope.get("path", ""), self.max_bytes)
        declared = dict(scope.get("headers", [])).get(b"content-length")
        if declared is not None and declared.isdigit() and int(declared) > limit:
            await self._too_large(scope, receive, send, int(declared), limit)
            return
        if scope.get("path", "") in self.larger and scope.get("method") == "POST":
            await self._spooled(scope, receive, send, limit)
            return
        chunks: list[bytes] = []
        if not await self._receive(scope, receive, send, limit, chunks.append):
            return
        body = b"".join(chunks)
        replayed = False

        async def replay() -> Message:
            nonlocal replayed
            if not replayed:
                replayed = True
                return {"type": "http.request", "body": body, "more_body": False}
            return await receive()

        await self.app(scope, replay, send)

    async def _spooled(self, scope: Scope, receive: Receive, send: Send, limit: int) -> None:
        """A whole file as the body (a library export): written to a temporary file as it arrives, never held in
        memory; the app finds the file's path in the request's state (``body_file``) and the file is removed
        once the app has answered."""
        handle, path = tempfile.mkstemp(prefix="synth-body-", suffix=".json")
        try:
            with os.fdopen(handle, "wb") as spool:
                if not await self._receive(scope, receive, send, limit, spool.write):
                    return
            scope.setdefault("state", {})["body_file"] = path
            done = False

            async def empty() -> Message:
                nonlocal done
                if not done:
                    done = True
                    return {"type": "http.request", "body": b"", "more_body": False}
                return await receive()

            await self.app(scope, empty, send)
        finally:
            os.unlink(path)

    async def _receive(self, scope: Scope, receive: Receive, send: Send, limit: int,
                       sink: Callable[[bytes], object]) -> bool:
        """Each chunk of the body to ``sink`` as it arrives, within the body's time and size bounds: True once the
        whole body came; False when it was answered 408 or 413 here, or the client went away."""
        loop = asyncio.get_running_loop()
        deadline = loop.time() + self.timeout_s
        size = 0
        while True:
            try:
                message = await asyncio.wait_for(receive(), timeout=max(0.0, deadline - loop.time()))
            except asyncio.TimeoutError:
                response = problem(408, "body-timeout", "Request body too slow",
                                   f"the body was not received within {self.timeout_s:g} s",
                                   headers={"Connection": "close"}, limit_s=self.timeout_s, received_bytes=size)
                await response(scope, receive, send)
                return False
            if message["type"] == "http.disconnect":
                return False
            chunk = message.get("body", b"")
            size += len(chunk)
            if size > limit:
                await self._too_large(scope, receive, send, size, limit)
                return False
            sink(chunk)
            if not message.get("more_body", False):
                return True

    async def _too_large(self, scope: Scope, receive: Receive, send: Send, got: int, limit: int) -> None:
        response = problem_response(TooLarge("request body bytes", limit, got))
        response.headers["Connection"] = "close"
        await response(scope, receive, send)


def install(app: FastAPI, settings: Settings) -> None:
    """Register every handler and the body limits on ``app``."""
    app.add_exception_handler(SynthError, _synth_handler)
    app.add_exception_handler(Overloaded, _overloaded_handler)
    app.add_exception_handler(StoreUnavailable, _store_handler)
    app.add_exception_handler(LibraryError, _library_handler)
    app.add_exception_handler(Forbidden, _forbidden_handler)
    app.add_exception_handler(RequestValidationError, _validation_handler)
    app.add_exception_handler(StarletteHTTPException, _http_handler)
    app.add_exception_handler(Exception, _unexpected_handler)
    app.add_middleware(BodyLimit, max_bytes=settings.max_body_bytes, timeout_s=settings.body_timeout_s,
                       larger={"/v1/library/import": settings.max_import_bytes})


def state_limits(doc: dict[str, Any], settings: Settings) -> None:
    """Every count the schemas mark with the setting that bounds it (``x-limit``) gets that setting's value as
    its ``maximum`` (a number) or ``maxItems`` (a list), or the schema's own bound when that is lower: the
    document states the limits of this service, which answers 413 beyond them."""

    def bound(node: dict[str, Any], limit: int) -> None:
        key = "maxItems" if node.get("type") == "array" else "maximum" if node.get("type") == "integer" else None
        if key is not None:
            node[key] = min(int(node.get(key, limit)), limit)
        for member in node.get("anyOf", ()):
            bound(member, limit)

    def walk(node: Any) -> None:
        if isinstance(node, dict):
            setting = node.get("x-limit")
            if isinstance(setting, str):
                limit = int(getattr(settings, setting))
                bound(node, limit)
                note = f"At most {limit} (the service's `{setting}` setting; 413 beyond)."
                node["description"] = f"{node['description']} {note}" if node.get("description") else note
            for value in node.values():
                walk(value)
        elif isinstance(node, list):
            for value in node:
                walk(value)

    walk(doc)


def tags_required(doc: dict[str, Any]) -> None:
    """A member of a discriminated union must name its tag (``"type": "fourbar"``) even where the member's own
    model gives it a default: say so in each member's ``required``."""
    schemas = doc.get("components", {}).get("schemas", {})

    def walk(node: Any) -> None:
        if isinstance(node, dict):
            disc = node.get("discriminator")
            if isinstance(disc, dict) and isinstance(disc.get("mapping"), dict):
                for ref in disc["mapping"].values():
                    member = schemas.get(str(ref).rsplit("/", 1)[-1])
                    if isinstance(member, dict) and disc["propertyName"] not in member.get("required", []):
                        member["required"] = [*member.get("required", []), disc["propertyName"]]
            for value in node.values():
                walk(value)
        elif isinstance(node, list):
            for value in node:
                walk(value)

    walk(doc)


def document(app: FastAPI) -> None:
    """Make the OpenAPI document tell the truth: every POST operation lists its problem responses as
    ``application/problem+json`` with the one Problem schema, in place of FastAPI's default 422 body."""
    build = app.openapi

    def openapi() -> dict[str, Any]:
        if app.openapi_schema is not None:
            return app.openapi_schema
        doc = build()
        settings: Settings = app.state.settings
        state_limits(doc, settings)
        tags_required(doc)
        doc.setdefault("components", {}).setdefault("schemas", {})["Problem"] = PROBLEM_SCHEMA
        for schemas in (doc["components"]["schemas"],):
            schemas.pop("HTTPValidationError", None)
            schemas.pop("ValidationError", None)
        ref = {"$ref": "#/components/schemas/Problem"}
        for path in doc.get("paths", {}).values():
            for method, operation in path.items():
                responses = operation.setdefault("responses", {})
                statuses = PROBLEM_STATUSES if method == "post" else {}
                # a parameter in the path or the query can be refused (422) like a body: every such operation
                # says so with the Problem schema, never FastAPI's own validation body
                if method == "post" or "422" in responses or any(
                        p.get("in") in ("query", "path") for p in operation.get("parameters", [])):
                    statuses = statuses or {k: v for k, v in PROBLEM_STATUSES.items() if k in (400, 422)}
                for status, description in statuses.items():
                    responses[str(status)] = {"description": description,
                                              "content": {PROBLEM_JSON: {"schema": ref}}}
                if "413" in responses and method == "post":
                    responses["413"]["description"] += f" The body may hold at most {settings.max_body_bytes} bytes."
                if "503" in responses:
                    responses["503"]["headers"] = {"Retry-After": {"schema": {"type": "integer"},
                                                                   "description": "Seconds to wait."}}
        app.openapi_schema = doc
        return doc

    app.openapi = openapi  # type: ignore[method-assign]
