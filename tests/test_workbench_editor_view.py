"""The drawing editor's view and tools in a real browser (Playwright, the system's Chromium, a live server): a drawing
zoomed to fit when it opens and on demand, zoomed and panned by wheel, buttons and drag, a clean canvas for a new
drawing, a coupler point put on any drawn link, kinematic inversion, and the animation exported as an SVG.

Positions checked come from the service's answer, read by the test, or from the drawing's own points."""

from __future__ import annotations

import json
import math
import re
from collections.abc import Iterator
from pathlib import Path

import pytest
from playwright.sync_api import Page

from test_workbench import CURVES, SHOTS, base_url, browser, open_page  # noqa: F401  (the service and the browser, per module)
from test_workbench_draw import _click, _settled, _tool

ED = "window.workbench.editor"


@pytest.fixture
def page(browser, base_url: str) -> Iterator[Page]:  # type: ignore[no-untyped-def]
    yield from open_page(browser, base_url, "[data-editor-ready='1']")


def _template(page: Page, key: str) -> None:
    page.evaluate(f"{ED}.ed.on || {ED}.setEditing(true)")
    page.evaluate(f"{ED}.openTemplate({json.dumps(key)})")
    _settled(page)


def _view(page: Page) -> dict[str, float]:
    return dict(page.evaluate(f"{ED}.ed.view"))


def _swept(page: Page) -> tuple[float, float, float, float]:
    """The box of every joint's path in the answer, in the drawing's coordinates (the answer's plus the offset)."""
    return tuple(page.evaluate(f"""(() => {{ const o = {ED}.ed.offset, xs = [], ys = [];
        for (const p of Object.values(window.workbench.state.answer.points)) for (const [x, y] of p.position_m) {{
          xs.push(x + o[0]); ys.push(y + o[1]); }}
        return [Math.min(...xs), Math.min(...ys), Math.max(...xs), Math.max(...ys)]; }})()"""))


def _fits(view: dict[str, float], box: tuple[float, float, float, float]) -> float:
    """The share of the view's width or height the box fills, asserting the box is inside the view."""
    x0, y0, x1, y1 = box
    assert view["x0"] <= x0 and x1 <= view["x0"] + view["w"] and view["y0"] <= y0 and y1 <= view["y0"] + view["h"]
    return max((x1 - x0) / view["w"], (y1 - y0) / view["h"])


def test_a_template_opens_zoomed_to_fit_and_zooms_and_pans(page: Page) -> None:
    # the press's six-bar after the four-bar: the view is the press's, not the four-bar's paths
    _template(page, "fourbar")
    _template(page, "press")
    view = _view(page)
    # every path the joints sweep is in view and fills most of it (the fit pads 20 % of the span each side)
    assert _fits(view, _swept(page)) > 0.55
    page.screenshot(path=str(SHOTS / "editor-fit.png"))
    # the wheel zooms in about the pointer: the model point under it stays under it
    sx, sy = page.evaluate(f"{ED}.toScreen(0.3, 0.5)")
    page.mouse.move(sx, sy)
    page.mouse.wheel(0, -120)
    page.wait_for_function(f"{ED}.ed.view.w < {view['w']} * 0.9")
    zoomed = _view(page)
    assert zoomed["w"] == pytest.approx(view["w"] / 1.2, rel=1e-9)
    assert page.evaluate(f"{ED}.toScreen(0.3, 0.5)") == pytest.approx([sx, sy], abs=1.0)
    # the buttons: out by 1.25, then fit again
    page.click("#draw-zoom-out")
    assert _view(page)["w"] == pytest.approx(zoomed["w"] * 1.25, rel=1e-9)
    # a drag on the empty canvas pans: the drawing follows the pointer, 100 px to the right
    _tool(page, "v")
    before = _view(page)
    corner = page.evaluate(f"{ED}.toScreen({before['x0']} + {before['w']} * 0.02, {before['y0']} + {before['h']} * 0.02)")
    page.mouse.move(*corner)
    page.mouse.down()
    page.mouse.move(corner[0] + 100, corner[1], steps=4)
    page.mouse.up()
    per_px = page.evaluate(f"{ED}.ed.view.w / document.getElementById('draw-canvas').getBoundingClientRect().width")
    assert _view(page)["x0"] == pytest.approx(before["x0"] - 100 * per_px, rel=1e-6, abs=1e-9)
    page.click("#draw-fit")
    assert _view(page) == pytest.approx(view, rel=1e-9)


def test_a_new_drawing_is_a_clean_canvas(page: Page) -> None:
    _template(page, "watt")
    assert page.locator("#draw-canvas .draw-path").count() > 0
    page.click("#draw-new")
    page.wait_for_function(f"{ED}.ed.model.points.length === 0")
    # no path, link or point of the linkage before is left on the canvas
    assert page.locator("#draw-canvas .draw-path, #draw-canvas .draw-link, #draw-canvas .draw-point").count() == 0


