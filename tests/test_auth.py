"""Sign-in and roles with SYNTH_AUTH=on: 401 without credentials, 403 for a role that does not allow the request,
API tokens as bearer tokens kept only as hashes, browser sessions with HttpOnly SameSite=Strict cookies and a CSRF
token, the admins' user and token endpoints; and with SYNTH_AUTH=off everything open as before."""

from __future__ import annotations

import hashlib
import logging
import os
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from http.cookies import SimpleCookie
from pathlib import Path

import httpx
import pytest
from argon2 import PasswordHasher
from fastapi.testclient import TestClient

import store
from api.app import create_app
from api.auth import passwords, tokens
from api.auth.users import Accounts
from api.settings import Settings
from mechsynth_client import SynthClient
from mechsynth_client.client import ForbiddenError, UnauthorizedError
from mechsynth_client.schemas.auth import TokenIn, UserIn, UserPatchIn
from mechsynth_client.schemas.gearing import SplitIn
from store.schema import api_tokens
from store_engines import open_store, pg_cluster, store_url  # noqa: F401  (fixtures)

SPLIT = {"total_ratio": 12.0, "stages": 2}
PASSWORD = "correct horse battery"
ROLES = {"vera": {"viewer"}, "emil": {"engineer"}, "ada": {"admin"}, "chen": {"checker"}}


@pytest.fixture(autouse=True, scope="module")
def _quick_hashes() -> Iterator[None]:
    """argon2 with its real parameters takes most of a second per hash on a busy machine; these tests are about
    who may do what, so they hash with the least parameters (test_passwords_are_argon2id checks the real ones)."""
    real = passwords._HASHER, passwords._DUMMY
    passwords._HASHER = PasswordHasher(time_cost=1, memory_cost=8, parallelism=1)
    passwords._DUMMY = passwords._HASHER.hash("no user has this password")
    yield
    passwords._HASHER, passwords._DUMMY = real


def _app(**settings: object) -> TestClient:
    """The service with authentication on and its own store in a scratch directory."""
    db = Path(tempfile.mkdtemp(prefix="synth-auth-")) / "store.sqlite"
    app = create_app(Settings(**{"executor": "serial", "auth": "on", "studies_db": str(db),  # type: ignore[arg-type]
                                 **settings}))
    return TestClient(app, base_url="http://localhost")


def _accounts(c: TestClient) -> Accounts:
    accounts: Accounts = c.app.state.access.accounts  # type: ignore[attr-defined]
    return accounts


@pytest.fixture(scope="module")
def http() -> Iterator[TestClient]:
    with _app() as c:
        hashed = passwords.hash_password(PASSWORD)
        for name, roles in ROLES.items():
            _accounts(c).create(name, roles, hashed)
        yield c


def _token(http: TestClient, user: str) -> str:
    admin = _bearer(http, "ada")
    r = http.post(f"/v1/users/{user}/tokens", json={"label": "test"}, headers=admin)
    assert r.status_code == 201, r.text
    return str(r.json()["token"])


_ADMIN_TOKEN: dict[int, str] = {}


def _bearer(http: TestClient, user: str) -> dict[str, str]:
    """Bearer headers of a token for ``user``; the admin's own token is made directly in the store."""
    if user == "ada":
        key = id(http)
        if key not in _ADMIN_TOKEN:
            _ADMIN_TOKEN[key] = tokens.new_token()
            admin = _accounts(http).by_name("ada")
            assert admin is not None
            _accounts(http).add_token(admin.id, _ADMIN_TOKEN[key], "bootstrap")
        return {"authorization": f"Bearer {_ADMIN_TOKEN[key]}"}
    return {"authorization": f"Bearer {_token(http, user)}"}


