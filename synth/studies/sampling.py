"""The variants of a study: parameter values by variant index, for grid, random and Latin hypercube sampling.

Values are a function of the study and the index alone, so a resumed study, a batch on another machine and a
re-read of the results all see the same variant; a request is built from them only when it is run.
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from typing import Any

import numpy as np
from scipy.stats import qmc

from ..model import FloatArray
from .model import Scalar, Study, StudyParameter
from .paths import set_path


class Sampler:
    """StudyParameter values of the variants of ``study`` by index (``0 <= index < study.variant_count``)."""

    def __init__(self, study: Study) -> None:
        self.study = study
        self.count = study.variant_count
        self._levels: list[list[Scalar]] = []
        self._unit: FloatArray | None = None
        if study.sampling == "grid":
            self._levels = [_grid_levels(p) for p in study.parameters]
        else:
            self._unit = self._draw_unit()

    def _draw_unit(self) -> FloatArray:
        k, n = len(self.study.parameters), self.count
        if self.study.sampling == "lhs":
            return np.asarray(qmc.LatinHypercube(d=k, rng=np.random.default_rng(self.study.seed)).random(n))
        return np.random.default_rng(self.study.seed).random((n, k))

    def values(self, index: int) -> list[Scalar]:
        """The parameter values of variant ``index``, in parameter order."""
        if not 0 <= index < self.count:
            raise IndexError(f"variant {index} is outside 0..{self.count - 1}")
        if self._unit is None:
            digits = np.unravel_index(index, [len(levels) for levels in self._levels])
            return [levels[int(d)] for levels, d in zip(self._levels, digits)]
        return [_from_unit(p, float(u)) for p, u in zip(self.study.parameters, self._unit[index])]


def _grid_levels(p: StudyParameter) -> list[Scalar]:
    if p.values is not None:
        return list(p.values)
    assert p.range is not None and p.count is not None
    levels: list[Scalar] = [float(v) for v in np.linspace(p.range[0], p.range[1], p.count)]
    return [int(round(float(v))) for v in levels] if p.integer else levels


def _from_unit(p: StudyParameter, u: float) -> Scalar:
    if p.values is not None:
        return p.values[min(int(u * len(p.values)), len(p.values) - 1)]
    assert p.range is not None
    value = p.range[0] + u * (p.range[1] - p.range[0])
    return int(round(value)) if p.integer else value


def variant_request(base: Any, paths: Sequence[str], values: Sequence[Scalar]) -> dict[str, Any]:
    """A copy of ``base`` with each of ``paths`` set to its value."""
    request: dict[str, Any] = copy.deepcopy(base)
    for path, value in zip(paths, values):
        set_path(request, path, value)
    return request
