"""The Machine panel's optimisation in a real browser (Playwright, the system's Chromium, a live server): the
machine it shows is the service's own answer, asked here directly, and a point of the Pareto scatter opens that
member's design."""

from __future__ import annotations

import json
from collections.abc import Iterator

import httpx
import pytest
from playwright.sync_api import Browser, Page

from test_workbench import SHOTS, base_url, browser, open_page  # noqa: F401  (the service and the browser, per module)


@pytest.fixture
def page(browser: Browser, base_url: str) -> Iterator[Page]:
    yield from open_page(browser, base_url, "[data-optimise-ready='1']")


def _wait(page: Page, kind: str, after: str = "") -> None:
    """The panel's next outcome is ``kind`` (the body's data-optimise is kind-N, N counting the outcomes); with
    ``after``, an outcome other than that one (the same kind may come twice in a row)."""
    page.wait_for_function(f"(document.body.dataset.optimise || '').startsWith({json.dumps(kind)}) && "
                           f"document.body.dataset.optimise !== {json.dumps(after)}", timeout=120_000)


def test_the_optimised_machine_is_the_services_and_a_point_opens_its_design(page: Page, base_url: str) -> None:
    assert not page.is_visible("#panel-optimise")
    page.click("button[data-panel=machine]")
    assert page.is_visible("#panel-optimise")
    body = json.loads(page.input_value("#opt-json"))
    assert body["function"]["type"] == "slider_crank"  # the manual's press
    assert body["pareto"] == ["added_mass", "rms_shaking_force"]
    page.click("#opt-run")
    _wait(page, "optimised")
    direct = httpx.post(f"{base_url}/v1/machines/optimise", json=body, timeout=120).json()
    heading = page.text_content("#opt-result h3") or ""
    assert f"motor {direct['design']['drive']['motor']['name']}" in heading
    assert f"{direct['parameter']:.5g}" in heading
    rows = page.locator("#opt-gains tr")
    assert rows.count() == 1 + len(direct["gains"]) == 6
    # one point per feasible member with both Pareto figures, the optimum among them
    feasible = [m for m in direct["members"] if m["feasible"]]
    points = page.locator("#opt-scatter circle.opt-point")
    assert points.count() == len(feasible)
    assert page.locator(f"#opt-scatter circle[data-parameter='{direct['parameter']}']").count() == 1
    assert "no gap bound" in (page.text_content("#opt-certificate") or "")
    c = direct["certificate"]
    assert (f"{c['cells_found']} cells between scanned members: {c['cells_searched']} searched, "
            f"{c['cells_pruned']} pruned") in (page.text_content("#opt-cells") or "")
    # a point other than the optimum opens its own design
    other = next(m for m in feasible if m["parameter"] != direct["parameter"])
    page.locator(f"#opt-scatter circle[data-parameter='{other['parameter']}']").dispatch_event("click")
    _wait(page, "member")
    shown = page.locator("#opt-member-design")
    assert shown.get_attribute("data-parameter") == str(other["parameter"])
    assert other["motor"] in (shown.text_content() or "")
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.locator("#panel-optimise").screenshot(path=str(SHOTS / "optimise.png"))
    print(f"screenshot: {SHOTS / 'optimise.png'}")


def test_a_request_that_is_not_json_is_named(page: Page) -> None:
    page.click("button[data-panel=machine]")
    page.fill("#opt-json", "{ not json")
    page.click("#opt-run")
    _wait(page, "problem")
    assert "not a JSON object" in (page.text_content("#opt-problem") or "")
    first = page.evaluate("document.body.dataset.optimise")
    page.fill("#opt-json", json.dumps({"function": {"type": "slider_crank"}}))
    page.click("#opt-run")
    _wait(page, "problem", after=first)
    assert "function" in (page.text_content("#opt-problem") or "")
