"""Dragging a joint of a drawn linkage in the workbench: pointer move to the redrawn mechanism and diagrams.

A live server and the system's Chromium driven by Playwright open the drawing editor on the six-bar press template
(360 samples) and drag its joint B to and fro. The page times each move itself with performance.now(), from the
pointer event to the last diagram and the canvas drawn; beside it, the part spent waiting for POST /v1/analysis,
and the service's own time for the same request sent here with httpx. Goal: p95 ≤ 100 ms.

Two hands: one at rest between moves (each move waits for its redraw), and one sweeping on without waiting, where the
editor keeps one analysis in flight and sends the joint's latest position when it returns (its latency counted from
the oldest move not yet analysed).

Before the drag kept one request in flight and left the address bar alone while dragging (commit df46b96, this
machine under the same shared load): at rest p50 62 ms, p95 82 ms, the request p50 55 ms, the service 11/15 ms.
"""

from __future__ import annotations

import os
import signal
import statistics
import time

import httpx

from bench.workbench import CHROMIUM, CHROMIUM_ARGS, _p95, _serve

MOVES = 40
SWEEP = 120  # moves of one 5 mm grid step each, sent as fast as the browser takes them


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
            page.evaluate("window.workbench.state.timings = []")
            at = page.evaluate("[...Array(17).keys()].map((k) => window.workbench.editor.toScreen(0.3 + 0.005 * k, 0.5))")
            t_sweep = time.perf_counter()
            for k in range(SWEEP):
                page.mouse.move(*at[k % 16 if (k // 16) % 2 == 0 else 16 - k % 16])
            sweep_s = time.perf_counter() - t_sweep
            page.wait_for_function("window.workbench.state.pending === null && !window.workbench.editor.ed.dragging.queued",
                                   timeout=30_000)
            sweep = [t["total"] for t in page.evaluate("window.workbench.state.timings")]
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
    print(f"sweeping on, {SWEEP} moves in {sweep_s:.1f} s, {len(sweep)} analyses drawn (one in flight at a time):")
    print(f"  oldest move -> redrawn   p50 {statistics.median(sweep):6.1f} ms  p95 {_p95(sweep):6.1f} ms")


if __name__ == "__main__":
    main()
