"""The difference between two revisions: every input field that differs, with the unit its name carries, and every
figure (number) of the answer with its change."""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from typing import Any

from synth.machine.record import unit_of

from mechsynth_client.schemas.library import FieldChange, FigureChange

# Lists of numbers longer than this (curves over crank angles) are compared by their summary figures only.
MAX_LIST_FIGURES = 16


def _leaves(value: Any, path: str = "") -> Iterator[tuple[str, Any]]:
    if isinstance(value, Mapping):
        for key, item in value.items():
            yield from _leaves(item, f"{path}.{key}" if path else str(key))
    elif isinstance(value, list) and value and all(isinstance(v, (Mapping, list)) for v in value):
        for k, item in enumerate(value):
            yield from _leaves(item, f"{path}.{k}")
    else:
        yield path, value


def _unit(path: str) -> str:
    names = [p for p in path.split(".") if not p.isdigit()]
    return unit_of(names[-1]) if names else ""


def request_changes(before: Mapping[str, Any], after: Mapping[str, Any]) -> list[FieldChange]:
    """Every input that differs (added and removed ones too), in the order of the newer request."""
    old, new = dict(_leaves(before)), dict(_leaves(after))
    paths = list(new) + [p for p in old if p not in new]
    return [FieldChange(path=p, unit=_unit(p), before=old.get(p), after=new.get(p))
            for p in paths if old.get(p) != new.get(p) or (p in old) != (p in new)]


def _figures(answer: Mapping[str, Any] | None) -> dict[str, float | None]:
    out: dict[str, float | None] = {}
    for path, value in _leaves(answer or {}):
        if isinstance(value, bool):
            continue
        if isinstance(value, (int, float)):
            out[path] = float(value)
        elif isinstance(value, list) and 0 < len(value) <= MAX_LIST_FIGURES and all(
                isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
            out.update({f"{path}.{k}": float(v) for k, v in enumerate(value)})
    return out


def answer_changes(before: Mapping[str, Any] | None, after: Mapping[str, Any] | None
                   ) -> tuple[list[FigureChange], int]:
    """Every figure of the answers that differs, with its change; and how many are equal."""
    old, new = _figures(before), _figures(after)
    changes, same = [], 0
    for path in list(new) + [p for p in old if p not in new]:
        a, b = old.get(path), new.get(path)
        if a == b:
            same += 1
            continue
        change = None if a is None or b is None else b - a
        rel = None if change is None or a == 0 or a is None else change / abs(a)
        changes.append(FigureChange(path=path, unit=_unit(path), before=a, after=b, change=change,
                                    change_rel=rel if rel is None or math.isfinite(rel) else None))
    return changes, same
