"""The Synthesis panel in a real browser (Playwright, the system's Chromium, a live server): an answer belongs to its
task, and goes when another task is chosen."""

from __future__ import annotations

from collections.abc import Iterator

import httpx
import pytest
from playwright.sync_api import Page

from test_workbench import base_url, browser, open_page  # noqa: F401  (the service and the browser, per module)


@pytest.fixture
def page(browser, base_url: str) -> Iterator[Page]:  # type: ignore[no-untyped-def]
    yield from open_page(browser, base_url)


def test_the_previous_answer_goes_with_a_change_of_task(page: Page, base_url: str) -> None:
    page.click("button[data-panel=synthesis]")
    page.click("#syn-run")
    page.wait_for_function("document.body.dataset.synthesised === 'crank-rocker'", timeout=60_000)
    # the answer shown is the service's: its crank, asked directly with the panel's own fields (40°, 1.2, 150 mm)
    speed = page.evaluate("window.workbench.state.design.speed_rpm")
    direct = httpx.post(f"{base_url}/v1/synthesis/crank-rocker", json={"swing_deg": 40, "time_ratio": 1.2,
                        "scale_link": "rocker", "scale_length_m": 0.15, "speed_rpm": speed}, timeout=60).json()
    crank_mm = direct["mechanism"]["crank_length_m"] * 1e3
    assert f"crank_length {crank_mm:.4g} mm" in page.inner_text("#syn-result")
    assert page.locator("#syn-open").is_enabled()
    # path points asked for instead: the crank-rocker is no answer to them
    page.select_option("#syn-task", "path")
    assert page.inner_text("#syn-result").strip() == ""
    assert page.locator("#syn-open").is_disabled()
    assert page.evaluate("document.body.dataset.synthesised") is None
