"""Worker side of a save: a design's request validated by its endpoint's own schema, and the answer (with the
design record, for machine designs) made from exactly that request."""

from __future__ import annotations

import json
from dataclasses import replace
from typing import Any

import orjson
from pydantic import ValidationError

from mechsynth_client.schemas.studies import StudyIn
from synth.errors import InvalidInput, SynthError

from ..execution.plans import PLANS, Limits
from ..studies.tasks import validate_request

STUDIES = "/v1/studies"
#: The endpoint whose revisions keep their design record (PDF).
MACHINE = "/v1/machines/design"
#: Endpoints whose requests the library keeps: every design endpoint, and studies.
ENDPOINTS = (*sorted(PLANS), STUDIES)


def canonical_request(endpoint: str, request: dict[str, Any]) -> dict[str, Any]:
    """The request as its endpoint's schema reads it (defaults filled, SI, JSON-compatible); an invalid one is
    :class:`InvalidInput` naming the field under ``request``."""
    if endpoint == STUDIES:
        try:
            return StudyIn.model_validate_json(json.dumps(request)).model_dump(mode="json")
        except ValidationError as exc:
            err = exc.errors()[0]
            name = ".".join(str(p) for p in ("request", *err.get("loc", ())))
            raise InvalidInput(f"{name}: {err.get('msg', 'invalid')}", field=name) from None
    if endpoint not in PLANS:
        raise InvalidInput(f"{endpoint!r} is not an endpoint the library keeps designs of; one of "
                           f"{list(ENDPOINTS)}", field="endpoint")
    dumped: dict[str, Any] = validate_request(endpoint, request, field="request").model_dump(mode="json")
    return dumped


def answer_revision(endpoint: str, limits: Limits, request: dict[str, Any]
                    ) -> tuple[dict[str, Any] | None, bool | None, bytes | None]:
    """The answer to a canonical request, whether it passed, and its design record (PDF) for a machine design;
    an engine problem is the answer (``{"problem": ...}``, not passed). A study has no answer here."""
    if endpoint == STUDIES:
        return None, None, None
    plan = PLANS[endpoint][1](validate_request(endpoint, request), limits)
    try:
        result = plan.fn(*plan.args, **plan.kwargs)
        content, _ = plan.render(result)
    except SynthError as exc:
        return {"problem": {"type": f"/problems/{exc.slug}", "title": exc.title, "detail": str(exc)}}, False, None
    answer: dict[str, Any] = orjson.loads(content)
    record = replace(plan.render, fmt="pdf")(result)[0] if endpoint == MACHINE else None
    passed = answer.get("passed")
    return answer, passed if isinstance(passed, bool) else True, record
