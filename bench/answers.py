"""What an answer costs beside its computation, and the class-III eight-bar beside the four-bar, measured as they
are judged: the service's own app and worker processes in this process (FastAPI's TestClient), calls alternated so
that a burst of load from other work on the machine falls on both sides of each ratio.

- A 3 600-sample analysis of a four-bar answered as JSON (the default, its curves at one quantum per array)
  against the same answer as npz (goal: at most 1.3x), and with ``?precision=full`` (every float64 exactly) beside
  it; and where the JSON's time goes in the worker's code path: the engine, the answer model, the answer's JSON
  in the default and in full precision, npz's archive of the same numbers, and as many plain floats from one
  numpy array written by the curve writer (``api.curve_text``) and by orjson in float64 and in float32 (its
  shortest text of each float). Those are the floors of a JSON answer in each precision; the answer's JSON
  written within a small factor of them means the rest of the gap is the float text itself.
- The docs' eight-bar (docs/linkages.md, a class-III group placed numerically) against the four-bar at 360 samples,
  in the engine and through the service (goal: at most 5x).

``python -m bench.answers``. The machine's load is printed beside the figures: on a machine whose cores are shared
with other work the medians move 2-5x between runs, the ratios much less.
"""

from __future__ import annotations

import io
import os
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
import orjson

import synth
from api.execution import plans
from api.execution.plans import Limits
from api.curve_text import curve_bytes
from api.media import json_bytes, npz_bytes
from api.settings import Settings
from api.translate.linkage import linkage_from
from bench._timing import interleaved
from mechsynth_client.schemas.analysis import AnalysisIn

SAMPLES = 3600
JSON_GOAL = 1.3
EIGHT_BAR_GOAL = 5.0
FOURBAR: dict[str, Any] = {
    "type": "fourbar", "ground_length_m": 0.30, "crank_length_m": 0.10, "coupler_length_m": 0.35,
    "rocker_length_m": 0.25, "branch": 1,
    "links": {k: {"mass_kg": m, "com_m": [length / 2, 0.0], "inertia_kgm2": m * length * length / 12}
              for k, m, length in (("crank", 1.0, 0.10), ("coupler", 2.0, 0.35), ("rocker", 1.5, 0.25))},
}


def _bar(name: str, a: str, b: str, length: float, **points: list[float]) -> dict[str, Any]:
    return {"name": name, "joints": [a, b], "length_m": length, "points_m": points, "mass_kg": 10 * length,
            "com_m": [length / 2, 0.0], "inertia_kgm2": 10 * length**3 / 12}


def _pin(name: str, a: str, b: str) -> dict[str, Any]:
    return {"name": name, "kind": "revolute", "links": [a, b]}


#: The eight-bar with a triad of docs/linkages.md, as drawn there.
EIGHT_BAR: dict[str, Any] = {
    "type": "linkage",
    "frame_points_m": {"O": [0.0, 0.0], "P": [0.45, 0.05], "R": [0.2, -0.35]},
    "links": [_bar("crank", "O", "A", 0.1), _bar("rod", "A", "B", 0.35),
              _bar("plate", "B", "C", 0.2, D=[0.1, -0.15]), _bar("rocker", "P", "C", 0.3),
              _bar("link", "R", "D", 0.32)],
    "joints": [_pin("O", "frame", "crank"), _pin("A", "crank", "rod"), _pin("B", "rod", "plate"),
               _pin("C", "plate", "rocker"), _pin("P", "frame", "rocker"), _pin("D", "plate", "link"),
               _pin("R", "frame", "link")],
    "crank": "crank", "output": "rocker",
    "assembly_m": {"B": [0.34, -0.26], "C": [0.2, -0.11]},
}


def _load() -> str:
    return f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores"


def worker_path() -> dict[str, tuple[float, float]]:
    """The JSON and npz answers' parts as a worker runs them, and the float-text floor, alternated [s]."""
    body = AnalysisIn.model_validate({"mechanism": FOURBAR, "speed_rpm": 120, "samples": SAMPLES})
    plan = plans.analysis(body, Limits.from_settings(Settings()))
    as_json, as_npz = replace(plan.render, fmt="json", precision="single"), replace(plan.render, fmt="npz")
    as_full = replace(as_json, precision="full")
    result = plan.fn(*plan.args, **plan.kwargs)
    model = plan.render.model(result, *plan.render.model_extra)
    # as many floats as the answer holds (npz keeps each as 8 bytes), drawn over the answers' own magnitudes
    count = sum(a.size for a in np.load(io.BytesIO(npz_bytes(model))).values())
    floats = np.random.default_rng(0).normal(scale=100.0, size=count)
    singles = floats.astype(np.float32)
    return interleaved({
        "request's worker, JSON": lambda: as_json(plan.fn(*plan.args, **plan.kwargs)),
        "request's worker, JSON full precision": lambda: as_full(plan.fn(*plan.args, **plan.kwargs)),
        "request's worker, npz": lambda: as_npz(plan.fn(*plan.args, **plan.kwargs)),
        "engine (synth.analyse)": lambda: plan.fn(*plan.args, **plan.kwargs),
        "answer model": lambda: plan.render.model(result, *plan.render.model_extra),
        "answer's JSON (json_bytes, single)": lambda: json_bytes(model, "single"),
        "answer's JSON (json_bytes, full)": lambda: json_bytes(model, "full"),
        "answer's npz (npz_bytes)": lambda: npz_bytes(model),
        f"curve writer of {count} floats (the floor)": lambda: curve_bytes(floats),
        f"orjson of {count} float64 (full's floor)": lambda: orjson.dumps(floats,
                                                                            option=orjson.OPT_SERIALIZE_NUMPY),
        f"orjson of {count} float32": lambda: orjson.dumps(singles, option=orjson.OPT_SERIALIZE_NUMPY),
    }, 9)


