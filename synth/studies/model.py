"""What a design study is: a base request, the parameters varied in it, the metrics read from each answer,
objectives for a Pareto front and constraints on the metrics. Plain data, picklable, validated on creation."""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

from ..errors import InvalidInput, TooLarge
from .paths import set_path, split_path

Sampling = Literal["grid", "random", "lhs"]
Sense = Literal["min", "max"]
Scalar = float | int | str | bool

# Variants beyond this are refused before anything is generated; a service lowers it with its own setting.
DEFAULT_MAX_VARIANTS = 100_000


@dataclass(frozen=True, slots=True)
class StudyParameter:
    """One varied input: a dotted ``path`` into the request and either explicit ``values`` or a ``range``.

    Parameters
    ----------
    path
        Dotted path into the base request, e.g. ``mechanism.crank_length_m`` [-].
    values
        Explicit values, taken as they are (numbers, names, flags) [unit of the field].
    range
        Lowest and highest value (inclusive) [unit of the field].
    count
        Grid points over ``range``, evenly spaced [-]; grid sampling only.
    integer
        Round sampled values to whole numbers (tooth counts, sample counts) [-].
    """

    path: str
    values: tuple[Scalar, ...] | None = None
    range: tuple[float, float] | None = None
    count: int | None = None
    integer: bool = False

    def __post_init__(self) -> None:
        split_path(self.path)
        if (self.values is None) == (self.range is None):
            raise InvalidInput(f"parameter {self.path!r}: give either values or a range", field=self.path)
        if self.values is not None and not self.values:
            raise InvalidInput(f"parameter {self.path!r}: values is empty", field=self.path)
        if self.values is not None and any(isinstance(v, float) and not math.isfinite(v) for v in self.values):
            raise InvalidInput(f"parameter {self.path!r}: values must be finite", field=self.path)
        if self.range is not None:
            lo, hi = self.range
            if not (math.isfinite(lo) and math.isfinite(hi) and lo <= hi):
                raise InvalidInput(f"parameter {self.path!r}: range must be finite with low <= high",
                                   field=self.path)
        if self.count is not None and self.count < 1:
            raise InvalidInput(f"parameter {self.path!r}: count must be at least 1", field=self.path)

    @property
    def levels(self) -> int | None:
        """Grid points this parameter contributes, or None when a range has no count."""
        return len(self.values) if self.values is not None else self.count


@dataclass(frozen=True, slots=True)
class StudyConstraint:
    """A bound on a metric: a variant is feasible when ``minimum <= metric <= maximum`` [unit of the metric]."""

    metric: str
    minimum: float | None = None
    maximum: float | None = None

    def __post_init__(self) -> None:
        if self.minimum is None and self.maximum is None:
            raise InvalidInput(f"constraint on {self.metric!r}: give min, max or both", field=self.metric)


