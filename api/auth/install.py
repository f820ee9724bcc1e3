"""Putting the security layer on the app: middleware in order, the sign-in and user endpoints, the first admin,
and the OpenAPI document's security schemes."""

from __future__ import annotations

import logging
import secrets
import threading
from typing import Any

import sqlalchemy as sa
from fastapi import FastAPI, Request
from fastapi.responses import JSONResponse
from starlette.middleware.cors import CORSMiddleware

import store

from ..settings import Settings
from . import passwords, roles
from ..problems import problem
from .guard import Access, Guard, NotOwner
from .headers import SecurityHeaders
from .hosts import AllowedHosts
from .origin import SameOrigin
from .router import AddressAttempts, Failures, Hashing
from .sessions import CSRF_HEADER, Sessions
from .users import Accounts

log = logging.getLogger("api.auth")


def bootstrap(accounts: Accounts, settings: Settings) -> None:
    """Make the first admin named by the settings, unless a user of that name exists."""
    if settings.admin_name is None or settings.admin_password is None:
        if settings.auth == "on" and not accounts.all():
            log.warning("authentication is on and there are no users: add an admin with "
                        "`python -m api.users add NAME --role admin` or SYNTH_ADMIN_NAME and SYNTH_ADMIN_PASSWORD")
        return
    if accounts.by_name(settings.admin_name) is None:
        try:
            accounts.create(settings.admin_name, {"admin"},
                            passwords.hash_password(settings.admin_password.get_secret_value()))
        except sa.exc.IntegrityError:
            # another service process on the same store made it first
            return
        log.info("made the first admin, %s", settings.admin_name)


# Seconds between writes of the API tokens' last uses (noted in memory as callers are recognised).
TOKEN_USES_EVERY_S = 15.0


def start(app: FastAPI) -> None:
    """At start, once the store is migrated: the first admin, and the thread writing the tokens' last uses; a
    store that cannot be reached is reported by /ready, and the admin is made at the next start."""
    try:
        bootstrap(app.state.access.accounts, app.state.settings)
    except store.StoreUnavailable as exc:
        log.error("the first admin was not made: %s", exc)
    stopping = threading.Event()
    app.state.token_uses_stop = stopping
    threading.Thread(target=_record_uses, args=(app.state.access.accounts, stopping), daemon=True,
                     name="token-uses").start()


def stop(app: FastAPI) -> None:
    """At shutdown: write the tokens' last uses noted since the last write."""
    stopping: threading.Event | None = getattr(app.state, "token_uses_stop", None)
    if stopping is not None:
        stopping.set()
    try:
        app.state.access.accounts.record_uses()
    except store.StoreUnavailable as exc:
        log.warning("the API tokens' last uses were not written: %s", exc)


def _record_uses(accounts: Accounts, stopping: threading.Event) -> None:
    while not stopping.wait(TOKEN_USES_EVERY_S):
        try:
            accounts.record_uses()
        except store.StoreUnavailable as exc:
            log.warning("the API tokens' last uses wait for the store: %s", exc)
        except Exception:
            log.exception("the API tokens' last uses were not written")


def install(app: FastAPI, settings: Settings) -> Access:
    """Add the security middleware to ``app`` (outermost last: headers, hosts, CORS, origin, then the caller's
    identity and roles); users live in ``app.state.store``. The app mounts :data:`router` (sign-in, users,
    tokens) under /v1 with the other routers."""
    key = (settings.session_key.get_secret_value().encode() if settings.session_key is not None
           else secrets.token_bytes(32))
    sessions = Sessions(key, settings.session_hours * 3600.0, settings.behind_tls)
    access = Access(settings.auth == "on", Accounts(app.state.store), sessions)
    app.state.access = access
    app.state.sign_in_failures = Failures()
    app.state.sign_in_addresses = AddressAttempts(settings.sign_ins_per_minute, 60.0)
    app.state.hashing = Hashing()
    app.add_middleware(Guard, access=access)
    app.add_middleware(SameOrigin, trusted_origins=settings.origin_list(), behind_tls=settings.behind_tls)
    if settings.origin_list():
        # Pages of these origins call with a bearer token; cookies stay same-site only.
        app.add_middleware(CORSMiddleware, allow_origins=settings.origin_list(), allow_credentials=False,
                           allow_methods=["GET", "POST", "PUT", "PATCH", "DELETE"],
                           allow_headers=["authorization", "content-type", "accept", CSRF_HEADER],
                           expose_headers=["location", "retry-after"])
    app.add_middleware(AllowedHosts, allowed_hosts=settings.host_list())
    app.add_middleware(SecurityHeaders, hsts=settings.behind_tls)
    app.add_exception_handler(NotOwner, _not_owner)
    _document(app)
    return access


async def _not_owner(_: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, NotOwner)
    return problem(403, "not-owner", "Not the owner", str(exc), owner=exc.owner)


def _problem(description: str) -> dict[str, Any]:
    return {"description": description,
            "content": {"application/problem+json": {"schema": {"$ref": "#/components/schemas/Problem"}}}}


def _document(app: FastAPI) -> None:
    """The OpenAPI document names the two ways to sign in and the 401 and 403 answers of every /v1 operation."""
    build = app.openapi

    def openapi() -> dict[str, Any]:
        doc = build()
        if "bearer" in doc.get("components", {}).get("securitySchemes", {}):
            return doc
        doc.setdefault("components", {})["securitySchemes"] = {
            "bearer": {"type": "http", "scheme": "bearer",
                       "description": "An API token (mst_...) made by an admin, when SYNTH_AUTH=on."},
            "session": {"type": "apiKey", "in": "cookie", "name": "synth_session",
                        "description": "A browser signed in with POST /v1/auth/signin; its changes carry "
                                       "X-CSRF-Token."},
        }
        for path, item in doc.get("paths", {}).items():
            for method, operation in item.items():
                needed = roles.required(method.upper(), path)
                responses = operation.setdefault("responses", {})
                if method.upper() not in roles.SAFE_METHODS:
                    responses.setdefault("403", _problem(
                        "Refused: the request comes from another site's page, or (SYNTH_AUTH=on) the caller's "
                        "roles do not allow it or a browser's change lacks its CSRF token."))
                if needed is None:
                    continue
                operation["security"] = [{"bearer": []}, {"session": []}, {}]
                responses.setdefault("401", _problem(
                    "SYNTH_AUTH=on and the request has no valid API token or signed-in session."))
                responses.setdefault("403", _problem(
                    f"SYNTH_AUTH=on and the caller has none of the roles {sorted(needed)}."))
        return doc

    app.openapi = openapi  # type: ignore[method-assign]