def test_without_credentials_v1_answers_401_and_the_public_paths_answer(http: TestClient) -> None:
    for method, path in [("GET", "/v1/studies"), ("POST", "/v1/gears/split"), ("GET", "/v1/users")]:
        r = http.request(method, path, json=SPLIT if method == "POST" else None)
        assert r.status_code == 401, (method, path)
        assert r.headers["www-authenticate"].startswith("Bearer")
        assert r.json()["type"] == "/problems/unauthenticated"
    for path in ["/", "/health", "/ready", "/docs", "/workbench/app.js"]:
        assert http.get(path).status_code == 200, path
    assert http.get("/v1/auth/session").json() == {"auth": "on", "signed_in": False, "name": None, "roles": [],
                                                    "via": "none", "csrf_token": None, "expires_at": None}


def test_401_comes_before_the_body_is_looked_at(http: TestClient) -> None:
    r = http.post("/v1/gears/split", content=b"{not json", headers={"content-type": "application/json"})
    assert r.status_code == 401


@pytest.mark.parametrize("sent", ["Bearer mst_" + "n" * 43, "Bearer garbage", "Basic YWRhOnB3", "Bearer "])
def test_a_bad_token_is_401_naming_why(http: TestClient, sent: str) -> None:
    r = http.get("/v1/studies", headers={"authorization": sent})
    assert r.status_code == 401
    assert "invalid_token" in r.headers["www-authenticate"]
    assert "nnnn" not in r.text and "YWRh" not in r.text


def test_roles_decide_reads_runs_and_management(http: TestClient) -> None:
    viewer, engineer, admin, checker = (_bearer(http, n) for n in ("vera", "emil", "ada", "chen"))
    for who in (viewer, engineer, admin, checker):
        assert http.get("/v1/studies", headers=who).status_code == 200
    r = http.post("/v1/gears/split", json=SPLIT, headers=viewer)
    assert r.status_code == 403 and r.json()["needed_roles"] == ["admin", "approver", "checker", "engineer"]
    assert r.json()["roles"] == ["viewer"]
    # in words a person understands: what they hold, what the request does, which role it needs
    assert r.json()["detail"] == ("vera holds the viewer role; computing a design needs the approver, checker or "
                                  "engineer role.")
    # a checker re-runs the design it checks, but saves nothing and runs no study
    assert http.post("/v1/gears/split", json=SPLIT, headers=checker).status_code == 200
    assert http.post("/v1/studies", json={}, headers=checker).status_code == 403
    assert http.post("/v1/gears/split", json=SPLIT, headers=engineer).status_code == 200
    assert http.post("/v1/gears/split", json=SPLIT, headers=admin).status_code == 200
    assert http.get("/v1/users", headers=engineer).status_code == 403
    assert http.post("/v1/users", json={"name": "x1", "password": PASSWORD, "roles": ["viewer"]},
                     headers=engineer).status_code == 403
    names = [u["name"] for u in http.get("/v1/users", headers=admin).json()]
    assert set(ROLES) <= set(names)