@dataclass(frozen=True, slots=True)
class Study:
    """Many variants of one request.

    Parameters
    ----------
    base
        The request every variant starts from (plain JSON-like data) [-].
    parameters
        The varied inputs [-].
    metrics
        Dotted paths into each answer whose values are collected [-].
    sampling
        ``grid`` (every combination), ``random`` (uniform) or ``lhs`` (Latin hypercube) [-].
    samples
        Variants drawn by ``random`` and ``lhs`` [-].
    seed
        Seed of the random draws; the same seed gives the same variants [-].
    objectives
        Metric -> ``min`` or ``max``, for the Pareto front [-].
    constraints
        Bounds on metrics; a variant outside them is infeasible and never on the front [-].
    objective_digits
        Objectives are compared on the front to this many significant digits of their largest value, never
        finer than the solvers' noise (:data:`synth.studies.pareto.SOLVER_NOISE`); None: to the noise only [-].
    """

    base: Mapping[str, Any]
    parameters: tuple[StudyParameter, ...]
    metrics: tuple[str, ...]
    sampling: Sampling = "grid"
    samples: int | None = None
    seed: int = 0
    objectives: Mapping[str, Sense] = field(default_factory=dict)
    constraints: tuple[StudyConstraint, ...] = ()
    objective_digits: int | None = 9

    def __post_init__(self) -> None:
        if not self.parameters:
            raise InvalidInput("a study varies at least one parameter", field="parameters")
        if not self.metrics:
            raise InvalidInput("a study collects at least one metric", field="metrics")
        for i, m in enumerate(self.metrics):
            split_path(m, field=f"metrics[{i}]")
            if m in self.metrics[:i]:
                raise InvalidInput(f"metric {m!r} appears twice", field=f"metrics[{i}]")
        paths = [p.path for p in self.parameters]
        if len(set(paths)) != len(paths):
            raise InvalidInput("a parameter path appears twice", field="parameters")
        for name, sense in self.objectives.items():
            # Objectives are keyed by metric, so the field is named by the key as a JSON body spells it.
            if name not in self.metrics:
                raise InvalidInput(f"objective {name!r} is not one of the metrics {list(self.metrics)}",
                                   field=f"objectives.{name}")
            if sense not in ("min", "max"):
                raise InvalidInput(f"objective {name!r}: expected 'min' or 'max', got {sense!r}",
                                   field=f"objectives.{name}")
        if self.objective_digits is not None and not 1 <= self.objective_digits <= 17:
            raise InvalidInput("objective_digits must be 1 to 17", field="objective_digits")
        for i, c in enumerate(self.constraints):
            if c.metric not in self.metrics:
                raise InvalidInput(f"constraint on {c.metric!r}: it is not one of the metrics {list(self.metrics)}",
                                   field=f"constraints[{i}].metric")
        if self.sampling == "grid":
            if missing := [p.path for p in self.parameters if p.levels is None]:
                raise InvalidInput(f"grid sampling needs values or a count for {missing}", field="parameters")
        elif self.sampling in ("random", "lhs"):
            if self.samples is None or self.samples < 1:
                raise InvalidInput(f"{self.sampling} sampling needs samples >= 1", field="samples")
        else:
            raise InvalidInput(f"unknown sampling {self.sampling!r}; expected grid, random or lhs", field="sampling")
        probe = copy.deepcopy(dict(self.base))
        for p in self.parameters:
            set_path(probe, p.path, p.values[0] if p.values is not None else p.range[0])  # type: ignore[index]

    @property
    def variant_count(self) -> int:
        """Number of variants, computed without generating any [-]."""
        if self.sampling == "grid":
            return math.prod(p.levels or 1 for p in self.parameters)
        return int(self.samples or 0)

    def check_size(self, max_variants: int = DEFAULT_MAX_VARIANTS) -> int:
        """The variant count, or :class:`TooLarge` when it is beyond ``max_variants``."""
        n = self.variant_count
        if n > max_variants:
            raise TooLarge("study variants", max_variants, n)
        return n

    @property
    def parameter_paths(self) -> tuple[str, ...]:
        """The varied paths, in order."""
        return tuple(p.path for p in self.parameters)

    @property
    def senses(self) -> tuple[tuple[int, Sense], ...]:
        """(metric column, sense) of each objective."""
        return tuple((self.metrics.index(name), sense) for name, sense in self.objectives.items())


def study_from_dict(spec: Mapping[str, Any]) -> Study:
    """A Study from its JSON form (``parameters`` with ``path``/``values``/``range``/``count``, ``constraints``
    with ``metric``/``min``/``max``)."""
    params = tuple(
        StudyParameter(p["path"], tuple(p["values"]) if p.get("values") is not None else None,
                  (float(p["range"][0]), float(p["range"][1])) if p.get("range") is not None else None,
                  p.get("count"), bool(p.get("integer", False)))
        for p in spec["parameters"]
    )
    constraints = tuple(StudyConstraint(c["metric"], c.get("min"), c.get("max")) for c in spec.get("constraints") or ())
    return Study(base=spec["base"], parameters=params, metrics=tuple(spec["metrics"]),
                 sampling=spec.get("sampling", "grid"), samples=spec.get("samples"), seed=int(spec.get("seed", 0)),
                 objectives=dict(spec.get("objectives") or {}), constraints=constraints,
                 objective_digits=spec.get("objective_digits", 9))
