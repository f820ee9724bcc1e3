"""The workbench's Parts panel in a real browser (Playwright, the system's Chromium, a live server): the links it
shows sized are the service's own answer for the editor's linkage, asked here directly, each drawn with its marks;
a family too small for the load names the link, the check and the crank angle."""

from __future__ import annotations

import json
from collections.abc import Iterator

import httpx
import pytest
from playwright.sync_api import Browser, Page

from test_workbench import SHOTS, base_url, browser, open_page  # noqa: F401  (the service and the browser, per module)


@pytest.fixture
def page(browser: Browser, base_url: str) -> Iterator[Page]:
    yield from open_page(browser, base_url, "[data-parts-ready='1']")


def _wait(page: Page, kind: str) -> None:
    page.wait_for_function(f"(document.body.dataset.parts || '').startsWith({json.dumps(kind)})", timeout=60_000)


def test_the_panel_sizes_the_editors_links_as_the_service_does(page: Page, base_url: str) -> None:
    page.click("button[data-panel=parts]")
    page.select_option("#parts-kind", "round")
    page.click("#parts-run")
    _wait(page, "sized")
    design = page.evaluate("window.workbench.state.design")
    request = {k: design[k] for k in ("mechanism", "speed_rpm", "gravity", "loads", "torques", "counterweights")
               if design and design.get(k) is not None}
    direct = httpx.post(f"{base_url}/v1/strength", timeout=60, json={
        **request, "samples": 180, "material": {"grade": "S355J2"},
        "section": {"kind": "round", "ratio": 3, "min_size_mm": 6},
        "limits": {"static_safety": 1.5, "fatigue_safety": 1.5, "buckling_safety": 2.5}}).json()
    rows = page.locator("#parts-table tr").all_inner_texts()[1:]
    assert len(rows) == len(direct["links"])
    for row, link in zip(rows, direct["links"]):
        assert link["link"] in row and link["section"] in row
    assert f"{direct['mass_kg']:.4g} kg" in (page.text_content("#parts-summary") or "")
    # each link drawn with a mark per check
    assert page.locator("svg.parts-link").count() == len(direct["links"])
    assert page.locator("svg.parts-link circle.mark-static").count() == len(direct["links"])
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(SHOTS / "parts.png"), full_page=True)
    print(f"screenshot: {SHOTS / 'parts.png'}")


def test_a_section_too_small_names_the_link_the_check_and_the_angle(page: Page) -> None:
    page.click("button[data-panel=parts]")
    page.select_option("#parts-grade", "EN AW-6082-T6")
    page.fill("#parts-min", "3")
    page.evaluate("document.getElementById('parts-min').dispatchEvent(new Event('change'))")
    page.route("**/v1/strength", lambda route: route.continue_(post_data=json.dumps(
        {**json.loads(route.request.post_data or "{}"), "section": {"kind": "round", "max_size_mm": 3}})))
    page.click("#parts-run")
    _wait(page, "problem")
    text = page.text_content("#parts-problem") or ""
    assert "link " in text and "crank angle" in text
