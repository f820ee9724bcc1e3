"""Who is calling and whether they may: an API token, a sign-in cookie, or nobody; 401 and 403 as problems.

The caller is found once per request, before the body is read, and kept on the request's state as a
:class:`Principal` for the endpoints (a study's owner, the admin endpoints). With authentication off every caller
is an admin without a name.
"""

from __future__ import annotations

import asyncio
from dataclasses import dataclass
from typing import Literal

from fastapi import Request
from fastapi.responses import JSONResponse
from starlette.datastructures import Headers
from starlette.requests import cookie_parser
from starlette.types import ASGIApp, Receive, Scope, Send

import store

from ..problems import problem
from . import roles, tokens
from .sessions import CSRF_HEADER, Session, Sessions
from .users import Accounts, TokenExpired

REALM = 'Bearer realm="mechsynth"'


@dataclass(frozen=True, slots=True)
class Principal:
    """The caller: the user (None with authentication off), the roles it acts with, and how it was recognised
    (``open`` when authentication is off, ``session`` for a browser, ``token`` for an API token)."""

    user: store.User | None
    roles: frozenset[str]
    via: Literal["open", "session", "token", "none"]
    session: Session | None = None
    token_id: int | None = None

    @property
    def name(self) -> str | None:
        """The caller's user name."""
        return None if self.user is None else self.user.name

    @property
    def is_admin(self) -> bool:
        """The caller may do everything."""
        return "admin" in self.roles

    def may_change(self, owner: str | None) -> bool:
        """The caller may cancel, resume or delete what ``owner`` made: its owner or an admin."""
        return self.is_admin or (self.name is not None and self.name == owner)


OPEN = Principal(None, frozenset({"admin"}), "open")
NOBODY = Principal(None, frozenset(), "none")


class NotOwner(Exception):
    """The caller may not change what another user made (answered 403)."""

    def __init__(self, what: str, owner: str | None, caller: str | None) -> None:
        super().__init__(f"{what} belongs to {owner or 'nobody'}; only its owner or an admin may change it, "
                         f"not {caller}")
        self.owner = owner


class Refused(Exception):
    """The credentials sent are not valid: the message says why (never echoing them)."""


class Access:
    """Authentication of one service: on or off, its users and tokens, and its sign-in sessions."""

    def __init__(self, enabled: bool, accounts: Accounts, sessions: Sessions) -> None:
        self.enabled = enabled
        self.accounts = accounts
        self.sessions = sessions

    def from_token(self, sent: str) -> Principal:
        """The caller of a bearer token; :class:`Refused` when it is unknown or revoked."""
        if not tokens.well_formed(sent):
            raise Refused("the bearer token is not one this service issued")
        try:
            found = self.accounts.token_user(sent)
        except TokenExpired as exc:
            raise Refused(str(exc)) from None
        if found is None:
            raise Refused("the bearer token is unknown or revoked")
        user, token_id = found
        return Principal(user, user.roles, "token", token_id=token_id)

    def from_cookie(self, cookie: str) -> Principal | None:
        """The caller of a sign-in cookie, or None when it is not valid (expired, signed out, forged, its user
        removed, or the user's credential epoch moved since: a password reset, a role removed)."""
        session = self.sessions.check(cookie)
        if session is None:
            return None
        user = self.accounts.get(session.user_id)
        if user is None or user.name != session.name or user.epoch != session.epoch:
            return None
        return Principal(user, user.roles, "session", session=session)

    def identify(self, headers: Headers) -> Principal:
        """The caller of a request's headers: a bearer token first, else the sign-in cookie, else nobody."""
        authorization = headers.get("authorization")
        if authorization is not None:
            scheme, _, credentials = authorization.partition(" ")
            if scheme.lower() != "bearer" or not credentials.strip():
                raise Refused("the Authorization header must be 'Bearer <token>'")
            return self.from_token(credentials.strip())
        cookie = cookie_parser(headers.get("cookie", "")).get(self.sessions.cookie_name)
        found = self.from_cookie(cookie) if cookie else None
        return found or NOBODY


def principal(request: Request) -> Principal:
    """The caller of this request, as :class:`Guard` found it."""
    found: Principal = getattr(request.state, "principal", OPEN)
    return found


class Guard:
    """ASGI middleware: find the caller, answer 401 when a request needs a sign-in it lacks, 403 when the caller's
    roles do not allow the request or a browser's change lacks its CSRF token."""

    def __init__(self, app: ASGIApp, access: Access) -> None:
        self.app = app
        self.access = access

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http" or not self.access.enabled:
            scope.setdefault("state", {})["principal"] = OPEN
            await self.app(scope, receive, send)
            return
        method, path = scope["method"], scope["path"]
        needed = roles.required(method, path)
        if needed is None and not path.startswith("/v1/"):
            # the workbench's files, the manual, health: nobody needs to be recognised, the store is not asked
            scope.setdefault("state", {})["principal"] = NOBODY
            await self.app(scope, receive, send)
            return
        try:
            caller = await asyncio.to_thread(self.access.identify, Headers(scope=scope))
        except store.StoreUnavailable as exc:
            await problem(503, "store-unavailable", "Store unavailable", f"{exc}: callers cannot be recognised",
                          headers={"Retry-After": "10"}, reason=exc.reason)(scope, receive, send)
            return
        except Refused as exc:
            if needed is not None:
                await problem(401, "unauthenticated", "Sign-in needed", str(exc),
                              headers={"WWW-Authenticate": REALM + ', error="invalid_token"'})(scope, receive, send)
                return
            caller = NOBODY
        response: JSONResponse | None = None
        if needed is None:
            pass
        elif caller.via == "none":
            response = problem(401, "unauthenticated", "Sign-in needed",
                               f"{method} {path} needs an API token (Authorization: Bearer <token>) or a signed-in "
                               f"browser", headers={"WWW-Authenticate": REALM})
        elif not roles.allows(caller.roles, needed):
            response = problem(403, "forbidden", "Not allowed",
                               roles.refusal(caller.name, caller.roles, method, path, needed),
                               roles=sorted(caller.roles), needed_roles=sorted(needed))
        elif (caller.session is not None and method not in roles.SAFE_METHODS
              and not self.access.sessions.csrf_ok(caller.session, Headers(scope=scope).get(CSRF_HEADER))):
            response = problem(403, "csrf-token-missing", "CSRF token missing",
                               f"a signed-in browser's {method} must carry the session's CSRF token in the "
                               f"X-CSRF-Token header (the sign-in answer and the {self.access.sessions.csrf_cookie_name} "
                               f"cookie hold it)")
        if response is not None:
            await response(scope, receive, send)
            return
        state = scope.setdefault("state", {})
        state["principal"] = caller
        state["user"] = caller.user          # the store's user, as api.identity reads it
        await self.app(scope, receive, send)
