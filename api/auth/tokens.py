"""API tokens: ``mst_<id>_<secret>``; the service keeps the id and the SHA-256 of the secret, never the token.

The id finds the stored token; the secret's hash is compared in constant time. The secret has 256 bits of
entropy, so a fast hash is enough (no password-style stretching is needed).
"""

from __future__ import annotations

import hashlib
import hmac
import secrets
from typing import NamedTuple

PREFIX = "mst_"


class NewToken(NamedTuple):
    """A token as shown once to its owner, and what is kept of it."""

    id: str
    token: str
    secret_hash: str


def new_token() -> NewToken:
    """A fresh token with a random id and secret."""
    token_id = secrets.token_hex(8)
    secret = secrets.token_urlsafe(32)
    return NewToken(token_id, f"{PREFIX}{token_id}_{secret}", secret_hash(secret))


def secret_hash(secret: str) -> str:
    """What is kept of a token's secret [hex SHA-256]."""
    return hashlib.sha256(secret.encode()).hexdigest()


def split(token: str) -> tuple[str, str] | None:
    """The id and secret of a token as sent, or None when it is not shaped like one of ours."""
    if not token.startswith(PREFIX):
        return None
    token_id, sep, secret = token[len(PREFIX):].partition("_")
    if not sep or len(token_id) != 16 or not secret or len(secret) > 128:
        return None
    return token_id, secret


def matches(stored_hash: str, secret: str) -> bool:
    """The secret hashes to the stored hash (compared in constant time)."""
    return hmac.compare_digest(stored_hash.encode(), secret_hash(secret).encode())
