"""Users and their API tokens. The store keeps only hashes: a password's (made by whoever signs users in) and a
token's (sha256 of the token, which is shown once when it is made)."""

from __future__ import annotations

import hashlib
import secrets
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import sqlalchemy as sa

from .db import Store
from .schema import api_tokens, users

#: Every role a user may hold: viewer, engineer and admin grant access; checker and approver sign revisions.
ROLES = ("viewer", "engineer", "admin", "checker", "approver")


@dataclass(frozen=True, slots=True)
class User:
    """A user of the service.

    Parameters
    ----------
    id
        The user's number in the store [-].
    name
        Unique sign-in and display name [-].
    roles
        The roles held, from :data:`ROLES` [-].
    created_at
        When the user was made, seconds since the epoch [s].
    epoch
        The user's credential epoch: sessions and tokens carry it and end when it moves (a password reset, a
        role removed); a new user starts at a random one, so a name or a number used again is not the same
        credential [-].
    """

    id: int
    name: str
    roles: frozenset[str]
    created_at: float
    epoch: int = 0

    def has(self, role: str) -> bool:
        """True when the user holds ``role``."""
        return role in self.roles


def token_hash(token: str) -> str:
    """The stored form of an API token: its sha256, hex."""
    return hashlib.sha256(token.encode()).hexdigest()


def _user(row: Sequence[Any]) -> User:
    return User(int(row[0]), str(row[1]), frozenset(str(row[2]).split()), float(row[3]), int(row[4]))


_USER_COLUMNS = (users.c.id, users.c.name, users.c.roles, users.c.created_at, users.c.credential_epoch)


class Users:
    """Users and API tokens in ``store``."""

    def __init__(self, store: Store) -> None:
        self.store = store

    def create(self, name: str, roles: set[str] | frozenset[str], password_hash: str | None = None) -> User:
        """Add a user; ``ValueError`` for an unknown role, ``sqlalchemy.exc.IntegrityError`` for a taken name."""
        if unknown := set(roles) - set(ROLES):
            raise ValueError(f"unknown roles {sorted(unknown)}; the roles are {list(ROLES)}")
        now = time.time()
        epoch = secrets.randbelow(2**30)
        with self.store.write() as db:
            user_id = db.execute(users.insert().values(name=name, password_hash=password_hash,
                                                       roles=" ".join(sorted(roles)), created_at=now,
                                                       credential_epoch=epoch)
                                 .returning(users.c.id)).scalar_one()
        return User(user_id, name, frozenset(roles), now, epoch)

    def get(self, user_id: int) -> User | None:
        """The user with this number, or None."""
        with self.store.read() as db:
            row = db.execute(sa.select(*_USER_COLUMNS).where(users.c.id == user_id)).one_or_none()
        return None if row is None else _user(row)

    def by_name(self, name: str) -> User | None:
        """The user with this name, or None."""
        with self.store.read() as db:
            row = db.execute(sa.select(*_USER_COLUMNS).where(users.c.name == name)).one_or_none()
        return None if row is None else _user(row)

    def all(self) -> list[User]:
        """Every user, by name."""
        with self.store.read() as db:
            return [_user(r) for r in db.execute(sa.select(*_USER_COLUMNS).order_by(users.c.name))]

    def password_hash(self, name: str) -> str | None:
        """The stored password hash of the user ``name`` (None without one or without such a user)."""
        with self.store.read() as db:
            return db.scalar(sa.select(users.c.password_hash).where(users.c.name == name))

    def set_password_hash(self, user_id: int, password_hash: str | None) -> None:
        """Replace a user's password hash."""
        with self.store.write() as db:
            db.execute(users.update().where(users.c.id == user_id).values(password_hash=password_hash))

    def set_roles(self, user_id: int, roles: set[str] | frozenset[str]) -> None:
        """Replace a user's roles; ``ValueError`` for an unknown role. Removing a role ends the user's sessions
        and tokens (:meth:`end_credentials`): nothing signed in keeps acting with what was taken away."""
        if unknown := set(roles) - set(ROLES):
            raise ValueError(f"unknown roles {sorted(unknown)}; the roles are {list(ROLES)}")
        with self.store.write() as db:
            held = db.scalar(sa.select(users.c.roles).where(users.c.id == user_id))
            values: dict[str, Any] = {"roles": " ".join(sorted(roles))}
            if held is not None and set(str(held).split()) - set(roles):
                values["credential_epoch"] = users.c.credential_epoch + 1
            db.execute(users.update().where(users.c.id == user_id).values(**values))

    def end_credentials(self, user_id: int) -> None:
        """End every session and API token of a user at once (a password reset): its credential epoch moves."""
        with self.store.write() as db:
            db.execute(users.update().where(users.c.id == user_id)
                       .values(credential_epoch=users.c.credential_epoch + 1))

    def add_token(self, user_id: int, token: str, label: str | None = None, expires_at: float | None = None) -> int:
        """Keep the hash of a new API token of a user, refused after ``expires_at`` [s since the epoch] when
        given; the token's number (to revoke it by)."""
        with self.store.write() as db:
            epoch = sa.select(users.c.credential_epoch).where(users.c.id == user_id).scalar_subquery()
            return int(db.execute(api_tokens.insert().values(token_hash=token_hash(token), user_id=user_id,
                                                             label=label, created_at=time.time(), epoch=epoch,
                                                             expires_at=expires_at)
                                  .returning(api_tokens.c.id)).scalar_one())

    def by_token(self, token: str) -> User | None:
        """The user holding this API token (and the token's last use set to now), or None."""
        digest = token_hash(token)
        with self.store.write() as db:
            row = db.execute(sa.select(*_USER_COLUMNS).join(api_tokens, api_tokens.c.user_id == users.c.id)
                             .where(api_tokens.c.token_hash == digest,
                                    api_tokens.c.epoch == users.c.credential_epoch,
                                    sa.or_(api_tokens.c.expires_at.is_(None),
                                           api_tokens.c.expires_at > time.time()))).one_or_none()
            if row is None:
                return None
            db.execute(api_tokens.update().where(api_tokens.c.token_hash == digest)
                       .values(last_used_at=time.time()))
        return _user(row)

    def revoke_token(self, token_id: int) -> bool:
        """Delete an API token; False when there was none with this number."""
        with self.store.write() as db:
            return db.execute(api_tokens.delete().where(api_tokens.c.id == token_id)).rowcount == 1
