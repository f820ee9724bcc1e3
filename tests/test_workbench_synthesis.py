"""The Synthesis panel in a real browser (Playwright, the system's Chromium, a live server): an answer belongs to its
task, and goes when another task is chosen."""

from __future__ import annotations

from collections.abc import Iterator

import httpx
import numpy as np
import pytest
from playwright.sync_api import Page

from test_workbench import CURVES, SHOTS, base_url, browser, open_page  # noqa: F401  (the service and the browser, per module)


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


def _four(v: float) -> str:
    """A number as the page writes it (plot.js fmt: four significant digits, exponent outside 1e-3..1e5)."""
    return f"{v:.2e}".replace("e-0", "e-").replace("e+0", "e+") if not 1e-3 <= abs(v) < 1e5 else f"{float(f'{v:.4g}'):g}"


def _joint(page: Page, name: str) -> np.ndarray:
    """A joint of the panel's drawing where it is drawn [m] (the SVG's y points down)."""
    c = page.locator(f"#syn-drawing .joint[data-joint={name}]")
    return np.array([float(c.get_attribute("cx") or "nan"), -float(c.get_attribute("cy") or "nan")])


def _region(page: Page) -> dict[str, float]:
    """The pivot region drawn in the panel's drawing, read back from the box's corners [m]."""
    r = page.locator("#syn-drawing rect.region")
    x, y, w, h = (float(r.get_attribute(k) or "nan") for k in ("x", "y", "width", "height"))
    return {"x_min_m": x, "x_max_m": x + w, "y_min_m": -(y + h), "y_max_m": -y}


def _played(page: Page) -> None:
    """Play turns the crank: the frame drawn moves on, and Pause holds it."""
    page.click("#syn-play")
    page.wait_for_function("Number(document.getElementById('syn-drawing').dataset.frame) > 5", timeout=10_000)
    page.click("#syn-play")
    assert page.get_attribute("#syn-play", "aria-pressed") == "false"


def test_a_crank_rocker_in_a_pivot_region_is_drawn_in_it_and_turns(page: Page, base_url: str) -> None:
    page.click("button[data-panel=synthesis]")
    # the region in the form's unit (mm): its upper edge below where the unbounded answer puts the crank pivot
    for edge, mm in {"x_min_m": "0", "x_max_m": "200", "y_min_m": "-200", "y_max_m": "80"}.items():
        page.fill(f"[id='syn-crank_pivot_region_m.{edge}']", mm)
    page.fill("[id='syn-max_m']", "300")
    assert not page.is_visible("#synth-canvas") and not page.is_visible("[id='syn-pivot_box_m.x_min_m']")
    with page.expect_request("**/v1/synthesis/crank-rocker") as sent:
        page.click("#syn-run")
    page.wait_for_function("document.body.dataset.synDrawn === 'crank-rocker-0'", timeout=60_000)
    body = sent.value.post_data_json
    region = {"x_min_m": 0.0, "x_max_m": 0.2, "y_min_m": -0.2, "y_max_m": 0.08}
    assert body["crank_pivot_region_m"] == pytest.approx(region, abs=1e-15)
    assert body["bounds_m"] == {k: {"max_m": pytest.approx(0.3, rel=1e-12)} for k in ("crank", "coupler", "rocker", "ground")}
    # the answer drawn is the service's for that request, asked here directly
    direct = httpx.post(f"{base_url}/v1/synthesis/crank-rocker", json=body, timeout=60).json()
    pivot = np.array(direct["crank_pivot_m"])
    # the region bites: the unbounded answer's pivot sits at y ≈ 120 mm, this one on the region's upper edge
    assert direct["optimality"]["binding_constraint"] == "pivot_y_max" and pivot[1] == pytest.approx(0.08, abs=1e-9)
    # drawn in the region's frame: the rocker pivot at the origin, the crank pivot where the answer puts it,
    # inside the box drawn from the fields (to the drawing's 7 significant digits)
    assert _region(page) == pytest.approx(region, abs=1e-9)
    assert np.allclose(_joint(page, "Q"), [0, 0], atol=CURVES)
    assert np.allclose(_joint(page, "O"), pivot, atol=CURVES)
    mech = direct["mechanism"]
    for name, other, length in (("O", "A", mech["crank_length_m"]), ("A", "B", mech["coupler_length_m"]),
                                ("Q", "B", mech["rocker_length_m"]), ("O", "Q", mech["ground_length_m"])):
        # every link drawn at its length (the analysis' positions, turned into the region's frame)
        assert float(np.hypot(*(_joint(page, name) - _joint(page, other)))) == pytest.approx(length, rel=1e-6)
    assert page.locator("#syn-drawing line.link").count() == 3
    a0 = _joint(page, "A")
    _played(page)
    a1 = _joint(page, "A")
    assert float(np.hypot(*(a1 - a0))) > 0.1 * mech["crank_length_m"]
    assert float(np.hypot(*(a1 - pivot))) == pytest.approx(mech["crank_length_m"], rel=1e-6)
    page.locator("#panel-synthesis").screenshot(path=str(SHOTS / "synthesis-crank-rocker.png"))


