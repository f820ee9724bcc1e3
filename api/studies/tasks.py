"""Worker side of design studies: one variant of a study is one request to a design endpoint, run as that
endpoint runs it and answered as the plain JSON it would send.

:func:`run_endpoint` is a module-level function of plain data (with the endpoint's path and the service limits
bound by ``functools.partial``), so the engine's study runner sends it to a local worker or a Dask worker as it
is. Each variant runs its endpoint's plan (:mod:`api.execution.plans`), the same one the endpoint's router runs.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from functools import partial
from typing import Any

from pydantic import BaseModel, ValidationError

from synth.errors import InvalidInput

from ..execution.plans import PLANS, Limits
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
        name = ".".join(str(p) for p in (field, *err.get("loc", ())) if p != "")
        raise InvalidInput(f"{name}: {err.get('msg', 'invalid')}", field=name) from None


def run_endpoint(endpoint: str, limits: Limits, request: dict[str, Any]) -> dict[str, Any]:
    """One variant: validate ``request`` as ``endpoint`` does, run its engine call, answer with its JSON."""
    plan = ENDPOINTS[endpoint][1](validate_request(endpoint, request), limits)
    content, _ = render_task(plan.render, plan.fn, plan.args, plan.kwargs)
    answer: dict[str, Any] = json.loads(content)
    return answer


def variant_function(endpoint: str, limits: Limits) -> Callable[[dict[str, Any]], dict[str, Any]]:
    """The picklable ``variant_fn(request) -> answer`` of one endpoint."""
    return partial(run_endpoint, endpoint, limits)
