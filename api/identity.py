"""Who is making a request: the one place the service asks. Without authentication configured nobody is signed
in and this answers None; then the library takes author and signer names from the request itself."""

from __future__ import annotations

from typing import Annotated

from fastapi import Depends, Request

from store import User


def current_user(request: Request) -> User | None:
    """The signed-in user of ``request``, None when nobody is (authentication off). Authentication puts the user it
    verified in ``request.state.user``."""
    user = getattr(request.state, "user", None)
    return user if isinstance(user, User) else None


CurrentUserDep = Annotated[User | None, Depends(current_user)]
