"""The service's protections that hold with or without sign-in: allowed hosts, requests from other sites, the
protective headers on the workbench and its files, and CORS closed unless origins are set."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from fastapi.testclient import TestClient

from api.app import create_app
from api.settings import Settings

SPLIT = {"total_ratio": 12.0, "stages": 2}
CSP_REQUIRED = {"script-src": "'self'", "style-src": "'self'", "object-src": "'none'", "frame-ancestors": "'none'",
                "base-uri": "'none'", "form-action": "'self'"}


def _client(**settings: object) -> TestClient:
    # the default allowed hosts, whatever the environment says: the tests below are about them
    base = {"executor": "serial", "allowed_hosts": "localhost,127.0.0.1,::1"}
    return TestClient(create_app(Settings(**{**base, **settings})), base_url="http://localhost")  # type: ignore[arg-type]


@pytest.fixture(scope="module", params=["off", "on"])
def client(request: pytest.FixtureRequest) -> Iterator[TestClient]:
    with _client(auth=request.param) as c:
        yield c


def _csp(value: str) -> dict[str, str]:
    return {d.split(" ", 1)[0]: d.split(" ", 1)[1] for d in (p.strip() for p in value.split(";")) if d}


@pytest.mark.parametrize("path", ["/", "/workbench/app.js", "/workbench/workbench.css", "/workbench/api.js"])
def test_workbench_and_its_files_carry_the_protective_headers(client: TestClient, path: str) -> None:
    r = client.get(path)
    assert r.status_code == 200
    csp = _csp(r.headers["content-security-policy"])
    for directive, value in CSP_REQUIRED.items():
        assert csp[directive] == value, (directive, csp)
    assert "unsafe-inline" not in r.headers["content-security-policy"]
    assert r.headers["x-content-type-options"] == "nosniff"
    assert r.headers["x-frame-options"] == "DENY"
    assert r.headers["referrer-policy"] in ("no-referrer", "same-origin")
    assert "strict-transport-security" not in r.headers      # only behind TLS
    assert "access-control-allow-origin" not in r.headers


def test_manual_allows_its_own_inline_script_by_hash_only(client: TestClient) -> None:
    import base64
    import hashlib
    import re

    r = client.get("/docs")
    inline = re.findall(rb"<script>(.*?)</script>", r.content, re.S)
    assert len(inline) == 1
    digest = base64.b64encode(hashlib.sha256(inline[0]).digest()).decode()
    scripts = _csp(r.headers["content-security-policy"])["script-src"].split()
    assert scripts == ["'self'", f"'sha256-{digest}'"]


def test_behind_tls_browsers_are_told_to_keep_to_https() -> None:
    with _client(behind_tls=True) as c:
        assert c.get("/health").headers["strict-transport-security"].startswith("max-age=")


@pytest.mark.parametrize("host", ["localhost", "localhost:8000", "127.0.0.1:8000", "[::1]:8000"])
def test_loopback_names_are_answered_by_default(client: TestClient, host: str) -> None:
    assert client.get("/health", headers={"host": host}).status_code == 200


@pytest.mark.parametrize("host", ["attacker.example", "attacker.example:8000", "10.0.0.5", "localhost.attacker.example"])
def test_other_hosts_are_refused_with_a_problem(client: TestClient, host: str) -> None:
    r = client.get("/health", headers={"host": host})
    assert r.status_code == 400
    assert r.headers["content-type"] == "application/problem+json"
    body = r.json()
    assert body["type"] == "/problems/host-not-allowed" and body["status"] == 400
    assert host in body["detail"] and "SYNTH_ALLOWED_HOSTS" in body["detail"]
    assert r.headers["x-content-type-options"] == "nosniff"


def test_allowed_hosts_setting_names_the_office_server() -> None:
    with _client(allowed_hosts="synth.office.example,*.lab.example") as c:
        assert c.get("/health", headers={"host": "synth.office.example"}).status_code == 200
        assert c.get("/health", headers={"host": "rig.lab.example"}).status_code == 200
        assert c.get("/health", headers={"host": "localhost"}).status_code == 400


CROSS_SITE = [
    {"origin": "https://attacker.example"},
    {"origin": "http://localhost:9999"},                  # another port is another origin
    {"origin": "null"},                                   # a sandboxed frame or a file
    {"referer": "https://attacker.example/page.html"},
    {"sec-fetch-site": "cross-site"},
]


@pytest.mark.parametrize("headers", CROSS_SITE)
@pytest.mark.parametrize("method, path", [("POST", "/v1/gears/split"), ("POST", "/v1/studies/abc/resume"),
                                          ("DELETE", "/v1/studies/abc"), ("PATCH", "/v1/users/ada")])
def test_changes_from_another_site_are_refused(client: TestClient, headers: dict[str, str], method: str,
                                               path: str) -> None:
    r = client.request(method, path, headers={**headers, "content-type": "application/x-www-form-urlencoded"},
                       content=b"a=1")
    assert r.status_code == 403
    body = r.json()
    assert body["type"] == "/problems/cross-origin-request"
    assert "another site" in body["detail"]


@pytest.mark.parametrize("headers", [{}, {"origin": "http://localhost"}, {"referer": "http://localhost/"},
                                     {"sec-fetch-site": "same-origin", "origin": "http://localhost"}])
def test_same_origin_and_programs_may_change(headers: dict[str, str]) -> None:
    # auth off: the request reaches the endpoint and is answered by it
    with _client() as c:
        r = c.post("/v1/gears/split", json=SPLIT, headers=headers)
        assert r.status_code == 200, r.text
        assert r.json()["stages"]


def test_reads_from_another_site_are_not_refused_but_not_shared() -> None:
    with _client() as c:
        r = c.get("/v1/studies", headers={"origin": "https://attacker.example"})
        assert r.status_code == 200
        assert "access-control-allow-origin" not in r.headers


def test_cors_is_open_only_to_the_origins_set() -> None:
    with _client(cors_origins="https://cad.example") as c:
        pre = c.options("/v1/gears/split", headers={"origin": "https://cad.example",
                                                    "access-control-request-method": "POST",
                                                    "access-control-request-headers": "authorization,content-type"})
        assert pre.status_code == 200
        assert pre.headers["access-control-allow-origin"] == "https://cad.example"
        r = c.post("/v1/gears/split", json=SPLIT, headers={"origin": "https://cad.example"})
        assert r.status_code == 200 and r.headers["access-control-allow-origin"] == "https://cad.example"
        other = c.post("/v1/gears/split", json=SPLIT, headers={"origin": "https://attacker.example"})
        assert other.status_code == 403 and "access-control-allow-origin" not in other.headers


def test_behind_tls_the_https_page_is_the_services_own() -> None:
    with _client(behind_tls=True) as c:
        assert c.post("/v1/gears/split", json=SPLIT, headers={"origin": "https://localhost"}).status_code == 200
        assert c.post("/v1/gears/split", json=SPLIT, headers={"origin": "https://attacker.example"}).status_code == 403
