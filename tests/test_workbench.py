"""The workbench at / in a real browser: Playwright driving the system's Chromium against a live server.

One server and one browser for the module. Every number the tests check comes from the service itself, asked
directly over HTTP by the test (an independent path past the page), or from what the test typed or clicked.
Each test saves a screenshot of its panel to a scratch directory (``WORKBENCH_SCREENSHOTS`` to choose it).
"""

from __future__ import annotations

import json
import math
import os
import re
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any
from urllib.parse import quote

import httpx
import numpy as np
import pytest
from playwright.sync_api import Browser, Page, expect, sync_playwright
from service import running_service

REPO = Path(__file__).resolve().parents[1]
CHROMIUM = "/usr/bin/chromium"
# The page holds the service's default JSON answers, whose curves are written at one quantum per array (each value
# within 5e-8 of its array's largest magnitude: a position in a curve reaching 0.5 m within 2.5e-8 m); 1e-6 of the
# scale leaves room for the page's own arithmetic on them.
CURVES = 1e-6
# Playwright's own browser download is not reachable: the system's Chromium, headless and quiet on the network.
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync"]
SHOTS = Path(os.environ.get("WORKBENCH_SCREENSHOTS") or tempfile.mkdtemp(prefix="workbench-screens-"))


@pytest.fixture(scope="module")
def base_url(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    command = lambda port: [sys.executable, "-m", "uvicorn", "api.app:app", "--host", "127.0.0.1",  # noqa: E731
                            "--port", str(port)]
    with running_service(command, tmp_path_factory.mktemp("studies"), start_timeout_s=60) as url:
        yield url


@pytest.fixture(scope="module")
def browser() -> Iterator[Browser]:
    # Never a skip: `make test` installs Chromium when it is missing, so its absence is a failure to see.
    assert Path(CHROMIUM).exists(), f"{CHROMIUM} is missing: `make test` installs it (apt-get install chromium)"
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        yield b
        b.close()


def open_page(browser: Browser, base_url: str, ready: str = "", *, bypass_csp: bool = True) -> Iterator[Page]:
    """A fresh page of the workbench, once the page (and ``ready``, a further attribute selector of the body such as
    ``[data-cam-ready='1']``) says it is ready; any script error on it fails the test that used it.

    Playwright's wait_for_function evaluates its predicate with eval, which the service's Content-Security-Policy
    forbids: tests run with the policy bypassed, except those about the policy (test_workbench_security.py checks
    the page under the service's own header)."""
    context = browser.new_context(viewport={"width": 1400, "height": 1000}, accept_downloads=True,
                                  bypass_csp=bypass_csp)
    pg = context.new_page()
    errors: list[str] = []
    pg.on("pageerror", lambda e: errors.append(str(e)))
    pg.goto(base_url + "/")
    pg.wait_for_selector(f"body[data-ready='1']{ready}", timeout=30_000)
    yield pg
    context.close()
    assert not errors, errors


@pytest.fixture
def page(browser: Browser, base_url: str, request: pytest.FixtureRequest) -> Iterator[Page]:
    yield from open_page(browser, base_url, bypass_csp="policy" not in request.node.name)


def _shot(page: Page, name: str) -> None:
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(SHOTS / f"{name}.png"), full_page=True)
    print(f"screenshot: {SHOTS / name}.png")


def field(page: Page, path: str) -> Any:
    return page.locator(f"[id='f-{path}']")


def edit_and_wait(page: Page, path: str, value: str, outcome: str = "analysed") -> None:
    """Type ``value`` into a form field and wait for the page's next answer (``analysed``) or problem."""
    before = page.evaluate(f"document.body.dataset.{outcome} || ''")
    field(page, path).fill(value)
    page.wait_for_function(f"(document.body.dataset.{outcome} || '') !== {json.dumps(before)}", timeout=15_000)


def state(page: Page, expr: str) -> Any:
    return page.evaluate(f"JSON.parse(JSON.stringify(window.workbench.state.{expr}))")


