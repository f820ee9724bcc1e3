"""Schemas of /v1/auth (sign-in, who is calling), /v1/users and /v1/tokens (the admins' user and token
management)."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, Field

from .common import StrictModel

Role = Literal["viewer", "engineer", "admin", "checker", "approver"]
Name = Annotated[str, Field(min_length=1, max_length=64, pattern=r"^[A-Za-z0-9][A-Za-z0-9_.@\-]*$",
                            description="A user's name: letters, digits and _ . @ -, starting with a letter or digit.",
                            examples=["ada"])]
Password = Annotated[str, Field(min_length=8, max_length=1024, description="At least 8 characters.",
                                examples=["correct horse battery"])]
Roles = Annotated[list[Role], Field(min_length=1, max_length=5, description="viewer: reads; engineer: runs solver "
                                    "requests and studies, saves designs; admin: everything; checker and "
                                    "approver: sign design revisions.", examples=[["engineer"]])]


class SignInIn(StrictModel):
    """A user's name and password."""

    name: Name
    password: Annotated[str, Field(min_length=1, max_length=1024, description="The user's password.",
                                   examples=["correct horse battery"])]


class SessionOut(BaseModel):
    """Who is calling: whether authentication is on, the caller's name and roles, and for a signed-in browser the
    CSRF token its changes must carry in `X-CSRF-Token`."""

    auth: Literal["on", "off"] = Field(description="off: the service is open and every caller may do everything.")
    signed_in: bool = Field(description="A user is signed in (by this browser's cookie) or named by the token.")
    name: str | None = Field(None, description="The caller's user name.")
    roles: list[str] = Field(default_factory=list, description="The roles the caller acts with.")
    via: Literal["open", "session", "token", "none"] = Field(description="How the caller was recognised.")
    csrf_token: str | None = Field(None, description="For a browser session: send it as X-CSRF-Token with every "
                                                     "POST, PUT, PATCH and DELETE.")
    expires_at: float | None = Field(None, description="When the browser session ends [s since the epoch].")


class UserIn(StrictModel):
    """A new user."""

    name: Name
    password: Password
    roles: Roles


class UserPatchIn(StrictModel):
    """A new password, new roles, or both."""

    password: Password | None = Field(None, description="The new password; left out: unchanged.")
    roles: Roles | None = Field(None, description="The new roles, replacing the old; left out: unchanged.")


class UserOut(BaseModel):
    """A user (never its password or hash)."""

    name: str = Field(description="The user's name.")
    roles: list[str] = Field(description="The user's roles.")
    created_at: float = Field(description="When the user was made [s since the epoch].")


class TokenIn(StrictModel):
    """A new API token for a user; it acts with the user's roles at the time of each request."""

    label: Annotated[str, Field(min_length=1, max_length=100, description="What the token is for.",
                                examples=["nightly studies"])]
    expires_in_days: Annotated[float | None, Field(
        ge=0, le=36_500, examples=[30],
        description="Days the token lasts, from now [days]; 0: until it is revoked; omitted: the service's "
                    "default (SYNTH_TOKEN_DAYS, 90 days unless set).")] = None


class TokenOut(BaseModel):
    """A kept API token (never its secret)."""

    id: int = Field(description="The token's number, to revoke it by.")
    user: str = Field(description="The user the token acts for.")
    label: str = Field(description="What the token is for.")
    created_at: float = Field(description="When the token was made [s since the epoch].")
    last_used_at: float | None = Field(description="When the token was last used [s since the epoch].")
    expires_at: float | None = Field(None, description="When the token stops working [s since the epoch]; null: "
                                                       "until it is revoked.")


class NewTokenOut(TokenOut):
    """A new API token, with its secret: shown this once, send it as `Authorization: Bearer <token>`."""

    token: str = Field(description="The token itself; the service keeps only a hash of it.")
