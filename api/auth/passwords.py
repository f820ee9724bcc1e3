"""Passwords kept as argon2id hashes (argon2-cffi's defaults, RFC 9106's second recommended setting)."""

from __future__ import annotations

from argon2 import PasswordHasher
from argon2.exceptions import InvalidHashError, VerificationError, VerifyMismatchError

_HASHER = PasswordHasher()
# Checked against when the user does not exist, so an unknown name costs as long as a wrong password.
_DUMMY = _HASHER.hash("no user has this password")

MIN_LENGTH = 8
MAX_LENGTH = 1024


def hash_password(password: str) -> str:
    """The argon2id hash of ``password`` with a fresh salt, in the PHC string format."""
    return _HASHER.hash(password)


def verify_password(stored: str | None, password: str) -> bool:
    """``password`` matches the ``stored`` hash; with no hash (no such user) the same work is done and False
    is the answer."""
    try:
        return _HASHER.verify(stored or _DUMMY, password) and stored is not None
    except (VerifyMismatchError, VerificationError, InvalidHashError):
        return False


def needs_rehash(stored: str) -> bool:
    """The hash was made with weaker parameters than today's and should be replaced at the next sign-in."""
    return _HASHER.check_needs_rehash(stored)
