"""The workbench under the service's own security headers, in Chromium, with authentication on: the page asks for
a sign-in, works once signed in (its changes carry the CSRF token) and signs out, and the browser refuses nothing
under the Content-Security-Policy (the page without authentication is the same page without the form, and runs
under the same header in test_workbench.py). The live server's log, at debug level, never holds a password,
cookie or token."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest
from playwright.sync_api import Browser, Page, sync_playwright
from service import free_port
from test_workbench import CHROMIUM, CHROMIUM_ARGS, REPO, _shot

ADMIN, PASSWORD = "root", "a long first admin password"
# Registered before any page script runs, so every refusal is counted.
WATCH = ("window.__violations = []; document.addEventListener('securitypolicyviolation', "
         "e => window.__violations.push(e.violatedDirective + ' ' + e.blockedURI));")


def _serve(tmp: Path, auth: str) -> Iterator[tuple[str, Path]]:
    port = free_port()
    log = tmp / "service.log"
    env = {**os.environ, "SYNTH_STUDIES_DB": str(tmp / "store.sqlite"), "SYNTH_AUTH": auth, "SYNTH_WORKERS": "1",
           "SYNTH_ADMIN_NAME": ADMIN, "SYNTH_ADMIN_PASSWORD": PASSWORD, "SYNTH_ALLOWED_HOSTS": "127.0.0.1"}
    with log.open("wb") as sink:
        proc = subprocess.Popen([sys.executable, "-m", "uvicorn", "api.app:app", "--host", "127.0.0.1", "--port",
                                 str(port), "--log-level", "debug"], cwd=REPO, env=env, start_new_session=True,
                                stdout=sink, stderr=subprocess.STDOUT)
        url = f"http://127.0.0.1:{port}"
        try:
            deadline = time.monotonic() + 60
            while True:
                try:
                    if httpx.get(f"{url}/health", timeout=1).status_code == 200:
                        break
                except httpx.TransportError:
                    pass
                if proc.poll() is not None or time.monotonic() > deadline:
                    pytest.fail(f"the service did not start: {log.read_text()[-2000:]}")
                time.sleep(0.2)
            yield url, log
        finally:
            os.killpg(proc.pid, signal.SIGTERM)
            proc.wait(timeout=30)


@pytest.fixture(scope="module")
def browser() -> Iterator[Browser]:
    assert Path(CHROMIUM).exists(), f"{CHROMIUM} is missing: `make test` installs it (apt-get install chromium)"
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        yield b
        b.close()


def _page(browser: Browser) -> tuple[Page, list[str]]:
    context = browser.new_context(viewport={"width": 1400, "height": 1000})
    context.add_init_script(WATCH)
    page = context.new_page()
    refused: list[str] = []
    page.on("console", lambda m: refused.append(m.text) if "Content Security Policy" in m.text else None)
    page.on("pageerror", lambda e: refused.append(f"page error: {e}"))
    return page, refused


def _no_refusal(page: Page, refused: list[str]) -> None:
    assert page.evaluate("window.__violations") == [] and refused == []


def _visit_every_panel(page: Page) -> None:
    for panel in ("balancing", "flywheel", "drive", "machine", "synthesis", "studies", "cams", "mechanism"):
        page.click(f"button[data-panel={panel}]")
    page.click("button[data-panel=balancing]")
    page.click("#bal-run")
    page.wait_for_selector("#bal-polar", timeout=30_000)


def test_signing_in_working_and_signing_out_under_the_policy_with_auth_on(browser: Browser,
                                                                          tmp_path: Path) -> None:
    for url, log in _serve(tmp_path, "on"):
        header = httpx.get(url + "/").headers["content-security-policy"]
        assert "unsafe-inline" not in header and "script-src 'self';" in header
        page, refused = _page(browser)
        asked: list[str] = []
        page.on("request", lambda r: asked.append(f"{r.method} {r.url[len(url):]}"))
        page.goto(url + "/")
        page.wait_for_selector("#signin-form", timeout=20_000)
        assert page.evaluate("document.body.dataset.auth") == "signed-out"
        # Signed out, the page asks the service nothing but who is signed in: its own files and the session; no
        # analysis refused with a 401 shown as a form error, and the header stays in view.
        page.wait_for_timeout(500)
        api = [a for a in asked if a != "GET /" and not a.startswith("GET /workbench/")]
        # (the sign-in and the library each read who is signed in: the session, and nothing else)
        assert api and set(api) == {"GET /v1/auth/session"}, asked
        assert page.evaluate("window.scrollY") == 0 and page.locator("#form-problem").is_hidden()
        assert page.locator("header h1").is_visible()
        page.fill("#signin-name", ADMIN)
        page.fill("#signin-password", "not the password")
        page.click("#signin-form button[type=submit]")
        page.wait_for_selector("#signin-problem:not([hidden])")
        assert page.inner_text("#signin-problem") == "the name or the password is wrong"
        _shot(page, "signin-form")
        page.fill("#signin-password", PASSWORD)
        page.click("#signin-form button[type=submit]")
        page.wait_for_selector("#signed-in", timeout=20_000)
        page.wait_for_selector("body[data-ready='1']", timeout=20_000)
        assert page.inner_text("#signed-in").startswith(ADMIN)
        cookies = {c["name"]: c for c in page.context.cookies()}
        assert cookies["synth_session"]["httpOnly"] and cookies["synth_session"]["sameSite"] == "Strict"
        assert page.evaluate("document.cookie").count("synth_session") == 0   # scripts cannot read it
        _visit_every_panel(page)                                               # POSTs carrying the CSRF token
        _shot(page, "signed-in")
        # the page made an API token for a program, as an admin would
        token = page.evaluate("""async () => {
            const { csrf } = await import('/workbench/signin.js');
            const r = await fetch('/v1/users/root/tokens', {method: 'POST', body: JSON.stringify({label: 'ci'}),
                                  headers: {'content-type': 'application/json', ...csrf()}});
            return (await r.json()).token; }""")
        assert httpx.get(url + "/v1/studies", headers={"authorization": f"Bearer {token}"}).status_code == 200
        assert httpx.get(url + "/v1/studies").status_code == 401
        page.click("#signout")
        page.wait_for_selector("#signin-form", timeout=20_000)
        _no_refusal(page, refused)
        session = cookies["synth_session"]["value"]
        csrf = cookies["synth_csrf"]["value"]
        page.context.close()
        text = log.read_text()
        assert "POST /v1/auth/signin" in text and "GET /v1/studies" in text      # the log is the access log
        for secret in (PASSWORD, "not the password", session, csrf, token, token[len("mst_"):]):
            assert secret not in text
