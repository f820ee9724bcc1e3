"""The OpenAPI document is the one committed: paths, models, fields, examples and descriptions, byte for byte."""

from __future__ import annotations

from tests.openapi_snapshot import SNAPSHOT, current


def test_openapi_document_is_the_committed_snapshot() -> None:
    now, committed = current(), SNAPSHOT.read_text()
    assert now == committed, (
        "the service's OpenAPI document differs from tests/openapi.json. If the wire changed on purpose, "
        "regenerate the snapshot with `python -m tests.openapi_snapshot` and commit it with the change; "
        "otherwise the change altered the wire by accident")
