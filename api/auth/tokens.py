"""API tokens: ``mst_`` and 43 characters of a 256-bit random secret. The store keeps the token's SHA-256, never
the token; a fast hash is enough for a secret of this entropy (no password-style stretching is needed)."""

from __future__ import annotations

import re
import secrets

PREFIX = "mst_"
_SHAPE = re.compile(r"mst_[A-Za-z0-9_\-]{43}")


def new_token() -> str:
    """A fresh token, shown once to whoever asked for it."""
    return PREFIX + secrets.token_urlsafe(32)


def well_formed(token: str) -> bool:
    """The token is shaped like one this service issues (checked before the store is asked)."""
    return _SHAPE.fullmatch(token) is not None
