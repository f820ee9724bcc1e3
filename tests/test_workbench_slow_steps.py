"""The workbench's slow steps in a real browser (Playwright, the system's Chromium, a live server): the Machine
panel's record is the design the page shows, and the record and a machine revision's save show their progress and
can be cancelled. (That the record of a design just made is written without designing again is counted in
tests/test_machine_held.py, where the engine's calls can be counted.)"""

from __future__ import annotations

import io
import re
from collections.abc import Iterator
from pathlib import Path

import pytest
from playwright.sync_api import Page, Route
from pypdf import PdfReader

from test_workbench import SHOTS, base_url, browser, open_page  # noqa: F401  (the service and the browser, per module)


@pytest.fixture
def page(browser, base_url: str) -> Iterator[Page]:  # type: ignore[no-untyped-def]
    yield from open_page(browser, base_url)


def _held(page: Page, pattern: str) -> list[Route]:
    """Requests to ``pattern`` held unanswered (a service busy for longer than anyone waits), so that the page's
    cancel is what ends them."""
    routes: list[Route] = []
    page.route(pattern, lambda route: routes.append(route))
    return routes


def _cancelled_while_waiting(page: Page, prefix: str, text: str) -> None:
    """The step's indeterminate bar counts its seconds; Cancel ends it."""
    page.wait_for_selector(f"#{prefix}-progress progress", timeout=5_000)
    page.wait_for_function(f"/{text} [1-9]\\d* s/.test(document.getElementById('{prefix}-elapsed').textContent)",
                           timeout=10_000)
    page.click(f"#{prefix}-cancel")


def test_the_record_is_the_design_shown_and_its_writing_can_be_cancelled(page: Page) -> None:
    page.click("button[data-panel=machine]")
    page.select_option("[id='mac-alternatives']", "false")
    with page.expect_request("**/v1/machines/design") as sent:
        page.click("#mac-run")
    page.wait_for_selector("#mac-verdict", timeout=60_000)
    shown = page.evaluate("[...document.querySelectorAll('#mac-result tr.check')].map(r => "
                          "[r.dataset.name, r.cells[2].textContent])")
    with page.expect_request("**/v1/machines/design?format=pdf") as asked, page.expect_download(timeout=60_000) as dl:
        page.click("#mac-pdf")
    # the record is asked for the very request whose answer the page shows
    assert asked.value.post_data_json == sent.value.post_data_json
    text = "\n".join(p.extract_text() for p in PdfReader(io.BytesIO(Path(dl.value.path()).read_bytes())).pages)
    checks = dict(shown)
    rms = float(checks["motor_rms_torque"].split()[0])
    found = re.search(r"motor torque, RMS \(heating\)\s+(-?[\d.]+)", text)
    # the page prints four significant digits, the record its own: the same figure within the page's rounding
    assert found and float(found.group(1)) == pytest.approx(rms, rel=5e-4)
    assert page.evaluate("document.body.dataset.record") == "downloaded"
    # a record that takes longer than one waits for: the bar counts, Cancel stops it, the button is back
    held = _held(page, "**/v1/machines/design?format=pdf")
    page.click("#mac-pdf")
    assert page.is_disabled("#mac-pdf")
    _cancelled_while_waiting(page, "mac", "writing the design record…")
    page.wait_for_function("document.body.dataset.record === 'cancelled'", timeout=5_000)
    assert len(held) == 1 and page.locator("#mac-progress").count() == 0
    assert page.is_enabled("#mac-pdf") and "cancelled" in page.inner_text("#mac-status")
    assert page.locator("#mac-verdict").is_visible()          # the answer shown stays
    page.unroute("**/v1/machines/design?format=pdf")


def test_a_machine_revisions_save_shows_its_progress_and_can_be_cancelled(page: Page) -> None:
    page.click("button[data-panel=library]")
    page.fill("#lib-project", "press-line")
    page.fill("#lib-design", "slow")
    page.fill("#lib-name", "ann")
    held = _held(page, "**/revisions")
    page.click("#lib-save")
    assert page.is_disabled("#lib-save")
    _cancelled_while_waiting(page, "lib", "saving: the machine is designed and its record written…")
    page.wait_for_function("(document.body.dataset.library || '').startsWith('cancelled-')", timeout=5_000)
    assert len(held) == 1 and held[0].request.method == "POST"
    assert page.locator("#lib-progress").count() == 0 and page.is_enabled("#lib-save")
    # said as it is: the page stopped waiting, the service may have saved it
    assert "may still save" in page.inner_text("#lib-status")
    page.locator("#panel-library").screenshot(path=str(SHOTS / "library-save-cancelled.png"))
    page.unroute("**/revisions")
