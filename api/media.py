"""Content negotiation shared by the routers: JSON by default; figures (PNG, SVG, PDF), curves (CSV), drawings
(DXF) and the answer's arrays as a NumPy ``.npz`` archive when asked for with ``?format=`` or an ``Accept`` header."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Annotated, Any, Literal

import io
import math
import zipfile

import numpy as np
import orjson
from fastapi import Query, Request
from fastapi.responses import Response
from pydantic import BaseModel, ValidationError

import synth
from synth.plots import close_figures

from .curve_text import curve_fragment

Format = Literal["json", "png", "svg", "pdf", "csv", "dxf", "npz"]
Precision = Literal["single", "full"]

FormatQuery = Annotated[
    Format | None,
    Query(description="Answer format: `json` (default); `png`, `svg` or `pdf` for the figure; `csv` for the curves, "
                      "one row per crank angle with units in the column names; `dxf` for a drawing of the mechanism "
                      "in millimetres; `npz` (array-heavy answers) for every number of the JSON answer as a NumPy "
                      "archive, one array per JSON path (`joint_reactions_N/A`, `links/crank/angle_deg`). An `Accept` "
                      "header (image/png, image/svg+xml, application/pdf, text/csv, image/vnd.dxf, "
                      "application/x-npz) chooses the same way."),
]

PrecisionQuery = Annotated[
    Precision,
    Query(description="Digits of a JSON answer's arrays (the curves over the samples): `single` (default) writes each "
                      "array at one quantum, 10^(e-7) for its largest magnitude in [10^e, 10^(e+1)): every value "
                      "as the shortest decimal of its nearest multiple of the quantum, eight significant digits at "
                      "the array's largest magnitude and within 5e-8 of it, about 60 % of the bytes and a third of "
                      "the time of full precision; `full` writes every number as the shortest text that reads back "
                      "as exactly the float64 computed. Single numbers (summaries, check figures, designs) are "
                      "always written in full, and an npz answer always holds float64."),
]

MEDIA_TYPES: dict[str, str] = {
    "json": "application/json",
    "png": "image/png",
    "svg": "image/svg+xml",
    "pdf": "application/pdf",
    "csv": "text/csv; charset=utf-8",
    "dxf": "image/vnd.dxf",
    "npz": "application/x-npz",
}
#: The answers a binary array format suits: those whose size grows with the crank angles.
ARRAYS: tuple[str, ...] = ("npz",)
_ACCEPT_ALIASES = {"application/dxf": "dxf", "application/x-dxf": "dxf", "image/x-dxf": "dxf"}
FIGURES: tuple[str, ...] = ("png", "svg", "pdf")


def format_responses(offered: Sequence[str]) -> dict[int | str, dict[str, Any]]:
    """OpenAPI ``responses`` entry for a 200 that can also be each of ``offered``."""
    content: dict[str, dict[str, Any]] = {MEDIA_TYPES[f].split(";")[0]: {} for f in offered}
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


# Values orjson writes as they are: most of an answer's fields, so they are told apart first, by exact type,
# before any call.
_LEAVES = frozenset({float, int, str, bool, type(None)})


def _plain(value: Any) -> Any:
    """A response model as dicts and lists for orjson, leaving numpy arrays and lists of numbers untouched."""
    if isinstance(value, BaseModel):
        return {name: item if type(item := getattr(value, name)) in _LEAVES else _plain(item)
                for name in type(value).model_fields}
    if isinstance(value, dict):
        return {key: item if type(item) in _LEAVES else _plain(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)) and value and (
            isinstance(value[0], (BaseModel, dict, list, tuple))
            or (value[0] is None and any(isinstance(item, BaseModel) for item in value))):
        # a list of models may open with a null (a stage that has none)
        return [_plain(item) for item in value]
    return value


def _default(value: Any) -> Any:
    """What orjson cannot write natively: strided numpy views (a column slice of the reaction unknowns)."""
    if isinstance(value, np.ndarray):
        return np.ascontiguousarray(value, dtype=np.float32 if value.dtype == np.float32 else float)
    raise TypeError(f"cannot serialise {type(value).__name__}")


def _quantised(value: np.ndarray) -> Any:
    """A 1-D or 2-D float array as its JSON text at one quantum (:mod:`api.curve_text`), spliced into the
    document by orjson as it is; any other array unchanged (written in full). Its values are finite (checked
    before)."""
    if value.dtype.kind != "f" or value.ndim not in (1, 2):
        return value
    return curve_fragment(value)


def curves_quantised(plain: Any) -> Any:
    """``plain`` (an answer as dicts, lists and arrays, every number finite) with its float arrays (the curves)
    as JSON text at one quantum each: eight significant digits at an array's largest magnitude, every value
    within half the quantum (5e-8 of that magnitude). Python floats (single figures, and the lists a response
    model builds itself) are left as they are, written in full."""
    if isinstance(value := plain, np.ndarray):
        return _quantised(value)
    if isinstance(value, dict):
        return {key: item if type(item) in _LEAVES else curves_quantised(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)) and value and not _numbers(value):
        return [item if type(item) in _LEAVES else curves_quantised(item) for item in value]
    return value


def _numbers(value: list[Any] | tuple[Any, ...]) -> bool:
    """A list of numbers or of rows of numbers, told by its first item: nothing in it to cast."""
    first = value[0]
    if isinstance(first, (list, tuple)) and first:
        first = first[0]
    return isinstance(first, (float, int))


def _non_finite(value: Any, path: str = "") -> str | None:
    """The JSON path (``corrections[0].mass_kg``) of the first NaN or infinity in a plain answer, or None."""
    if isinstance(value, float):
        return None if math.isfinite(value) else path
    if isinstance(value, np.ndarray):
        if value.dtype.kind not in "fc" or bool(np.isfinite(value).all()):
            return None
        index = np.argwhere(~np.isfinite(value))[0]
        return path + "".join(f"[{int(i)}]" for i in index)
    if isinstance(value, np.floating):
        return None if math.isfinite(float(value)) else path
    if isinstance(value, dict):
        for key, item in value.items():
            # most of an answer's values are single figures and text: told apart here, without a call
            kind = type(item)
            if kind is float:
                if math.isfinite(item):
                    continue
            elif kind in _LEAVES:
                continue
            if (found := _non_finite(item, f"{path}.{key}" if path else str(key))) is not None:
                return found
    elif isinstance(value, (list, tuple)):
        if value and _numbers(value) and _all_finite(value):
            return None
        for i, item in enumerate(value):
            if type(item) in _LEAVES and (type(item) is not float or math.isfinite(item)):
                continue
            if (found := _non_finite(item, f"{path}[{i}]")) is not None:
                return found
    return None


def _all_finite(numbers: list[Any] | tuple[Any, ...]) -> bool:
    """A list of numbers (or of rows of numbers) with every one finite, checked in one array pass; False also
    when it is not one array of numbers (ragged, or holding a null, which numpy reads as NaN): the item-by-item
    walk then finds what, if anything, is not finite."""
    try:
        return bool(np.isfinite(np.asarray(numbers, dtype=float)).all())
    except (TypeError, ValueError, OverflowError):
        return False


def finite_answer(plain: Any) -> Any:
    """``plain`` (an answer as dicts, lists and arrays) unchanged when every number in it is finite.

    JSON has no NaN or infinity (orjson would write null, a silent wrong number), so an answer holding one is
    refused naming where: the input drove the computation somewhere it has no finite result.
    """
    if (path := _non_finite(plain)) is not None:
        raise synth.InvalidInput(f"the answer's {path} would not be a finite number: the input leads to a "
                                 f"computation without a finite result (check near-coincident positions, zero "
                                 f"masses or lengths, and the units)", field=path)
    return plain


def json_bytes(model: BaseModel, precision: Precision = "full") -> bytes:
    """JSON of a response model whose array fields may hold the engine's numpy arrays, written by orjson.

    The field names, order and values are those of pydantic's ``model_dump_json`` for the same content; the
    arrays are written straight from their buffers instead of through per-element Python floats, with
    ``precision="single"`` at one quantum per array (:func:`curves_quantised`). An answer holding a NaN or an
    infinity is refused (:func:`finite_answer`): every answer of the service goes through here or
    :func:`npz_bytes`.
    """
    plain = finite_answer(_plain(model))
    if precision == "single":
        plain = curves_quantised(plain)
    return orjson.dumps(plain, default=_default, option=orjson.OPT_SERIALIZE_NUMPY)


def _numeric(value: Any) -> bool:
    """A number, a numpy array of numbers, or a (nested) list of numbers: one array of the archive."""
    while isinstance(value, (list, tuple)) and value:
        value = value[0]
    if isinstance(value, np.ndarray):
        return value.dtype.kind in "biuf"
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def array_columns(model: BaseModel) -> dict[str, np.ndarray]:
    """Every number of a response model's JSON answer as arrays keyed by their JSON path (names joined by ``/``,
    list positions as numbers), in the JSON's order: scalars as 0-d arrays, lists of numbers as 1-d, lists of
    pairs as (N, 2). Text, booleans and nulls are left to the JSON answer."""
    out: dict[str, np.ndarray] = {}

    def walk(value: Any, path: str) -> None:
        if isinstance(value, dict):
            for key, item in value.items():
                walk(item, f"{path}/{key}" if path else str(key))
        elif _numeric(value):
            array = np.asarray(value, dtype=float)
            out[path] = np.ascontiguousarray(array) if array.ndim else array
        elif isinstance(value, (list, tuple)):
            for i, item in enumerate(value):
                walk(item, f"{path}/{i}")

    walk(finite_answer(_plain(model)), "")
    return out


def npz_bytes(model: BaseModel) -> bytes:
    """A response model's numbers as an uncompressed NumPy ``.npz`` archive (see :func:`array_columns`)."""
    buffer = io.BytesIO()
    # What np.savez writes, without its keyword arguments: a JSON path may be any name.
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_STORED) as archive:
        for key, array in array_columns(model).items():
            with archive.open(f"{key}.npy", "w", force_zip64=True) as member:
                np.lib.format.write_array(member, array, allow_pickle=False)
    return buffer.getvalue()


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


