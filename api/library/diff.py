"""The difference between two revisions: every input field that differs, with the unit its name carries, and every
figure (number) of the answer with its change, the largest relative change first.

A figure that moved by less than the answer's own tolerance is noise, not a change: the tolerance of a unit is the
largest disagreement the answers' own checks report in it (two paths to one figure, such as the kinetostatic and
the virtual-power torque: ``checks.virtual_power_torque_max_diff_Nm``), and never less than a billionth of the
largest figure of that unit (rounding).
"""

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


# Below this fraction of the largest figure of its unit, a change is rounding (the workbench reads it as zero too).
ROUNDING = 1e-9


def _unit(path: str) -> str:
    """The unit of the innermost name that carries one: ``joint_reactions_N.O.0.1`` is in N."""
    for name in reversed([p for p in path.split(".") if not p.isdigit()]):
        unit = unit_of(name)
        if unit:
            return unit
    return ""


def _is_check_tolerance(path: str) -> bool:
    """A figure of the answer's own checks that says how far two paths to one quantity disagree, in a unit."""
    names = path.split(".")
    return "checks" in names[:-1] and any(w in names[-1] for w in ("diff", "error")) and _unit(path) not in ("", "-")


def _largest(*answers: Mapping[str, Any] | None) -> dict[str, float]:
    """Per unit, the largest |figure| of these answers."""
    out: dict[str, float] = {}
    for answer in answers:
        for path, value in _figures(answer).items():
            if value is not None and math.isfinite(value):
                out[_unit(path)] = max(out.get(_unit(path), 0.0), abs(value))
    return out


def tolerances(*answers: Mapping[str, Any] | None) -> dict[str, float]:
    """Per unit, the change below which a figure of these answers is noise [the unit]: the largest disagreement
    their checks report in that unit, and at least ROUNDING of the largest figure in it."""
    out = {unit: ROUNDING * big for unit, big in _largest(*answers).items()}
    for answer in answers:
        for path, value in _figures(answer).items():
            if value is not None and math.isfinite(value) and _is_check_tolerance(path):
                out[_unit(path)] = max(out.get(_unit(path), 0.0), abs(value))
    return out


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


def answer_changes(before: Mapping[str, Any] | None, after: Mapping[str, Any] | None, *, order: str = "relative",
                   noise: bool = False) -> tuple[list[FigureChange], int, int]:
    """The figures of the answers that differ, with their change; how many are equal; and how many moved by less
    than the answers' own tolerance (left out unless ``noise``).

    ``order`` "relative": a figure that appeared or vanished first, then the largest |change| / |before| (a figure
    from zero by its change over its unit's largest figure); "path": in the newer answer's order.
    """
    old, new = _figures(before), _figures(after)
    tol = tolerances(before, after)
    scale = _largest(before, after)
    ranked: list[tuple[float, FigureChange]] = []
    same = quiet = 0
    for path in list(new) + [p for p in old if p not in new]:
        a, b = old.get(path), new.get(path)
        if a == b:
            same += 1
            continue
        unit = _unit(path)
        change = None if a is None or b is None else b - a
        if change is not None and abs(change) <= tol.get(unit, 0.0):
            quiet += 1
            if not noise:
                continue
        rel = None if change is None or a == 0 or a is None else change / abs(a)
        rel = rel if rel is None or math.isfinite(rel) else None
        size = math.inf if change is None else abs(rel) if rel is not None else abs(change) / (scale.get(unit) or 1.0)
        ranked.append((size, FigureChange(path=path, unit=unit, before=a, after=b, change=change, change_rel=rel)))
    if order == "relative":
        ranked.sort(key=lambda r: -r[0])      # stable: equal sizes keep the answer's order
    return [c for _, c in ranked], same, quiet