def answer_sizes() -> dict[str, int]:
    """The 3 600-sample answer's bytes as JSON, JSON in full precision and npz."""
    body = AnalysisIn.model_validate({"mechanism": FOURBAR, "speed_rpm": 120, "samples": SAMPLES})
    plan = plans.analysis(body, Limits.from_settings(Settings()))
    model = plan.render.model(plan.fn(*plan.args, **plan.kwargs), *plan.render.model_extra)
    return {"json": len(json_bytes(model, "single")), "full": len(json_bytes(model, "full")),
            "npz": len(npz_bytes(model))}


def engine_eight_bar() -> dict[str, tuple[float, float]]:
    """The eight-bar and the four-bar analysed at 360 samples in the engine, alternated [s]."""
    eight = linkage_from(AnalysisIn.model_validate({"mechanism": EIGHT_BAR, "speed_rpm": 120}))
    four = linkage_from(AnalysisIn.model_validate({"mechanism": FOURBAR, "speed_rpm": 120}))
    omega = 120 * 2 * np.pi / 60
    return interleaved({"eight-bar": lambda: synth.analyse(eight, omega, samples=360),
                        "four-bar": lambda: synth.analyse(four, omega, samples=360)}, 9)


def service() -> dict[str, tuple[float, float]]:
    """Through the service's app and worker processes: the JSON and npz answers, the eight-bar and the
    four-bar, each pair alternated [s]."""
    from fastapi.testclient import TestClient

    from api.app import app

    client = TestClient(app, base_url="http://127.0.0.1")

    def post(path: str, body: dict[str, Any]) -> Callable[[], object]:
        def call() -> object:
            response = client.post(path, json=body)
            assert response.status_code == 200, (path, response.status_code, response.text[:300])
            return response
        return call

    answer = {"mechanism": FOURBAR, "speed_rpm": 120, "samples": SAMPLES}
    with client:
        formats = interleaved({"JSON": post("/v1/analysis", answer),
                               "JSON full": post("/v1/analysis?precision=full", answer),
                               "npz": post("/v1/analysis?format=npz", answer)}, 11)
        linkages = interleaved({
            "eight-bar": post("/v1/analysis", {"mechanism": EIGHT_BAR, "speed_rpm": 120, "samples": 360}),
            "four-bar": post("/v1/analysis", {"mechanism": FOURBAR, "speed_rpm": 120, "samples": 360})}, 11)
    return {**formats, **linkages}


def _row(name: str, t: tuple[float, float]) -> str:
    return f"  {name:44s} {t[0] * 1e3:9.2f} {t[1] * 1e3:9.2f}"


def main() -> None:
    """The worker's parts, the engine's eight-bar, then both through the service."""
    print(f"A {SAMPLES}-sample four-bar analysis in the worker's code path, alternated, min / median [ms] "
          f"({_load()}):")
    w = worker_path()
    for name, t in w.items():
        print(_row(name, t))
    floor = next(t for name, t in w.items() if name.startswith("orjson of") and "float64" in name)
    floor32 = next(t for name, t in w.items() if name.startswith("orjson of") and "float32" in name)
    writer = next(t for name, t in w.items() if name.startswith("curve writer"))
    worker_ratio = w["request's worker, JSON"][1] / w["request's worker, npz"][1]
    full_ratio = w["request's worker, JSON full precision"][1] / w["request's worker, npz"][1]
    single = w["answer's JSON (json_bytes, single)"][1] / writer[1]
    full = w["answer's JSON (json_bytes, full)"][1] / floor[1]
    print(f"  JSON/npz in the worker {worker_ratio:.2f} ({full_ratio:.2f} in full precision); the answer's JSON "
          f"{single:.2f}x the curve writer's floor, in full precision {full:.2f}x orjson's float64 one; the "
          f"writer {writer[1] / floor32[1]:.2f}x orjson's float32 text, {writer[1] / floor[1]:.2f}x its float64")
    sizes = answer_sizes()
    print(f"  answer bytes: JSON {sizes['json'] / 1e6:.2f} MB, full precision {sizes['full'] / 1e6:.2f} MB, "
          f"npz {sizes['npz'] / 1e6:.2f} MB")
    e = engine_eight_bar()
    print(f"The docs' eight-bar against the four-bar at 360 samples in the engine ({_load()}): "
          f"{e['eight-bar'][1] * 1e3:.1f} / {e['four-bar'][1] * 1e3:.2f} ms median, "
          f"{e['eight-bar'][1] / e['four-bar'][1]:.0f}x")
    s = service()
    json_ratio = s["JSON"][1] / s["npz"][1]
    eight_ratio = s["eight-bar"][1] / s["four-bar"][1]
    print(f"Through the service in-process, alternated, median ({_load()}):")
    print(f"  analysis {SAMPLES} samples: JSON {s['JSON'][1] * 1e3:.1f} ms, npz {s['npz'][1] * 1e3:.1f} ms, "
          f"{json_ratio:.2f}x (goal <= {JSON_GOAL:g}: {'met' if json_ratio <= JSON_GOAL else 'not met'}); "
          f"?precision=full {s['JSON full'][1] * 1e3:.1f} ms, {s['JSON full'][1] / s['npz'][1]:.2f}x")
    print(f"  360 samples: eight-bar {s['eight-bar'][1] * 1e3:.1f} ms, four-bar {s['four-bar'][1] * 1e3:.1f} ms, "
          f"{eight_ratio:.1f}x (goal <= {EIGHT_BAR_GOAL:g}: {'met' if eight_ratio <= EIGHT_BAR_GOAL else 'not met'})")


if __name__ == "__main__":
    main()