def test_crank_length_edit_redraws_drawing_and_torque(page: Page, base_url: str) -> None:
    torque_before = page.get_attribute("#plot-torque polyline[data-series='kinetostatic']", "points")
    circle_before = float(page.get_attribute("#drawing .crank-circle", "r") or "nan")
    crank_before = state(page, "design.mechanism.crank_length_m")   # the manual's example four-bar
    edit_and_wait(page, "mechanism.crank_length_m", "120")          # the form is in mm
    _shot(page, "mechanism")
    design = state(page, "design")
    # 120 mm typed: the request carries 0.12 m (SI at the API).
    assert design["mechanism"]["crank_length_m"] == pytest.approx(0.12, rel=1e-12)
    # The drawing is in metres: the crank circle's radius is |OA| from the new answer, the typed length (to the
    # answer's quantum, 5e-8 of the largest coordinate of the curve).
    circle_after = float(page.get_attribute("#drawing .crank-circle", "r") or "nan")
    assert circle_before == pytest.approx(crank_before, rel=1e-6) and circle_after == pytest.approx(0.12, rel=1e-6)
    torque_after = page.get_attribute("#plot-torque polyline[data-series='kinetostatic']", "points")
    assert torque_after != torque_before
    # The torque drawn is the service's: the same request posted by the test gives the same peak torque.
    direct = httpx.post(f"{base_url}/v1/analysis", json=design, timeout=30).json()
    shown = state(page, "answer.driving_torque_Nm")
    assert np.allclose(shown, direct["driving_torque_Nm"], rtol=1e-12, atol=1e-12)
    # The curve's vertical extent on screen spans the answer's torque range (plot padding 5 % each side).
    box = page.locator("#plot-torque")
    lo, hi = float(box.get_attribute("data-ymin") or "nan"), float(box.get_attribute("data-ymax") or "nan")
    t = np.asarray(direct["driving_torque_Nm"])
    pad = 0.05 * (t.max() - t.min())
    assert lo == pytest.approx(t.min() - pad, rel=1e-9) and hi == pytest.approx(t.max() + pad, rel=1e-9)


def test_units_of_the_form_are_chosen_and_the_api_stays_si(page: Page) -> None:
    page.select_option("#unit-length", "m")
    page.select_option("#unit-mass", "g")
    # The same design read in the other units: 100 mm is 0.1 m, 1 kg is 1000 g.
    assert float(field(page, "mechanism.crank_length_m").input_value()) == pytest.approx(0.1, rel=1e-12)
    assert float(field(page, "mechanism.links.crank.mass_kg").input_value()) == pytest.approx(1000, rel=1e-12)
    edit_and_wait(page, "mechanism.links.crank.mass_kg", "1500")
    edit_and_wait(page, "mechanism.crank_length_m", "0.11")
    assert state(page, "design.mechanism.links.crank.mass_kg") == pytest.approx(1.5, rel=1e-12)
    assert state(page, "design.mechanism.crank_length_m") == pytest.approx(0.11, rel=1e-12)
    assert "units=m,g" in page.url
    # a choice among values (the assembly branch, +1 or -1) has no unit beside it
    assert page.inner_text(".row[data-path='mechanism.branch'] .unit") == ""


def test_dragging_joint_a_changes_the_crank_length(page: Page) -> None:
    joint = page.locator("#drawing .joint[data-joint=A]").bounding_box()
    origin = page.locator("#drawing .joint[data-joint=O]").bounding_box()
    assert joint is not None and origin is not None
    ax, ay = joint["x"] + joint["width"] / 2, joint["y"] + joint["height"] / 2
    ox, oy = origin["x"] + origin["width"] / 2, origin["y"] + origin["height"] / 2
    before = page.evaluate("document.body.dataset.analysed")
    page.mouse.move(ax, ay)
    page.mouse.down()
    # A dragged along O->A to 1.3 times its distance from O on screen: the crank 1.3 times as long.
    for k in range(1, 7):
        page.mouse.move(ox + (ax - ox) * (1 + 0.05 * k), oy + (ay - oy) * (1 + 0.05 * k))
    page.mouse.up()
    page.wait_for_function(f"document.body.dataset.analysed !== '{before}' && window.workbench.state.pending === null")
    # 0.1 m before; the screen's pixel grid and the page's 4-digit rounding of a dragged length allow 1 %.
    assert state(page, "design.mechanism.crank_length_m") == pytest.approx(0.13, rel=0.01)
    assert float(field(page, "mechanism.crank_length_m").input_value()) == pytest.approx(130, rel=0.01)


def test_a_general_linkage_from_the_manual_is_edited_as_json_and_drawn(page: Page) -> None:
    before = page.evaluate("document.body.dataset.analysed")
    page.select_option("#family", "linkage")
    page.wait_for_function(f"document.body.dataset.analysed !== '{before}'", timeout=15_000)
    _shot(page, "linkage")
    mech = state(page, "design.mechanism")
    assert mech["type"] == "linkage"
    # Every link of the description is drawn: a bar between two points, a plate through more, a block on one.
    drawn = page.evaluate("[...document.querySelectorAll('#drawing title')].map(t => t.textContent)")
    assert {link["name"] for link in mech["links"]} <= set(drawn)
    # The JSON in the form is the mechanism sent; a changed crank length in it is analysed again.
    text = json.loads(field(page, "mechanism").input_value())
    assert text == mech
    crank = next(link for link in text["links"] if link["name"] == text["crank"])
    crank["length_m"] = round(crank["length_m"] * 1.1, 6)
    edit_and_wait(page, "mechanism", json.dumps(text))
    drawn_crank = state(page, "answer.points")
    a, o = (np.asarray(drawn_crank[n]["position_m"][0]) for n in crank["joints"][::-1])
    # the crank's two joints now lie the new length apart (the answer's positions, to their curves' quanta)
    assert float(np.hypot(*(a - o))) == pytest.approx(crank["length_m"], rel=1e-6)


