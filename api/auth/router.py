"""/v1/auth: sign-in, who is calling, sign-out; /v1/users and /v1/tokens: the admins' users and API tokens."""

from __future__ import annotations

import asyncio
import collections
import contextlib
import math
import os
import threading
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from functools import partial
from typing import Annotated, Any, Literal, TypeVar

import sqlalchemy as sa
from fastapi import APIRouter, Depends, Path, Request, Response
from fastapi.responses import JSONResponse

import store
from mechsynth_client.schemas.auth import (
    NewTokenOut,
    SessionOut,
    SignInIn,
    TokenIn,
    TokenOut,
    UserIn,
    UserOut,
    UserPatchIn,
)
from ..problems import problem
from . import passwords, tokens
from .guard import Access, Principal, principal
from .users import Accounts, TokenInfo

T = TypeVar("T")
router = APIRouter(tags=["users"])
UserName = Annotated[str, Path(min_length=1, max_length=64, pattern=r"^[A-Za-z0-9][A-Za-z0-9_.@\-]*$",
                               description="The user's name.")]
# the store numbers tokens with 32-bit integers (PostgreSQL's integer)
TokenId = Annotated[int, Path(ge=1, le=2**31 - 1, description="The token's number.")]
PrincipalDep = Annotated[Principal, Depends(principal)]


def _ref(description: str) -> dict[str, Any]:
    return {"description": description,
            "content": {"application/problem+json": {"schema": {"$ref": "#/components/schemas/Problem"}}}}


NO_USER: dict[int | str, dict[str, Any]] = {404: _ref("No user has this name.")}
SIGN_IN_PROBLEMS: dict[int | str, dict[str, Any]] = {
    401: _ref("The name or the password is wrong."),
    409: _ref("Authentication is off on this service: there is nothing to sign in to."),
    429: _ref("Too many wrong passwords for this name lately, too many sign-ins from this address, or too many "
              "sign-ins being checked at once; retry after Retry-After seconds."),
}

MAX_FAILURES = 5
FAILURE_WINDOW_S = 900.0
# Sign-in attempts one client address may make per window, right or wrong (SYNTH_SIGN_INS_PER_MINUTE): a spray
# of fresh names meets this bound, which the per-name one never does.
MAX_ADDRESS_ATTEMPTS = 10
ADDRESS_WINDOW_S = 60.0
# Password hashes (argon2: about half a second of a core and 64 MiB each) are computed on threads of their own,
# never on the pool that recognises callers or serves the routes; beyond this many waiting, sign-in answers 429.
HASH_THREADS = 1
MAX_HASHES_WAITING = 4
#: The hashing threads' niceness: a spray's hashes take the core only when the routes leave it idle.
HASH_NICENESS = 10


def _lower_priority() -> None:
    """The calling thread yields the core to the routes (Linux's niceness is a thread's own)."""
    with contextlib.suppress(OSError, AttributeError):
        os.setpriority(os.PRIO_PROCESS, threading.get_native_id(), HASH_NICENESS)


_HASHING = ThreadPoolExecutor(max_workers=HASH_THREADS, thread_name_prefix="password-hash",
                              initializer=_lower_priority)


class Failures:
    """Wrong passwords per name over the last window: past the limit, sign-in for that name waits."""

    def __init__(self) -> None:
        self._seen: dict[str, list[float]] = {}
        self._lock = threading.Lock()

    def wait_s(self, name: str, now: float) -> float:
        """Seconds before ``name`` may try again (0: now)."""
        with self._lock:
            recent = [t for t in self._seen.get(name, []) if t > now - FAILURE_WINDOW_S]
            self._seen[name] = recent
            return 0.0 if len(recent) < MAX_FAILURES else recent[0] + FAILURE_WINDOW_S - now

    def failed(self, name: str, now: float) -> None:
        """A wrong password for ``name`` now."""
        with self._lock:
            self._seen.setdefault(name, []).append(now)
            if len(self._seen) > 10_000:        # bounded memory whatever names are tried
                self._seen = {k: v for k, v in self._seen.items() if v and v[-1] > now - FAILURE_WINDOW_S}

    def cleared(self, name: str) -> None:
        """``name`` signed in: its count starts again."""
        with self._lock:
            self._seen.pop(name, None)


class AddressAttempts:
    """Sign-in attempts per client address over the last window; past the limit that address waits."""

    def __init__(self, limit: int = MAX_ADDRESS_ATTEMPTS, window_s: float = ADDRESS_WINDOW_S) -> None:
        self.limit = limit
        self.window_s = window_s
        self._seen: dict[str, collections.deque[float]] = {}
        self._lock = threading.Lock()

    def attempt(self, address: str, now: float) -> float:
        """Count an attempt from ``address`` now; 0 when it may go on, else the seconds before it may."""
        with self._lock:
            seen = self._seen.setdefault(address, collections.deque())
            while seen and seen[0] <= now - self.window_s:
                seen.popleft()
            if len(seen) >= self.limit:
                return seen[0] + self.window_s - now
            seen.append(now)
            if len(self._seen) > 10_000:        # bounded memory whatever addresses call
                self._seen = {k: v for k, v in self._seen.items() if v and v[-1] > now - self.window_s}
            return 0.0


