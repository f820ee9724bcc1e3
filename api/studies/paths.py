"""A study's metric paths checked against the answer its endpoint sends, when the study is created.

Metrics are read from each variant's JSON answer by dotted paths, and the answer's shape is the endpoint's
response model. Walking that model finds a misspelt path before anything runs, instead of a missing value in
every row: model fields by name, list items by index, dictionary entries by any key, Optional and Union fields
through each of their branches. The path must end at a number, since a row keeps only numbers.
"""

from __future__ import annotations

import functools
import types
from collections.abc import Mapping, Sequence
from typing import Annotated, Any, Literal, Union, get_args, get_origin

from pydantic import BaseModel

from synth.errors import InvalidInput

from ..routers import PREFIX, all_routers
from .tasks import ENDPOINTS, check_endpoint

# Stands for a list item among the names valid at a level: any index of the list.
LIST_INDEX = "<index>"


class MetricPathError(InvalidInput):
    """A metric the endpoint's answer does not have as a number: the path, the part where it went wrong (None
    when the whole path exists but is not a number) and the names valid there, sorted."""

    def __init__(self, message: str, field: str, path: str, segment: str | None, valid: list[str]) -> None:
        super().__init__(message, field=field)
        self.path = path
        self.segment = segment
        self.valid = valid

    def extras(self) -> dict[str, Any]:
        """The field, the metric's path, the part that is not there and the names that are."""
        return {**super().extras(), "path": self.path, "segment": self.segment, "valid": self.valid}


@functools.cache
def response_models() -> Mapping[str, type[BaseModel]]:
    """The response model of every endpoint a study can vary, as that endpoint's router declares it."""
    from fastapi.routing import APIRoute


    found = {PREFIX + route.path: route.response_model
             for router in all_routers() for route in router.routes
             if isinstance(route, APIRoute) and "POST" in (route.methods or ())}
    return {endpoint: found[endpoint] for endpoint in ENDPOINTS}


def check_metrics(endpoint: str, metrics: Sequence[str]) -> None:
    """:class:`MetricPathError` naming ``metrics[i]`` for the first metric ``endpoint`` does not answer as a
    number; :class:`InvalidInput` naming ``endpoint`` when a study cannot vary it."""
    check_endpoint(endpoint)
    model = response_models()[endpoint]
    for i, path in enumerate(metrics):
        check_metric(model, path, f"metrics[{i}]", endpoint)


def check_metric(model: type[BaseModel], path: str, field: str, answer: str = "the endpoint") -> None:
    """:class:`MetricPathError` naming ``field`` unless ``path`` leads to a number in an answer of ``model``."""
    parts = path.split(".")
    current: list[Any] = [model]
    for depth, part in enumerate(parts):
        found: list[Any] = []
        valid: set[str] = set()
        for tp in _branches(current):
            children, names = _children(tp, part)
            found += children or []
            valid.update(names)
        if not found:
            where = ".".join(parts[:depth])
            names = sorted(valid)
            raise MetricPathError(f"{field}: {path!r} is not in the answer of {answer}: {where or 'its top level'} "
                                  f"has no {part!r}; {_hint(where, names, current)}", field, path, part, names)
        current = found
    if not any(_is_number(tp) for tp in _branches(current)):
        names = sorted({name for tp in _branches(current) for name in _children(tp, "")[1]})
        below = ("" if not names else "; give an item's index" if names == [LIST_INDEX]
                 else f"; the names below it are {', '.join(names)}")
        raise MetricPathError(f"{field}: {path!r} in the answer of {answer} is {_kind(current)}, not a number{below}",
                              field, path, None, names)


def _hint(where: str, names: list[str], declared: list[Any]) -> str:
    """How to go on from ``where``, whose valid names are ``names``."""
    if names == [LIST_INDEX]:
        return f"{where} is a list: give an item's index"
    if names:
        return f"the names there are {', '.join(names)}"
    return f"{where} is {_kind(declared)}, with nothing below it"


def _branches(declared: list[Any]) -> list[Any]:
    """The types values of the ``declared`` types may have: Annotated unwrapped, Optional and Union split, None
    left out."""
    out: list[Any] = []
    for tp in declared:
        origin = get_origin(tp)
        if origin is Annotated:
            out += _branches([get_args(tp)[0]])
        elif origin is Union or origin is types.UnionType:
            out += _branches(list(get_args(tp)))
        elif tp is not type(None):
            out.append(tp)
    return out


def _container(tp: Any) -> type | None:
    container = get_origin(tp) or tp
    return container if isinstance(container, type) else None


def _children(tp: Any, part: str) -> tuple[list[Any] | None, list[str]]:
    """The types ``part`` leads to below a value of type ``tp`` (None: it leads nowhere), and the names valid
    there (none for a dictionary, where any key is)."""
    if tp is Any:
        return [Any], []
    if isinstance(tp, type) and issubclass(tp, BaseModel):
        fields = tp.model_fields
        return ([fields[part].annotation] if part in fields else None), list(fields)
    container, args = _container(tp), get_args(tp)
    if container is None or issubclass(container, (str, bytes)):
        return None, []
    if issubclass(container, Mapping):
        return [args[1] if len(args) == 2 else Any], []
    if issubclass(container, Sequence):
        if container is tuple and args and args[-1] is not Ellipsis:
            names = [str(i) for i in range(len(args))]
            return ([args[int(part)]] if part in names else None), names
        return ([args[0] if args else Any] if part.isdigit() else None), [LIST_INDEX]
    return None, []


def _is_number(tp: Any) -> bool:
    if tp is Any:
        return True
    if get_origin(tp) is Literal:
        return all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in get_args(tp))
    return isinstance(tp, type) and issubclass(tp, (int, float)) and not issubclass(tp, bool)


def _kind(declared: list[Any]) -> str:
    """How a person would call a value of the ``declared`` types."""
    kinds = []
    for tp in _branches(declared):
        container = _container(tp)
        if isinstance(tp, type) and issubclass(tp, BaseModel):
            kind = "an object"
        elif container is not None and issubclass(container, bool):
            kind = "true or false"
        elif _is_number(tp):
            kind = "a number"
        elif container is not None and issubclass(container, (str, bytes)) or get_origin(tp) is Literal:
            kind = "text"
        elif container is not None and issubclass(container, Mapping):
            kind = "an object keyed by name"
        elif container is not None and issubclass(container, Sequence):
            kind = "a list"
        else:
            kind = "a value"
        if kind not in kinds:
            kinds.append(kind)
    return " or ".join(kinds) or "null"
