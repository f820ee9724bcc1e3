"""The workbench's Foundation panel in a real browser (Playwright, the system's Chromium, a live server): the
manual's compressor on its isolators shows the service's own natural frequencies, the force to the foundation,
its spectrum and the modes drawn; a bad isolator stiffness is named beside its field. And the Machine panel draws
the elastic-drive and load-step figures when those folded fields are given."""

from __future__ import annotations

import json
from collections.abc import Iterator

import httpx
import pytest
from playwright.sync_api import Browser, Page

from test_workbench import SHOTS, base_url, browser, open_page  # noqa: F401  (the service and the browser, per module)


@pytest.fixture
def page(browser: Browser, base_url: str) -> Iterator[Page]:
    yield from open_page(browser, base_url, "[data-foundation-ready='1']")


def _wait(page: Page, kind: str) -> None:
    page.wait_for_function(f"(document.body.dataset.foundation || '').startsWith({json.dumps(kind)})",
                           timeout=90_000)


def _example(base_url: str) -> dict:  # type: ignore[type-arg]
    api = httpx.get(f"{base_url}/openapi.json", timeout=30).json()
    return api["components"]["schemas"]["IsolationIn"]["examples"][0]  # type: ignore[no-any-return]


def test_the_compressor_on_its_isolators_shows_the_services_answer(page: Page, base_url: str) -> None:
    page.click("button[data-panel=foundation]")
    page.click("#fnd-example")
    page.wait_for_function("window.workbench.state.design.mechanism.type === 'slider_crank'")
    page.click("#fnd-run")
    _wait(page, "isolated")
    ex = _example(base_url)
    # the same request straight to the service: the panel shows its natural frequencies to 4 digits
    direct = httpx.post(f"{base_url}/v1/machines/isolation", timeout=90, json={
        "mechanism": ex["mechanism"], "speed_rpm": ex["speed_rpm"], "samples": 360, "frame": ex["frame"],
        "isolators": ex["isolators"]}).json()
    shown = [float(t) for t in page.locator("#fnd-mode-table td.freq").all_text_contents()]
    assert shown == pytest.approx([m["frequency_Hz"] for m in direct["modes"]], rel=5e-4)
    assert f"{direct['peak_force_N']:.4g}" in (page.text_content("#fnd-peaks") or "")
    # the force over the cycle, its spectrum (a bar per harmonic and series) and the three modes drawn
    assert page.locator("#fnd-force polyline.curve").count() == 4
    assert page.locator("#fnd-spectrum rect[data-order='1']").count() == 2
    assert page.locator("#fnd-modes polygon.mode-shape").count() == 3
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(SHOTS / "foundation.png"), full_page=True)
    print(f"screenshot: {SHOTS / 'foundation.png'}")
    # the isolators chosen for the panel's limits (600 N, 20 mm, no block) are the design endpoint's and fill
    # the table
    page.click("#fnd-design")
    _wait(page, "designed")
    designed = httpx.post(f"{base_url}/v1/machines/isolation/design", timeout=90, json={
        "mechanism": ex["mechanism"], "speed_rpm": ex["speed_rpm"], "samples": 360, "frame": ex["frame"],
        "positions_m": [i["position_m"] for i in ex["isolators"]], "objective": "amplitude", "max_force_N": 600,
        "max_static_deflection_m": 0.02, "max_block_mass_kg": 0}).json()
    assert float(page.input_value("[id='fnd-isolators.0.ky_N_m']")) == designed["ky_N_m"]
    shown = (page.text_content("#fnd-designed") or "").split("k_y ")[1].split(" N/m")[0]
    assert float(shown) == pytest.approx(designed["ky_N_m"], rel=5e-4)


def test_a_negative_isolator_stiffness_is_named_beside_its_field(page: Page) -> None:
    page.click("button[data-panel=foundation]")
    page.fill("[id='fnd-isolators.1.ky_N_m']", "-1e5")
    page.click("#fnd-run")
    _wait(page, "problem")
    msg = page.locator("[id='fnd-isolators.1.ky_N_m-msg']")
    assert msg.is_visible() and "0" in (msg.text_content() or "")
    assert page.get_attribute("[id='fnd-isolators.1.ky_N_m']", "aria-invalid") == "true"
    page.screenshot(path=str(SHOTS / "foundation-problem.png"), full_page=True)


def test_the_machine_panel_draws_the_elastic_drive_and_the_load_step(page: Page) -> None:
    page.click("button[data-panel=machine]")
    page.click("#mac-more-elastic_drive summary")
    page.click("#mac-more-regulation summary")
    page.fill("[id='mac-elastic_drive.stiffness_Nm_rad']", "2e4")
    page.fill("[id='mac-regulation.load_step_Nm']", "10")
    page.select_option("#mac-alternatives", "false")
    before = page.evaluate("Number(document.body.dataset.machine || 0)")
    page.click("#mac-run")
    page.wait_for_function(f"Number(document.body.dataset.machine || 0) > {before}", timeout=120_000)
    assert not page.is_visible("#mac-problem"), page.text_content("#mac-problem")
    for plot in ("mac-elastic", "mac-regulation-speed", "mac-regulation-torque"):
        assert page.locator(f"#{plot} polyline.curve").count() == 2, plot
    assert "Elastic drive:" in (page.text_content("#mac-around-notes") or "")
    page.screenshot(path=str(SHOTS / "machine-around.png"), full_page=True)
    print(f"screenshot: {SHOTS / 'machine-around.png'}")
