"""schemathesis against the app in-process: every operation, positive and negative data, no 5xx, and every answer
conforming to the status codes, media types, headers and schemas the OpenAPI document promises.

Schema-valid requests may still be refused (a linkage that cannot assemble is valid JSON), so the check that
positive data is accepted is left out; every other default check runs. ``SYNTH_FUZZ_EXAMPLES`` raises the count.
"""

from __future__ import annotations

import os

import schemathesis
from hypothesis import HealthCheck, settings
from schemathesis.checks import positive_data_acceptance

from api.app import create_app

EXAMPLES = int(os.environ.get("SYNTH_FUZZ_EXAMPLES", "4"))

schema = schemathesis.openapi.from_asgi("/openapi.json", create_app())
schema.config.generation.update(
    modes=[schemathesis.GenerationMode.POSITIVE, schemathesis.GenerationMode.NEGATIVE], max_examples=EXAMPLES,
)
# The documented examples and random fuzzing; the coverage phase's hundreds of boundary cases per operation would
# dominate the suite's time (run them with `st run` against a server when needed).
schema.config.phases.update(phases=["examples", "fuzzing"])


@schema.parametrize()
@settings(max_examples=EXAMPLES, derandomize=True, deadline=None, suppress_health_check=list(HealthCheck))
def test_every_operation_conforms(case: schemathesis.Case) -> None:
    case.call_and_validate(excluded_checks=[positive_data_acceptance])


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
