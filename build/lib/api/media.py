"""Content negotiation shared by the routers: JSON by default, a PNG figure when asked for."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import Query, Request
from fastapi.responses import Response
from pydantic import BaseModel

FormatQuery = Annotated[
    Literal["json", "png"] | None,
    Query(description="Answer format; `png` (or an `Accept: image/png` header) returns the figure."),
]

PNG_RESPONSES: dict[int | str, dict[str, Any]] = {
    200: {"content": {"image/png": {}}, "description": "The result, or its figure with ?format=png."}
}


def wants_png(request: Request, fmt: str | None) -> bool:
    """True when the query or the Accept header asks for a PNG."""
    if fmt is not None:
        return fmt == "png"
    accept = request.headers.get("accept", "")
    return "image/png" in accept and "application/json" not in accept


def json_response(model: BaseModel) -> Response:
    """Serialise a response model built from engine arrays straight to JSON.

    FastAPI would validate a returned model against ``response_model`` again; for arrays of thousands of
    floats built by the engine that second pass costs more than the analysis itself.
    """
    return Response(content=model.model_dump_json(), media_type="application/json")


def png(content: bytes) -> Response:
    """A PNG response."""
    return Response(content=content, media_type="image/png")
