"""Dragging a joint of a drawn linkage in the workbench: pointer move to the redrawn mechanism and diagrams.

A live server and the system's Chromium driven by Playwright open the drawing editor on the six-bar press template
(360 samples) and drag its joint B to and fro. The page times each move itself with performance.now(), from the
pointer event to the last diagram and the canvas drawn; beside it, the part spent waiting for POST /v1/analysis,
and the service's own time for the same request sent here with httpx. Goal: p95 ≤ 100 ms.

Two hands: one at rest between moves (each move waits for its redraw), and one sweeping on without waiting, where the
editor keeps one analysis in flight (its latency counted from the oldest move not yet analysed). The sweep runs the
editor's drag as it was before (`early` off: the next position sent once the answer in flight is drawn, the canvas
drawn before the request goes) and as it is (the next position sent as soon as an answer arrives, before it is
drawn, and the canvas drawn after the request has gone), alternately in the same browser. The
sweep's time is split with the page's Resource Timing entries: the wait for the analysis in flight (oldest move to
the request sent), the request (sent to its last byte: the service, the network, the 0.7 MB answer), and the answer
read and drawn.
"""

from __future__ import annotations

import os
import signal
import statistics
import time
from typing import Any

import httpx

from bench.workbench import CHROMIUM, CHROMIUM_ARGS, _p95, _serve

MOVES = 40
SWEEP = 120  # moves of one 5 mm grid step each, sent as fast as the browser takes them
ROUNDS = 3  # sweeps of each kind, alternated, so both see the machine's load alike

# each analysis drawn, split at its request's Resource Timing entry (the last answer to end before it was read)
_PHASES = """() => {
  const req = performance.getEntriesByType('resource')
    .filter((e) => e.name.endsWith('/v1/analysis') && e.encodedBodySize > 0);
  return window.workbench.state.timings.map((t) => {
    const read = t.t0 + t.service, r = req.filter((e) => e.responseEnd <= read + 0.5).pop();
    return { total: t.total, wait: r ? r.startTime - t.t0 : NaN, request: r ? r.responseEnd - r.startTime : NaN,
             drawn: r ? t.t0 + t.total - r.responseEnd : NaN };
  });
}"""


def _sweep(page: Any, at: list[list[float]], early: bool) -> tuple[list[dict[str, float]], float]:
    page.evaluate(f"window.workbench.state.timings = []; window.workbench.editor.ed.early = {str(early).lower()}; "
                  "performance.clearResourceTimings()")
    t0 = time.perf_counter()
    for k in range(SWEEP):
        page.mouse.move(*at[k % 16 if (k // 16) % 2 == 0 else 16 - k % 16])
    sweep_s = time.perf_counter() - t0
    page.wait_for_function("window.workbench.state.pending === null && !window.workbench.editor.ed.dragging.queued",
                           timeout=30_000)
    return page.evaluate(_PHASES), sweep_s


def _line(name: str, xs: list[float]) -> str:
    xs = [x for x in xs if x == x]  # an analysis whose request has no timing entry is left out of its phases
    if not xs:
        return f"    {name:<28} (no timing entries)"
    return f"    {name:<28} p50 {statistics.median(xs):6.1f} ms  p95 {_p95(xs):6.1f} ms"


def main() -> None:
    from playwright.sync_api import sync_playwright

    proc, url = _serve()
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
            page = browser.new_context(viewport={"width": 1400, "height": 1000}, bypass_csp=True).new_page()
            page.goto(url + "/")
            page.wait_for_selector("body[data-ready='1'][data-editor-ready='1']", timeout=60_000)
            page.click("#draw-toggle")
            page.evaluate("window.workbench.editor.openTemplate('press')")
            page.wait_for_function("window.workbench.state.pending === null && !window.workbench.editor.ed.fit",
                                   timeout=60_000)
            page.evaluate("performance.setResourceTimingBufferSize(5000)")
            page.focus("#draw-canvas")
            page.keyboard.press("v")
            page.evaluate("window.workbench.state.timings = []")
            sx, sy = page.evaluate("window.workbench.editor.toScreen(0.3, 0.5)")
            page.mouse.move(sx, sy)
            page.mouse.down()
            for k in range(MOVES):
                # one grid step (10 mm) per move, waiting for each redraw as a hand at rest would
                n = len(page.evaluate("window.workbench.state.timings"))
                dx = 0.01 * (1 + k % 8) * (1 if (k // 8) % 2 == 0 else -1)
                tx, ty = page.evaluate(f"window.workbench.editor.toScreen({0.3 + dx}, 0.5)")
                page.mouse.move(tx, ty)
                page.wait_for_function(f"window.workbench.state.timings.length > {n} && "
                                       "window.workbench.state.pending === null", timeout=30_000)
            timings = page.evaluate("window.workbench.state.timings")
            design = page.evaluate("window.workbench.state.design")
            at = page.evaluate("[...Array(17).keys()].map((k) => window.workbench.editor.toScreen(0.3 + 0.005 * k, 0.5))")
            sweeps: dict[bool, list[tuple[list[dict[str, float]], float]]] = {False: [], True: []}
            for _ in range(ROUNDS):
                for early in (False, True):
                    sweeps[early].append(_sweep(page, at, early))
            page.mouse.up()
            browser.close()
        service = []
        with httpx.Client(timeout=60) as client:
            for _ in range(MOVES):
                t0 = time.perf_counter()
                client.post(f"{url}/v1/analysis", json=design).raise_for_status()
                service.append((time.perf_counter() - t0) * 1000)
    finally:
        os.killpg(proc.pid, signal.SIGTERM)
    total = [t["total"] for t in timings]
    wait = [t["service"] for t in timings]
    print(f"drag of a press joint, 360 samples, {len(total)} moves:")
    print(f"  pointer move -> redrawn  p50 {statistics.median(total):6.1f} ms  p95 {_p95(total):6.1f} ms  (goal ≤ 100)")
    print(f"  of which the request     p50 {statistics.median(wait):6.1f} ms  p95 {_p95(wait):6.1f} ms")
    print(f"  service alone (httpx)    p50 {statistics.median(service):6.1f} ms  p95 {_p95(service):6.1f} ms")
    p95s = {}
    for early, runs in sweeps.items():
        drawn = [x for phases, _ in runs for x in phases]
        p95s[early] = _p95([x["total"] for x in drawn])
        print(f"sweeping on, {ROUNDS} x {SWEEP} moves in {sum(s for _, s in runs):.1f} s, {len(drawn)} analyses "
              "drawn, " + ("now:" if early else "before (early off):"))
        print(_line("oldest move -> redrawn", [x["total"] for x in drawn]))
        print(_line("waiting for the one in flight", [x["wait"] for x in drawn]))
        print(_line("request, sent to last byte", [x["request"] for x in drawn]))
        print(_line("answer read and drawn", [x["drawn"] for x in drawn]))
    print(f"sweep p95, now / before: {p95s[True] / p95s[False]:.2f}")


if __name__ == "__main__":
    main()