def test_a_coupler_point_on_any_drawn_link_traces_its_path(page: Page) -> None:
    _template(page, "watt")
    model = page.evaluate(f"{ED}.ed.model")
    pts = {p["name"]: (p["x"], p["y"]) for p in model["points"]}
    # the link last in the Watt chain (not the crank's neighbour), clicked in the middle of its first two points
    link = model["links"][-1]
    (ax, ay), (bx, by) = pts[link["points"][0]], pts[link["points"][1]]
    _tool(page, "p")
    before = page.evaluate("window.workbench.state.seq")
    _click(page, (ax + bx) / 2, (ay + by) / 2)
    page.wait_for_function(f"window.workbench.state.seq > {before}")
    _settled(page)
    tp = page.evaluate("window.workbench.state.design.trace_points")
    assert len(tp) == 1 and tp[0]["link"] == link["name"]
    # the answer's P at the drawn crank angle is where it was clicked (the link frame written from the drawing): the
    # drawing's points and the answer agree there (the editor's own check, within a pixel)
    answer = page.evaluate("window.workbench.state.answer")
    offset = page.evaluate(f"{ED}.ed.offset")
    mech = page.evaluate("window.workbench.state.design.mechanism")
    crank = next(lk for lk in mech["links"] if lk["name"] == mech["crank"])
    p0, p1 = pts[crank["joints"][0]], pts[crank["joints"][1]]
    phi = math.degrees(math.atan2(p1[1] - p0[1], p1[0] - p0[0])) % 360
    k = min(range(len(answer["crank_angle_deg"])),
            key=lambda j: abs((answer["crank_angle_deg"][j] - phi + 180) % 360 - 180))
    got = answer["points"]["P"]["position_m"][k]
    landed = page.evaluate(f"{ED}.ed.lastPress")
    step = math.radians(360 / len(answer["crank_angle_deg"]))
    reach = max(math.hypot(x - p0[0], y - p0[1]) for x, y in pts.values()) * 2
    assert math.hypot(got[0] + offset[0] - landed[0], got[1] + offset[1] - landed[1]) < step * reach + 1e-3
    # its path is drawn among the joints' paths, and its marker on the link
    assert page.locator("#draw-canvas .draw-trace").count() == 1
    assert page.locator("#draw-canvas .draw-path").count() >= len([p for p in model["points"] if not p["ground"]]) + 1


def test_inversion_makes_the_coupler_the_frame(page: Page) -> None:
    _template(page, "fourbar")
    model = page.evaluate(f"{ED}.ed.model")
    pts = {p["name"]: (p["x"], p["y"]) for p in model["points"]}
    lengths = {frozenset(lk["points"]): math.dist(pts[lk["points"][0]], pts[lk["points"][1]]) for lk in model["links"]}
    lengths[frozenset(["O", "Q"])] = math.dist(pts["O"], pts["Q"])
    _tool(page, "v")
    _click(page, (pts["A"][0] + pts["B"][0]) / 2, (pts["A"][1] + pts["B"][1]) / 2)     # select the coupler A-B
    assert page.evaluate(f"{ED}.ed.selected") == "link:coupler"
    page.click("#draw-invert")
    _settled(page)
    assert page.get_attribute("body", "data-draw-problem") == "" and page.get_attribute("body", "data-mobility") == "1"
    mech = page.evaluate("window.workbench.state.design.mechanism")
    assert set(mech["frame_points_m"]) == {"A", "B"}
    answer = page.evaluate("window.workbench.state.answer")
    track = {n: answer["points"][n]["position_m"] for n in "OQAB"}
    # A and B stand still; O and Q move; every link keeps its length over the whole cycle (the same four lengths)
    for n in "AB":
        assert max(math.dist(p, track[n][0]) for p in track[n]) < 1e-9
    for n in "OQ":
        assert max(math.dist(p, track[n][0]) for p in track[n]) > 0.01
    for pair, length in lengths.items():
        a, b = sorted(pair)
        assert max(abs(math.dist(p, q) - length) for p, q in zip(track[a], track[b], strict=True)) < CURVES, pair
    page.screenshot(path=str(SHOTS / "editor-inverted.png"))


def test_the_animation_exports_as_an_animated_svg(page: Page) -> None:
    with page.expect_download() as dl:
        page.click("#export-animation")
    text = Path(dl.value.path()).read_text()
    frames = re.findall(r'<g[^>]*class="frame"[^>]*data-angle="([-\d.e]+)"', text)
    animates = re.findall(r"<animate [^>]*attributeName=\"visibility\"", text)
    answer = page.evaluate("window.workbench.state.answer")
    # one frame per crank angle shown, 72 of the answer's samples round one turn, each with its own animation
    assert len(frames) == len(animates) == min(72, len(answer["crank_angle_deg"]))
    angles = [float(a) for a in frames]
    assert angles == sorted(angles) and angles[0] == answer["crank_angle_deg"][0]
    # the cycle at the design's speed: 60 / n seconds (kept within 1 to 10 s)
    speed = page.evaluate("window.workbench.state.design.speed_rpm")
    dur = float(re.search(r'dur="([\d.]+)s"', text).group(1))     # type: ignore[union-attr]
    assert dur == pytest.approx(min(10, max(1, 60 / speed)), rel=1e-3)
    assert text.startswith("<svg") and 'xmlns="http://www.w3.org/2000/svg"' in text
