"""The workbench's drawing editor in a real browser (Playwright, the system's Chromium, a live server): a six-bar
press drawn from clicks alone is analysed as the same press written as JSON here (its link frames and masses derived
in this file from the clicked coordinates), a dragged joint changes the diagrams, undo goes back to the start, a
two-degree-of-freedom chain is named as such, and every template opens and analyses on the branch it is drawn in."""

from __future__ import annotations

import json
import math
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from playwright.sync_api import Browser, Page, sync_playwright
from service import running_service

from test_workbench import CHROMIUM, CHROMIUM_ARGS, CURVES, SHOTS

KG_PER_M, BLOCK_KG = 10.0, 5.0  # the editor's stated rule for a drawn link's mass (docs/workbench.md)


@pytest.fixture(scope="module")
def base_url(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    command = lambda port: [sys.executable, "-m", "uvicorn", "api.app:app", "--host", "127.0.0.1",  # noqa: E731
                            "--port", str(port)]
    with running_service(command, tmp_path_factory.mktemp("draw"), start_timeout_s=60) as url:
        yield url


@pytest.fixture(scope="module")
def page(base_url: str) -> Iterator[Page]:
    assert Path(CHROMIUM).exists(), f"{CHROMIUM} is missing"
    with sync_playwright() as p:
        b: Browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        context = b.new_context(viewport={"width": 1400, "height": 1000}, bypass_csp=True)  # wait_for_function evals
        pg = context.new_page()
        errors: list[str] = []
        pg.on("pageerror", lambda e: errors.append(str(e)))
        pg.goto(base_url + "/")
        pg.wait_for_selector("body[data-ready='1'][data-editor-ready='1']", timeout=30_000)
        yield pg
        context.close()
        b.close()
        assert not errors, errors


def _shot(page: Page, name: str) -> None:
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(SHOTS / f"{name}.png"), full_page=False)
    print(f"screenshot: {SHOTS / name}.png")


def _click(page: Page, x: float, y: float, hold: str = "") -> None:
    """Click the canvas at model point (x, y) [m] and wait until the editor has handled the press; where it landed is
    checked, so a canvas that moved between reading its position and the click fails here, not as a wrong link."""
    n = page.evaluate("window.workbench.editor.ed.presses")
    sx, sy = page.evaluate(f"window.workbench.editor.toScreen({x}, {y})")
    if hold:
        page.keyboard.down(hold)
    page.mouse.click(sx, sy)
    if hold:
        page.keyboard.up(hold)
    page.wait_for_function(f"window.workbench.editor.ed.presses > {n}", timeout=10_000)
    landed = page.evaluate("window.workbench.editor.ed.lastPress")
    per_px = page.evaluate("window.workbench.editor.ed.view.w / document.getElementById('draw-canvas')"
                           ".getBoundingClientRect().width")
    assert math.hypot(landed[0] - x, landed[1] - y) < 2 * per_px, (x, y, landed)


def _tool(page: Page, key: str) -> None:
    page.focus("#draw-canvas")
    page.keyboard.press(key)


def _settled(page: Page) -> None:
    """The last edit analysed, its branches read off the drawing, nothing in flight."""
    try:
        page.wait_for_function("window.workbench.state.pending === null && document.body.dataset.editorFit === "
                               "String(window.workbench.state.seq) && !window.workbench.editor.ed.fit", timeout=30_000)
    except Exception:
        said = page.evaluate("[JSON.stringify(window.workbench.editor.ed.model), document.body.dataset.drawProblem, "
                             "document.getElementById('status').textContent, document.body.dataset.problem]")
        raise AssertionError(f"the drawing did not settle: {said}") from None


