"""Roles and what each may call: a table read top to bottom, the first rule matching a request decides.

Every signed-in role reads; engineers run solver requests and studies and save designs; checkers and approvers
run solver requests too (to re-run a design they sign) and sign; admins do everything but sign, which needs the
checker or approver role itself (:data:`RULES`).
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Literal

Role = Literal["viewer", "engineer", "admin", "checker", "approver"]
ROLES: tuple[Role, ...] = ("viewer", "engineer", "admin", "checker", "approver")
SAFE_METHODS = frozenset({"GET", "HEAD", "OPTIONS"})
ANY_ROLE: frozenset[str] = frozenset(ROLES)


@dataclass(frozen=True, slots=True)
class Rule:
    """Requests whose method is in ``methods`` (empty: any) and whose path matches ``pattern`` need one of
    ``roles``; ``None`` means no sign-in at all."""

    methods: frozenset[str]
    pattern: re.Pattern[str]
    roles: frozenset[str] | None
    #: What the request does, in words, for a refusal a person understands.
    doing: str = "this"

    def matches(self, method: str, path: str) -> bool:
        """The rule applies to this request."""
        return (not self.methods or method in self.methods) and self.pattern.match(path) is not None


def rule(methods: Iterable[str], pattern: str, roles: Iterable[str] | None, doing: str = "this",
         admin: bool = True) -> Rule:
    """A rule; ``pattern`` is a regular expression matched at the start of the path; admins may too unless
    ``admin`` is false (signatures: an admin signs only with the role)."""
    granted = None if roles is None else frozenset(roles) | ({"admin"} if admin else set())
    return Rule(frozenset(methods), re.compile(pattern), granted, doing)


_REVISION = r"/v1/library/projects/[^/]+/designs/[^/]+/revisions/[^/]+"


RULES: list[Rule] = [
    rule(["POST"], r"/v1/auth/signin$", None),
    rule(["GET", "HEAD"], r"/v1/auth/session$", None),
    rule([], r"/v1/auth/", ANY_ROLE, "signing in and out"),
    rule([], r"/v1/(users|tokens)(/|$)", ["admin"], "managing users and tokens"),
    # the design library's signatures: the library itself checks the signer again (and that it is not the author)
    rule(["POST"], _REVISION + "/check$", ["checker"], "checking a revision", admin=False),
    rule(["POST"], _REVISION + "/approve$", ["approver"], "approving a revision", admin=False),
    rule(["POST"], _REVISION + "/return$", ["checker", "approver"], "returning a revision to its author",
         admin=False),
    rule(["POST"], _REVISION + "/comments$", ["engineer", "checker", "approver"], "commenting on a revision"),
    rule(SAFE_METHODS, r"/v1(/|$)", ANY_ROLE, "reading"),
    rule([], r"/v1/library(/|$)", ["engineer"], "saving, restoring or importing designs"),
    rule([], r"/v1/studies(/|$)", ["engineer"], "running or changing studies"),
    # a checker or approver re-runs the design they sign: every computing endpoint is theirs too
    rule(["POST"], r"/v1/", ["engineer", "checker", "approver"], "computing a design"),
    rule([], r"/v1(/|$)", ["engineer"], "changing the service's data"),
]
"""What each request needs; a path outside ``/v1`` (the workbench, the manual, health) needs no sign-in."""


def required(method: str, path: str) -> frozenset[str] | None:
    """The roles of which a caller needs one for ``method path``; None when no sign-in is needed."""
    return next((r.roles for r in RULES if r.matches(method.upper(), path)), None)


def doing(method: str, path: str) -> str:
    """What ``method path`` does, in words (for a refusal)."""
    return next((r.doing for r in RULES if r.matches(method.upper(), path)), "this")


def refusal(name: str | None, held: Iterable[str], method: str, path: str, needed: frozenset[str]) -> str:
    """Why a caller is refused, in words: what they hold, what the request does and which role it needs."""
    roles = sorted(held)
    have = f"holds the {' and '.join(roles)} role{'s' if len(roles) > 1 else ''}" if roles else "holds no role"
    wanted = sorted(needed - {"admin"}) or ["admin"]
    need = ", ".join(wanted[:-1]) + (" or " if len(wanted) > 1 else "") + wanted[-1]
    signing = "admin" not in needed and "admin" in roles
    hint = (" An admin manages users but signs only when given the role itself, like anyone else."
            if signing else "")
    return f"{name or 'this caller'} {have}; {doing(method, path)} needs the {need} role.{hint}"


def allows(roles: Iterable[str], needed: frozenset[str] | None) -> bool:
    """A caller with ``roles`` may make a request needing ``needed``."""
    return needed is None or bool(set(roles) & needed)
