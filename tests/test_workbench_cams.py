"""The workbench's Cams panel in a real browser (Playwright, the system's Chromium, a live server): the least cam
it shows is the service's own answer, asked here directly, and its files download."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest
from playwright.sync_api import Browser, Page

from test_workbench import SHOTS, base_url, browser, open_page  # noqa: F401  (the service and the browser, per module)


@pytest.fixture
def page(browser: Browser, base_url: str) -> Iterator[Page]:
    yield from open_page(browser, base_url, "[data-cam-ready='1']")


def _wait(page: Page, kind: str) -> None:
    page.wait_for_function(f"(document.body.dataset.cam || '').startsWith({json.dumps(kind)})", timeout=60_000)


def test_least_cam_in_the_panel_is_the_services_and_its_files_download(page: Page, base_url: str) -> None:
    page.click("button[data-panel=cams]")
    page.fill("[id='cam-alpha-rise']", "25")
    page.click("#cam-least-run")
    _wait(page, "synthesised")
    body = json.loads(page.input_value("#cam-json"))
    request = {k: v for k, v in body.items() if k != "base_radius_m"}
    # the offset is kept (no offset range is given): the editor's offset is the request's
    direct = httpx.post(f"{base_url}/v1/cams/synthesis", timeout=60, json={
        **request, "max_pressure_angle_rise_deg": 25, "max_pressure_angle_return_deg": 45,
        "base_radius_bounds_m": [0.005, 0.2]}).json()
    assert body["base_radius_m"] == direct["base_radius_m"]
    shown = page.text_content("#cam-least") or ""
    assert f"{direct['base_radius_m'] * 1000:.5g} mm" in shown and direct["active_constraint"] in shown
    assert page.evaluate("document.getElementById('cam-figure').naturalWidth") > 500
    with page.expect_download() as dl:
        page.click("#cam-dxf")
    assert dl.value.suggested_filename == "cam.dxf"
    assert "LWPOLYLINE" in Path(dl.value.path()).read_text()
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(SHOTS / "cams.png"), full_page=True)
    print(f"screenshot: {SHOTS / 'cams.png'}")


def test_a_program_that_does_not_close_the_turn_names_its_field(page: Page) -> None:
    page.click("button[data-panel=cams]")
    body = json.loads(page.input_value("#cam-json"))
    body["segments"] = body["segments"][:3]
    page.fill("#cam-json", json.dumps(body))
    page.click("#cam-analyse")
    _wait(page, "problem")
    text = page.text_content("#cam-problem") or ""
    assert "360" in text and "field segments" in text