def _link(name: str, pts: list[tuple[str, tuple[float, float]]]) -> dict[str, Any]:
    """A link through drawn points as the request writes it: frame on the first two, the rest in that frame."""
    (_, p0), (_, p1) = pts[0], pts[1]
    th = math.atan2(p1[1] - p0[1], p1[0] - p0[0])
    c, s = math.cos(th), math.sin(th)
    local = [(c * (x - p0[0]) + s * (y - p0[1]), -s * (x - p0[0]) + c * (y - p0[1])) for _, (x, y) in pts]
    com = (sum(q[0] for q in local) / len(local), sum(q[1] for q in local) / len(local))
    mass = KG_PER_M * sum(math.hypot(*q) for q in local[1:])
    r2 = sum((q[0] - com[0]) ** 2 + (q[1] - com[1]) ** 2 for q in local) / len(local)
    out: dict[str, Any] = {"name": name, "joints": [pts[0][0], pts[1][0]], "length_m": math.hypot(*local[1])}
    if len(pts) > 2:
        out["points_m"] = {n: list(q) for (n, _), q in zip(pts[2:], local[2:], strict=True)}
    return {**out, "mass_kg": mass, "com_m": list(com), "inertia_kgm2": mass * r2 / 3}


O, Q, G, A, B, C, D = (0.0, 0.0), (0.3, 0.0), (0.9, 0.0), (0.0, 0.1), (0.3, 0.5), (0.6, 0.4), (0.9, 1.0)
PRESS = {
    "type": "linkage", "frame_points_m": {"O": list(O), "Q": list(Q), "G": list(G)},
    "links": [_link("L1", [("O", O), ("A", A)]), _link("L2", [("A", A), ("B", B)]),
              _link("L3", [("Q", Q), ("B", B), ("C", C)]), _link("L4", [("C", C), ("D", D)]),
              {"name": "block1", "joints": ["D"], "mass_kg": BLOCK_KG}],
    "joints": [{"name": "O", "kind": "revolute", "links": ["frame", "L1"]},
               {"name": "Q", "kind": "revolute", "links": ["frame", "L3"]},
               {"name": "A", "kind": "revolute", "links": ["L1", "L2"]},
               {"name": "B", "kind": "revolute", "links": ["L2", "L3"]},
               {"name": "C", "kind": "revolute", "links": ["L3", "L4"]},
               {"name": "D", "kind": "revolute", "links": ["L4", "block1"]},
               {"name": "block1_guide", "kind": "prismatic", "links": ["frame", "block1"], "through": "G",
                "axis_deg": 90.0}],
    # B left of the line A->Q and D above C's foot on the guide: both dyads on branch +1, the default
    "crank": "L1", "output": "block1",
}
COMPARED = ["driving_torque_Nm", "shaking_force_N", "shaking_moment_Nm", "reduced_inertia_kgm2"]


def _flat(v: list[Any]) -> list[float]:
    return [float(x) for row in v for x in (row if isinstance(row, list) else [row])]


def _assert_same(page_answer: dict[str, Any], ref: dict[str, Any], tol: float = CURVES,
                 points: tuple[str, ...] = ("A", "B", "C", "D")) -> None:
    """Every diagram's values equal to ``tol`` relative to its own largest value, every joint's path to ``tol`` m."""
    for key in COMPARED:
        got, want = _flat(page_answer[key]), _flat(ref[key])
        scale = max(1.0, max(abs(w) for w in want))
        assert max(abs(g - w) for g, w in zip(got, want, strict=True)) <= tol * scale, key
    for name in points:
        got, want = _flat(page_answer["points"][name]["position_m"]), _flat(ref["points"][name]["position_m"])
        assert max(abs(g - w) for g, w in zip(got, want, strict=True)) <= tol, name