class Hashing:
    """The password-hashing threads with a bound on the work waiting for them."""

    def __init__(self, limit: int = MAX_HASHES_WAITING) -> None:
        self.limit = limit
        self.waiting = 0
        self._lock = threading.Lock()

    async def run(self, fn: Callable[..., T], *args: Any) -> T | None:
        """``fn(*args)`` on the hashing threads; None at once when ``limit`` calls are waiting already."""
        with self._lock:
            if self.waiting >= self.limit:
                return None
            self.waiting += 1
        try:
            return await asyncio.get_running_loop().run_in_executor(_HASHING, partial(fn, *args))
        finally:
            with self._lock:
                self.waiting -= 1


def _too_many(detail: str, wait_s: float) -> JSONResponse:
    retry = max(1, math.ceil(wait_s))
    return problem(429, "too-many-sign-ins", "Too many sign-ins", detail, headers={"Retry-After": str(retry)},
                   retry_after_s=retry)


def get_access(request: Request) -> Access:
    """The app's authentication."""
    access: Access = request.app.state.access
    return access


AccessDep = Annotated[Access, Depends(get_access)]


def _session_out(access: Access, caller: Principal) -> SessionOut:
    session = caller.session
    return SessionOut(auth="on" if access.enabled else "off", signed_in=caller.user is not None,
                      name=caller.name, roles=sorted(caller.roles), via=caller.via,
                      csrf_token=None if session is None else access.sessions.csrf_token(session),
                      expires_at=None if session is None else session.expires)


def _user_out(user: store.User) -> UserOut:
    return UserOut(name=user.name, roles=sorted(user.roles), created_at=user.created_at)


def _token_out(token: TokenInfo) -> TokenOut:
    return TokenOut(id=token.id, user=token.user, label=token.label, created_at=token.created_at,
                    last_used_at=token.last_used_at, expires_at=token.expires_at)


def _no_user(name: str) -> JSONResponse:
    return problem(404, "user-not-found", "No such user", f"no user is named {name!r}", name=name)


def _check_in(accounts: Accounts, name: str, password: str) -> store.User | Literal[False]:
    """The user when the password is right (its hash renewed when made with weaker parameters), else False."""
    stored = accounts.password_hash(name)
    if not passwords.verify_password(stored, password) or stored is None:
        return False
    user = accounts.by_name(name)
    if user is not None and passwords.needs_rehash(stored):
        accounts.set_password_hash(user.id, passwords.hash_password(password))
    return user or False


async def _hash(password: str) -> str:
    """A new password's hash on the hashing threads (an admin's change waits its turn, it is never refused)."""
    return await asyncio.get_running_loop().run_in_executor(_HASHING, passwords.hash_password, password)


@router.post("/auth/signin", response_model=SessionOut, responses=SIGN_IN_PROBLEMS)
async def sign_in(body: SignInIn, request: Request, response: Response, access: AccessDep) -> Any:
    """Sign a browser in: sets an HttpOnly, SameSite=Strict session cookie and a CSRF cookie, and answers the
    CSRF token that the page's POST, PUT, PATCH and DELETE requests carry in `X-CSRF-Token`. Scripts and other
    programs use an API token instead."""
    if not access.enabled:
        return problem(409, "auth-off", "Authentication is off",
                       "this service is open (SYNTH_AUTH=off): every request is allowed without signing in")
    failures: Failures = request.app.state.sign_in_failures
    now = time.time()
    address = request.client.host if request.client is not None else "unknown"
    if (wait := request.app.state.sign_in_addresses.attempt(address, now)) > 0:
        return _too_many(f"too many sign-ins from {address}; retry in {math.ceil(wait)} s", wait)
    if (wait := failures.wait_s(body.name, now)) > 0:
        return _too_many(f"too many wrong passwords for {body.name!r}; retry in {math.ceil(wait)} s", wait)
    hashing: Hashing = request.app.state.hashing
    checked = await hashing.run(_check_in, access.accounts, body.name, body.password)
    if checked is None:
        return _too_many("too many sign-ins are being checked at once; retry in a second", 1.0)
    user = checked or None
    if user is None:
        failures.failed(body.name, now)
        return problem(401, "invalid-credentials", "Sign-in refused", "the name or the password is wrong")
    failures.cleared(body.name)
    cookie, session = access.sessions.issue(user.name, user_id=user.id, epoch=user.epoch)
    max_age = int(access.sessions.lifetime_s)
    secure = access.sessions.secure
    response.set_cookie(access.sessions.cookie_name, cookie, max_age=max_age, path="/", secure=secure,
                        httponly=True, samesite="strict")
    response.set_cookie(access.sessions.csrf_cookie_name, access.sessions.csrf_token(session), max_age=max_age,
                        path="/", secure=secure, httponly=False, samesite="strict")
    return _session_out(access, Principal(user, user.roles, "session", session=session))


