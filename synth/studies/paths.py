"""Dotted paths into plain JSON-like data: ``mechanism.crank_length_m``, ``tradeoff.0.objective``.

A path is a sequence of dictionary keys and list indices separated by dots; a part made only of digits is a
list index when the container is a list.
"""

from __future__ import annotations

from typing import Any

from ..errors import InvalidInput

_MISSING = object()


def split_path(path: str, field: str | None = None) -> tuple[str, ...]:
    """The parts of a dotted path; an empty part (``a..b``, a leading or trailing dot) is refused, naming
    ``field`` (default: the path itself)."""
    parts = tuple(path.split("."))
    if not path or any(not p for p in parts):
        raise InvalidInput(f"{path!r} is not a dotted path (expected names separated by single dots)",
                           field=field or path)
    return parts


def _child(node: Any, part: str) -> Any:
    if isinstance(node, dict):
        return node.get(part, _MISSING)
    if isinstance(node, list) and part.isdigit():
        i = int(part)
        return node[i] if i < len(node) else _MISSING
    return _MISSING


def get_path(data: Any, path: str) -> Any:
    """The value at ``path`` in ``data``; :class:`InvalidInput` naming the path when it is not there."""
    node = data
    for depth, part in enumerate(split_path(path)):
        node = _child(node, part)
        if node is _MISSING:
            reached = ".".join(split_path(path)[:depth]) or "the top level"
            raise InvalidInput(f"{path!r} is not in the data: {reached} has no {part!r}", field=path)
    return node


def set_path(data: Any, path: str, value: Any) -> None:
    """Set ``path`` in ``data`` to ``value`` in place, creating missing dictionaries on the way."""
    parts = split_path(path)
    node = data
    for depth, part in enumerate(parts):
        last = depth == len(parts) - 1
        if isinstance(node, dict):
            if last:
                node[part] = value
                return
            if part not in node:
                node[part] = {}
            node = node[part]
        elif isinstance(node, list) and part.isdigit() and int(part) < len(node):
            if last:
                node[int(part)] = value
                return
            node = node[int(part)]
        else:
            where = ".".join(parts[:depth]) or "the top level"
            raise InvalidInput(f"cannot set {path!r}: {where} is a {type(node).__name__} without {part!r}",
                               field=path)