def file_headers(fmt: str, stem: str) -> dict[str, str] | None:
    """CSV, DXF and PDF answers come as files named ``stem``.csv, .dxf or .pdf."""
    return {"content-disposition": f'attachment; filename="{stem}.{fmt}"'} if fmt in ("csv", "dxf", "pdf") else None


@dataclass(frozen=True, slots=True)
class Render:
    """How a worker turns an engine result into the answer's bytes: a response model as JSON, or an export
    (a figure, the curves as CSV, a drawing) in the negotiated format ``fmt``.

    The callables are module-level functions (or classmethods), so a Render travels to a worker process as it is.
    ``model`` is called as ``model(result, *model_extra)`` and ``export`` as ``export(result, fmt, *export_extra)``.
    """

    model: Callable[..., BaseModel]
    export: Callable[..., bytes] | None = None
    fmt: str = "json"
    model_extra: tuple[Any, ...] = ()
    export_extra: tuple[Any, ...] = ()
    #: The largest answer the service sends [bytes]; 0 for no bound (a study's variant stays in the worker).
    max_bytes: int = 0
    #: Digits of a JSON answer's arrays: full unless the request's answer asks for fewer (stored answers, a
    #: study's variants and a library's revisions are kept in full).
    precision: Precision = "full"

    def __call__(self, result: Any) -> tuple[bytes, str]:
        """The bytes of the answer and their media type."""
        if self.fmt not in ("json", *ARRAYS) and self.export is not None:
            try:
                return self.export(result, self.fmt, *self.export_extra), MEDIA_TYPES[self.fmt]
            finally:
                # an export that failed half-way leaves its figures open; a worker runs one task at a time
                close_figures()
        try:
            model = self.model(result, *self.model_extra)
        except ValidationError as exc:
            # The engine computed a number beyond the physical range the answer's schema allows; that is the
            # input's doing (units, sizes), so it is named like an input problem, never a 500.
            err = exc.errors()[0]
            field = ".".join(str(p) for p in err.get("loc", ()))
            raise synth.InvalidInput(f"the answer's {field} would be beyond any physical range "
                                     f"({err.get('msg', '')}); check the input's units and sizes",
                                     field=field) from None
        if self.max_bytes:
            check_answer_size(model, self.fmt, self.max_bytes)
        if self.fmt == "npz":
            return npz_bytes(model), MEDIA_TYPES["npz"]
        return json_bytes(model, self.precision), "application/json"


