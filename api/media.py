"""Content negotiation shared by the routers: JSON by default; figures (PNG, SVG, PDF), curves (CSV) and
drawings (DXF) when asked for with ``?format=`` or an ``Accept`` header."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Annotated, Any, Literal

from fastapi import Query, Request
from fastapi.responses import Response
from pydantic import BaseModel

import synth

Format = Literal["json", "png", "svg", "pdf", "csv", "dxf"]

FormatQuery = Annotated[
    Format | None,
    Query(description="Answer format: `json` (default); `png`, `svg` or `pdf` for the figure; `csv` for the curves, "
                      "one row per crank angle with units in the column names; `dxf` for a drawing of the mechanism "
                      "in millimetres. An `Accept` header (image/png, image/svg+xml, application/pdf, text/csv, "
                      "image/vnd.dxf) chooses the same way."),
]

MEDIA_TYPES: dict[str, str] = {
    "json": "application/json",
    "png": "image/png",
    "svg": "image/svg+xml",
    "pdf": "application/pdf",
    "csv": "text/csv; charset=utf-8",
    "dxf": "image/vnd.dxf",
}
_ACCEPT_ALIASES = {"application/dxf": "dxf", "application/x-dxf": "dxf", "image/x-dxf": "dxf"}
FIGURES: tuple[str, ...] = ("png", "svg", "pdf")


def format_responses(offered: Sequence[str]) -> dict[int | str, dict[str, Any]]:
    """OpenAPI ``responses`` entry for a 200 that can also be each of ``offered``."""
    content = {MEDIA_TYPES[f].split(";")[0]: {} for f in offered}
    return {200: {"content": content, "description": "The result as JSON, or with ?format= as " + ", ".join(offered)}}


PNG_RESPONSES = format_responses(["png"])


def negotiate(request: Request, fmt: str | None, offered: Sequence[str]) -> str:
    """The answer format: the query's if given (InvalidInput unless offered here), else the first offered media
    type the Accept header names, else JSON."""
    if fmt is not None:
        if fmt != "json" and fmt not in offered:
            raise synth.InvalidInput(f"format {fmt!r} is not offered here; choose json or one of {list(offered)}",
                                     field="format")
        return fmt
    accept = request.headers.get("accept", "")
    if not accept or "application/json" in accept:
        return "json"
    for alias, f in _ACCEPT_ALIASES.items():
        if alias in accept and f in offered:
            return f
    for f in offered:
        if MEDIA_TYPES[f].split(";")[0] in accept:
            return f
    return "json"


def wants_png(request: Request, fmt: str | None) -> bool:
    """True when the query or the Accept header asks for a PNG."""
    return negotiate(request, fmt, ["png"]) == "png"


def media(content: bytes, fmt: str, stem: str) -> Response:
    """A non-JSON answer of format ``fmt``; CSV and DXF come as files named ``stem``.csv or .dxf."""
    headers = {}
    if fmt in ("csv", "dxf"):
        headers["content-disposition"] = f'attachment; filename="{stem}.{fmt}"'
    return Response(content=content, media_type=MEDIA_TYPES[fmt], headers=headers)


def json_response(model: BaseModel) -> Response:
    """Serialise a response model built from engine arrays straight to JSON.

    FastAPI would validate a returned model against ``response_model`` again; for arrays of thousands of
    floats built by the engine that second pass costs more than the analysis itself.
    """
    return Response(content=model.model_dump_json(), media_type="application/json")


def png(content: bytes) -> Response:
    """A PNG response."""
    return Response(content=content, media_type="image/png")