def test_a_press_drawn_from_clicks_is_the_json_press_drags_and_undoes(page: Page, base_url: str) -> None:
    page.click("#draw-new")
    _tool(page, "f")
    for p in (O, Q, G):
        _click(page, *p)
    _tool(page, "b")
    _click(page, *O); _click(page, *A)          # crank O-A, placing A  # noqa: E702
    _click(page, *A); _click(page, *B)          # coupler A-B, placing B  # noqa: E702
    _tool(page, "t")
    _click(page, *Q); _click(page, *B); _click(page, *C)  # rocker Q-B with its arm to C  # noqa: E702
    _tool(page, "b")
    _click(page, *C); _click(page, *D, "Shift")  # rod C-D, D on the grid at any length  # noqa: E702
    assert "degrees of freedom" in (page.text_content("#draw-messages") or "")  # W = 3·4 − 2·5 = 2 before the ram
    _tool(page, "s")
    _click(page, *D); _click(page, *G)          # the ram on a guide through G, upwards  # noqa: E702
    _settled(page)
    assert page.text_content("#draw-mobility") == "W = 3n − 2p = 3·5 − 2·7 = 1"
    design = page.evaluate("window.workbench.state.design")
    assert _close(design["mechanism"]["links"], PRESS["links"])  # lengths, link frames, masses of the clicks
    request = {k: v for k, v in design.items() if k != "mechanism"}
    ref = httpx.post(f"{base_url}/v1/analysis", json={**request, "mechanism": PRESS}, timeout=60).json()
    drawn = page.evaluate("window.workbench.state.answer")
    _assert_same(drawn, ref)
    assert json.loads(page.input_value("[id='f-mechanism']")) == design["mechanism"]  # the JSON box is the drawing
    assert "II (L2, L3)" in (page.text_content("#draw-side .groups") or "")
    _assert_names_apart(page, "press from clicks")  # a view with the crank near the canvas's left edge
    _shot(page, "draw-press")

    # drag B 40 mm to the right: the coupler and rocker lengths change and the torque with them
    _tool(page, "v")
    b0 = page.evaluate(f"window.workbench.editor.toScreen({B[0]}, {B[1]})")
    b1 = page.evaluate(f"window.workbench.editor.toScreen({B[0] + 0.04}, {B[1]})")
    page.mouse.move(*b0)
    page.mouse.down()
    page.mouse.move(*b1, steps=8)
    page.mouse.up()
    _settled(page)
    moved = page.evaluate("window.workbench.state.answer")
    assert abs(page.evaluate("window.workbench.state.design.mechanism.links[1].length_m") - math.hypot(0.34, 0.4)) < 1e-9
    assert max(abs(a - b) for a, b in zip(moved["driving_torque_Nm"], ref["driving_torque_Nm"], strict=True)) > 1e-3
    assert page.input_value("[id='dl-L2']") == f"{math.hypot(0.34, 0.4) * 1000:.8g}"
    _shot(page, "draw-dragged")

    # one undo puts B back and the analysis is the JSON press's again; undo to the empty canvas, redo one step
    page.focus("#draw-canvas")
    page.keyboard.press("Control+z")
    _settled(page)
    _assert_same(page.evaluate("window.workbench.state.answer"), ref)
    steps = page.evaluate("window.workbench.editor.ed.undo.length")
    for _ in range(steps):
        page.keyboard.press("Control+z")
    # the start: the page's four-bar as the editor opened it, before "New drawing"
    assert [p["name"] for p in page.evaluate("window.workbench.editor.ed.model.points")] == ["O", "Q", "A", "B"]
    page.keyboard.press("Control+y")
    assert page.evaluate("window.workbench.editor.ed.model.points.length") == 0  # the empty canvas again


def _close(got: Any, want: Any, tol: float = 1e-12) -> bool:
    """Same structure, numbers equal to ``tol``."""
    if isinstance(want, dict):
        return isinstance(got, dict) and got.keys() == want.keys() and all(_close(got[k], want[k], tol) for k in want)
    if isinstance(want, list):
        return isinstance(got, list) and len(got) == len(want) and all(_close(g, w, tol) for g, w in zip(got, want))
    if isinstance(want, float | int) and not isinstance(want, bool):
        return isinstance(got, float | int) and abs(got - want) <= tol
    return bool(got == want)


def test_a_two_degree_of_freedom_chain_is_named_at_once(page: Page) -> None:
    page.click("#draw-new")
    _tool(page, "f")
    _click(page, 0.0, 0.0); _click(page, 0.5, 0.0)  # noqa: E702
    _tool(page, "b")
    for a, b in [((0.0, 0.0), (0.0, 0.1)), ((0.0, 0.1), (0.2, 0.3)), ((0.2, 0.3), (0.45, 0.25)),
                 ((0.45, 0.25), (0.5, 0.0))]:
        _click(page, *a); _click(page, *b)  # noqa: E702
    text = page.text_content("#draw-messages") or ""
    assert "W = 3·4 − 2·5 = 2" in text and "2 degrees of freedom" in text
    assert page.get_attribute("body", "data-mobility") == "2"
    assert "2 degrees of freedom" in (page.text_content("#draw-canvas .draw-msg") or "")
    _shot(page, "draw-two-dof")