def test_tokens_are_kept_as_hashes_and_act_with_their_users_current_roles(http: TestClient) -> None:
    admin = _bearer(http, "ada")
    assert http.post("/v1/users", json={"name": "tess", "password": PASSWORD, "roles": ["engineer", "viewer"]},
                     headers=admin).status_code == 201
    made = http.post("/v1/users/tess/tokens", json={"label": "ci"}, headers=admin).json()
    token = made["token"]
    assert token.startswith("mst_") and len(token) == 47
    stored = Path(http.app.state.settings.studies_db)  # type: ignore[attr-defined]
    db = b"".join(p.read_bytes() for p in stored.parent.glob(stored.name + "*"))     # the file and its WAL
    assert token.encode() not in db and hashlib.sha256(token.encode()).hexdigest().encode() in db
    assert PASSWORD.encode() not in db and b"$argon2id$" in db
    listed = http.get("/v1/users/tess/tokens", headers=admin).json()
    assert [t["id"] for t in listed] == [made["id"]] and "token" not in listed[0]
    assert listed[0]["last_used_at"] is None
    bearer = {"authorization": f"Bearer {token}"}
    assert http.post("/v1/gears/split", json=SPLIT, headers=bearer).status_code == 200
    assert http.get("/v1/users/tess/tokens", headers=admin).json()[0]["last_used_at"] is not None
    # promoted: the token acts with the roles its user has now
    assert http.patch("/v1/users/tess", json={"roles": ["engineer", "viewer", "checker"]},
                      headers=admin).json()["roles"] == ["checker", "engineer", "viewer"]
    assert http.get("/v1/auth/session", headers=bearer).json()["roles"] == ["checker", "engineer", "viewer"]
    # revoked: refused at once
    assert http.delete(f"/v1/tokens/{made['id']}", headers=admin).status_code == 204
    assert http.get("/v1/studies", headers=bearer).status_code == 401
    assert http.delete(f"/v1/tokens/{made['id']}", headers=admin).status_code == 404
    # demoted: a role taken away ends the user's tokens at once (test_signoff.py: its sessions too)
    demoted = http.post("/v1/users/tess/tokens", json={"label": "z"}, headers=admin).json()["token"]
    assert http.get("/v1/studies", headers={"authorization": f"Bearer {demoted}"}).status_code == 200
    assert http.patch("/v1/users/tess", json={"roles": ["viewer"]}, headers=admin).json()["roles"] == ["viewer"]
    assert http.get("/v1/studies", headers={"authorization": f"Bearer {demoted}"}).status_code == 401
    # a removed user's tokens go with it
    other = http.post("/v1/users/tess/tokens", json={"label": "y"}, headers=admin).json()["token"]
    assert http.delete("/v1/users/tess", headers=admin).status_code == 204
    assert http.get("/v1/studies", headers={"authorization": f"Bearer {other}"}).status_code == 401
    assert http.get("/v1/users/tess", headers=admin).status_code == 404


def test_user_management_problems(http: TestClient) -> None:
    admin = _bearer(http, "ada")
    r = http.post("/v1/users", json={"name": "vera", "password": PASSWORD, "roles": ["viewer"]}, headers=admin)
    assert r.status_code == 409 and r.json()["type"] == "/problems/user-exists"
    r = http.post("/v1/users", json={"name": "short", "password": "abc", "roles": ["viewer"]}, headers=admin)
    assert r.status_code == 422 and r.json()["field"] == "password"
    r = http.post("/v1/users", json={"name": "x2", "password": PASSWORD, "roles": ["root"]}, headers=admin)
    assert r.status_code == 422 and r.json()["field"].startswith("roles")
    assert http.patch("/v1/users/nobody", json={"roles": ["viewer"]}, headers=admin).status_code == 404


def _cookies(response: httpx.Response) -> dict[str, SimpleCookie]:
    found = {}
    for raw in response.headers.get_list("set-cookie"):
        c: SimpleCookie = SimpleCookie()
        c.load(raw)
        found.update({k: c for k in c})
    return found


def test_browser_sign_in_sets_strict_cookies_and_needs_the_csrf_token_for_changes() -> None:
    with _app() as c:
        _accounts(c).create("emil", {"engineer"}, passwords.hash_password(PASSWORD))
        page = {"origin": "http://localhost"}
        assert c.post("/v1/auth/signin", json={"name": "emil", "password": "wrong one"},
                      headers=page).status_code == 401
        assert c.post("/v1/auth/signin", json={"name": "nobody", "password": PASSWORD},
                      headers=page).json()["detail"] == "the name or the password is wrong"
        r = c.post("/v1/auth/signin", json={"name": "emil", "password": PASSWORD}, headers=page)
        assert r.status_code == 200, r.text
        out = r.json()
        assert out["name"] == "emil" and out["roles"] == ["engineer"] and out["via"] == "session"
        cookies = _cookies(r)
        session = cookies["synth_session"]["synth_session"]
        assert session["httponly"] and session["samesite"] == "strict" and session["path"] == "/"
        assert not session["secure"]
        csrf = cookies["synth_csrf"]["synth_csrf"]
        assert not csrf["httponly"] and csrf.value == out["csrf_token"]
        assert c.get("/v1/studies").status_code == 200       # the cookie is enough for reads
        r = c.post("/v1/gears/split", json=SPLIT, headers=page)
        assert r.status_code == 403 and r.json()["type"] == "/problems/csrf-token-missing"
        r = c.post("/v1/gears/split", json=SPLIT, headers={**page, "x-csrf-token": "forged"})
        assert r.status_code == 403
        assert c.post("/v1/gears/split", json=SPLIT,
                      headers={**page, "x-csrf-token": out["csrf_token"]}).status_code == 200
        assert c.get("/v1/auth/session").json()["csrf_token"] == out["csrf_token"]
        old = c.cookies.get("synth_session")
        assert c.post("/v1/auth/signout", headers={**page, "x-csrf-token": out["csrf_token"]}).status_code == 204
        c.cookies.set("synth_session", str(old))            # a copy of the cookie kept after signing out
        assert c.get("/v1/studies").status_code == 401


