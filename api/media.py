"""Content negotiation shared by the routers: JSON by default, a PNG figure when asked for."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Annotated, Any, Literal

import numpy as np
import orjson
from fastapi import Query, Request
from fastapi.responses import Response
from pydantic import BaseModel, ValidationError

from synth.errors import InvalidInput

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


@dataclass(frozen=True, slots=True)
class Render:
    """How a worker turns an engine result into the answer's bytes: a response model as JSON, or a figure.

    Both callables are module-level functions (or classmethods), so a Render travels to a worker process as it is;
    ``extra`` follows the result in the call (the stages of a drive, the drawing angle of a figure).
    """

    model: Callable[..., BaseModel]
    figure: Callable[..., bytes] | None = None
    as_png: bool = False
    model_extra: tuple[Any, ...] = ()
    figure_extra: tuple[Any, ...] = ()
    figure_media: str = "image/png"

    def __call__(self, result: Any) -> tuple[bytes, str]:
        """The bytes of the answer and their media type."""
        if self.as_png and self.figure is not None:
            return self.figure(result, *self.figure_extra), self.figure_media
        try:
            model = self.model(result, *self.model_extra)
        except ValidationError as exc:
            # The engine computed a number beyond the physical range the answer's schema allows; that is the
            # input's doing (units, sizes), so it is named like an input problem, never a 500.
            err = exc.errors()[0]
            field = ".".join(str(p) for p in err.get("loc", ()))
            raise InvalidInput(f"the answer's {field} would be beyond any physical range ({err.get('msg', '')}); "
                               "check the input's units and sizes", field=field) from None
        return json_bytes(model), "application/json"


def render_for(request: Request, fmt: str | None, model: Callable[..., BaseModel],
               figure: Callable[..., bytes] | None = None, model_extra: tuple[Any, ...] = (),
               figure_extra: tuple[Any, ...] = ()) -> Render:
    """The Render a request asks for: its figure when it wants a PNG and there is one, else its JSON."""
    return Render(model, figure, figure is not None and wants_png(request, fmt), model_extra, figure_extra)