@pytest.mark.parametrize("key", ["fourbar", "slider_crank", "quick_return", "watt", "press", "toggle", "stephenson", "shaper"])
def test_every_template_analyses_on_the_branch_it_is_drawn_in(page: Page, key: str) -> None:
    page.evaluate("window.workbench.editor.ed.on || window.workbench.editor.setEditing(true)")
    page.evaluate(f"window.workbench.editor.openTemplate({json.dumps(key)})")
    _settled(page)
    assert page.get_attribute("body", "data-draw-problem") == "", key
    assert page.get_attribute("body", "data-mobility") == "1", key
    ed = page.evaluate("window.workbench.editor.ed")
    answer = page.evaluate("window.workbench.state.answer")
    mech = page.evaluate("window.workbench.state.design.mechanism")
    pts = {p["name"]: (p["x"], p["y"]) for p in ed["model"]["points"]}
    crank = next(lk for lk in mech["links"] if lk["name"] == mech["crank"])
    p0, p1 = pts[crank["joints"][0]], pts[crank["joints"][1]]
    phi = math.degrees(math.atan2(p1[1] - p0[1], p1[0] - p0[0])) % 360
    k = min(range(len(answer["crank_angle_deg"])), key=lambda j: abs((answer["crank_angle_deg"][j] - phi + 180) % 360 - 180))
    step = math.radians(360 / len(answer["crank_angle_deg"]))
    for name, (x, y) in pts.items():
        got = answer["points"][name]["position_m"][k]
        # within what half a sample of crank turn moves a point (a generous 5 crank lengths' worth of lever)
        assert math.hypot(got[0] + ed["offset"][0] - x, got[1] + ed["offset"][1] - y) < 5 * crank["length_m"] * step, (key, name)
    if key == "press":
        _shot(page, "draw-template-press")
    if key == "stephenson":
        # its two ternary links, the frame and the coupler, share no pair; the service split it into two dyads
        assert len(mech["frame_points_m"]) == 3 and len(mech["links"][1]["points_m"]) == 1
        assert not any(set(j["links"]) == {"frame", "coupler"} for j in mech["joints"])
        groups = page.evaluate("window.workbench.editor.ed.groups")
        assert [(g["group_class"], g["links"]) for g in groups] == [("II", ["coupler", "rocker"]), ("II", ["link", "follower"])]
        _shot(page, "draw-template-stephenson")
    if key == "shaper":
        _shot(page, "draw-template-shaper")


# A four-bar written as a general linkage with its own masses, centres and inertias (none by the editor's bar rule)
BALANCED_FOURBAR = {
    "type": "linkage", "frame_points_m": {"O": [0.0, 0.0], "Q": [0.3, 0.0]},
    "links": [{"name": "crank", "joints": ["O", "A"], "length_m": 0.1, "mass_kg": 1.2, "com_m": [0.04, 0.0],
               "inertia_kgm2": 0.002},
              {"name": "coupler", "joints": ["A", "B"], "length_m": 0.5, "mass_kg": 3.0, "com_m": [0.22, 0.03],
               "inertia_kgm2": 0.07},
              {"name": "rocker", "joints": ["Q", "B"], "length_m": 0.5, "mass_kg": 2.5, "com_m": [0.2, -0.01],
               "inertia_kgm2": 0.05}],
    "joints": [{"name": "O", "kind": "revolute", "links": ["frame", "crank"]},
               {"name": "A", "kind": "revolute", "links": ["crank", "coupler"]},
               {"name": "B", "kind": "revolute", "links": ["coupler", "rocker"]},
               {"name": "Q", "kind": "revolute", "links": ["frame", "rocker"]}],
    "crank": "crank", "output": "rocker",
}
PROPS = ("mass_kg", "com_m", "inertia_kgm2")


def _drag(page: Page, frm: tuple[float, float], to: tuple[float, float]) -> None:
    _tool(page, "v")
    page.mouse.move(*page.evaluate(f"window.workbench.editor.toScreen({frm[0]}, {frm[1]})"))
    page.mouse.down()
    page.mouse.move(*page.evaluate(f"window.workbench.editor.toScreen({to[0]}, {to[1]})"), steps=6)
    page.mouse.up()
    _settled(page)