def test_behind_tls_the_cookies_are_secure_and_host_only() -> None:
    with _app(behind_tls=True) as c:
        _accounts(c).create("emil", {"engineer"}, passwords.hash_password(PASSWORD))
        r = c.post("/v1/auth/signin", json={"name": "emil", "password": PASSWORD})
        cookies = _cookies(r)
        assert set(cookies) == {"__Host-synth_session", "__Host-synth_csrf"}
        assert all(c[k]["secure"] for k, c in cookies.items())


def test_repeated_wrong_passwords_wait() -> None:
    with _app() as c:
        _accounts(c).create("emil", {"engineer"}, passwords.hash_password(PASSWORD))
        for _ in range(5):
            assert c.post("/v1/auth/signin", json={"name": "emil", "password": "wrong one"}).status_code == 401
        r = c.post("/v1/auth/signin", json={"name": "emil", "password": PASSWORD})
        assert r.status_code == 429 and int(r.headers["retry-after"]) > 0


def test_first_admin_from_the_settings_and_the_client_with_a_token() -> None:
    with _app(admin_name="root", admin_password="first admin password") as c:
        # the clients share the test's transport (closing them would close it)
        anonymous = SynthClient(http=c)
        with pytest.raises(UnauthorizedError):
            anonymous.gears_split(SplitIn(**SPLIT))
        signed = anonymous.sign_in("root", "first admin password")
        assert signed.roles == ["admin"]
        anonymous.add_user(UserIn(name="emil", password=PASSWORD, roles=["engineer"]))
        new = anonymous.add_token("emil", TokenIn(label="notebook"))
        root = anonymous.add_token("root", TokenIn(label="admin scripts"))
        anonymous.sign_out()
        engineer = SynthClient(http=c, token=new.token)
        assert engineer.session().name == "emil"
        assert engineer.gears_split(SplitIn(**SPLIT)).stages
        with pytest.raises(ForbiddenError):
            engineer.users()
        admin = SynthClient(http=c, token=root.token)
        assert [t.label for t in admin.user_tokens("emil")] == ["notebook"]
        assert admin.update_user("emil", UserPatchIn(roles=["viewer"])).roles == ["viewer"]
        assert admin.user("emil").roles == ["viewer"]
        admin.revoke_token(new.id)
        with pytest.raises(UnauthorizedError):
            engineer.gears_split(SplitIn(**SPLIT))
        admin.remove_user("emil")
        assert "emil" not in [u.name for u in admin.users()]


def test_with_auth_off_everything_is_open_as_before() -> None:
    with _app(auth="off") as c:
        assert c.post("/v1/gears/split", json=SPLIT).status_code == 200
        assert c.get("/v1/auth/session").json()["auth"] == "off"
        assert c.post("/v1/auth/signin", json={"name": "a", "password": "b"}).status_code == 409
        assert c.post("/v1/users", json={"name": "ada", "password": PASSWORD, "roles": ["admin"]}).status_code == 201