def test_full_balancing_collapses_the_polar_curve_to_the_origin(page: Page) -> None:
    page.click("button[data-panel=balancing]")
    page.select_option("[id='bal-mode']", "full")
    page.click("#bal-run")
    page.wait_for_selector("#bal-polar", timeout=30_000)
    _shot(page, "balancing")
    polar = page.locator("#bal-polar")
    before = float(polar.get_attribute("data-before-radius") or "nan")
    after = float(polar.get_attribute("data-after-radius") or "nan")
    # Full balance: the shaking force vanishes identically; what is left is round-off of the re-analysis.
    assert before > 100 and after < 1e-9 * before
    # On screen, every point of the "after" curve sits on the origin (within a tenth of a drawing unit).
    origin = page.eval_on_selector("#bal-polar svg > circle[r='2.5']", "c => [c.cx.baseVal.value, c.cy.baseVal.value]")
    pts = page.get_attribute("#bal-polar polygon[data-series='after']", "points") or ""
    xy = np.array([[float(v) for v in p.split(",")] for p in pts.split()])
    assert len(xy) == len(state(page, "answer.crank_angle_deg")) and np.abs(xy - origin).max() < 0.1
    # Put on the design, the counterweights are drawn and the editor's answer has no shaking force left.
    page.click("#bal-apply")
    page.wait_for_function("document.querySelectorAll('#drawing .cw').length === 2", timeout=15_000)
    page.wait_for_function("window.workbench.state.answer.summary.max_shaking_force_N < 1e-6", timeout=15_000)
    # The balanced linkage's force and moment are rounding (1e-13): read as zero, on axes that do not blow the
    # noise up to fill the plot (at least a thousandth of the linkage's own force scale Σm·ω²·size wide).
    design, lay = state(page, "design"), state(page, "layout")
    w = design["speed_rpm"] * math.pi / 30
    masses = sum(v["mass_kg"] for v in design["mechanism"]["links"].values()) + sum(
        c["mass_kg"] for c in design["counterweights"])
    f_scale = masses * w * w * lay["span"]
    radius = float(page.get_attribute("#plot-polar", "data-axis-radius") or "nan")
    moment_top = float(page.get_attribute("#plot-moment", "data-ymax") or "nan")
    assert radius == pytest.approx(1e-3 * f_scale, rel=1e-9) and radius > 1e6 * after
    assert moment_top == pytest.approx(1e-3 * f_scale * lay["span"], rel=1e-9)
    for plot in ("#plot-polar", "#plot-moment"):
        assert page.get_attribute(plot, "data-zero") == "true"
        assert page.locator(f"{plot} .zero-note").text_content().startswith("≈ 0")
    _shot(page, "balanced-zero")


def test_machine_design_downloads_its_pdf(page: Page) -> None:
    page.click("button[data-panel=machine]")
    page.select_option("[id='mac-alternatives']", "false")     # one design, not four: the record within its deadline
    page.click("#mac-run")
    page.wait_for_selector("#mac-verdict", timeout=60_000)
    _shot(page, "machine")
    rows = page.locator("#mac-result tr.check")
    assert rows.count() >= 4                                     # delta, mean speed, motor RMS and peak torque
    with page.expect_download(timeout=60_000) as dl:
        page.click("#mac-pdf")
    path = dl.value.path()
    data = Path(path).read_bytes()
    assert dl.value.suggested_filename == "design-record.pdf"
    assert data[:5] == b"%PDF-" and len(re.findall(rb"/Type\s*/Page\b", data)) >= 1
    # A run that fails after one that passed: the old verdict and tables go, the record button with them, and the
    # service's message stands next to the field it names.
    runs = page.evaluate("document.body.dataset.machine")
    page.fill("[id='mac-delta']", "0")
    page.click("#mac-run")
    page.wait_for_function(f"document.body.dataset.machine !== '{runs}'", timeout=60_000)
    assert page.locator("#mac-verdict, #mac-result tr.check").count() == 0
    assert page.locator("#mac-pdf").is_disabled()
    msg = page.locator("[id='mac-delta-msg']")
    assert msg.is_visible() and "greater than" in msg.inner_text()
    _shot(page, "machine-failed")
    # The less common fields, folded away: two stages with a ratio range each, a run-up that must take 10 ms. The
    # request carries them; the answer's one list of checks holds the failed start-up, and the verdict says so.
    page.fill("[id='mac-delta']", "0.02")
    page.select_option("[id='mac-stage-count']", "2")
    page.fill("[id='mac-drive.stages.1.ratio_min']", "2")
    page.fill("[id='mac-drive.stages.1.ratio_max']", "4")
    page.click("#panel-machine details.more:has-text('Start-up') summary")
    page.fill("[id='mac-max_startup_time_s']", "0.01")
    runs = page.evaluate("document.body.dataset.machine")
    with page.expect_request("**/v1/machines/design") as sent:
        page.click("#mac-run")
    page.wait_for_function(f"document.body.dataset.machine !== '{runs}'", timeout=90_000)
    body = sent.value.post_data_json
    assert body["max_startup_time_s"] == 0.01 and len(body["drive"]["stages"]) == 2
    assert body["drive"]["stages"][1] == {"type": "helical", "ratio_min": 2, "ratio_max": 4}
    failed = page.locator("#mac-result tr.check[data-passed='false']")
    assert failed.count() == 1 and failed.get_attribute("data-name") == "startup_time"
    assert "✘" in page.locator("#mac-verdict").inner_text() and page.locator("#mac-result tr.check").count() >= 5
    page.locator("#panel-machine").screenshot(path=str(SHOTS / "machine-panel.png"))


