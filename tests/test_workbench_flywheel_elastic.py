"""The workbench's Flywheel panel in a real browser (Playwright, the system's Chromium, a live server): with a motor
and an elastic link in its folded fields, it shows the service's own elastic drive for the sized flywheel."""

from __future__ import annotations

import json
from collections.abc import Iterator

import httpx
import pytest
from playwright.sync_api import Browser, Page

from test_workbench import SHOTS, base_url, browser, open_page  # noqa: F401  (the service and the browser, per module)


@pytest.fixture
def page(browser: Browser, base_url: str) -> Iterator[Page]:
    yield from open_page(browser, base_url)


def test_the_flywheel_panel_shows_the_elastic_drive(page: Page, base_url: str) -> None:
    page.click("button[data-panel=flywheel]")
    page.wait_for_selector("#fly-run", timeout=30_000)
    # a motor whose steady speed is the design's crank speed: the panel's request without it gives the mean load
    # torque at the crank M; at a 5:1 ratio the motor carries M/5, half its rated torque, so it slips half of its
    # 100 rev/min from synchronous to rated speed
    with page.expect_request("**/v1/flywheel") as sent:
        page.click("#fly-run")
    page.wait_for_selector("#fly-body", timeout=30_000)
    plain = json.loads(sent.value.post_data or "{}")
    load = httpx.post(f"{base_url}/v1/flywheel", json=plain, timeout=60).json()["constant_driving_torque_Nm"]
    n = plain["mean_speed_rpm"]
    page.click("#fly-more-motor summary")
    page.click("#fly-more-elastic_drive summary")
    for path, value in (("motor.synchronous_speed_rpm", 5 * n + 50), ("motor.rated_speed_rpm", 5 * n - 50),
                        ("motor.rated_torque_Nm", 0.4 * load), ("motor.gear_ratio", 5),
                        ("motor.rotor_inertia_kgm2", 0.002), ("elastic_drive.stiffness_Nm_rad", 3000)):
        page.fill(f"[id='fly-{path}']", repr(value))
    page.select_option("[id='fly-elastic_drive.flywheel_on']", "crank")
    with page.expect_request("**/v1/flywheel") as sent:
        page.click("#fly-run")
    page.wait_for_selector("#fly-elastic svg", timeout=60_000)
    body = json.loads(sent.value.post_data or "{}")
    assert body["elastic_drive"]["stiffness_Nm_rad"] == 3000 and body["motor"]["gear_ratio"] == 5
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(SHOTS / "flywheel-elastic.png"), full_page=True)
    # the same request straight to the service: the panel shows its natural frequency and dynamic factor
    direct = httpx.post(f"{base_url}/v1/flywheel", json=body, timeout=60).json()["elastic_drive"]
    text = page.inner_text("#fly-elastic-table")
    assert f"{direct['natural_frequency_Hz']:.4g} Hz" in text
    assert f"{direct['dynamic_factor']:.4g}" in text
    assert page.locator("#fly-elastic polyline.curve").count() == 2
