"""The workbench's diagrams in a real browser (Playwright, the system's Chromium, a live server): tick labels never
repeat on an axis, legend entries never overlap nor leave their plot, on every template's diagrams; a figure waiting
for a new answer is marked as the last one's."""

from __future__ import annotations

import json
from collections.abc import Iterator
from typing import Any

import pytest
from playwright.sync_api import Page

from test_workbench import SHOTS, base_url, browser, open_page  # noqa: F401  (the service and the browser, per module)
from test_workbench_draw import _settled

# Every plot's tick labels per axis, and the boxes of its legend entries and of the plot, as the page lays them out.
BOXES = """() => [...document.querySelectorAll('.plot')].filter(p => p.offsetParent).map(p => {
  const box = (e) => { const r = e.getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom]; };
  const svg = p.querySelector('svg');
  return { id: p.id, svg: box(svg),
    x: [...svg.querySelectorAll('text.tick[data-axis=x]')].map(t => t.textContent),
    y: [...svg.querySelectorAll('text.tick[data-axis=y]')].map(t => t.textContent),
    legend: [...svg.querySelectorAll('g.legend-entry')].map(box) }; })"""


@pytest.fixture
def page(browser, base_url: str) -> Iterator[Page]:  # type: ignore[no-untyped-def]
    yield from open_page(browser, base_url, "[data-editor-ready='1']")


def _apart(a: list[float], b: list[float]) -> bool:
    return a[2] <= b[0] or b[2] <= a[0] or a[3] <= b[1] or b[3] <= a[1]


def _check(plots: list[dict[str, Any]], where: str) -> None:
    assert plots, where
    for p in plots:
        for axis in ("x", "y"):
            assert len(set(p[axis])) == len(p[axis]), (where, p["id"], axis, p[axis])
        boxes = p["legend"]
        for i, a in enumerate(boxes):
            # inside its plot, and apart from every other entry
            s = p["svg"]
            assert s[0] - 0.5 <= a[0] and a[2] <= s[2] + 0.5 and s[1] - 0.5 <= a[1] and a[3] <= s[3] + 0.5, (where, p["id"], a)
            for b in boxes[i + 1:]:
                assert _apart(a, b), (where, p["id"], a, b)


@pytest.mark.parametrize("key", ["fourbar", "slider_crank", "quick_return", "watt", "press", "toggle", "stephenson", "shaper"])
def test_every_templates_diagrams_have_distinct_ticks_and_legends_apart(page: Page, key: str) -> None:
    page.evaluate("window.workbench.editor.ed.on || window.workbench.editor.setEditing(true)")
    page.evaluate(f"window.workbench.editor.openTemplate({json.dumps(key)})")
    _settled(page)
    plots = page.evaluate(BOXES)
    # the shaper's joint reactions carry long names (slider_slot, ram_guide, ram_slider_slot …): two rows if need be
    _check(plots, key)
    if key == "shaper":
        page.locator("#plot-reactions").screenshot(path=str(SHOTS / "figures-shaper-reactions.png"))


def test_ticks_at_solver_noise_read_apart(page: Page) -> None:
    # a Pareto front at solver noise: objective values 4.5 + k·1e-12 (the studies scatter that read "4.5" five times)
    labels = page.evaluate("""async () => {
        const { scatterPlot } = await import('/workbench/plot.js');
        const box = document.createElement('div'); document.body.appendChild(box);
        scatterPlot(box, 'noise-scatter', { title: 'noise', xLabel: 'x', yLabel: 'y',
          points: [0, 1, 2, 3, 4].map(k => ({ x: k, y: 4.5 + k * 1e-12 })) });
        return [...box.querySelectorAll('text.tick[data-axis=y]')].map(t => t.textContent); }""")
    assert len(labels) >= 2 and len(set(labels)) == len(labels), labels
    # each label is its tick's value to the digits shown: read back, they increase with the ticks
    values = [float(v) for v in labels]
    assert values == sorted(values) and values[0] == pytest.approx(4.5, abs=1e-11)


def test_the_cam_figure_is_marked_while_the_least_cam_is_on_its_way(page: Page) -> None:
    page.click("button[data-panel=cams]")
    page.wait_for_selector("body[data-cam-ready='1']")
    page.click("#cam-analyse")
    page.wait_for_function("(document.body.dataset.cam || '').startsWith('analysed')", timeout=60_000)
    assert not page.locator("#cam-figure").evaluate("e => e.classList.contains('stale-view')")
    page.click("#cam-least-run")
    # the old figure greyed, and said so, until the least cam's answer replaces it
    assert page.locator("#cam-figure").evaluate("e => e.classList.contains('stale-view')")
    assert "last cam" in page.inner_text("#cam-updating")
    page.wait_for_function("(document.body.dataset.cam || '').startsWith('synthesised')", timeout=60_000)
    assert not page.locator("#cam-figure").evaluate("e => e.classList.contains('stale-view')")
    assert page.locator("#cam-updating").is_hidden()
