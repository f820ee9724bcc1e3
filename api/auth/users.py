"""The users and API tokens of the service's store, with what sign-in and the admins need beyond it: a token's
user found by the token's hash and confirmed by a constant-time comparison, a user's tokens, removing a user.

A token acts with its user's roles at the time of the request, so changing a user's roles changes its tokens; a
token made before the user's credential epoch last moved (a password reset, a role removed) is refused.
"""

from __future__ import annotations

import hmac
import threading
import time
from dataclasses import dataclass

import sqlalchemy as sa

import store
from store.schema import api_tokens, users


@dataclass(frozen=True, slots=True)
class TokenInfo:
    """A kept API token, without its secret: its number, user, label and when it was made and last used."""

    id: int
    user: str
    label: str
    created_at: float
    last_used_at: float | None
    expires_at: float | None = None


class TokenExpired(Exception):
    """The token was valid until ``expires_at`` [s since the epoch] and is refused from then on."""

    def __init__(self, expires_at: float) -> None:
        super().__init__(f"the bearer token expired at {time.strftime('%Y-%m-%d %H:%M:%S', time.gmtime(expires_at))} "
                         "UTC; an admin makes a new one")
        self.expires_at = expires_at


class Accounts(store.Users):
    """Users and API tokens in the service's store; the tokens' last uses are kept here and written in batches."""

    def __init__(self, db: store.Store) -> None:
        super().__init__(db)
        self._uses: dict[int, float] = {}
        self._uses_lock = threading.Lock()

    def used(self, token_id: int, when: float | None = None) -> None:
        """Note a use of token ``token_id`` (now, by default); :meth:`record_uses` writes it."""
        with self._uses_lock:
            self._uses[token_id] = time.time() if when is None else when

    def record_uses(self) -> int:
        """Write the tokens' last uses noted since the previous call, in one transaction; how many. When the
        store cannot take them they are kept (the latest use per token) for the next call."""
        with self._uses_lock:
            uses, self._uses = self._uses, {}
        if not uses:
            return 0
        try:
            with self.store.write() as db:
                for token_id, when in sorted(uses.items()):
                    last = api_tokens.c.last_used_at
                    db.execute(api_tokens.update()
                               .where(api_tokens.c.id == token_id, sa.or_(last.is_(None), last < when))
                               .values(last_used_at=when))
        except BaseException:
            with self._uses_lock:
                for token_id, when in uses.items():
                    self._uses[token_id] = max(when, self._uses.get(token_id, when))
            raise
        return len(uses)

    def noted_use(self, token_id: int) -> float | None:
        """The last use of a token noted and not yet written, if any."""
        with self._uses_lock:
            return self._uses.get(token_id)

    def token_user(self, token: str) -> tuple[store.User, int] | None:
        """The user holding ``token`` and the token's number, or None (:class:`TokenExpired` past its expiry); the
        token's use now is noted (written by
        :meth:`record_uses`, off the request's path: recognising a caller never writes).

        The row is found by the token's SHA-256 (a 256-bit random secret, so the index lookup tells an attacker
        nothing); the stored hash is then compared byte for byte in constant time, whatever the database's
        collation does with case or trailing spaces."""
        digest = store.token_hash(token)
        with self.store.read() as db:
            row = db.execute(sa.select(api_tokens.c.id, api_tokens.c.token_hash, users.c.id, users.c.name,
                                       users.c.roles, users.c.created_at, users.c.credential_epoch,
                                       api_tokens.c.expires_at)
                             .join(users, api_tokens.c.user_id == users.c.id)
                             .where(api_tokens.c.token_hash == digest,
                                    api_tokens.c.epoch == users.c.credential_epoch)).one_or_none()
            if row is None or not hmac.compare_digest(str(row[1]).encode(), digest.encode()):
                return None
        if row[7] is not None and float(row[7]) <= time.time():
            raise TokenExpired(float(row[7]))
        self.used(int(row[0]))
        user = store.User(int(row[2]), str(row[3]), frozenset(str(row[4]).split()), float(row[5]), int(row[6]))
        return user, int(row[0])

    def tokens(self, user: store.User) -> list[TokenInfo]:
        """A user's tokens, oldest first."""
        with self.store.read() as db:
            rows = db.execute(sa.select(api_tokens.c.id, api_tokens.c.label, api_tokens.c.created_at,
                                        api_tokens.c.last_used_at, api_tokens.c.expires_at)
                              .where(api_tokens.c.user_id == user.id).order_by(api_tokens.c.id)).all()
        out = []
        for r in rows:
            last = max((float(t) for t in (r[3], self.noted_use(int(r[0]))) if t is not None), default=None)
            out.append(TokenInfo(int(r[0]), user.name, str(r[1] or ""), float(r[2]), last,
                                 None if r[4] is None else float(r[4])))
        return out

    def remove(self, user: store.User) -> None:
        """Remove a user and its tokens."""
        with self.store.write() as db:
            db.execute(api_tokens.delete().where(api_tokens.c.user_id == user.id))
            db.execute(users.delete().where(users.c.id == user.id))