def test_path_fits_and_cognates_are_listed_and_a_click_draws_the_one_chosen(page: Page, base_url: str) -> None:
    page.click("button[data-panel=synthesis]")
    page.select_option("#syn-task", "path")
    # the manual's path example (PathIn's first example), typed point by point in mm
    api = httpx.get(f"{base_url}/openapi.json").json()
    targets = api["components"]["schemas"]["PathIn"]["examples"][0]["points_m"]
    for x, y in targets:
        page.fill("[id='syn-px']", f"{x * 1e3:.4f}")
        page.fill("[id='syn-py']", f"{y * 1e3:.4f}")
        page.click("#syn-add")
    box = {"x_min_m": 0.05, "x_max_m": 0.35, "y_min_m": -0.1, "y_max_m": 0.1}
    for edge, v in box.items():
        page.fill(f"[id='syn-pivot_box_m.{edge}']", f"{v * 1e3:g}")
    page.fill("[id='syn-max_m']", "250")
    # the box is drawn on the points' grid as it is typed
    assert page.locator("#synth-canvas rect.region").count() == 1
    with page.expect_request("**/v1/synthesis/path") as sent:
        page.click("#syn-run")
    page.wait_for_function("document.body.dataset.synDrawn === 'path-0'", timeout=60_000)
    body = sent.value.post_data_json
    assert body["pivot_box_m"] == pytest.approx(box, abs=1e-15)
    direct = httpx.post(f"{base_url}/v1/synthesis/path", json=body, timeout=60).json()
    designs = direct["fits"] + direct["cognates"]
    rows = page.locator("#syn-fit-table tr[data-fit]")
    assert rows.count() == len(designs) >= 2
    for k, f in enumerate(designs):
        cells = rows.nth(k).locator("td")
        # each row: the service's residual (in mm, 4 digits), Grashof class and transmission angle
        assert cells.nth(1).inner_text() == f"{_four(f['max_residual_m'] * 1e3)} mm"
        assert cells.nth(3).inner_text() == f["grashof"]
        ta = f["transmission_angle"]
        assert cells.nth(4).inner_text() == (f"{_four(ta['min_deg'])}° … {_four(ta['max_deg'])}°" if ta else "–")
    assert _region(page) == pytest.approx(box, abs=1e-9)

    def pivots(f: dict) -> tuple[np.ndarray, np.ndarray]:
        t = np.radians(f["ground_angle_deg"])
        o = np.array(f["crank_pivot_m"])
        return o, o + f["mechanism"]["ground_length_m"] * np.array([np.cos(t), np.sin(t)])

    for k, f in enumerate(designs):
        if k:
            rows.nth(k).click()
            page.wait_for_function(f"document.body.dataset.synDrawn === 'path-{k}'", timeout=30_000)
        o, q = pivots(f)
        # the design chosen is the one drawn: its ground pivots where the service puts them, in the targets'
        # frame, and both within the box (IPOPT's bound tolerance, 1e-8 m)
        assert np.allclose(_joint(page, "O"), o, atol=CURVES) and np.allclose(_joint(page, "Q"), q, atol=CURVES)
        for p in (o, q):
            assert box["x_min_m"] - 1e-8 <= p[0] <= box["x_max_m"] + 1e-8
            assert box["y_min_m"] - 1e-8 <= p[1] <= box["y_max_m"] + 1e-8
        assert page.get_attribute(f"#syn-fit-table tr[data-fit='{k}']", "aria-selected") == "true"
    _played(page)
    page.locator("#panel-synthesis").screenshot(path=str(SHOTS / "synthesis-path.png"))
    # the design opened in the editor is the one chosen
    page.click("#syn-open")
    page.wait_for_function("document.body.dataset.panel === 'mechanism'")
    opened = page.evaluate("JSON.parse(JSON.stringify(window.workbench.state.design.mechanism))")
    assert opened == designs[-1]["mechanism"]


def test_a_slider_crank_is_drawn_with_its_slider_on_its_guide(page: Page, base_url: str) -> None:
    page.click("button[data-panel=synthesis]")
    page.select_option("#syn-task", "slider-crank")
    page.fill("[id='syn-max_length_ratio']", "3")
    with page.expect_request("**/v1/synthesis/slider-crank") as sent:
        page.click("#syn-run")
    page.wait_for_function("document.body.dataset.synDrawn === 'slider-crank-0'", timeout=60_000)
    body = sent.value.post_data_json
    assert body["max_length_ratio"] == 3 and body["stroke_m"] == pytest.approx(0.1, rel=1e-12)
    direct = httpx.post(f"{base_url}/v1/synthesis/slider-crank", json=body, timeout=60).json()
    mech = direct["mechanism"]
    assert page.locator("#syn-drawing rect.slider").count() == 1
    assert page.locator("#syn-drawing line.link").count() == 2
    # crank and rod drawn at the answer's lengths; the slider's pin at the offset from the crank pivot's line
    o, a, b = (_joint(page, n) for n in "OAB")
    assert float(np.hypot(*(a - o))) == pytest.approx(mech["crank_length_m"], rel=1e-6)
    assert float(np.hypot(*(b - a))) == pytest.approx(mech["rod_length_m"], rel=1e-6)
    _played(page)
    assert abs(_joint(page, "B")[1] - b[1]) < CURVES   # the slider stays on its guide
    page.locator("#panel-synthesis").screenshot(path=str(SHOTS / "synthesis-slider-crank.png"))
