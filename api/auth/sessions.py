"""Browser sign-in: a cookie carrying the user's number, name and credential epoch, an expiry and a session id,
signed with HMAC-SHA256. The session belongs to that user, not to the name: a user removed and made again, or
whose password is reset or a role removed (the epoch moves), is signed out at once.

The cookie is HttpOnly and SameSite=Strict (and Secure behind TLS), so page scripts cannot read it and no other
site's page can make the browser send it. State-changing requests signed in this way must also carry the
session's CSRF token in ``X-CSRF-Token``; the token is derived from the session id with the same key, handed to
the page at sign-in and in a second cookie the page's scripts can read (double submit). Signing out ends the
session at once in this process (the id is remembered until it would have expired anyway).
"""

from __future__ import annotations

import base64
import hashlib
import hmac
import json
import secrets
import threading
import time
from dataclasses import dataclass

COOKIE = "synth_session"
CSRF_COOKIE = "synth_csrf"
CSRF_HEADER = "x-csrf-token"
# Behind TLS the __Host- prefix makes browsers refuse the cookie unless it is Secure, for this host only, path /.
SECURE_PREFIX = "__Host-"


def _b64(data: bytes) -> str:
    return base64.urlsafe_b64encode(data).rstrip(b"=").decode()


def _unb64(text: str) -> bytes:
    return base64.urlsafe_b64decode(text + "=" * (-len(text) % 4))


@dataclass(frozen=True, slots=True)
class Session:
    """A valid sign-in: who (name, user number and credential epoch), until when [s since the epoch], and its
    id."""

    name: str
    expires: float
    sid: str
    user_id: int = 0
    epoch: int = 0


class Sessions:
    """Makes and checks sign-in cookies with one key; remembers sessions signed out before their expiry."""

    def __init__(self, key: bytes, lifetime_s: float, secure: bool) -> None:
        self._key = key
        self.lifetime_s = lifetime_s
        self.secure = secure
        self._ended: dict[str, float] = {}
        self._lock = threading.Lock()

    @property
    def cookie_name(self) -> str:
        """The session cookie's name (with the __Host- prefix behind TLS)."""
        return SECURE_PREFIX + COOKIE if self.secure else COOKIE

    @property
    def csrf_cookie_name(self) -> str:
        """The CSRF cookie's name."""
        return SECURE_PREFIX + CSRF_COOKIE if self.secure else CSRF_COOKIE

    def _sign(self, payload: bytes) -> str:
        return _b64(hmac.new(self._key, payload, hashlib.sha256).digest())

    def issue(self, name: str, now: float | None = None, *, user_id: int = 0, epoch: int = 0
              ) -> tuple[str, Session]:
        """A new session for the user ``name`` (number ``user_id``, credential epoch ``epoch``): the cookie value
        and the session."""
        session = Session(name, (time.time() if now is None else now) + self.lifetime_s, secrets.token_urlsafe(16),
                          user_id, epoch)
        payload = json.dumps({"u": session.name, "e": session.expires, "s": session.sid, "i": user_id,
                              "p": epoch}, separators=(",", ":")).encode()
        return f"{_b64(payload)}.{self._sign(payload)}", session

    def check(self, cookie: str, now: float | None = None) -> Session | None:
        """The session of a cookie value, or None when it is forged, malformed, expired or signed out."""
        body, sep, signature = cookie.partition(".")
        if not sep or len(cookie) > 4096:
            return None
        try:
            payload = _unb64(body)
            if not hmac.compare_digest(signature.encode(), self._sign(payload).encode()):
                return None
            data = json.loads(payload)
            session = Session(str(data["u"]), float(data["e"]), str(data["s"]), int(data.get("i", 0)),
                              int(data.get("p", 0)))
        except (ValueError, KeyError, TypeError):
            return None
        if session.expires <= (time.time() if now is None else now):
            return None
        with self._lock:
            if session.sid in self._ended:
                return None
        return session

    def csrf_token(self, session: Session) -> str:
        """The CSRF token of a session: a keyed hash of its id, so it cannot be made without the key."""
        return self._sign(b"csrf:" + session.sid.encode())

    def csrf_ok(self, session: Session, sent: str | None) -> bool:
        """The request carries its session's CSRF token (compared in constant time)."""
        return sent is not None and hmac.compare_digest(sent.encode(), self.csrf_token(session).encode())

    def end(self, session: Session) -> None:
        """Sign a session out: its cookie is refused from now on."""
        now = time.time()
        with self._lock:
            self._ended = {sid: exp for sid, exp in self._ended.items() if exp > now}
            self._ended[session.sid] = session.expires
