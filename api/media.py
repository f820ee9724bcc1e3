"""Content negotiation shared by the routers: JSON by default, a PNG figure when asked for."""

from __future__ import annotations

from typing import Annotated, Any, Literal

import numpy as np
import orjson
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


def _plain(value: Any) -> Any:
    """A response model as dicts and lists for orjson, leaving numpy arrays and lists of numbers untouched."""
    if isinstance(value, BaseModel):
        return {name: _plain(getattr(value, name)) for name in type(value).model_fields}
    if isinstance(value, dict):
        return {key: _plain(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)) and value and isinstance(value[0], (BaseModel, dict, list, tuple)):
        return [_plain(item) for item in value]
    return value


def _default(value: Any) -> Any:
    """What orjson cannot write natively: strided numpy views (a column slice of the reaction unknowns)."""
    if isinstance(value, np.ndarray):
        return np.ascontiguousarray(value, dtype=float)
    raise TypeError(f"cannot serialise {type(value).__name__}")


def json_bytes(model: BaseModel) -> bytes:
    """JSON of a response model whose array fields may hold the engine's numpy arrays, written by orjson.

    The field names, order and values are those of pydantic's ``model_dump_json`` for the same content; the
    arrays are written straight from their buffers instead of through per-element Python floats.
    """
    return orjson.dumps(_plain(model), default=_default, option=orjson.OPT_SERIALIZE_NUMPY)


def json_response(model: BaseModel) -> Response:
    """Serialise a response model built from engine arrays straight to JSON.

    FastAPI would validate a returned model against ``response_model`` again; for arrays of thousands of
    floats built by the engine that second pass, and turning each float into a Python object, cost more than
    the analysis itself.
    """
    return Response(content=json_bytes(model), media_type="application/json")


def png(content: bytes) -> Response:
    """A PNG response."""
    return Response(content=content, media_type="image/png")