def test_a_balanced_linkage_keeps_its_masses_and_counterweights_as_it_is_edited(page: Page, base_url: str) -> None:
    design = {"mechanism": BALANCED_FOURBAR, "speed_rpm": 120}
    balanced = httpx.post(f"{base_url}/v1/balancing/optimal", json=design, timeout=120).json()
    counterweights = balanced["counterweights"]
    assert {cw["link"] for cw in counterweights} == {"crank", "rocker"}  # the service's default links
    page.evaluate("window.workbench.editor.ed.on && window.workbench.editor.setEditing(false)")
    page.evaluate("d => window.workbench.setDesign(d)", {**design, "counterweights": counterweights})
    page.wait_for_function("window.workbench.state.pending === null && window.workbench.state.answer && "
                           "window.workbench.state.design.counterweights", timeout=30_000)
    page.click("#draw-toggle")
    _settled(page)

    # drag B 30 mm to the right: coupler and rocker change length, every mass and counterweight stays with its link
    b = next(p for p in page.evaluate("window.workbench.editor.ed.model.points") if p["name"] == "B")
    _drag(page, (b["x"], b["y"]), (b["x"] + 0.03, b["y"]))
    got = page.evaluate("window.workbench.state.design")
    lengths = {lk["name"]: lk["length_m"] for lk in got["mechanism"]["links"]}
    assert abs(lengths["coupler"] - 0.5) > 1e-3 and abs(lengths["rocker"] - 0.5) > 1e-3, lengths
    for want, have in zip(BALANCED_FOURBAR["links"], got["mechanism"]["links"], strict=True):
        assert {k: have[k] for k in PROPS} == {k: want[k] for k in PROPS}, have["name"]
    assert got["counterweights"] == counterweights
    assert json.loads(page.input_value("[id='f-mechanism']")) == got["mechanism"]  # the JSON view holds them

    # the page's answer is the service's for this design, and neither the massless nor the unbalanced one
    shown = page.evaluate("window.workbench.state.answer")
    ref = httpx.post(f"{base_url}/v1/analysis", json=got, timeout=60).json()
    massless_mech = {**got["mechanism"], "links": [{k: v for k, v in lk.items() if k not in PROPS}
                                                    for lk in got["mechanism"]["links"]]}
    massless = httpx.post(f"{base_url}/v1/analysis", json={"mechanism": massless_mech, "speed_rpm": 120}, timeout=60)
    bare = httpx.post(f"{base_url}/v1/analysis", json={**got, "counterweights": []}, timeout=60).json()
    _assert_same(shown, ref, points=("A", "B"))
    assert max(abs(t) for t in massless.json()["driving_torque_Nm"]) < 1e-9  # no mass, no load: no torque
    assert max(abs(t) for t in shown["driving_torque_Nm"]) > 1.0
    # the counterweights still take most of the shaking force off the frame after a 30 mm change
    assert shown["summary"]["rms_shaking_force_N"] < 0.5 * bare["summary"]["rms_shaking_force_N"]
    _shot(page, "draw-balanced")

    # deleting the rocker takes its counterweight with it; undo brings both back
    q = next(p for p in page.evaluate("window.workbench.editor.ed.model.points") if p["name"] == "Q")
    _tool(page, "x")
    mid = ((q["x"] + b["x"] + 0.03) / 2, (q["y"] + b["y"]) / 2)
    page.mouse.click(*page.evaluate(f"window.workbench.editor.toScreen({mid[0]}, {mid[1]})"))
    page.wait_for_function("!window.workbench.editor.ed.model.links.some((l) => l.name === 'rocker')", timeout=10_000)
    assert [cw["link"] for cw in page.evaluate("window.workbench.state.design.counterweights")] == ["crank"]
    page.focus("#draw-canvas")
    page.keyboard.press("Control+z")
    _settled(page)
    assert page.evaluate("window.workbench.state.design.counterweights") == counterweights
    _assert_same(page.evaluate("window.workbench.state.answer"), ref, points=("A", "B"))