def test_study_reaches_100_percent_and_a_pareto_point_opens_its_variant(page: Page, base_url: str) -> None:
    page.click("button[data-panel=studies]")
    for n in (0, 1):
        page.fill(f"[id='stu-p{n}.count']", "3")
    page.click("#stu-run")
    page.wait_for_function("document.getElementById('stu-status').dataset.percent === '100'", timeout=60_000)
    page.wait_for_selector("#stu-pareto circle[data-front='true']", timeout=30_000)
    _shot(page, "studies")
    assert page.get_attribute("#stu-progress", "value") == page.get_attribute("#stu-progress", "max") == "9"
    point = page.locator("#stu-pareto circle[data-front='true']").first
    index = int(point.get_attribute("data-variant") or "-1")
    point.click()
    page.wait_for_function(f"document.body.dataset.openedVariant === '{index}'", timeout=15_000)
    page.wait_for_function("window.workbench.state.pending === null", timeout=15_000)
    # The variant's parameters, as the service stores them, are now the editor's design.
    studies = httpx.get(f"{base_url}/v1/studies", timeout=10).json()
    results = httpx.get(f"{base_url}{studies[0]['links']['results']}", timeout=10).json()
    variant = next(v for v in results["variants"] if v["index"] == index)
    design = state(page, "design")
    for path, value in variant["parameters"].items():
        got: Any = design
        for part in path.split("."):
            got = got[int(part)] if isinstance(got, list) else got[part]
        assert got == pytest.approx(value, rel=1e-12), path
    # and the form shows the crank length in its unit (mm)
    crank = variant["parameters"]["mechanism.crank_length_m"]
    assert float(field(page, "mechanism.crank_length_m").input_value()) == pytest.approx(crank * 1000, rel=1e-9)


def _distance_to_polyline(p: np.ndarray, curve: np.ndarray) -> float:
    a, b = curve, np.roll(curve, -1, axis=0)
    ab = b - a
    t = np.clip(((p - a) * ab).sum(axis=1) / np.maximum((ab * ab).sum(axis=1), 1e-30), 0, 1)
    return float(np.min(np.hypot(*(a + t[:, None] * ab - p).T)))


def test_clicked_path_points_yield_a_linkage_whose_coupler_curve_passes_near_them(page: Page, base_url: str) -> None:
    page.click("button[data-panel=synthesis]")
    page.select_option("[id='syn-task']", "path")
    page.locator("#synth-canvas").scroll_into_view_if_needed()   # whole in the window, so every click lands on it
    box = page.locator("#synth-canvas").bounding_box()
    assert box is not None
    for k in range(7):
        a = 2 * math.pi * k / 7
        page.mouse.click(box["x"] + box["width"] * (0.45 + 0.12 * math.cos(a)),
                         box["y"] + box["height"] * (0.5 + 0.28 * math.sin(a)))
    targets = np.array(json.loads(page.get_attribute("#synth-canvas", "data-points") or "[]"))
    assert targets.shape == (7, 2)
    page.click("#syn-run")
    page.wait_for_selector("body[data-synthesised='path']", timeout=60_000)
    _shot(page, "synthesis")
    page.click("#syn-open")
    page.wait_for_function("window.workbench.state.answer && window.workbench.state.answer.points.P", timeout=15_000)
    page.wait_for_function("window.workbench.state.pending === null", timeout=15_000)
    _shot(page, "synthesis-in-editor")
    # The same points posted by the test: where the answer's frame sits among the targets.
    syn = httpx.post(f"{base_url}/v1/synthesis/path", json={"points_m": targets.tolist(), "starts": 16, "seed": 1},
                     timeout=60).json()
    shown = state(page, "design.mechanism")
    for name in ("ground_length_m", "crank_length_m", "coupler_length_m", "rocker_length_m"):
        assert shown[name] == pytest.approx(syn["mechanism"][name], rel=1e-9), name
    # The editor's analysis of that linkage (360 samples), its coupler curve moved into the targets' frame.
    curve = np.asarray(state(page, "answer.points.P.position_m"))
    th = math.radians(syn["ground_angle_deg"])
    rot = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
    curve = curve @ rot.T + np.asarray(syn["crank_pivot_m"])
    scale = float(np.ptp(targets, axis=0).max())
    for p in targets:
        # Near: within 1 % of the targets' spread, or the synthesis' own residual if larger.
        assert _distance_to_polyline(p, curve) < max(0.01 * scale, 2 * syn["max_residual_m"]), p


