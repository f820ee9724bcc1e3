"""Roles and what each may call: a table read top to bottom, the first rule matching a request decides.

Every signed-in role reads; engineers run solver requests and studies and save designs; admins do everything,
:data:`RULES`).
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

    def matches(self, method: str, path: str) -> bool:
        """The rule applies to this request."""
        return (not self.methods or method in self.methods) and self.pattern.match(path) is not None


def rule(methods: Iterable[str], pattern: str, roles: Iterable[str] | None) -> Rule:
    """A rule; ``pattern`` is a regular expression matched at the start of the path."""
    return Rule(frozenset(methods), re.compile(pattern), None if roles is None else frozenset(roles) | {"admin"})


RULES: list[Rule] = [
    rule(["POST"], r"/v1/auth/signin$", None),
    rule(["GET", "HEAD"], r"/v1/auth/session$", None),
    rule([], r"/v1/auth/", ANY_ROLE),
    rule([], r"/v1/(users|tokens)(/|$)", ["admin"]),
    # the design library's signatures: the library itself checks that the signer holds the role
    rule(["POST"], r"/v1/library/projects/[^/]+/designs/[^/]+/revisions/[^/]+/check$", ["checker"]),
    rule(["POST"], r"/v1/library/projects/[^/]+/designs/[^/]+/revisions/[^/]+/approve$", ["approver"]),
    rule(SAFE_METHODS, r"/v1(/|$)", ANY_ROLE),
    rule([], r"/v1(/|$)", ["engineer"]),
]
"""What each request needs; a path outside ``/v1`` (the workbench, the manual, health) needs no sign-in."""


def required(method: str, path: str) -> frozenset[str] | None:
    """The roles of which a caller needs one for ``method path``; None when no sign-in is needed."""
    return next((r.roles for r in RULES if r.matches(method.upper(), path)), None)


def allows(roles: Iterable[str], needed: frozenset[str] | None) -> bool:
    """A caller with ``roles`` may make a request needing ``needed``."""
    return needed is None or bool(set(roles) & needed)