def test_a_link_drawn_from_a_point_snaps_to_a_round_length_and_shift_places_it_freely(page: Page) -> None:
    page.click("#draw-new")
    page.select_option("#draw-grid", "0.005")
    _tool(page, "f")
    _click(page, 0.0, 0.0)
    _tool(page, "b")
    _click(page, 0.0, 0.0); _click(page, 0.2, 0.11)  # noqa: E702
    # clicked on the grid point (0.2, 0.11), 228.25 mm from O: placed along that line at 230 mm, 46 grid steps
    a = next(p for p in page.evaluate("window.workbench.editor.ed.model.points") if p["name"] == "A")
    scale = 0.23 / math.hypot(0.2, 0.11)
    assert abs(a["x"] - 0.2 * scale) < 1e-12 and abs(a["y"] - 0.11 * scale) < 1e-12, a
    assert page.input_value("[id='dl-L1']") == "230"
    # Shift: the far end on the grid point itself, the link as long as that makes it
    _click(page, a["x"], a["y"]); _click(page, 0.35, 0.2, "Shift")  # noqa: E702
    b = next(p for p in page.evaluate("window.workbench.editor.ed.model.points") if p["name"] == "B")
    assert (b["x"], b["y"]) == (0.35, 0.2)
    assert page.input_value("[id='dl-L2']") == f"{math.hypot(0.35 - a['x'], 0.2 - a['y']) * 1000:.8g}"


def test_a_block_in_the_slot_of_a_moving_lever_is_drawn_and_the_lever_follows_the_crank_pin(page: Page) -> None:
    page.click("#draw-new")
    # O1 300 mm below O, the pin A 100 mm from O, B on the line O1-A 1.5 times as far
    o, o1, a, b = (0.0, 0.35), (0.0, 0.05), (0.06, 0.43), (0.09, 0.62)
    _tool(page, "f")
    _click(page, *o); _click(page, *o1)  # noqa: E702
    _tool(page, "b")
    _click(page, *o); _click(page, *a)  # crank O-A, 100 mm  # noqa: E702
    _click(page, *o1); _click(page, *b, "Shift")  # the lever O1-B  # noqa: E702
    lever_mid = ((o1[0] + a[0]) / 2, (o1[1] + a[1]) / 2)
    _tool(page, "s")
    _click(page, *a); _click(page, *lever_mid)  # a block at the crank pin A in the lever's slot  # noqa: E702
    _tool(page, "o")
    _click(page, *lever_mid)
    _settled(page)
    assert page.get_attribute("body", "data-mobility") == "1"
    assert page.get_attribute("body", "data-draw-problem") == ""
    mech = page.evaluate("window.workbench.state.design.mechanism")
    assert {"name": "block1_slot", "kind": "prismatic", "links": ["L2", "block1"], "axis_link": "L2",
            "axis_deg": 0} in mech["joints"]
    assert mech["output"] == "L2"
    answer = page.evaluate("window.workbench.state.answer")
    # the lever always points from its pivot O1 through the crank pin A (positions relative to the crank pivot O)
    pins = answer["points"]["A"]["position_m"]
    want = [math.degrees(math.atan2(p[1] - (o1[1] - o[1]), p[0] - (o1[0] - o[0]))) for p in pins]
    got = answer["links"]["L2"]["angle_deg"]
    # angles to their curve's quantum (5e-8 × 180° = 1e-5°) and positions to theirs (5e-8 of 0.1 m, 5e-7 rad)
    assert max(abs((g - w + 180) % 360 - 180) for g, w in zip(got, want, strict=True)) < 1e-4
    _shot(page, "draw-slot")


@pytest.mark.parametrize("family", ["fourbar", "slider_crank", "slotted_lever"])
def test_a_family_design_opened_in_the_editor_is_the_same_linkage(page: Page, family: str) -> None:
    """The manual's example of each family, opened on the canvas, is analysed as a general linkage with the family's
    masses and pair names: the same torque, shaking force and moment, reduced inertia and joint paths."""
    page.evaluate("window.workbench.editor.ed.on && window.workbench.editor.setEditing(false)")
    page.evaluate("f => window.workbench.setDesign({mechanism: window.workbench.editor.familyExample(f), speed_rpm: 120})",
                  family)
    page.wait_for_function(f"window.workbench.state.pending === null && window.workbench.state.answer && "
                           f"window.workbench.state.design.mechanism.type === '{family}'", timeout=30_000)
    ref = page.evaluate("window.workbench.state.answer")
    page.click("#draw-toggle")
    _settled(page)
    assert page.evaluate("window.workbench.state.design.mechanism.type") == "linkage"
    drawn = page.evaluate("window.workbench.state.answer")
    _assert_same(drawn, ref, points=("A", "B") if family != "slotted_lever" else ("A", "B", "R"))
    assert sorted(drawn["joint_reactions_N"]) == sorted(ref["joint_reactions_N"])  # the family's pair names
    if family == "slotted_lever":
        _shot(page, "draw-shaper-family")


