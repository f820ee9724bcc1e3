"""The Machine panel's optimisation in a real browser (Playwright, the system's Chromium, a live server): a form of
the request's fields as the manual describes them, the machine it shows is the service's own answer, asked here
directly, a point of the Pareto scatter opens that member's design, and a long optimisation can be cancelled."""

from __future__ import annotations

import json
import re
from collections.abc import Iterator

import httpx
import pytest
from playwright.sync_api import Browser, Page, Route

from test_workbench import SHOTS, base_url, browser, open_page  # noqa: F401  (the service and the browser, per module)
from test_workbench_fields import _leaves, check_rows, panel_rows

# The request's tables of objects, left to the API's defaults by the form (a client sends them as JSON).
TABLES = ["friction", "drive.motor_catalogue", "balancing.counterweight_links", "balancing.max_radius_m",
          "balancing.rotor_ratios", "prices.motors"]
FUNCTIONS = {"crank_rocker": "CrankRockerFunctionIn", "slider_crank": "SliderCrankFunctionIn"}


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
    with page.expect_request("**/v1/machines/optimise") as sent:
        page.click("#opt-run")
    body = sent.value.post_data_json
    # the form starts from the manual's press (MachineOptimiseIn's second example), its Pareto set changed
    example = httpx.get(f"{base_url}/openapi.json").json()["components"]["schemas"]["MachineOptimiseIn"]["examples"][1]
    assert body == {**example, "pareto": ["added_mass", "rms_shaking_force"]}
    _wait(page, "optimised")
    direct = httpx.post(f"{base_url}/v1/machines/optimise", json=body, timeout=120).json()
    heading = page.text_content("#opt-result h3") or ""
    assert f"motor {direct['design']['drive']['motor']['name']}" in heading
    assert f"{direct['parameter']:.5g}" in heading
    rows = page.locator("#opt-gains tr")
    assert rows.count() == 1 + len(direct["gains"]) == 6
    # every objective named in words with its unit, the cost in the prices' currency
    shown = {r[0]: r[3] for r in page.eval_on_selector_all("#opt-gains tr", "rs => rs.slice(1).map(r => "
                                                             "[...r.cells].map(c => c.textContent))")}
    assert shown == {"motor power": "W", "added mass": "kg", "RMS shaking force": "N", "machine mass": "kg",
                     "cost": "currency"}
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


def test_every_field_of_the_request_is_a_widget_with_its_unit(page: Page, base_url: str) -> None:
    schemas = httpx.get(f"{base_url}/openapi.json").json()["components"]["schemas"]
    page.click("button[data-panel=machine]")
    # no raw JSON: every field a widget, no label in snake_case
    assert page.locator("#panel-optimise textarea").count() == 0
    labels = page.eval_on_selector_all("#panel-optimise label", "ls => ls.map(l => l.textContent)")
    assert labels and not [t for t in labels if re.search(r"\b[a-z]+_[a-z]+", t)], labels
    rest = [leaf for leaf in _leaves("MachineOptimiseIn", ["function", *TABLES], schemas)]
    for kind, model in FUNCTIONS.items():
        page.select_option("[id='opt-function.type']", kind)
        own = [(f"function.{p}", shapes, prop) for p, shapes, prop in _leaves(model, ["type"], schemas)]
        missing, wrong = check_rows(panel_rows(page, "#panel-optimise"), rest + own)
        assert not missing, f"{kind}: fields with no widget: {missing}"
        assert not wrong, f"{kind}: {wrong}"
    # every number typed has its unit beside it (– for a pure number)
    units = page.eval_on_selector_all("#panel-optimise .row input", "is => is.map(i => [i.id, "
                                      "i.closest('.row').querySelector('.unit').textContent])")
    assert units and not [u for u in units if not u[1].strip()], units
    page.locator("#panel-optimise").screenshot(path=str(SHOTS / "optimise-form.png"))


def test_a_field_that_is_no_number_and_a_value_the_service_refuses_are_named_at_their_field(page: Page) -> None:
    page.click("button[data-panel=machine]")
    page.fill("[id='opt-speed_rpm']", "fast")
    page.click("#opt-run")
    _wait(page, "problem")
    assert page.inner_text("[id='opt-speed_rpm-msg']") == "enter a number"
    first = page.evaluate("document.body.dataset.optimise")
    # a swing of 200° is outside (0, 180): the service's 422 names the function's field, shown beside it
    page.select_option("[id='opt-function.type']", "crank_rocker")
    page.fill("[id='opt-speed_rpm']", "120")
    page.fill("[id='opt-function.swing_deg']", "200")
    page.click("#opt-run")
    _wait(page, "problem", after=first)
    msg = page.locator("[id='opt-function.swing_deg-msg']")
    assert msg.is_visible() and "180" in msg.inner_text()
    assert page.get_attribute("[id='opt-function.swing_deg']", "aria-invalid") == "true"


def test_lengths_and_masses_follow_the_forms_units(page: Page) -> None:
    page.click("button[data-panel=machine]")
    stroke = page.locator("[id='opt-function.stroke_m']")
    assert stroke.input_value() == "120"                      # the manual's press: 0.12 m, in the form's mm
    page.select_option("#unit-length", "m")
    page.select_option("#unit-mass", "g")
    # the same values in the new units: 0.12 m, the slider's 8 kg as 8000 g
    assert stroke.input_value() == "0.12"
    assert page.locator("[id='opt-function.slider_mass_kg']").input_value() == "8000"
    row = stroke.locator("xpath=ancestor::div[contains(@class, 'row')]")
    assert row.locator(".unit").inner_text() == "m"
    with page.expect_request("**/v1/machines/optimise") as sent:
        page.click("#opt-run")
    body = sent.value.post_data_json
    # the wire stays SI
    assert body["function"]["stroke_m"] == pytest.approx(0.12, rel=1e-12)
    assert body["function"]["slider_mass_kg"] == pytest.approx(8, rel=1e-12)
    _wait(page, "optimised")


def test_a_long_optimisation_shows_its_progress_and_is_cancelled(page: Page) -> None:
    page.click("button[data-panel=machine]")
    # the request held unanswered: a service busier than anyone waits, however fast this machine optimises
    held: list[Route] = []
    page.route("**/v1/machines/optimise", lambda route: held.append(route))
    page.click("#opt-run")
    page.wait_for_selector("#opt-progress progress", timeout=5_000)
    assert page.is_disabled("#opt-run")
    page.wait_for_function("/optimising… [1-9]\\d* s/.test(document.getElementById('opt-elapsed').textContent)",
                           timeout=10_000)
    assert len(held) == 1
    page.click("#opt-cancel")
    _wait(page, "cancelled")
    assert page.locator("#opt-progress").count() == 0 and page.is_enabled("#opt-run")
    assert page.inner_text("#opt-result").strip() == ""
    assert "cancelled" in page.inner_text("#opt-status")
    page.unroute("**/v1/machines/optimise")