def test_no_secret_reaches_the_logs(caplog: pytest.LogCaptureFixture) -> None:
    caplog.set_level(logging.DEBUG)
    with _app(admin_name="root", admin_password="first admin password") as c:
        r = c.post("/v1/auth/signin", json={"name": "root", "password": "first admin password"})
        session_cookie = c.cookies.get("synth_session")
        csrf = r.json()["csrf_token"]
        token = c.post("/v1/users/root/tokens", json={"label": "ci"}, headers={"x-csrf-token": csrf}).json()["token"]
        c.post("/v1/users", json={"name": "emil", "password": PASSWORD, "roles": ["engineer"]},
               headers={"x-csrf-token": csrf})
        c.cookies.clear()
        assert c.post("/v1/gears/split", json=SPLIT, headers={"authorization": f"Bearer {token}"}).status_code == 200
        c.get("/v1/studies", headers={"authorization": f"Bearer {token}x"})
    logged = caplog.text + "".join(str(rec.args) for rec in caplog.records)
    assert caplog.records                                   # the capture did see the service's and httpx's logs
    for secret in ("first admin password", PASSWORD, token, token[len("mst_"):], str(session_cookie), csrf):
        assert secret not in logged


def test_passwords_are_argon2id_and_weaker_hashes_are_renewed_at_sign_in() -> None:
    real = passwords.REAL
    stored = real.hash(PASSWORD)
    # RFC 9106's second recommended memory and passes, on one lane (one thread per check)
    assert stored.startswith("$argon2id$v=19$m=65536,t=3,p=1$")
    assert real.verify(stored, PASSWORD)
    # a hash of RFC 9106's four lanes (argon2-cffi's default, this service's earlier hashes) is renewed
    assert real.check_needs_rehash(PasswordHasher().hash(PASSWORD))
    # the module's hasher is the quick one here: a hash made with the real parameters is "weaker" than nothing,
    # so check renewal the other way round, from a hash with fewer passes than the current hasher's
    weak = PasswordHasher(time_cost=1, memory_cost=8, parallelism=1)
    stronger = PasswordHasher(time_cost=2, memory_cost=8, parallelism=1)
    old = weak.hash(PASSWORD)
    saved = passwords._HASHER
    passwords._HASHER = stronger
    try:
        assert passwords.verify_password(old, PASSWORD) and not passwords.verify_password(old, "wrong one")
        assert not passwords.verify_password(None, PASSWORD)
        assert passwords.needs_rehash(old)
        with _app() as c:
            _accounts(c).create("emil", {"engineer"}, old)
            assert c.post("/v1/auth/signin", json={"name": "emil", "password": PASSWORD}).status_code == 200
            renewed = _accounts(c).password_hash("emil")
        assert renewed is not None
        assert renewed != old and not passwords.needs_rehash(renewed) and stronger.verify(renewed, PASSWORD)
    finally:
        passwords._HASHER = saved


