"""The office-server setup of docs/deployment.md, run: the documented nginx site (Debian's nginx) on loopback with
a self-signed certificate in front of the service with authentication on, behind TLS, answering to one name.

Through the proxy: HTTPS with HSTS, the plain-HTTP redirect, a browser's sign-in with Secure __Host- cookies, a
same-origin change with its CSRF token accepted (the service sees the browser's scheme and host), a change from
another site refused, and a host the service does not answer to refused."""

from __future__ import annotations

import os
import re
import signal
import ssl
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest
from service import REPO, free_port

NGINX = "/usr/sbin/nginx"
ADMIN, PASSWORD = "ada", "a long first admin password"
SPLIT = {"total_ratio": 12.0, "stages": 2}


def _documented_site() -> str:
    text = (REPO / "docs" / "deployment.md").read_text()
    blocks = re.findall(r"^```nginx\n(.*?)^```$", text, flags=re.M | re.S)
    assert len(blocks) == 1, "docs/deployment.md has one nginx site"
    return str(blocks[0])


def _trust(cert: Path) -> ssl.SSLContext:
    """A TLS context trusting the test's self-signed certificate only."""
    return ssl.create_default_context(cafile=str(cert))


def _wait(url: str, proc: subprocess.Popen[bytes], log: Path, **kw: object) -> None:
    deadline = time.monotonic() + 60
    while True:
        try:
            httpx.get(url, timeout=1, **kw)  # type: ignore[arg-type]
            return
        except httpx.TransportError:
            pass
        if proc.poll() is not None or time.monotonic() > deadline:
            pytest.fail(f"{proc.args} did not start: {log.read_text()[-2000:]}")
        time.sleep(0.2)


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[str, str, Path]]:
    # Never a skip: `make test` installs nginx-light when it is missing.
    assert Path(NGINX).exists(), f"{NGINX} is missing: `make test` installs it (apt-get install nginx-light)"
    tmp = tmp_path_factory.mktemp("deployment")
    cert, key = tmp / "fullchain.pem", tmp / "privkey.pem"
    subprocess.run(["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "1", "-subj", "/CN=localhost",
                    "-addext", "subjectAltName=DNS:localhost", "-keyout", str(key), "-out", str(cert)],
                   check=True, capture_output=True)
    app_port, tls_port, http_port = free_port(), free_port(), free_port()
    site = (_documented_site()
            .replace("listen 443 ssl;", f"listen 127.0.0.1:{tls_port} ssl;")
            .replace("listen 80;", f"listen 127.0.0.1:{http_port};")
            .replace("synth.office.example", "localhost")
            .replace("/etc/ssl/mechsynth/fullchain.pem", str(cert))
            .replace("/etc/ssl/mechsynth/privkey.pem", str(key))
            .replace("http://127.0.0.1:8000", f"http://127.0.0.1:{app_port}"))
    (tmp / "site.conf").write_text(site)
    # nginx's own frame for the site: everything in the scratch directory, in the foreground
    (tmp / "nginx.conf").write_text(
        ("user root;\n" if os.geteuid() == 0 else "")
        + f"daemon off;\npid {tmp}/nginx.pid;\nerror_log {tmp}/nginx-error.log;\nevents {{}}\n"
        f"http {{\n  access_log {tmp}/access.log;\n  client_body_temp_path {tmp}/body;\n"
        f"  proxy_temp_path {tmp}/proxy;\n  include {tmp}/site.conf;\n}}\n")
    env = {**os.environ, "SYNTH_STUDIES_DB": str(tmp / "store.sqlite"), "SYNTH_AUTH": "on",
           "SYNTH_BEHIND_TLS": "true", "SYNTH_ALLOWED_HOSTS": "localhost", "SYNTH_WORKERS": "1",
           "SYNTH_ADMIN_NAME": ADMIN, "SYNTH_ADMIN_PASSWORD": PASSWORD}
    app_log, nginx_log = tmp / "service.log", tmp / "nginx.out"
    with app_log.open("wb") as app_out, nginx_log.open("wb") as nginx_out:
        # the documented command, on this test's port
        app = subprocess.Popen([sys.executable, "-m", "uvicorn", "api.app:app", "--host", "127.0.0.1", "--port",
                                str(app_port), "--proxy-headers", "--forwarded-allow-ips", "127.0.0.1"], cwd=REPO,
                               env=env, start_new_session=True, stdout=app_out, stderr=subprocess.STDOUT)
        proxy = subprocess.Popen([NGINX, "-c", str(tmp / "nginx.conf"), "-p", str(tmp)], start_new_session=True,
                                 stdout=nginx_out, stderr=subprocess.STDOUT)
        try:
            _wait(f"http://127.0.0.1:{app_port}/health", app, app_log)
            _wait(f"https://localhost:{tls_port}/health", proxy, nginx_log, verify=_trust(cert))
            yield f"https://localhost:{tls_port}", f"http://localhost:{http_port}", cert
        finally:
            for proc in (proxy, app):
                os.killpg(proc.pid, signal.SIGTERM)
                proc.wait(timeout=30)


def test_https_with_hsts_and_the_plain_http_redirect(site: tuple[str, str, Path]) -> None:
    url, plain, cert = site
    r = httpx.get(url + "/", verify=_trust(cert))
    assert r.status_code == 200 and r.headers["strict-transport-security"].startswith("max-age=")
    assert "unsafe-inline" not in r.headers["content-security-policy"]
    moved = httpx.get(plain + "/v1/studies?limit=5")
    # the documented redirect keeps the path and query and names the host without the plain port
    assert moved.status_code == 301 and moved.headers["location"] == "https://localhost/v1/studies?limit=5"


def test_a_browser_signs_in_and_changes_through_the_proxy(site: tuple[str, str, Path]) -> None:
    url, _, cert = site
    page = {"origin": url}
    with httpx.Client(base_url=url, verify=_trust(cert)) as browser:
        assert browser.post("/v1/gears/split", json=SPLIT, headers=page).status_code == 401
        signed = browser.post("/v1/auth/signin", json={"name": ADMIN, "password": PASSWORD}, headers=page)
        assert signed.status_code == 200, signed.text
        raw = signed.headers.get_list("set-cookie")
        assert {c.split("=", 1)[0] for c in raw} == {"__Host-synth_session", "__Host-synth_csrf"}
        assert all("Secure" in c and "SameSite=strict" in c and "Path=/" in c for c in raw)
        assert "HttpOnly" in next(c for c in raw if c.startswith("__Host-synth_session"))
        csrf = {"x-csrf-token": signed.json()["csrf_token"]}
        # the service sees the browser's https origin through the proxy: the page's own change is accepted
        r = browser.post("/v1/gears/split", json=SPLIT, headers={**page, **csrf})
        assert r.status_code == 200, r.text
        r = browser.post("/v1/gears/split", json=SPLIT, headers={"origin": "https://attacker.example", **csrf})
        assert r.status_code == 403 and r.json()["type"] == "/problems/cross-origin-request"
        r = browser.get("/health", headers={"host": "attacker.example"})
        assert r.status_code == 400 and r.json()["type"] == "/problems/host-not-allowed"