def test_a_bad_value_shows_its_message_next_to_its_field(page: Page) -> None:
    edit_and_wait(page, "mechanism.crank_length_m", "-5", outcome="problem")
    msg = page.locator("[id='m-mechanism.crank_length_m']")
    assert msg.is_visible()
    # The service's bound (1e-6 m, read from the manual here) said in the form's unit, in the field's own row.
    bound = page.evaluate("fetch('/openapi.json').then(r => r.json()).then(d => "
                          "d.components.schemas.FourBarIn.properties.crank_length_m)")
    low = bound.get("minimum", bound.get("exclusiveMinimum"))
    assert f"{low * 1000:g} mm" in msg.inner_text() and "greater than" not in msg.inner_text()
    assert page.locator(".row[data-path='mechanism.crank_length_m'] [id='m-mechanism.crank_length_m']").count() == 1
    assert field(page, "mechanism.crank_length_m").get_attribute("aria-invalid") == "true"
    _shot(page, "bad-value")
    # A linkage that cannot be built: the engine's reason under the family, where the linkage as a whole is named.
    edit_and_wait(page, "mechanism.crank_length_m", "1000", outcome="problem")
    whole = page.locator("[id='m-mechanism']")
    assert whole.is_visible() and "longest link" in whole.inner_text()
    # One that assembles over part of the turn only: the crank-angle gaps the service names, in the same place.
    edit_and_wait(page, "mechanism.crank_length_m", "100", outcome="analysed")
    edit_and_wait(page, "mechanism.rocker_length_m", "80", outcome="problem")
    assert whole.is_visible() and "cannot be assembled" in whole.inner_text()
    # the gaps as degree ranges a reader writes (one decimal), not a tuple of nine
    assert re.search(r"\d+\.\d°–\d+\.\d°", whole.inner_text()) and "((" not in whole.inner_text()
    # Not a number at all: said at once, without asking the service.
    field(page, "mechanism.coupler_length_m").fill("abc")
    assert page.locator("[id='m-mechanism.coupler_length_m']").inner_text() == '"abc" is not a number'


def _focus_walk(page: Page, presses: int) -> set[str]:
    seen: set[str] = set()
    for _ in range(presses):
        page.keyboard.press("Tab")
        seen.add(page.evaluate("document.activeElement && (document.activeElement.id || document.activeElement.dataset.panel || '')"))
    return seen


def test_keyboard_alone_reaches_every_input(page: Page) -> None:
    for panel in ("mechanism", "balancing", "flywheel", "drive", "machine", "synthesis", "studies"):
        # Open the panel from the keyboard: focus its tab and press Enter.
        page.focus(f"button[data-panel={panel}]")
        page.keyboard.press("Enter")
        page.wait_for_function(f"document.body.dataset.panel === '{panel}'")
        wanted = set(page.evaluate(
            "[...document.querySelectorAll('input, select, button, textarea')]"
            ".filter(e => e.checkVisibility() && !e.disabled).map(e => e.id || e.dataset.panel)"))
        # (a folded <details> is opened from the keyboard on its summary; its fields are not shown until then)
        stops = page.evaluate("[...document.querySelectorAll('summary, [tabindex]')].filter(e => e.checkVisibility()"
                              " && e.tabIndex >= 0).length")
        # From the first control of the page, Tab alone walks through every visible one (and every summary).
        page.focus("button[data-panel=mechanism]")
        seen = {"mechanism"} | _focus_walk(page, len(wanted) + stops + 12)
        assert wanted <= seen, (panel, sorted(wanted - seen))


def test_the_design_travels_as_a_link_and_as_a_file(page: Page, browser: Browser) -> None:
    edit_and_wait(page, "mechanism.rocker_length_m", "260")
    link = page.url
    other = browser.new_page()
    try:
        other.goto(link)
        other.wait_for_selector("body[data-ready='1']", timeout=20_000)
        # The link reopens the design: the rocker typed in the first page, in the form of the second.
        assert float(other.locator("[id='f-mechanism.rocker_length_m']").input_value()) == pytest.approx(260, rel=1e-12)
    finally:
        other.close()
    with page.expect_download() as dl:
        page.click("#save-json")
    saved = json.loads(Path(dl.value.path()).read_text())
    assert saved == state(page, "design") and saved["mechanism"]["rocker_length_m"] == pytest.approx(0.26, rel=1e-12)
    # Opening the saved file in a fresh page brings the same design back.
    edit_and_wait(page, "mechanism.rocker_length_m", "250")
    before = page.evaluate("document.body.dataset.analysed")
    page.set_input_files("#load-json", str(dl.value.path()))
    page.wait_for_function(f"document.body.dataset.analysed !== '{before}'", timeout=15_000)
    assert state(page, "design.mechanism.rocker_length_m") == pytest.approx(0.26, rel=1e-12)


