"""Schemas of /v1/studies: many variants of one design request, their results and their Pareto front."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from .common import FOURBAR_EXAMPLE, StrictModel, at_least_one, exactly_one, service_limit

Path = Annotated[str, Field(min_length=1, max_length=200, pattern=r"^[A-Za-z0-9_\-]+(\.[A-Za-z0-9_\-]+)*$",
                            description="Dotted path: names and list indices separated by dots.")]
Value = Annotated[float, Field(ge=-1e12, le=1e12)] | int | bool | Annotated[str, Field(max_length=200)]

MAX_BASE_DEPTH = 32

STUDY_EXAMPLE: dict[str, Any] = {
    "endpoint": "/v1/balancing/optimal",
    "base": {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 90,
             "max_radius_m": {"crank": 0.1, "rocker": 0.25},
             "weights": {"shaking_force": 1.0, "driving_torque": 0.5}},
    "parameters": [
        {"path": "mechanism.crank_length_m", "range": [0.06, 0.12], "count": 4},
        {"path": "mass_budget_kg", "values": [1.0, 2.0, 4.0]},
    ],
    "sampling": "grid",
    "metrics": ["summary_after.rms_shaking_force_N", "summary_after.rms_driving_torque_Nm", "total_added_mass_kg"],
    "objectives": {"summary_after.rms_shaking_force_N": "min", "total_added_mass_kg": "min"},
    "constraints": [{"metric": "summary_after.rms_driving_torque_Nm", "max": 40.0}],
}


class StudyParameterIn(StrictModel):
    """One varied field of the base request: explicit values, or a range with a grid count (grid) or drawn
    uniformly (random, lhs)."""

    path: Path
    values: list[Value] | None = Field(None, min_length=1, max_length=10_000,
                                       description="Explicit values, used as they are.")
    range: list[Annotated[float, Field(ge=-1e12, le=1e12)]] | None = Field(
        None, min_length=2, max_length=2, description="Lowest and highest value, in the field's unit.")
    count: int | None = Field(None, ge=1, le=10_000_000, description="Grid points over the range.")
    distribution: Literal["uniform"] = Field("uniform", description="How random and lhs sampling spread a range.")
    integer: bool = Field(False, description="Round values drawn from a range to whole numbers.")

    model_config = ConfigDict(json_schema_extra=exactly_one("values", "range"))

    @model_validator(mode="after")
    def _one_source(self) -> StudyParameterIn:
        if (self.values is None) == (self.range is None):
            raise ValueError("give either values or a range")
        if self.range is not None and self.range[0] > self.range[1]:
            raise ValueError("range must be [low, high] with low <= high")
        return self


class StudyConstraintIn(StrictModel):
    """Bounds on a metric; a variant outside them is infeasible and never on the Pareto front."""

    metric: Path
    min: float | None = Field(None, description="Least admissible value of the metric, in the metric's unit.")
    max: float | None = Field(None, description="Largest admissible value of the metric, in the metric's unit.")

    model_config = ConfigDict(json_schema_extra=at_least_one("min", "max"))

    @model_validator(mode="after")
    def _a_bound(self) -> StudyConstraintIn:
        if self.min is None and self.max is None:
            raise ValueError("give min, max or both")
        return self


class StudyIn(StrictModel):
    """A design study: the variants of one design request, the metrics read from each answer, and what is best."""

    endpoint: str = Field(max_length=100, description="The design endpoint each variant is sent to, "
                                                      "e.g. /v1/balancing/optimal.")
    base: dict[str, Any] = Field(description="That endpoint's request body, which every variant starts from.")
    parameters: list[StudyParameterIn] = Field(min_length=1, max_length=16,
                                               description="The request fields to vary, each by a dotted path.")
    sampling: Literal["grid", "random", "lhs"] = Field(
        "grid", description="grid: every combination; random: uniform draws; lhs: a Latin hypercube.")
    samples: int | None = Field(None, ge=1, le=10_000_000, json_schema_extra=service_limit("max_study_variants"),
                                description="Variants drawn by random and lhs.")
    seed: int = Field(0, ge=0, le=2**63 - 1, description="Seed of random and lhs; the same seed, the same variants.")
    metrics: list[Path] = Field(min_length=1, max_length=32,
                                description="Dotted paths into the endpoint's answer, e.g. "
                                            "summary_after.rms_shaking_force_N.")
    objectives: dict[str, Literal["min", "max"]] = Field(default_factory=dict, max_length=8,
                                                         description="Metric -> min or max, for the Pareto front.")
    constraints: list[StudyConstraintIn] = Field(default_factory=list, max_length=32,
                                                 description="Bounds on metrics: a variant outside one is infeasible "
                                                             "and kept off the Pareto front.")
    objective_digits: int | None = Field(
        9, ge=1, le=17, description="Objectives are compared on the Pareto front to this many significant digits "
                                    "of their largest value, and never finer than the solvers' noise (1e-6 of "
                                    "it), so designs that differ only by noise do not beat each other; null: to "
                                    "the noise only.")
    name: str | None = Field(None, max_length=200, description="A label for people.")
    owner: str = Field("anonymous", min_length=1, max_length=200,
                       description="Who the study runs for: owners take turns for the running places, and each "
                                   "owner's queued and running studies share one bound of estimated work.")

    model_config = ConfigDict(json_schema_extra={"examples": [STUDY_EXAMPLE]})

    @field_validator("base")
    @classmethod
    def _shallow(cls, base: dict[str, Any]) -> dict[str, Any]:
        # Every design request is a few levels deep; a deeper body would only exhaust copying and serialising.
        stack: list[tuple[Any, int]] = [(base, 1)]
        while stack:
            node, depth = stack.pop()
            if depth > MAX_BASE_DEPTH:
                raise ValueError(f"base is nested deeper than {MAX_BASE_DEPTH} levels")
            children = node.values() if isinstance(node, dict) else node if isinstance(node, list) else ()
            stack.extend((child, depth + 1) for child in children if isinstance(child, (dict, list)))
        return base


class StudyLinks(BaseModel):
    """Where to find a study's parts."""

    self: str = Field(description="Path of this study's status (GET), cancel (DELETE) and resume (POST …/resume).")
    results: str = Field(description="Path of the variants' results: JSON pages, or CSV with `?format=csv`.")
    pareto: str = Field(description="Path of the Pareto front: JSON, or a scatter of two metrics with `?format=png`.")


