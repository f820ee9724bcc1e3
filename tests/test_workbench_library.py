"""The workbench's Library panel in a real browser (Playwright, the system's Chromium, a live server): a design saved
by one name, edited and saved again, a stale save refused in words, the two revisions compared, checked and
approved by other names, and the design record downloaded with the signed title block.

Every number checked comes from the service asked directly over HTTP by the test, or from what the test typed.
Screenshots of each step go to a scratch directory (``WORKBENCH_SCREENSHOTS`` to choose it).
"""

from __future__ import annotations

import io
import json
import os
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Iterator
from datetime import datetime, timezone
from pathlib import Path

import httpx
import pytest
from playwright.sync_api import Page, sync_playwright
from pypdf import PdfReader
from service import running_process

CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync"]
SHOTS = Path(os.environ.get("WORKBENCH_SCREENSHOTS") or tempfile.mkdtemp(prefix="workbench-screens-"))
DESIGN = "/v1/library/projects/press-line/designs/press"
# a machine design is made on each save and its record written again once signed: minutes on a busy machine
SLOW_MS = 180_000


@pytest.fixture(scope="module")
def base_url(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    command = lambda port: [sys.executable, "-m", "uvicorn", "api.app:app", "--host", "127.0.0.1",  # noqa: E731
                            "--port", str(port)]
    # a machine design is worked out on every save: more than the default deadline on a machine shared with others
    with running_process(command, tmp_path_factory.mktemp("library"), start_timeout_s=120,
                         env={"SYNTH_REQUEST_DEADLINE_S": "600"}) as (url, _):
        yield url


@pytest.fixture()
def page(base_url: str) -> Iterator[Page]:
    assert Path(CHROMIUM).exists(), f"{CHROMIUM} is missing: `make test` installs it (apt-get install chromium)"
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        # the service's Content-Security-Policy forbids the eval wait_for_function uses; the page itself runs
        # under it in test_workbench.py
        context = browser.new_context(viewport={"width": 1400, "height": 1000}, accept_downloads=True,
                                      bypass_csp=True)
        pg = context.new_page()
        errors: list[str] = []
        pg.on("pageerror", lambda e: errors.append(str(e)))
        pg.goto(base_url + "/")
        pg.wait_for_selector("body[data-ready='1']", timeout=30_000)
        yield pg
        browser.close()
        assert not errors, errors


def _shot(page: Page, name: str) -> None:
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.locator("#panel-library").screenshot(path=str(SHOTS / f"library-{name}.png"), animations="disabled",
                                              timeout=120_000)
    print(f"screenshot: {SHOTS}/library-{name}.png")


def _act(page: Page, selector: str, expect: str, timeout: float = 30_000) -> None:
    """Click and wait for the panel's next outcome, which must be ``expect`` (saved, refused, compared, ...)."""
    before = page.evaluate("document.body.dataset.library || ''")
    page.click(selector)
    page.wait_for_function(f"(document.body.dataset.library || '') !== {json.dumps(before)}", timeout=timeout)
    outcome = page.evaluate("document.body.dataset.library")
    assert outcome.startswith(expect + "-"), (outcome, page.inner_text("#lib-status"))


def test_save_edit_save_compare_check_approve_and_download_the_signed_record(page: Page, base_url: str) -> None:
    page.click("button[data-panel=library]")
    page.fill("#lib-project", "press-line")
    page.fill("#lib-design", "press")
    page.fill("#lib-name", "ann")
    page.fill("#lib-message", "first")
    speed = page.evaluate("window.workbench.state.design.speed_rpm")
    _act(page, "#lib-save", "saved", SLOW_MS)
    _shot(page, "1-saved")
    first = httpx.get(f"{base_url}{DESIGN}/revisions/1", timeout=30).json()
    assert (first["author"], first["endpoint"], first["state"]) == ("ann", "/v1/machines/design", "draft")
    assert first["request"]["mechanism"] == page.evaluate("window.workbench.state.design.mechanism")

    # an edit in the form, saved on top of revision 1
    before = page.evaluate("document.body.dataset.analysed || ''")
    page.fill("[id='f-speed_rpm']", str(speed + 30))
    page.wait_for_function(f"(document.body.dataset.analysed || '') !== {json.dumps(before)}", timeout=30_000)
    page.fill("#lib-message", "faster")
    _act(page, "#lib-save", "saved", SLOW_MS)
    second = httpx.get(f"{base_url}{DESIGN}/revisions/2", timeout=30).json()
    assert (second["parent"], second["request"]["speed_rpm"]) == (1, speed + 30)

    # revision 1 opened again: the form holds its speed, and a save from it would overwrite revision 2
    _act(page, "#lib-history tr[data-revision='1'] button:has-text('Open')", "opened")
    page.wait_for_function(f"window.workbench.state.design.speed_rpm === {speed}", timeout=30_000)
    _act(page, "#lib-save", "refused")
    status = page.inner_text("#lib-status")
    assert "at revision 2" in status and "overwrite" in status and page.locator("#lib-branch").is_visible()
    _shot(page, "2-stale")

    # the two revisions compared: the speed typed, and every figure the service's own diff says moved
    _act(page, "#lib-compare", "compared")
    diff = httpx.get(f"{base_url}{DESIGN}/diff", params={"from": 1, "to": 2}, timeout=30).json()
    inputs = page.locator("#lib-diff-inputs tr").all_inner_texts()[1:]
    assert [r.split("\t") for r in inputs] == [["speed_rpm", "rpm", f"{speed:g}", f"{speed + 30:g}"]]
    # the single figures one row each; the curves (a value per crank angle) one row a curve
    single = [c for c in diff["answer"] if not any(p.isdigit() for p in c["path"].split("."))]
    assert page.locator("#lib-diff-figures tr[data-path]").count() == len(single) > 0
    assert page.locator("#lib-diff-curves tr").count() > 1
    torque = next(c for c in diff["answer"] if c["path"].endswith("rms_driving_torque_Nm"))
    row = page.locator(f"#lib-diff-figures tr[data-path='{torque['path']}'] td").all_text_contents()
    assert float(row[2]) == pytest.approx(torque["before"], rel=1e-5)
    assert float(row[3]) == pytest.approx(torque["after"], rel=1e-5)
    # ranked: the page's rows in the service's order, the largest relative change first; the joint reactions in N;
    # the figures that moved within the answers' own tolerance left out, counted, and listed when asked for
    shown = page.eval_on_selector_all("#lib-diff-figures tr[data-path]", "rs => rs.map(r => r.dataset.path)")
    assert shown == [c["path"] for c in single]
    rels = [abs(c["change_rel"]) for c in diff["answer"] if c["change_rel"] is not None and c["before"] is not None]
    assert rels == sorted(rels, reverse=True)
    assert {c["unit"] for c in diff["answer"] if "joint_reactions_N" in c["path"]} <= {"N"}
    every = httpx.get(f"{base_url}{DESIGN}/diff", params={"from": 1, "to": 2, "noise": "true"}, timeout=30).json()
    assert len(every["answer"]) == len(diff["answer"]) + diff["noise_figures"]
    _shot(page, "3-compared")

    # the author may not check their own revision; bob checks it, cid approves it
    _act(page, "#lib-history tr[data-revision='2'] button:has-text('Check')", "refused")
    assert "ann wrote revision 2" in page.inner_text("#lib-status")
    page.fill("#lib-name", "bob")
    _act(page, "#lib-history tr[data-revision='2'] button:has-text('Check')", "check")
    page.fill("#lib-name", "cid")
    _act(page, "#lib-history tr[data-revision='2'] button:has-text('Approve')", "approve")
    signed = httpx.get(f"{base_url}{DESIGN}/revisions/2", timeout=30).json()
    assert (signed["state"], signed["checked_by"], signed["approved_by"]) == ("approved", "bob", "cid")
    assert page.inner_text("#lib-history tr[data-revision='2'] td.state") == "approved"
    _shot(page, "4-approved")

    with page.expect_download(timeout=SLOW_MS) as dl:
        page.click("#lib-history tr[data-revision='2'] button:has-text('Record (PDF)')")
    assert dl.value.suggested_filename == "press-line-press-r2.pdf"
    pdf = Path(dl.value.path()).read_bytes()
    today = datetime.now(timezone.utc).strftime("%Y-%m-%d")
    title = "".join(PdfReader(io.BytesIO(pdf)).pages[0].extract_text().split())
    for text in ("press-line/press", "approved", "ann" + today, "bob" + today, "cid" + today,
                 second["content_hash"]):
        assert text in title, text
    if shutil.which("pdftoppm"):
        (SHOTS / "library-5-record.pdf").write_bytes(pdf)
        subprocess.run(["pdftoppm", "-png", "-r", "70", "-f", "1", "-l", "1", str(SHOTS / "library-5-record.pdf"),
                        str(SHOTS / "library-5-record")], check=True)

    # revision 1 restored: a new revision 3 on top of the approved 2, with revision 1's request byte for byte
    page.fill("#lib-name", "ann")
    page.fill("#lib-message", "back to the first speed")
    _act(page, "#lib-history tr[data-revision='1'] button:has-text('Restore')", "restored", SLOW_MS)
    third = httpx.get(f"{base_url}{DESIGN}/revisions/3", timeout=30).json()
    assert (third["parent"], third["author"], third["state"]) == (2, "ann", "draft")
    assert third["content_hash"] == first["content_hash"] and third["request"]["speed_rpm"] == speed
    assert page.inner_text("#lib-history tr[data-revision='3'] td.state") == "draft"
    assert page.locator("#lib-history tr[data-revision='3'] button:has-text('Restore')").count() == 0
    _shot(page, "6-restored")
