"""The service's OpenAPI document as committed in ``tests/openapi.json``, and the command that writes it.

The document is the wire: a change to it is a change for every client. Regenerate the snapshot only when the wire
changes on purpose, and commit it with that change::

    python -m tests.openapi_snapshot
"""

from __future__ import annotations

import json
from pathlib import Path

SNAPSHOT = Path(__file__).resolve().parent / "openapi.json"


def current() -> str:
    """The OpenAPI document of a fresh app with the default settings, keys sorted, as the snapshot holds it."""
    from api.app import create_app
    from api.settings import Settings

    return json.dumps(create_app(Settings()).openapi(), sort_keys=True, indent=1, ensure_ascii=False) + "\n"


if __name__ == "__main__":
    SNAPSHOT.write_text(current())
    print(f"wrote {SNAPSHOT}")
