"""Who acts on the library and whether they may: the signed-in user (roles checked), or without sign-in the name
the request gives (the author-is-not-the-signer rule still holds by name)."""

from __future__ import annotations

from synth.errors import InvalidInput

from store import User

#: What each role lets a person do in the library, in words.
DOING = {"engineer": "save designs", "checker": "check revisions", "approver": "approve revisions"}


class Forbidden(Exception):
    """The acting user lacks the role an action needs: a 403 problem."""


def actor(user: User | None, given: str | None, field: str, *roles: str) -> str:
    """The name acting: the signed-in ``user``'s when there is one (who must hold one of ``roles``; an admin
    saves as an engineer does, but signs only with the checker or approver role itself), else ``given`` (the
    body's ``field`` or the X-Synth-User header), which is then required."""
    if user is not None:
        allowed = any(user.has(r) for r in roles) or ("engineer" in roles and user.has("admin"))
        if not allowed:
            held = ", ".join(sorted(user.roles)) or "no role"
            need = " or ".join(f"the {r} role" for r in roles)
            admin = (" An admin manages users; to sign, an admin is given the checker or approver role like "
                     "anyone else." if user.has("admin") and "engineer" not in roles else "")
            raise Forbidden(f"{user.name} holds {held}; this needs {need} (a person with it may "
                            f"{' or '.join(DOING.get(r, r) for r in roles)}).{admin}")
        return user.name
    name = (given or "").strip()
    if not name:
        raise InvalidInput(f"{field}: say who you are: the field {field!r} or the X-Synth-User header (the service "
                           "has no sign-in)", field=field)
    return name