def test_a_double_parallelogram_is_analysed_though_the_formula_says_it_cannot_move(page: Page,
                                                                                    base_url: str) -> None:
    """W = 3·4 − 2·6 = 0 is said, but the analysis is asked for: the service finds the passive link from the
    geometry (docs/linkages.md), and the page shows its answer and its redundant_constraint warning. The coupler's
    middle F moves like the crank pin (the coupler translates): on a circle of 0.1 m about (0.15, 0)."""
    examples = httpx.get(f"{base_url}/openapi.json", timeout=60).json()["components"]["schemas"]["StructureIn"]
    mech = next(e["mechanism"] for e in examples["examples"] if "mechanism" in e)
    mech["links"][1]["points_m"]["F"] = [0.15, 0.0]
    page.evaluate("window.workbench.editor.ed.on && window.workbench.editor.setEditing(false)")
    page.evaluate("m => window.workbench.setDesign({mechanism: m, speed_rpm: 60, samples: 72})", mech)
    page.click("#draw-toggle")
    _settled(page)
    assert page.get_attribute("body", "data-mobility") == "0"
    assert "W = 3·4 − 2·6 = 0 by the formula" in (page.text_content("#draw-messages") or "")
    answer = page.evaluate("window.workbench.state.answer")
    assert "redundant_constraint" in [w["code"] for w in answer["warnings"]]  # beside: the links have no masses
    said = next(w for w in answer["warnings"] if w["code"] == "redundant_constraint")["message"]
    assert page.get_by_text(said).first.is_visible()
    f = answer["points"]["F"]["position_m"]
    assert max(abs(math.hypot(x - 0.15, y) - 0.1) for x, y in f) < CURVES
    _shot(page, "draw-double-parallelogram")


_RECTS = """sel => [...document.querySelectorAll(sel)].map((e) => {
  const r = e.getBoundingClientRect();
  return { of: e.dataset.label || e.dataset.point, left: r.left, top: r.top, right: r.right, bottom: r.bottom };
})"""


def _meet(a: dict[str, Any], b: dict[str, Any]) -> bool:
    return bool(a["left"] < b["right"] and b["left"] < a["right"] and a["top"] < b["bottom"] and b["top"] < a["bottom"])


@pytest.mark.parametrize("key", ["press", "stephenson"])
def test_no_name_on_the_canvas_covers_another_or_a_joint(page: Page, key: str) -> None:
    """Where links meet at a joint or lie close (the press's rocker plate, the Stephenson's coupler plate), each name
    is drawn where it covers no other name and no joint's marker, inside the canvas."""
    page.evaluate("window.workbench.editor.ed.on || window.workbench.editor.setEditing(true)")
    page.evaluate(f"window.workbench.editor.openTemplate({json.dumps(key)})")
    _settled(page)
    _assert_names_apart(page, key)
    _shot(page, f"draw-labels-{key}")


def _assert_names_apart(page: Page, key: str) -> None:
    """The browser's own boxes of the drawn names (not the editor's plan) cover no other name and no joint's marker
    and lie inside the canvas; the editor's plan holds each drawn name (to 1 px)."""
    model = page.evaluate("window.workbench.editor.ed.model")
    drawn = page.evaluate(_RECTS, "#draw-canvas text[data-label]")
    # every joint's name, every link's and the output block's
    output = page.evaluate("window.workbench.state.design.mechanism.output")
    want = {p["name"] for p in model["points"]} | {lk["name"] for lk in model["links"]} | {output}
    assert sorted(r["of"] for r in drawn) == sorted(want), key
    markers = page.evaluate(_RECTS, "#draw-canvas circle.draw-point")
    assert len(markers) == len(model["points"])
    canvas = page.evaluate("(() => { const r = document.getElementById('draw-canvas').getBoundingClientRect(); "
                           "return { left: r.left, top: r.top, right: r.right, bottom: r.bottom }; })()")
    for k, a in enumerate(drawn):
        assert all(not _meet(a, b) for b in drawn[k + 1:]), (key, a["of"],
                                                               [b["of"] for b in drawn[k + 1:] if _meet(a, b)])
        assert not any(_meet(a, m) for m in markers), (key, a["of"], [m["of"] for m in markers if _meet(a, m)])
        assert (canvas["left"] <= a["left"] and a["right"] <= canvas["right"] and canvas["top"] <= a["top"]
                and a["bottom"] <= canvas["bottom"]), (key, a)
    planned = {b["of"]: b for b in page.evaluate("window.workbench.editor.labelBoxes()")}
    for a in drawn:
        b = planned[a["of"]]
        assert (b["left"] - 1 <= a["left"] and a["right"] <= b["right"] + 1 and b["top"] - 1 <= a["top"]
                and a["bottom"] <= b["bottom"] + 1), (key, a, b)


