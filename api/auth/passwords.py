"""Passwords kept as argon2id hashes: RFC 9106's second recommended memory and passes (64 MiB, t=3) on one lane.

One lane rather than RFC 9106's four: the C library runs a hash on as many threads as it has lanes, so on a
2-core office server a four-lane check takes both cores from everyone for its half second, where one lane leaves
a core to the routes. The work per guess (memory times passes) is the same, and so is an attacker's cost.
"""

from __future__ import annotations

from argon2 import PasswordHasher
from argon2.exceptions import InvalidHashError, VerificationError, VerifyMismatchError

#: The hasher of new passwords; a hash made with other parameters (RFC 9106's four lanes) is renewed at sign-in.
REAL = PasswordHasher(time_cost=3, memory_cost=65536, parallelism=1)
_HASHER = REAL
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