def test_flywheel_and_drive_panels_answer_from_the_service(page: Page, base_url: str) -> None:
    page.click("button[data-panel=flywheel]")
    page.click("#fly-run")
    page.wait_for_selector("#fly-body", timeout=30_000)
    _shot(page, "flywheel")
    # The speed band drawn is the service's: its limits are mean·(1 ± δ/2) of the answer, δ as typed (0.05).
    limits = page.locator("#fly-speed .limit")
    assert limits.count() == 2
    page.click("button[data-panel=drive]")
    page.click("#drv-run")
    page.wait_for_selector("#drv-result table", timeout=30_000)
    _shot(page, "drive")
    text = page.inner_text("#drv-result")
    motor = re.search(r"Motor (\S+):", text)
    assert motor is not None
    power = float(page.input_value("[id='drv-output_power_W']"))
    direct = httpx.post(f"{base_url}/v1/gears/drive", json={"output_power_W": power, "output_speed_rpm": 300,
                                                           "stages": ["helical", "helical"]}, timeout=30).json()
    assert motor.group(1) == direct["motor"]["name"]

    # The gears sized for strength in the Drive panel: the same stages as the API sizes them, and a life the
    # schema refuses is named beside its field.
    page.click("#drv-more-strength summary")
    page.select_option("[id='drv-size_gears']", "true")
    page.fill("[id='drv-strength.life_h']", "-5")
    page.click("#drv-run")
    page.wait_for_selector("[id='drv-strength.life_h-msg']:not([hidden])", timeout=30_000)
    page.fill("[id='drv-strength.life_h']", "40000")
    page.click("#drv-run")
    page.wait_for_selector("#drv-result h3:has-text('strength')", timeout=60_000)
    _shot(page, "drive-strength")
    sized = httpx.post(f"{base_url}/v1/gears/drive", json={"output_power_W": power, "output_speed_rpm": 300,
                                                          "stages": ["helical", "helical"],
                                                          "strength": {"life_h": 40000}}, timeout=60).json()
    rows = page.locator("#drv-result table").nth(2).locator("tr").all_inner_texts()[1:]
    assert len(rows) == len(sized["gears"]) == 2
    names = ("First", "Second")
    for row, gear, name in zip(rows, sized["gears"], names):
        cells = row.split("\t")
        assert cells[0] == f"{name} ({gear['pinion_teeth']}/{gear['gear_teeth']})"
        assert float(cells[1].split()[0]) == pytest.approx(gear["module_mm"], rel=1e-3)
        assert float(cells[2].split()[0]) == pytest.approx(gear["face_width_mm"], rel=1e-3)
    # One drive per answer: the table of the drive to build holds the sized teeth (not a second tooth search), and
    # says how far each built ratio lies from the split's (the API's own ratios, compared here).
    built = page.locator("#drv-result table.drive-built tr").all_inner_texts()[1:]
    assert len(built) == 2
    for row, gear, u, name in zip(built, sized["gears"], sized["stage_ratios"], names):
        cells = row.split("\t")
        assert cells[0].startswith(name) and cells[2] == f"{gear['pinion_teeth']} / {gear['gear_teeth']}"
        assert float(cells[4].rstrip(" %")) == pytest.approx(100 * (gear["ratio"] / u - 1), abs=5e-3)
    pairs = set(re.findall(r"\b(\d+) ?/ ?(\d+)\b", page.inner_text("#drv-result table.drive-built")))
    assert pairs == {(str(g["pinion_teeth"]), str(g["gear_teeth"])) for g in sized["gears"]}


def test_page_assets_are_light_and_local() -> None:
    web = REPO / "api" / "web"
    files = [f for f in web.iterdir() if f.is_file()]
    # The budget: every asset of the page together under 3 MB.
    assert sum(f.stat().st_size for f in files) < 3_000_000
    # Nothing from another host: no absolute URL in any asset (the API manual and the service are relative);
    # the SVG namespace is a name, never fetched.
    for f in files:
        text = f.read_text().replace("http://www.w3.org/2000/svg", "")
        assert not re.search(r"(?:https?:)?//[a-z0-9.-]+\.[a-z]{2,}", text), f.name


# Names that would run script if the page wrote them as HTML: each payload, if run, counts in window.__pwned or opens
# a dialog.
PAYLOADS = ["<img src=x onerror=\"window.__pwned=(window.__pwned||0)+1\">", "<svg onload=alert(1)>",
            "\"><script>window.__pwned=1</script>", "<b onmouseover=alert(2)>x</b>", "<iframe src=javascript:alert(3)>",
            "<a href=javascript:alert(4)>crank</a>"]


def _hostile_design(base_url: str) -> dict[str, Any]:
    """The manual's general linkage with its links, joints and a point renamed to the payloads."""
    examples = httpx.get(f"{base_url}/openapi.json", timeout=10).json()["components"]["schemas"]["AnalysisIn"]["examples"]
    text = json.dumps(next(e for e in examples if e["mechanism"]["type"] == "linkage"))
    for old, new in zip(('"coupler"', '"B"', '"C"', '"rod"'), PAYLOADS):
        text = text.replace(old, json.dumps(new))
    design: dict[str, Any] = json.loads(text)
    design["trace_points"] = [{"name": PAYLOADS[4], "link": PAYLOADS[0], "position_m": [0.1, 0.05]}]
    return design