def test_a_long_problem_is_said_whole_and_the_canvas_stays_where_it_was(page: Page, base_url: str) -> None:
    """A four-bar whose coupler is made too short to close: the service's problem (its crank angles) is shown in
    full in the note above the canvas and on the canvas, wrapped, not cut off; the canvas does not move while the
    note comes and goes (a click aimed before an answer lands where it was aimed)."""
    page.evaluate("window.workbench.editor.ed.on || window.workbench.editor.setEditing(true)")
    page.evaluate("window.workbench.editor.openTemplate('fourbar')")
    _settled(page)
    where = ("(() => { const r = document.getElementById('draw-canvas').getBoundingClientRect(); "
             "return [r.left, r.top, r.width, r.height]; })()")
    before = page.evaluate(where)
    assert page.evaluate("document.getElementById('stale-note').hidden")
    n = page.evaluate("window.workbench.state.seq")
    page.fill("[id='dl-coupler']", "100")  # mm: A-B 100 mm cannot reach from A to the rocker's circle at every angle
    page.press("[id='dl-coupler']", "Tab")  # the field's change: one edit
    page.wait_for_function(f"document.body.dataset.problem === String(window.workbench.state.seq) && "
                           f"window.workbench.state.seq > {n}", timeout=30_000)
    design = page.evaluate("window.workbench.state.design")
    problem = httpx.post(f"{base_url}/v1/analysis", json=design, timeout=60)
    assert problem.status_code == 422, problem.text
    detail = problem.json()["detail"]
    assert page.evaluate(where) == before
    note = page.evaluate("(() => { const e = document.getElementById('stale-note'), r = e.getBoundingClientRect(); "
                         "return { text: e.textContent, sw: e.scrollWidth, cw: e.clientWidth, sh: e.scrollHeight, "
                         "ch: e.clientHeight, left: r.left, right: r.right, top: r.top, bottom: r.bottom, "
                         "vw: innerWidth, hidden: e.hidden, "
                         "lines: Math.round(r.height / parseFloat(getComputedStyle(e).lineHeight)) }; })()")
    assert not note["hidden"] and detail in note["text"], (detail, note["text"])
    assert note["sw"] <= note["cw"] and note["sh"] <= note["ch"], note  # nothing scrolled out of sight
    assert 0 <= note["left"] and note["right"] <= note["vw"], note
    assert note["lines"] >= 2, note  # long enough to wrap in this window: the case the note was cut off in
    # on the canvas: the same words, every line inside the canvas
    said = page.evaluate("[...document.querySelectorAll('#draw-canvas text.draw-msg')].map((e) => { "
                         "const r = e.getBoundingClientRect(); return { left: r.left, right: r.right, top: r.top, "
                         "bottom: r.bottom, text: [...e.querySelectorAll('tspan')].map((t) => t.textContent)"
                         ".join(' ') }; })")
    mine = [m for m in said if detail in m["text"]]
    assert mine, said
    for m in said:
        assert before[0] <= m["left"] and m["right"] <= before[0] + before[2], m
        assert before[1] <= m["top"] and m["bottom"] <= before[1] + before[3], m
    _shot(page, "draw-long-problem")

    # the length put back: the note goes, the canvas stays
    page.focus("#draw-canvas")
    page.keyboard.press("Control+z")
    _settled(page)
    assert page.evaluate("document.getElementById('stale-note').hidden")
    assert page.evaluate(where) == before
