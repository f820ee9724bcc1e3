"""The users and API tokens a service keeps: what the security layer needs of a store, and an in-memory store.

A user has a name, an argon2 password hash and roles; a token belongs to a user, has a label and roles (at most
the user's: a token acts with the roles it and its user both have now), and is kept as the hash of its secret.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field, replace
from typing import Protocol


@dataclass(frozen=True, slots=True)
class User:
    """A user: name, argon2 password hash, roles and when it was made [s since the epoch]."""

    name: str
    password_hash: str
    roles: frozenset[str]
    created_at: float = field(default_factory=time.time)


@dataclass(frozen=True, slots=True)
class ApiToken:
    """A kept API token: its id, its user, a label, its roles, the hash of its secret and when it was made."""

    id: str
    user: str
    label: str
    roles: frozenset[str]
    secret_hash: str
    created_at: float = field(default_factory=time.time)


class UserExists(Exception):
    """A user of this name exists already."""


class Users(Protocol):
    """Where users and tokens are kept; every method is a short blocking call (run off the event loop)."""

    def user(self, name: str) -> User | None:
        """The user of this name, or None."""

    def users(self) -> list[User]:
        """Every user, by name."""

    def add_user(self, user: User) -> None:
        """Keep a new user; :class:`UserExists` when the name is taken."""

    def update_user(self, name: str, *, password_hash: str | None = None,
                    roles: frozenset[str] | None = None) -> User | None:
        """Change a user's password hash or roles; None when there is no such user."""

    def remove_user(self, name: str) -> bool:
        """Remove a user and its tokens; False when there was none."""

    def add_token(self, token: ApiToken) -> None:
        """Keep a new token (its user exists)."""

    def token(self, token_id: str) -> ApiToken | None:
        """The token of this id, or None."""

    def tokens(self, user: str) -> list[ApiToken]:
        """A user's tokens, oldest first."""

    def remove_token(self, token_id: str) -> bool:
        """Revoke a token; False when there was none."""


class MemoryUsers:
    """Users and tokens in this process's memory (tests, or a service that keeps no users across restarts)."""

    def __init__(self) -> None:
        self._users: dict[str, User] = {}
        self._tokens: dict[str, ApiToken] = {}
        self._lock = threading.Lock()

    def user(self, name: str) -> User | None:
        """The user of this name, or None."""
        return self._users.get(name)

    def users(self) -> list[User]:
        """Every user, by name."""
        return sorted(self._users.values(), key=lambda u: u.name)

    def add_user(self, user: User) -> None:
        """Keep a new user; :class:`UserExists` when the name is taken."""
        with self._lock:
            if user.name in self._users:
                raise UserExists(user.name)
            self._users[user.name] = user

    def update_user(self, name: str, *, password_hash: str | None = None,
                    roles: frozenset[str] | None = None) -> User | None:
        """Change a user's password hash or roles; None when there is no such user."""
        with self._lock:
            user = self._users.get(name)
            if user is None:
                return None
            user = replace(user, password_hash=password_hash or user.password_hash,
                           roles=user.roles if roles is None else roles)
            self._users[name] = user
            return user

    def remove_user(self, name: str) -> bool:
        """Remove a user and its tokens; False when there was none."""
        with self._lock:
            self._tokens = {k: t for k, t in self._tokens.items() if t.user != name}
            return self._users.pop(name, None) is not None

    def add_token(self, token: ApiToken) -> None:
        """Keep a new token."""
        with self._lock:
            self._tokens[token.id] = token

    def token(self, token_id: str) -> ApiToken | None:
        """The token of this id, or None."""
        return self._tokens.get(token_id)

    def tokens(self, user: str) -> list[ApiToken]:
        """A user's tokens, oldest first."""
        return sorted((t for t in self._tokens.values() if t.user == user), key=lambda t: t.created_at)

    def remove_token(self, token_id: str) -> bool:
        """Revoke a token; False when there was none."""
        with self._lock:
            return self._tokens.pop(token_id, None) is not None
