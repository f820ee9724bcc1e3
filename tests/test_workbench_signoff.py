"""A design signed through in the workbench by three people on a real service with sign-in on (Playwright, the
system's Chromium): the author saves a machine design; the checker opens it read only, sees its linkage move and
its stored answer, and checks it with a remark; the approver approves it; the design record downloaded carries the
revision table and the remark. Each person sees only the buttons they may press and no name field.

Every name and text checked is what the test typed or what the service answers over HTTP. Screenshots of each
step go to a scratch directory (``WORKBENCH_SCREENSHOTS`` to choose it)."""

from __future__ import annotations

import io
import json
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path

import pytest
from playwright.sync_api import Browser, Page, sync_playwright
from pypdf import PdfReader

from signoff_office import PASSWORD, Office, office, ok

CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync"]
SHOTS = Path(os.environ.get("WORKBENCH_SCREENSHOTS") or tempfile.mkdtemp(prefix="workbench-screens-"))
DESIGN = "/v1/library/projects/press-line/designs/press"
# a machine design is made on the save and its record written again once signed: minutes on a busy machine
SLOW_MS = 300_000
REMARK = "flywheel checked against drawing 7"


@pytest.fixture(scope="module")
def the_office(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Office]:
    scratch = tmp_path_factory.mktemp("signoff-browser")
    with office(f"sqlite:///{scratch / 'store.sqlite'}", scratch) as it:
        yield it


@pytest.fixture(scope="module")
def browser() -> Iterator[Browser]:
    assert Path(CHROMIUM).exists(), f"{CHROMIUM} is missing: `make test` installs it (apt-get install chromium)"
    with sync_playwright() as p:
        launched = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        yield launched
        launched.close()


def _person(browser: Browser, url: str, name: str) -> Page:
    """A browser of its own for ``name``, signed in through the page's form, on the Library panel."""
    context = browser.new_context(viewport={"width": 1400, "height": 1000}, accept_downloads=True, bypass_csp=True)
    page = context.new_page()
    errors: list[str] = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.goto(url + "/")
    page.fill("#signin-name", name)
    page.fill("#signin-password", PASSWORD)
    page.click("#signin-form button[type=submit]")
    page.wait_for_selector("body[data-ready='1']", timeout=120_000)
    page.click("button[data-panel=library]")
    page.wait_for_selector("#lib-who", timeout=30_000)
    assert not errors, errors
    return page


def _shot(page: Page, name: str) -> None:
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.locator("#panel-library").screenshot(path=str(SHOTS / f"signoff-{name}.png"), animations="disabled",
                                              timeout=120_000)
    print(f"screenshot: {SHOTS}/signoff-{name}.png")


def _act(page: Page, selector: str, expect: str, timeout: float = 60_000) -> None:
    """Click and wait for the panel's next outcome, which must be ``expect``."""
    before = page.evaluate("document.body.dataset.library || ''")
    page.click(selector)
    page.wait_for_function(f"(document.body.dataset.library || '') !== {json.dumps(before)}", timeout=timeout)
    outcome = page.evaluate("document.body.dataset.library")
    assert outcome.startswith(expect + "-"), (outcome, page.inner_text("#lib-status"))


def _find(page: Page) -> None:
    page.fill("#lib-find", "press")
    _act(page, "#lib-search", "found")
    page.click("#lib-found-table button:has-text('History')")
    page.wait_for_selector("#lib-history tr[data-revision='1']", timeout=30_000)


def test_three_people_sign_a_design_through_and_the_record_shows_it(the_office: Office, browser: Browser) -> None:
    url = the_office.urls[0]
    row = "#lib-history tr[data-revision='1']"

    ann = _person(browser, url, "ann")
    assert ann.locator("#lib-name").count() == 0          # signed in: the service knows who saves
    assert "ann (engineer)" in ann.inner_text("#lib-who")
    ann.fill("#lib-project", "press-line")
    ann.fill("#lib-design", "press")
    ann.fill("#lib-message", "the press as drawn")
    _act(ann, "#lib-save", "saved", SLOW_MS)
    saved = ok(the_office.as_("vic").get(f"{DESIGN}/revisions/1"))
    assert (saved["author"], saved["state"], saved["passed"]) == ("ann", "draft", True)
    # an engineer neither checks nor approves: no such buttons
    assert ann.locator(f"{row} button:has-text('Check')").count() == 0
    assert ann.locator(f"{row} button:has-text('Approve')").count() == 0
    assert ann.inner_text(f"{row} td.result") == "passed"
    _shot(ann, "1-author")

    bob = _person(browser, url, "bob")
    assert bob.locator("#lib-name").count() == 0 and bob.locator("#lib-save").count() == 0
    _find(bob)
    assert bob.inner_text("#lib-found-table td.state") == "draft"
    # opened read only: the linkage analysed again as it was saved, and every figure of the stored answer
    before = bob.evaluate("document.body.dataset.analysed || ''")
    _act(bob, f"{row} button:has-text('Open')", "opened")
    bob.wait_for_function(f"(document.body.dataset.analysed || '') !== {json.dumps(before)}", timeout=60_000)
    assert "read only" in bob.inner_text("#lib-status")
    answer = bob.inner_text("#lib-answer")
    assert "Stored answer of revision 1" in answer and "computed by this service" in answer
    assert bob.locator(f"{row} button:has-text('Approve')").count() == 0
    assert bob.locator(f"{row} button:has-text('Restore')").count() == 0
    bob.fill("#lib-remark", REMARK)
    _act(bob, f"{row} button:has-text('Check')", "check")
    assert bob.inner_text(f"{row} td.state") == "checked"
    assert REMARK in bob.inner_text(f"{row} td.comments")
    assert bob.inner_text("#lib-found-table td.state") == "checked"     # the search row moved with it
    _shot(bob, "2-checker")

    cid = _person(browser, url, "cid")
    _find(cid)
    assert cid.locator(f"{row} button:has-text('Check')").count() == 0
    _act(cid, f"{row} button:has-text('Approve')", "approve")
    signed = ok(the_office.as_("vic").get(f"{DESIGN}/revisions/1"))
    assert (signed["state"], signed["checked_by"], signed["approved_by"]) == ("approved", "bob", "cid")
    assert cid.inner_text(f"{row} td.state") == "approved"
    _shot(cid, "3-approver")

    # a viewer opens it read only: its stored answer, and not one button that signs or saves
    vic = _person(browser, url, "vic")
    assert "open any revision and its stored answer, read only" in vic.inner_text("#lib-who")
    _find(vic)
    _act(vic, f"{row} button:has-text('Open')", "opened")
    assert "Stored answer of revision 1" in vic.inner_text("#lib-answer")
    for button in ("Check", "Approve", "Return", "Restore"):
        assert vic.locator(f"{row} button:has-text('{button}')").count() == 0, button
    assert vic.locator("#lib-save").count() == 0 and vic.locator("#lib-name").count() == 0
    _shot(vic, "4-viewer")

    with cid.expect_download(timeout=SLOW_MS) as download:
        cid.click(f"{row} button:has-text('Record (PDF)')")
    pdf = Path(download.value.path()).read_bytes()
    first = "".join(PdfReader(io.BytesIO(pdf)).pages[0].extract_text().split())
    for text in ("Revisions", "thepressasdrawn", "checker'sremarkbybob", "".join(REMARK.split()), "approved",
                 signed["content_hash"]):
        assert text in first, text
