"""Worker side of design studies: one variant of a study is one request to a design endpoint, run as that
endpoint runs it and answered as the plain JSON it would send.

:func:`run_endpoint` is a module-level function of plain data (with the endpoint's path and the service limits
bound by ``functools.partial``), so the engine's study runner sends it to a local worker or a Dask worker as it
is. Each variant runs its endpoint's plan (:mod:`api.execution.plans`), the same one the endpoint's router runs.

An endpoint whose engine call has a batched form (:data:`BATCHED`: static balancing) also has a batch function,
:func:`run_endpoint_batch`: a task's requests validated and planned one by one as above, their engine calls made
in one batched call, each result written by its plan's own renderer, so every answer is the one
:func:`run_endpoint` gives.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping, Sequence
from functools import partial
from typing import Any

import orjson
from pydantic import BaseModel, ValidationError

import synth
from synth.errors import InvalidInput, SynthError

from ..execution.plans import PLANS, Limits, Plan
from ..execution.admission import render_task

# Design endpoints a study may vary: every one with a plan.
ENDPOINTS = PLANS


def check_endpoint(endpoint: str) -> None:
    """:class:`InvalidInput` naming the ``endpoint`` field unless a study can vary ``endpoint``."""
    if endpoint not in ENDPOINTS:
        raise InvalidInput(f"{endpoint!r} is not a design endpoint a study can vary; one of {sorted(ENDPOINTS)}",
                           field="endpoint")


def validate_request(endpoint: str, request: Mapping[str, Any], field: str = "") -> BaseModel:
    """The endpoint's request model of ``request``, parsed as the endpoint parses its JSON body; a bad field is
    :class:`InvalidInput` naming it (prefixed with ``field``)."""
    check_endpoint(endpoint)
    try:
        return ENDPOINTS[endpoint][0].model_validate_json(json.dumps(request))
    except ValidationError as exc:
        err = exc.errors()[0]
    # Raised outside the handler, the error carries no context whose traceback would hold this frame.
    name = ".".join(str(p) for p in (field, *err.get("loc", ())) if p != "")
    raise InvalidInput(f"{name}: {err.get('msg', 'invalid')}", field=name)


def run_endpoint(endpoint: str, limits: Limits, request: dict[str, Any]) -> dict[str, Any]:
    """One variant: validate ``request`` as ``endpoint`` does, run its engine call, answer with its JSON."""
    plan = ENDPOINTS[endpoint][1](validate_request(endpoint, request), limits)
    content, _ = render_task(plan.render, plan.fn, plan.args, plan.kwargs)
    answer: dict[str, Any] = orjson.loads(content)
    return answer


def variant_function(endpoint: str, limits: Limits) -> Callable[[dict[str, Any]], dict[str, Any]]:
    """The picklable ``variant_fn(request) -> answer`` of one endpoint."""
    return partial(run_endpoint, endpoint, limits)


def _balance_static_batch(plans: Sequence[Plan]) -> list[object]:
    """The engine results (or errors) of static-balancing plans, their engine calls made as one batch."""
    if any(p.fn is not synth.balance_static for p in plans):
        raise ValueError("a static-balancing plan calls another engine function; the variants run one by one")
    return list(synth.balance_static_batch([synth.StaticCase(*p.args, **p.kwargs) for p in plans]))


#: Endpoints whose plans' engine calls run as one batch: plans in, per plan its result or its engine error.
BATCHED: dict[str, Callable[[Sequence[Plan]], list[object]]] = {
    "/v1/balancing/static": _balance_static_batch,
}


def run_endpoint_batch(endpoint: str, limits: Limits, requests: list[dict[str, Any]]
                       ) -> list[dict[str, Any] | Exception]:
    """Many variants of ``endpoint`` at once: per request the answer :func:`run_endpoint` gives, or the
    exception it raises."""
    out: list[dict[str, Any] | Exception | None] = [None] * len(requests)
    planned: list[tuple[int, Plan]] = []
    for k, request in enumerate(requests):
        try:
            planned.append((k, ENDPOINTS[endpoint][1](validate_request(endpoint, request), limits)))
        except Exception as exc:
            out[k] = _kept(exc)
    results = BATCHED[endpoint]([plan for _, plan in planned])
    for (k, plan), result in zip(planned, results, strict=True):
        if isinstance(result, Exception):
            out[k] = result
            continue
        try:
            out[k] = orjson.loads(plan.render(result)[0])
        except Exception as exc:
            out[k] = _kept(exc)
    return [answer if answer is not None else InvalidInput("the variant gave no answer") for answer in out]


def _kept(exc: Exception) -> Exception:
    """An error kept as a variant's answer: a request's own error as :meth:`SynthError.as_answer` keeps it;
    anything else is a fault worth its traceback."""
    return exc.as_answer() if isinstance(exc, SynthError) else exc


def batch_function(endpoint: str, limits: Limits
                   ) -> Callable[[list[dict[str, Any]]], list[dict[str, Any] | Exception]] | None:
    """The picklable batched ``batch_fn(requests) -> answers`` of ``endpoint``; None when it has no batched path."""
    return partial(run_endpoint_batch, endpoint, limits) if endpoint in BATCHED else None