#: Bytes a number takes in an answer: JSON writes a float in up to 24 characters with its separator (about 20
#: on average for the engine's values), an npz archive in 8.
_BYTES_PER_NUMBER = {"json": 20, "npz": 8}


def count_numbers(value: Any) -> int:
    """Numbers in a response model's answer, counted from the arrays' shapes without writing anything."""
    if isinstance(value, BaseModel):
        return _count_items(getattr(value, name) for name in type(value).model_fields)
    if isinstance(value, np.ndarray):
        return int(value.size)
    if isinstance(value, dict):
        return _count_items(value.values())
    if isinstance(value, (list, tuple)):
        if value and isinstance(value[0], (int, float)) and not isinstance(value[0], bool):
            return len(value)
        if value and isinstance(value[0], (list, tuple)) and value[0] and isinstance(value[0][0], float):
            return len(value) * len(value[0])  # rows of numbers (points over the cycle)
        return _count_items(value)
    return 1 if isinstance(value, (int, float)) and not isinstance(value, bool) else 0


def _count_items(items: Iterable[Any]) -> int:
    """:func:`count_numbers` summed over ``items``; a single figure or text is told apart without a call."""
    n = 0
    for item in items:
        kind = type(item)
        if kind is float or kind is int:
            n += 1
        elif kind not in _LEAVES:
            n += count_numbers(item)
    return n


def check_answer_size(model: BaseModel, fmt: str, max_bytes: int) -> None:
    """TooLarge naming the bound when the answer's estimated size (its numbers times their size in ``fmt``)
    passes ``max_bytes``, before the answer is written."""
    numbers = count_numbers(model)
    estimate = numbers * _BYTES_PER_NUMBER.get(fmt, 20)
    if estimate > max_bytes:
        hint = ("ask for fewer samples" if fmt == "npz" else
                "ask for ?format=npz (8 bytes a number instead of about 20) or for fewer samples")
        raise synth.TooLarge("answer size [bytes]", max_bytes, estimate,
                             f"the answer would hold {numbers} numbers, about {estimate / 1e6:.1f} MB as {fmt}, "
                             f"beyond this service's bound of {max_bytes / 1e6:.1f} MB: {hint}", field="samples")