class StudyOut(BaseModel):
    """A study's state and progress."""

    id: str = Field(description="The study's id, as in its paths.")
    name: str | None = Field(description="The name given at creation; null when none was given.")
    endpoint: str = Field(description="The design endpoint every variant is a request to (e.g. `/v1/balancing/optimal`).")
    state: Literal["queued", "running", "done", "cancelled", "interrupted", "failed"] = Field(
        description="`queued` or `running`; `done` when every variant has a row; `cancelled` by DELETE; "
        "`interrupted` by a restart of the service (POST …/resume finishes it); `failed` when the study itself "
        "could not go on (see `message`).")
    total: int = Field(description="Variants in the study.")
    done: int = Field(description="Variants with a result (failed ones included).")
    failed: int = Field(description="Variants that ended as a problem (not assemblable, infeasible, ...).")
    elapsed_s: float = Field(description="Running time over all runs [s].")
    eta_s: float | None = Field(description="Estimated time to finish [s], while running.")
    created_at: float = Field(description="Creation time [s since the epoch].")
    message: str | None = Field(None, description="Why the study failed or stopped.")
    links: StudyLinks = Field(description="Paths of the study's status, results and Pareto front.")
    owner: str = Field("anonymous", description="Who the study runs for.")
    position: int | None = Field(None, description="While queued: its place in the queue of studies waiting to "
                                                   "run, 1 for the next to start; null otherwise.")


class VariantOut(BaseModel):
    """One variant: its parameter values and metrics, or the problem it ended with."""

    index: int = Field(description="The variant's position in the study's sampling order, from 0.")
    parameters: dict[str, Any] = Field(description="The value of every varied path in this variant's request.")
    metrics: dict[str, float | None] | None = Field(
        description="The value of every collected metric in this variant's answer, in the answer's units; null "
        "when the variant failed.")
    feasible: bool | None = Field(description="Within every constraint; null when the variant failed.")
    problem_type: str | None = Field(None, description="Problem type URI, as the endpoint would answer it.")
    detail: str | None = Field(None, description="The problem's message when the variant failed; null otherwise.")


class ResultsOut(BaseModel):
    """A page of a study's variants in index order."""

    id: str = Field(description="The study's id.")
    total: int = Field(description="Variants in the study.")
    done: int = Field(description="Variants with a result so far (failed ones included).")
    offset: int = Field(description="Results skipped before this page, as asked (counted over the variants that "
                        "have a result, in index order).")
    limit: int = Field(description="Largest number of variants on a page, as asked.")
    parameters: list[str] = Field(description="The varied paths, in order.")
    metrics: list[str] = Field(description="The collected metrics, in order.")
    variants: list[VariantOut] = Field(description="The results on this page, in index order; a variant still "
                                       "waiting or running has none yet.")


class ParetoOut(BaseModel):
    """The feasible variants no other feasible variant beats in every objective."""

    id: str = Field(description="The study's id.")
    objectives: dict[str, Literal["min", "max"]] = Field(
        description="Each objective metric and whether it is minimised or maximised.")
    candidates: int = Field(description="Feasible variants the front was chosen from.")
    front: list[VariantOut] = Field(description="The non-dominated feasible variants, in index order.")