def test_hostile_names_from_a_link_and_a_file_are_text_and_run_nothing(page: Page, base_url: str,
                                                                     tmp_path: Path) -> None:
    dialogs: list[str] = []
    page.on("dialog", lambda d: (dialogs.append(d.message), d.dismiss()))
    design = _hostile_design(base_url)
    assert httpx.post(f"{base_url}/v1/analysis", json=design, timeout=30).status_code == 200   # the service takes it
    page.goto("about:blank")
    page.goto(f"{base_url}/#design={quote(json.dumps(design))}")
    page.wait_for_selector("body[data-ready='1']", timeout=20_000)
    names = page.eval_on_selector_all("#drawing text, #drawing title", "els => els.map(e => e.textContent)")
    # The names are on the page as the characters they are, and no element came out of them.
    assert PAYLOADS[1] in names and PAYLOADS[2] in names and PAYLOADS[4] in names
    assert page.locator("#drawing img, #drawing script, #drawing foreignObject, body script:not([src])").count() == 0
    page.hover("#drawing")
    # From a file, with the output link renamed too; then the balancing panel's answer drawn from that design.
    saved = tmp_path / "hostile.json"
    mech = design["mechanism"]
    mech["links"][-1]["name"] = mech["output"] = PAYLOADS[5]
    for j in mech["joints"]:
        j["links"] = [PAYLOADS[5] if n == "ram" else n for n in j["links"]]
    saved.write_text(json.dumps(design))
    before = page.evaluate("document.body.dataset.analysed")
    page.set_input_files("#load-json", str(saved))
    page.wait_for_function(f"document.body.dataset.analysed !== '{before}'", timeout=15_000)
    page.click("button[data-panel=balancing]")
    page.click("#bal-run")
    page.wait_for_selector("#bal-polar", timeout=30_000)
    assert PAYLOADS[5] in page.eval_on_selector_all("#drawing title", "els => els.map(e => e.textContent)")
    _shot(page, "hostile-names")
    assert page.evaluate("window.__pwned") is None and dialogs == []
    # the page's own images (the cam's figure) are made by the page; none comes from a name
    assert page.locator("img:not(#cam-figure), img[onerror], script:not([src])").count() == 0


def test_the_page_runs_under_a_policy_without_inline_script_or_style(page: Page, base_url: str) -> None:
    """Served with a Content-Security-Policy that forbids inline script and style, the page and every panel work and
    the browser reports no refusal."""
    policy = ("default-src 'self'; script-src 'self'; style-src 'self'; img-src 'self' data: blob:; "
              "object-src 'none'; base-uri 'none'")
    refused: list[str] = []
    page.on("console", lambda m: refused.append(m.text) if "Content Security Policy" in m.text else None)

    def with_policy(route: Any) -> None:
        response = route.fetch()
        route.fulfill(response=response, headers={**response.headers, "content-security-policy": policy})

    page.route(f"{base_url}/", with_policy)
    page.goto("about:blank")
    page.goto(f"{base_url}/")
    page.wait_for_selector("body[data-ready='1']", timeout=20_000)
    page.evaluate("document.addEventListener('securitypolicyviolation', e => "
                  "(window.__violations = window.__violations || []).push(e.violatedDirective))")
    for panel in ("balancing", "flywheel", "drive", "machine", "synthesis", "studies", "mechanism"):
        page.click(f"button[data-panel={panel}]")
    page.click("button[data-panel=balancing]")
    page.select_option("[id='bal-mode']", "full")
    page.click("#bal-run")
    page.wait_for_selector("#bal-polar", timeout=30_000)
    page.hover("#bal-polar svg")
    assert page.evaluate("window.__violations || []") == [] and refused == []


def test_a_size_limit_names_its_field_in_view_and_the_stale_picture_is_marked(page: Page, base_url: str,
                                                                              tmp_path: Path) -> None:
    limit = httpx.post(f"{base_url}/v1/analysis", json={**state(page, "design"), "samples": 10**6}, timeout=30).json()
    edit_and_wait(page, "samples", str(limit["limit"] + 1), outcome="problem")
    msg = page.locator("[id='m-samples']")
    # the service's 413 names the field, so its words stand under the samples field, scrolled into view
    assert limit["status"] == 413 and limit["field"] == "samples"
    expect(msg).to_be_in_viewport()
    assert str(limit["limit"]) in msg.inner_text()
    # the drawing and the diagrams are of the last design that analysed: greyed and labelled while the error stands
    assert page.locator("#drawing-box.stale-view, #plots.stale-view").count() == 2
    expect(page.locator("#stale-note")).to_be_visible()
    _shot(page, "stale-picture")
    edit_and_wait(page, "samples", "360")
    assert page.locator(".stale-view").count() == 0 and page.locator("#stale-note").is_hidden()
    # A file that is not JSON: said in the page's words, not the parser's.
    bad = tmp_path / "notes.json"
    bad.write_text("{ this is not json")
    before = page.evaluate("document.body.dataset.problem || ''")
    page.set_input_files("#load-json", str(bad))
    page.wait_for_function(f"(document.body.dataset.problem || '') !== '{before}'", timeout=15_000)
    text = page.locator("#form-problem").inner_text()
    assert "notes.json is not a design" in text and "Unexpected" not in text and "JSON.parse" not in text


