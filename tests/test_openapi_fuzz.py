"""schemathesis against the app in-process: every operation, positive and negative data, no 5xx, and every answer
conforming to the status codes, media types, headers and schemas the OpenAPI document promises.

Schema-valid requests may still be refused (a linkage that cannot assemble is valid JSON), so the check that
positive data is accepted is left out; every other default check runs. What the fuzzing reached is counted per
operation: every operation answers 2xx to some of the generated requests (its schema examples, and the requests
drawn from its schema), so the solvers behind it are exercised, not only the validation in front of them.
``SYNTH_FUZZ_EXAMPLES`` raises the count.

The app runs with worker processes and a shorter request deadline than the service's, so a generated request
that asks for long work (thousands of synthesis starts) is stopped at it; its 504 is a documented answer (a
problem saying how far the work got), the one 5xx allowed.
"""

from __future__ import annotations

import os
import re
from collections import Counter, defaultdict
from typing import Any

import schemathesis
from fastapi.testclient import TestClient
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st
from schemathesis.checks import not_a_server_error, positive_data_acceptance

from api.app import create_app
from api.settings import Settings
from mechsynth_client.schemas.studies import StudyIn

EXAMPLES = int(os.environ.get("SYNTH_FUZZ_EXAMPLES", "4"))
DEADLINE_S = 20.0

app = create_app(Settings(request_deadline_s=DEADLINE_S, solver_time_limit_s=DEADLINE_S))
schema = schemathesis.openapi.from_asgi("/openapi.json", app)
schema.config.generation.update(
    modes=[schemathesis.GenerationMode.POSITIVE, schemathesis.GenerationMode.NEGATIVE], max_examples=EXAMPLES,
)
# The documented examples and random fuzzing; the coverage phase's hundreds of boundary cases per operation would
# dominate the suite's time (run them with `st run` against a server when needed).
schema.config.phases.update(phases=["examples", "fuzzing"])

#: Per operation ("POST /v1/analysis"), the answers by phase and status class: ("examples", "2xx") -> count.
ANSWERED: dict[str, Counter[tuple[str, str]]] = defaultdict(Counter)
_STUDY: dict[str, str] = {}


def _known_study() -> str:
    """A study of the app under test, made once from the schema's own example: the study paths' generated ids
    are random and would only ever meet 404."""
    if "id" not in _STUDY:
        example = StudyIn.model_config["json_schema_extra"]["examples"][0]  # type: ignore[index]
        answer = TestClient(app).post("/v1/studies", json=example)
        assert answer.status_code == 202, answer.text
        _STUDY["id"] = answer.json()["id"]
    return _STUDY["id"]


@schema.hook
def flatmap_path_parameters(context: Any, path_parameters: dict[str, Any]) -> st.SearchStrategy[dict[str, Any]]:
    if "study_id" not in (path_parameters or {}):
        return st.just(path_parameters)
    return st.sampled_from([{**path_parameters, "study_id": _known_study()}, path_parameters])


@schema.parametrize()
@settings(max_examples=EXAMPLES, derandomize=True, deadline=None, suppress_health_check=list(HealthCheck))
def test_every_operation_conforms(case: schemathesis.Case) -> None:
    response = case.call_and_validate(excluded_checks=[positive_data_acceptance, not_a_server_error],
                                      timeout=DEADLINE_S + 10)
    assert response.status_code < 500 or (
        response.status_code == 504 and response.json()["type"] == "/problems/solver-timeout"), response.text
    phase = case.meta.phase.name.value if case.meta is not None else "unknown"
    ANSWERED[case.operation.label][(str(phase), f"{response.status_code // 100}xx")] += 1



def _app_with_token() -> tuple[object, str]:
    """The service with authentication on, its store in a scratch file, and an admin's API token."""
    import tempfile
    from pathlib import Path

    from api.auth import tokens
    from api.auth.users import Accounts
    from api.settings import Settings

    db = Path(tempfile.mkdtemp(prefix="synth-fuzz-")) / "store.sqlite"
    # solver work in this process's thread: the operations fuzzed here are about the caller, and one worker pool
    # per test process (the app above) is enough for the machine
    app = create_app(Settings(auth="on", studies_db=str(db), executor="serial"))  # type: ignore[call-arg]
    accounts: Accounts = app.state.access.accounts
    token = tokens.new_token()
    accounts.add_token(accounts.create("fuzz", {"admin"}).id, token, "fuzz")
    return app, token


signed_app, TOKEN = _app_with_token()
# With a token, the operations whose answer depends on who calls (sign-in, users, tokens, studies and their
# owners) and one design endpoint: the others answer a token's caller as they answer anyone above.
signed_schema = schemathesis.openapi.from_asgi("/openapi.json", signed_app).include(
    path_regex=r"^/(health|ready|v1/(auth|users|tokens|studies|gears/split))")
signed_schema.config.generation.update(
    modes=[schemathesis.GenerationMode.POSITIVE, schemathesis.GenerationMode.NEGATIVE], max_examples=EXAMPLES,
)
signed_schema.config.phases.update(phases=["examples", "fuzzing"])


@signed_schema.parametrize()
@settings(max_examples=EXAMPLES, derandomize=True, deadline=None, suppress_health_check=list(HealthCheck))
def test_every_operation_conforms_with_authentication_on_and_a_token(case: schemathesis.Case) -> None:
    case.call_and_validate(headers={"authorization": f"Bearer {TOKEN}"}, excluded_checks=[positive_data_acceptance])


def test_every_operation_answers_2xx_to_generated_requests() -> None:
    if not ANSWERED:
        import pytest

        pytest.skip("runs after the fuzzing above, in the same session")
    operations = {op.label for op in (result.ok() for result in schema.get_all_operations())}
    lines = []
    for label in sorted(operations):
        counts = ANSWERED[label]
        by_phase = {phase: sum(n for (p, _), n in counts.items() if p == phase) for phase, _ in counts}
        ok = {phase: counts[(phase, "2xx")] for phase in by_phase}
        lines.append(f"{label:45s} " + "  ".join(f"{phase}: {ok[phase]}/{by_phase[phase]} 2xx"
                                                 for phase in sorted(by_phase)))
    print("\nGenerated requests answered 2xx, per operation:\n" + "\n".join(lines))
    never = sorted(label for label in operations
                   if not any(n for (_, status), n in ANSWERED[label].items() if status == "2xx"))
    print("Not reached with a 2xx: " + ", ".join(never))
    unmade = sorted(label for label in never if _NEEDS_A_RESOURCE.search(label))
    assert not set(never) - set(unmade), f"operations no generated request reached with a 2xx answer: {never}"


# Operations that answer 2xx only about a user, a token, a library design or a signed-in session that the fuzzing
# does not make first (a study it does make: _known_study); they are fuzzed for conformance all the same.
_NEEDS_A_RESOURCE = re.compile(r"/v1/(library/projects/\{project\}|users/\{name\}|tokens/\{token_id\}|auth/signin)")