def test_the_command_line_bootstraps_an_admin_whose_token_the_service_accepts(
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    import io

    from api import users as cli

    db = Path(tempfile.mkdtemp(prefix="synth-auth-")) / "store.sqlite"
    monkeypatch.setenv("SYNTH_STUDIES_DB", str(db))
    monkeypatch.setattr("sys.stdin", io.StringIO(PASSWORD + "\n"))
    assert cli.main(["add", "ada", "--role", "admin", "--password-stdin"]) == 0
    assert cli.main(["token", "ada", "--label", "setup"]) == 0
    token = capsys.readouterr().out.strip().splitlines()[-1]
    assert cli.main(["list"]) == 0
    assert capsys.readouterr().out == "ada\tadmin\n"
    with pytest.raises(SystemExit, match="exists already"):
        monkeypatch.setattr("sys.stdin", io.StringIO(PASSWORD + "\n"))
        cli.main(["add", "ada", "--role", "viewer", "--password-stdin"])
    with _app(studies_db=str(db)) as c:
        r = c.get("/v1/auth/session", headers={"authorization": f"Bearer {token}"})
        assert r.json()["name"] == "ada" and r.json()["roles"] == ["admin"]
        assert c.post("/v1/auth/signin", json={"name": "ada", "password": PASSWORD}).status_code == 200


STUDY = {"endpoint": "/v1/gears/split", "base": SPLIT, "metrics": ["reduced_inertia_kgm2"],
         "parameters": [{"path": "total_ratio", "values": [8.0, 10.0, 12.0]}]}


def test_a_study_belongs_to_its_creator_and_only_it_or_an_admin_may_cancel_or_resume_it(http: TestClient) -> None:
    emil, admin, viewer = _bearer(http, "emil"), _bearer(http, "ada"), _bearer(http, "vera")
    http.post("/v1/users", json={"name": "otto", "password": PASSWORD, "roles": ["engineer"]}, headers=admin)
    otto = _bearer(http, "otto")
    # an owner named in the body (where the schema has one) is not taken: the signed-in user is the owner
    created = http.post("/v1/studies", json={**STUDY, "owner": "otto"} if "owner" in _study_fields() else STUDY,
                        headers=emil)
    assert created.status_code == 202, created.text
    study_id = created.json()["id"]
    stored = http.app.state.studies.get(study_id)  # type: ignore[attr-defined]
    assert stored.spec["owner"] == "emil"
    for who in (otto, viewer):
        for method, path in [("DELETE", f"/v1/studies/{study_id}"), ("POST", f"/v1/studies/{study_id}/resume")]:
            r = http.request(method, path, headers=who)
            assert r.status_code == 403, (method, r.text)
    r = http.delete(f"/v1/studies/{study_id}", headers=otto)
    assert r.json()["type"] == "/problems/not-owner" and r.json()["owner"] == "emil"
    assert http.get(f"/v1/studies/{study_id}", headers=otto).status_code == 200      # reading is for everyone
    assert http.delete(f"/v1/studies/{study_id}", headers=emil).status_code == 200
    # an admin may resume anyone's study: 202, or 409 when it finished before it was cancelled
    finished = http.get(f"/v1/studies/{study_id}", headers=admin).json()["state"] == "done"
    assert http.post(f"/v1/studies/{study_id}/resume", headers=admin).status_code == (409 if finished else 202)
    assert http.delete("/v1/studies/nosuchstudy", headers=otto).status_code == 404


def _study_fields() -> set[str]:
    from mechsynth_client.schemas.studies import StudyIn
    return set(StudyIn.model_fields)


def test_a_bad_secret_setting_stops_the_service_without_echoing_it(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("SYNTH_SESSION_KEY", "tooshortsecret")
    with pytest.raises(SystemExit) as stopped:
        Settings.from_env()
    assert "SYNTH_SESSION_KEY" in str(stopped.value) and "tooshortsecret" not in str(stopped.value)
    monkeypatch.delenv("SYNTH_SESSION_KEY")
    monkeypatch.setenv("SYNTH_SESSION_HOURS", "-1")
    with pytest.raises(SystemExit, match=r"SYNTH_SESSION_HOURS: .* \(got '-1'\)"):
        Settings.from_env()


@pytest.mark.parametrize("method, path, roles", [
    ("GET", "/v1/studies", {"viewer", "engineer", "admin", "checker", "approver"}),
    ("POST", "/v1/analysis", {"engineer", "admin", "checker", "approver"}),
    ("POST", "/v1/studies", {"engineer", "admin"}),
    ("DELETE", "/v1/studies/abc", {"engineer", "admin"}),
    ("GET", "/v1/users", {"admin"}),
    ("POST", "/v1/tokens/3", {"admin"}),
    # an admin manages users but signs only with the role itself
    ("POST", "/v1/library/projects/p/designs/d/revisions/2/check", {"checker"}),
    ("POST", "/v1/library/projects/p/designs/d/revisions/2/approve", {"approver"}),
    ("POST", "/v1/library/projects/p/designs/d/revisions/2/return", {"checker", "approver"}),
    ("POST", "/v1/library/projects/p/designs/d/revisions/2/comments", {"engineer", "checker", "approver", "admin"}),
    ("POST", "/v1/library/import", {"engineer", "admin"}),
    ("POST", "/v1/library/projects/p/designs/d/revisions", {"engineer", "admin"}),
    ("POST", "/v1/auth/signout", {"viewer", "engineer", "admin", "checker", "approver"}),
])
def test_the_role_table(method: str, path: str, roles: set[str]) -> None:
    from api.auth.roles import ROLES, allows, required

    assert {r for r in ROLES if allows([r], required(method, path))} == roles
    assert required("POST", "/v1/auth/signin") is None and required("GET", "/workbench/app.js") is None


def test_accounts_on_both_engines(open_store: Callable[[], store.Store]) -> None:
    """The calls sign-in adds to the store's users, on SQLite and on PostgreSQL: a token's user by the token,
    a user's tokens, removing a user with its tokens."""
    accounts = Accounts(open_store())
    ada = accounts.create("ada", {"engineer"}, "hash")
    first, second = tokens.new_token(), tokens.new_token()
    first_id = accounts.add_token(ada.id, first, "one")
    accounts.add_token(ada.id, second, "two")
    found = accounts.token_user(first)
    assert found is not None and found[0].name == "ada" and found[1] == first_id
    assert accounts.token_user(tokens.new_token()) is None
    listed = accounts.tokens(ada)
    assert [t.label for t in listed] == ["one", "two"] and listed[0].last_used_at is not None
    assert listed[1].last_used_at is None
    accounts.remove(ada)
    assert accounts.by_name("ada") is None and accounts.token_user(second) is None
    assert not accounts.revoke_token(2**31 - 1)       # the largest number the path accepts, on either engine


def test_a_token_lasts_its_days_then_is_refused_naming_its_expiry(http: TestClient) -> None:
    admin = _bearer(http, "ada")
    made = http.post("/v1/users/emil/tokens", json={"label": "default"}, headers=admin).json()
    # the service's default, SYNTH_TOKEN_DAYS = 90 days from now
    assert made["expires_at"] == pytest.approx(made["created_at"] + 90 * 86_400, abs=1.0)
    forever = http.post("/v1/users/emil/tokens", json={"label": "kept", "expires_in_days": 0}, headers=admin)
    assert forever.json()["expires_at"] is None
    short = http.post("/v1/users/emil/tokens", json={"label": "short", "expires_in_days": 1}, headers=admin).json()
    bearer = {"authorization": f"Bearer {short['token']}"}
    assert http.get("/v1/studies", headers=bearer).status_code == 200
    with _accounts(http).store.write() as db:      # its day has passed
        db.execute(api_tokens.update().where(api_tokens.c.id == short["id"]).values(expires_at=time.time() - 1))
    refused = http.get("/v1/studies", headers=bearer)
    assert refused.status_code == 401 and "expired at" in refused.json()["detail"], refused.text
    listed = {t["label"]: t for t in http.get("/v1/users/emil/tokens", headers=admin).json()}
    assert listed["kept"]["expires_at"] is None and listed["short"]["expires_at"] < time.time()


def test_passwords_are_hashed_on_one_core_at_a_lower_priority_than_the_routes() -> None:
    """A spray's hashes must leave the routes a core: one lane is one thread in argon2's C library, and the
    hashing thread's own niceness (Linux keeps one per thread) yields the core to the event loop's."""
    import importlib

    auth_router = importlib.import_module("api.auth.router")

    def niceness() -> int:
        return os.getpriority(os.PRIO_PROCESS, threading.get_native_id())

    assert auth_router._HASHING.submit(niceness).result(timeout=30) == auth_router.HASH_NICENESS == 10
    assert niceness() == 0                      # this thread (a route's) keeps the default
    assert passwords.REAL.parallelism == 1