def test_a_1600_variant_study_draws_every_point_and_its_whole_front(page: Page, base_url: str) -> None:
    edit_and_wait(page, "samples", "24")            # a light variant: the study is about the scatter, not the cost
    page.click("button[data-panel=studies]")
    for n in (0, 1):
        page.fill(f"[id='stu-p{n}.count']", "40")
    page.click("#stu-run")
    page.wait_for_function("document.getElementById('stu-status').dataset.percent === '100'", timeout=240_000)
    page.wait_for_selector("#stu-pareto[data-points]", timeout=60_000)
    studies = httpx.get(f"{base_url}/v1/studies", timeout=10).json()
    study = next(s for s in studies if s["total"] == 1600)
    pareto = httpx.get(f"{base_url}{study['links']['pareto']}", timeout=30).json()
    # every variant the service holds is a point (two pages of results), and every front point is among them
    assert page.get_attribute("#stu-pareto", "data-points") == "1600"
    assert page.locator("#stu-pareto circle.pick").count() == 1600
    drawn = {int(v) for v in page.eval_on_selector_all("#stu-pareto circle[data-front='true']",
                                                        "cs => cs.map(c => c.dataset.variant)")}
    assert drawn == {v["index"] for v in pareto["front"]}
    assert f"{len(pareto['front'])} of {pareto['candidates']}" in page.locator("#stu-pareto h4").inner_text()
    page.locator("#panel-studies").screenshot(path=str(SHOTS / "study-1600.png"))


def test_a_new_user_finds_the_link_a_narrow_window_and_a_speed_warning(page: Page) -> None:
    # the address bar holds the design from the first view
    assert "#design=" in page.url and "units=mm,kg" in page.url
    # a 760 px window: no sideways scroll, on the editor or any panel
    page.set_viewport_size({"width": 760, "height": 900})
    for panel in ("mechanism", "balancing", "machine", "studies"):
        page.click(f"button[data-panel={panel}]")
        assert page.evaluate("document.documentElement.scrollWidth") <= 760, panel
    page.click("button[data-panel=mechanism]")
    _shot(page, "narrow-760")
    # a crank speed no machine turns at is answered, with a warning under the field
    edit_and_wait(page, "speed_rpm", "300000")
    msg = page.locator("[id='m-speed_rpm']")
    assert msg.is_visible() and "rev/min" in msg.inner_text() and "warn" in (msg.get_attribute("class") or "")


def test_exports_download_and_open_and_vectors_are_drawn(page: Page) -> None:
    files = {}
    for label, name in (("CSV", "analysis.csv"), ("SVG", "mechanism.svg"), ("DXF", "mechanism.dxf"),
                        ("PNG", "analysis.png")):
        with page.expect_download(timeout=60_000) as dl:
            page.click(f".exports button:has-text('{label}')")
        assert dl.value.suggested_filename == name
        files[name] = Path(dl.value.path()).read_bytes()
    rows = files["analysis.csv"].decode().splitlines()
    samples = len(state(page, "answer.crank_angle_deg"))
    assert "crank_angle" in rows[0] and len(rows) == samples + 1
    assert b"<svg" in files["mechanism.svg"][:400] and b"SECTION" in files["mechanism.dxf"][:200]
    assert files["analysis.png"][:8] == b"\x89PNG\r\n\x1a\n"
    # velocities at the joints, each along the answer's velocity of that point at this crank angle
    page.select_option("#vectors", "velocity")
    arrows = page.locator("#drawing g.vector.velocity")
    points = state(page, "answer.points")
    i = state(page, "index")
    moving = [n for n, p in points.items() if not n.startswith("cw") and math.hypot(*p["velocity_m_s"][i]) > 0]
    assert arrows.count() == len(moving) >= 3
    for n in range(arrows.count()):
        g = arrows.nth(n)
        name = g.get_attribute("data-point") or ""
        x1, y1, x2, y2 = (float(g.locator("line").get_attribute(a) or "nan") for a in ("x1", "y1", "x2", "y2"))
        vx, vy = points[name]["velocity_m_s"][i]
        if math.hypot(vx, vy) > 1e-9:
            # the arrow points the way the velocity does (y drawn downwards in SVG)
            assert math.atan2(-(y2 - y1), x2 - x1) == pytest.approx(math.atan2(vy, vx), abs=1e-6), name
    page.select_option("#vectors", "reaction")
    assert page.locator("#drawing g.vector.reaction").count() >= 3
    assert page.locator("#plot-reactions polyline.curve").count() == len(state(page, "answer.joint_reactions_N"))
    _shot(page, "exports-and-vectors")
