"""Who may do what, and from where: the office server's security.

- ``hosts``: the Host header must name this service (DNS rebinding); 400 problem otherwise.
- ``headers``: Content-Security-Policy and the other protective headers on every answer; CORS only when set.
- ``origin``: a state-changing request from another site's page is refused (403), whether or not sign-in is on.
- ``passwords``, ``tokens``, ``sessions``: argon2 password hashes, API tokens kept as hashes, signed sign-in
  cookies with their CSRF token.
- ``users``: the users and tokens in the service's store, with what sign-in needs beyond the store's own calls.
- ``roles``: viewer, engineer, admin, checker, approver and what each may call.
- ``guard``: who is calling (a token, a sign-in cookie, or nobody) and whether the role allows it (401/403).
- ``router``: sign-in, sign-out and the admins' user and token management under ``/v1``.

With ``SYNTH_AUTH=off`` (the default) every caller acts as an admin, as on a laptop; the host, origin and header
protections stay on.
"""

from __future__ import annotations

from .install import install, start, stop
from .router import router

__all__ = ["install", "router", "start", "stop"]
