"""The one place that maps engine errors and bad requests to RFC 9457 problem responses."""

from __future__ import annotations

import logging
from typing import Any

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.types import ASGIApp, Receive, Scope, Send

from synth.errors import (
    Infeasible,
    InvalidInput,
    NotAssemblable,
    SolverFailed,
    SolverTimeout,
    SynthError,
    TooLarge,
)

log = logging.getLogger("api")

PROBLEM_JSON = "application/problem+json"
_STATUS: dict[type[SynthError], int] = {
    InvalidInput: 422,
    NotAssemblable: 422,
    Infeasible: 422,
    SolverFailed: 422,
    TooLarge: 413,
    SolverTimeout: 504,
}


def problem(status: int, slug: str, title: str, detail: str, **extras: Any) -> JSONResponse:
    """A problem+json response; ``type`` is a relative URI naming the kind of problem."""
    body = {"type": f"/problems/{slug}", "title": title, "status": status, "detail": detail, **extras}
    return JSONResponse(body, status_code=status, media_type=PROBLEM_JSON)


def problem_response(exc: SynthError) -> JSONResponse:
    """Map an engine error to its status code and problem body."""
    status = next((_STATUS[c] for c in type(exc).__mro__ if c in _STATUS), 422)
    return problem(status, exc.slug, exc.title, str(exc), **exc.extras())


def _field_name(loc: tuple[Any, ...]) -> str:
    parts = [str(p) for p in loc if p not in ("body",)]
    return ".".join(parts)


async def _synth_handler(_: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, SynthError)
    return problem_response(exc)


async def _validation_handler(_: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, RequestValidationError)
    errors = [
        {"field": _field_name(tuple(e.get("loc", ()))), "message": e.get("msg", ""), "type": e.get("type", "")}
        for e in exc.errors()
    ]
    first = errors[0] if errors else {"field": "", "message": "invalid request"}
    detail = f"{first['field']}: {first['message']}" if first["field"] else str(first["message"])
    return problem(422, "invalid-input", "Invalid input", detail, field=first["field"], errors=errors)


async def _http_handler(_: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, StarletteHTTPException)
    return problem(exc.status_code, "http-error", str(exc.detail), str(exc.detail))


async def _unexpected_handler(_: Request, exc: Exception) -> JSONResponse:
    log.exception("unexpected error", exc_info=exc)
    return problem(500, "internal-error", "Internal error", "the service failed unexpectedly; the error was logged")


class BodyLimit:
    """ASGI middleware answering 413 for a request body over ``max_bytes`` (declared or streamed)."""

    def __init__(self, app: ASGIApp, max_bytes: int) -> None:
        self.app = app
        self.max_bytes = max_bytes

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        declared = dict(scope.get("headers", [])).get(b"content-length")
        if declared is not None and declared.isdigit() and int(declared) > self.max_bytes:
            await self._reject(scope, receive, send, int(declared))
            return
        await self.app(scope, receive, send)

    async def _reject(self, scope: Scope, receive: Receive, send: Send, got: int) -> None:
        response = problem_response(TooLarge("request body bytes", self.max_bytes, got))
        await response(scope, receive, send)


def install(app: FastAPI, max_body_bytes: int) -> None:
    """Register every handler and the body-size limit on ``app``."""
    app.add_exception_handler(SynthError, _synth_handler)
    app.add_exception_handler(RequestValidationError, _validation_handler)
    app.add_exception_handler(StarletteHTTPException, _http_handler)
    app.add_exception_handler(Exception, _unexpected_handler)
    app.add_middleware(BodyLimit, max_bytes=max_body_bytes)