@router.get("/auth/session", response_model=SessionOut)
async def session(caller: PrincipalDep, access: AccessDep) -> SessionOut:
    """Who is calling: authentication on or off, the signed-in user or the token's user, its roles, and a
    browser session's CSRF token and end."""
    return _session_out(access, caller)


@router.post("/auth/signout", status_code=204, response_model=None)
async def sign_out(caller: PrincipalDep, access: AccessDep) -> Response:
    """End this browser's session: its cookie is refused from now on, and both cookies are removed."""
    if caller.session is not None:
        access.sessions.end(caller.session)
    response = Response(status_code=204)
    for name in (access.sessions.cookie_name, access.sessions.csrf_cookie_name):
        response.delete_cookie(name, path="/", secure=access.sessions.secure,
                               httponly=name == access.sessions.cookie_name, samesite="strict")
    return response


@router.get("/users", response_model=list[UserOut])
async def users(access: AccessDep) -> list[UserOut]:
    """Every user, by name, with its roles (admins only)."""
    return [_user_out(u) for u in await asyncio.to_thread(access.accounts.all)]


@router.post("/users", status_code=201, response_model=UserOut,
             responses={409: _ref("A user of this name exists already.")})
async def add_user(body: UserIn, access: AccessDep) -> Any:
    """Make a user with a password and roles (admins only)."""
    hashed = await _hash(body.password)
    try:
        user = await asyncio.to_thread(access.accounts.create, body.name, frozenset(body.roles), hashed)
    except sa.exc.IntegrityError:
        return problem(409, "user-exists", "User exists", f"a user named {body.name!r} exists already",
                       name=body.name)
    return _user_out(user)


@router.get("/users/{name}", response_model=UserOut, responses=NO_USER)
async def user(name: UserName, access: AccessDep) -> Any:
    """One user and its roles (admins only)."""
    found = await asyncio.to_thread(access.accounts.by_name, name)
    return _no_user(name) if found is None else _user_out(found)


@router.patch("/users/{name}", response_model=UserOut, responses=NO_USER)
async def update_user(name: UserName, body: UserPatchIn, access: AccessDep) -> Any:
    """Set a user's password, roles, or both (admins only). A new password, or a role taken away, ends the
    user's browser sessions and API tokens at once; added roles apply to them at once."""
    found = await asyncio.to_thread(access.accounts.by_name, name)
    if found is None:
        return _no_user(name)
    if body.password is not None:
        hashed = await _hash(body.password)
        await asyncio.to_thread(access.accounts.set_password_hash, found.id, hashed)
        await asyncio.to_thread(access.accounts.end_credentials, found.id)
    if body.roles is not None:
        await asyncio.to_thread(access.accounts.set_roles, found.id, frozenset(body.roles))
    changed = await asyncio.to_thread(access.accounts.by_name, name)
    return _no_user(name) if changed is None else _user_out(changed)


@router.delete("/users/{name}", status_code=204, response_model=None, responses=NO_USER)
async def remove_user(name: UserName, access: AccessDep) -> Response:
    """Remove a user and revoke its tokens (admins only); its browser sessions end at once (a user made again
    with the same name is another user)."""
    found = await asyncio.to_thread(access.accounts.by_name, name)
    if found is None:
        return _no_user(name)
    await asyncio.to_thread(access.accounts.remove, found)
    return Response(status_code=204)


@router.get("/users/{name}/tokens", response_model=list[TokenOut], responses=NO_USER)
async def user_tokens(name: UserName, access: AccessDep) -> Any:
    """A user's API tokens, oldest first, without their secrets (admins only)."""
    found = await asyncio.to_thread(access.accounts.by_name, name)
    if found is None:
        return _no_user(name)
    return [_token_out(t) for t in await asyncio.to_thread(access.accounts.tokens, found)]


@router.post("/users/{name}/tokens", status_code=201, response_model=NewTokenOut, responses=NO_USER)
async def add_token(name: UserName, body: TokenIn, request: Request, access: AccessDep) -> Any:
    """Make an API token for a user (admins only); the answer shows the token this once. Programs send it as
    `Authorization: Bearer <token>`; it acts with the user's roles, until `expires_in_days` (the service's
    default when omitted; 0: until revoked)."""
    found = await asyncio.to_thread(access.accounts.by_name, name)
    if found is None:
        return _no_user(name)
    token = tokens.new_token()
    now = time.time()
    days = request.app.state.settings.token_days if body.expires_in_days is None else body.expires_in_days
    expires_at = now + days * 86_400.0 if days > 0 else None
    token_id = await asyncio.to_thread(access.accounts.add_token, found.id, token, body.label, expires_at)
    return NewTokenOut(id=token_id, user=name, label=body.label, created_at=now, last_used_at=None,
                       expires_at=expires_at, token=token)


@router.delete("/tokens/{token_id}", status_code=204, response_model=None,
               responses={404: _ref("No token has this number.")})
async def revoke_token(token_id: TokenId, access: AccessDep) -> Response:
    """Revoke an API token at once (admins only)."""
    if not await asyncio.to_thread(access.accounts.revoke_token, token_id):
        return problem(404, "token-not-found", "No such token", f"no token has the number {token_id}")
    return Response(status_code=204)
