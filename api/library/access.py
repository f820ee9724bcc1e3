"""Who acts on the library and whether they may: the signed-in user (roles checked), or without sign-in the name
the request gives (the author-is-not-the-signer rule still holds by name)."""

from __future__ import annotations

from synth.errors import InvalidInput

from store import User


class Forbidden(Exception):
    """The acting user lacks the role an action needs: a 403 problem."""


def actor(user: User | None, given: str | None, field: str, role: str) -> str:
    """The name acting: the signed-in ``user``'s when there is one (who must hold ``role``, or admin to save), else
    ``given`` (the body's ``field`` or the X-Synth-User header), which is then required."""
    if user is not None:
        allowed = user.has(role) or (role == "engineer" and user.has("admin"))
        if not allowed:
            raise Forbidden(f"{user.name} does not hold the {role} role this needs")
        return user.name
    name = (given or "").strip()
    if not name:
        raise InvalidInput(f"{field}: say who you are: the field {field!r} or the X-Synth-User header (the service "
                           "has no sign-in)", field=field)
    return name
