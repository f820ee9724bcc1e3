"""Analysis against hand-written closed forms in the same run, then the request and its serialisation.

First the four-bar at its floor: ``bench.closed_forms.fourbar_careful`` computes every output the engine returns
the fastest way numpy allows (constants folded, trigonometry once, no per-link objects); the engine is timed
against it at 3 angles (the fixed cost of a call), 360, 3 600 and 36 000, beside the previous baseline
(``closed_forms.fourbar``), with the Python calls per analysis. The goal there: at most 2x the careful form.

Then every family against the previous baseline's closed forms:
For every family (four-bar, slider-crank, and the six-bar press as a linkage of dyads) ``bench.closed_forms`` has a
vectorised numpy closed form that computes every array ``synth.analyse`` returns, written the fastest way numpy
allows (plane vectors as complex numbers, each dyad's reactions from its two moment equations); each is checked
equal to the engine to 1e-12 of its scale before it is timed. The goal is the engine within 3x of it. Engine and closed form are timed in alternation (a burst of load
from other developers' work on the shared machine falls on both), at 90, 360, 3600 and 20 000 crank angles, with
the allocator as the service's workers set it; minimum and median of each, and their ratio. Then the per-angle
loop a user would write, POST /v1/analysis at 3600 samples in-process, and the response's JSON written by orjson
against pydantic's model_dump_json of the same answer.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable

import numpy as np

import synth
from api.translate.analysis import analysis_out
from api.translate.linkage import linkage_from
from mechsynth_client.client import SynthClient
from api.media import json_bytes
from mechsynth_client.schemas.analysis import AnalysisIn, AnalysisOut
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE, SIX_BAR_PRESS_EXAMPLE
from bench import closed_forms
from bench._timing import asgi_medians, interleaved, median_of
from synth.execution import keep_freed_memory

SAMPLES = 3600
SIZES = (90, 360, 3600, 20_000)
OMEGA = 30.0
TOLERANCE = 1e-12
GOAL_RATIO = 3.0
SLIDER_CRANK = {
    "type": "slider_crank", "crank_length_m": 0.1, "rod_length_m": 0.35, "offset_m": 0.02, "branch": 1,
    "links": {"crank": {"mass_kg": 1.0, "com_m": [0.03, 0.01], "inertia_kgm2": 0.001},
              "rod": {"mass_kg": 2.0, "com_m": [0.12, 0.01], "inertia_kgm2": 0.02},
              "slider": {"mass_kg": 3.0, "com_m": [0.0, 0.0], "inertia_kgm2": 0.0}},
}
FAMILIES: dict[str, tuple[dict[str, object], Callable[[synth.Linkage, np.ndarray, float], closed_forms.Outputs]]] = {
    "four-bar": (FOURBAR_EXAMPLE, closed_forms.fourbar),
    "slider-crank": (SLIDER_CRANK, closed_forms.slider_crank),
    "six-bar press (linkage of dyads)": (SIX_BAR_PRESS_EXAMPLE, closed_forms.six_bar_press),
}


def _linkage(mechanism: dict[str, object] = FOURBAR_EXAMPLE) -> synth.Linkage:
    """The mechanism with gravity on, so that every term of the closed forms is exercised."""
    return linkage_from(AnalysisIn.model_validate({"mechanism": mechanism, "gravity": {"g_m_s2": 9.81}}))


def compare_families(sizes: tuple[int, ...] = SIZES) -> list[tuple[str, int, float, float, float, float]]:
    """Each family at each size: (family, angles, engine min, engine median, closed-form min, median) [s], after
    checking that the closed form computes every array the engine returns, equal to ``TOLERANCE``."""
    rows = []
    for family, (mechanism, closed) in FAMILIES.items():
        linkage = _linkage(mechanism)
        for n in sizes:
            phi = synth.cycle_angles(n)
            reference = closed(linkage, phi, OMEGA)
            engine = closed_forms.engine_outputs(synth.analyse(linkage, OMEGA, samples=n), list(reference))
            worst, where = closed_forms.worst_relative_difference(engine, reference)
            assert worst < TOLERANCE, f"{family}, {n} angles: the closed form disagrees at {where} by {worst:.1e}"
            repeat = max(5, min(61, 600_000 // (n * 40)))
            t = interleaved({"engine": lambda: synth.analyse(linkage, OMEGA, samples=n),
                             "closed": lambda: closed(linkage, phi, OMEGA)}, repeat)
            rows.append((family, n, *t["engine"], *t["closed"]))
    return rows


def print_families(rows: list[tuple[str, int, float, float, float, float]]) -> None:
    """The table of engine against closed form."""
    print(f"synth.analyse against a vectorised closed form of every output it returns (checked equal to "
          f"{TOLERANCE:.0e} of scale), alternated, min / median [ms]:")
    print(f"  {'mechanism':34s} {'angles':>6s} {'engine':>17s} {'closed form':>17s} {'ratio min/median':>17s}"
          f"  goal <= {GOAL_RATIO:g}x")
    for family, n, e_min, e_med, c_min, c_med in rows:
        ratio = e_min / c_min
        print(f"  {family:34s} {n:6d} {e_min * 1e3:8.3f}/{e_med * 1e3:8.3f} {c_min * 1e3:8.3f}/{c_med * 1e3:8.3f}"
              f" {ratio:8.2f}/{e_med / c_med:.2f}  {'met' if ratio <= GOAL_RATIO else 'not met'}")


#: Sizes of the floor comparison: 3 samples measures the fixed cost of a call, the rest the cost per sample.
FLOOR_SIZES = (3, 360, 3600, 36_000)
FLOOR_GOAL = 2.0
FIXED_COST_GOAL = 0.3e-3


def python_calls(fn: Callable[[], object], runs: int = 20) -> float:
    """Python function calls (the interpreter's and numpy's functions written in Python included, C functions
    too as cProfile counts them) per call of ``fn``."""
    import cProfile
    import pstats

    fn()
    profile = cProfile.Profile()
    profile.enable()
    for _ in range(runs):
        fn()
    profile.disable()
    return pstats.Stats(profile).total_calls / runs  # type: ignore[attr-defined, no-any-return]


def compare_floor(sizes: tuple[int, ...] = FLOOR_SIZES) -> list[tuple[int, tuple[float, float], tuple[float, float],
                                                                       tuple[float, float]]]:
    """The four-bar (gravity on) at each size: engine, the careful closed form and the previous baseline's
    closed form, alternated, each (min, median) [s], after checking both closed forms equal to the engine."""
    linkage = _linkage(FOURBAR_EXAMPLE)
    rows = []
    for n in sizes:
        phi = synth.cycle_angles(n)
        engine = synth.analyse(linkage, OMEGA, samples=n)
        for closed in (closed_forms.fourbar_careful, closed_forms.fourbar):
            reference = closed(linkage, phi, OMEGA)
            worst, where = closed_forms.worst_relative_difference(
                closed_forms.engine_outputs(engine, list(reference)), reference)
            assert worst < TOLERANCE, f"{closed.__name__}, {n} angles: disagrees at {where} by {worst:.1e}"
        repeat = max(7, min(201, 1_500_000 // (n * 40 + 2000)))
        t = interleaved({"engine": lambda: synth.analyse(linkage, OMEGA, samples=n),
                         "careful": lambda: closed_forms.fourbar_careful(linkage, phi, OMEGA),
                         "previous": lambda: closed_forms.fourbar(linkage, phi, OMEGA)}, repeat)
        rows.append((n, t["engine"], t["careful"], t["previous"]))
    return rows


def print_floor(rows: list[tuple[int, tuple[float, float], tuple[float, float], tuple[float, float]]]) -> None:
    """The floor table: the engine against the careful closed form, beside the previous baseline."""
    import os

    print(f"The four-bar's analysis at its floor: synth.analyse against the careful closed form "
          f"(closed_forms.fourbar_careful) and the previous baseline (closed_forms.fourbar), alternated, "
          f"min / median [ms] (load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores):")
    print(f"  {'angles':>6s} {'engine':>17s} {'careful':>17s} {'previous':>17s} {'/careful':>11s} {'/previous':>11s}"
          f"  goal <= {FLOOR_GOAL:g}x the careful form")
    for n, e, c, p in rows:
        ratio = e[0] / c[0]
        print(f"  {n:6d} {e[0] * 1e3:8.3f}/{e[1] * 1e3:8.3f} {c[0] * 1e3:8.3f}/{c[1] * 1e3:8.3f} "
              f"{p[0] * 1e3:8.3f}/{p[1] * 1e3:8.3f} {ratio:5.2f}/{e[1] / c[1]:4.2f} {e[0] / p[0]:5.2f}/{e[1] / p[1]:4.2f}"
              f"  {'met' if ratio <= FLOOR_GOAL else 'not met'}")
    linkage = _linkage(FOURBAR_EXAMPLE)
    fixed = rows[0][1][0] if rows and rows[0][0] == 3 else float("nan")
    calls = python_calls(lambda: synth.analyse(linkage, OMEGA, samples=3))
    careful_calls = python_calls(lambda: closed_forms.fourbar_careful(linkage, synth.cycle_angles(3), OMEGA))
    print(f"  fixed cost per analysis (3 angles, min): {fixed * 1e3:.3f} ms (goal <= {FIXED_COST_GOAL * 1e3:g} ms: "
          f"{'met' if fixed <= FIXED_COST_GOAL else 'not met'}); {calls:.0f} function calls (the careful form "
          f"{careful_calls:.0f})")


def per_angle_torque(linkage: synth.Linkage, phi: np.ndarray, omega: float) -> np.ndarray:
    """Driving torque angle by angle, the way a user would write it: closed-form kinematics, then one 9x9
    reaction solve per angle."""
    fb = linkage.mechanism
    assert isinstance(fb, synth.FourBar)
    a, b, c, d = fb.crank, fb.coupler, fb.rocker, fb.ground
    props = [linkage.mass_props(n) for n in ("crank", "coupler", "rocker")]
    out = np.empty(len(phi))

    def rot(t: float, v: tuple[float, float]) -> np.ndarray:
        return np.array([math.cos(t) * v[0] - math.sin(t) * v[1], math.sin(t) * v[0] + math.cos(t) * v[1]])

    def kperp(v: np.ndarray) -> np.ndarray:
        return np.array([-v[1], v[0]])

    for i, p in enumerate(phi):
        ax, ay = a * math.cos(p), a * math.sin(p)
        qx, qy = d - ax, -ay
        dist = math.hypot(qx, qy)
        t2 = math.atan2(qy, qx) + fb.branch * math.acos((b * b + dist * dist - c * c) / (2 * b * dist))
        bx, by = ax + b * math.cos(t2), ay + b * math.sin(t2)
        t3 = math.atan2(by, bx - d)
        e1, e2, e3 = (np.array([math.cos(t), math.sin(t)]) for t in (p, t2, t3))
        m2 = np.column_stack([b * kperp(e2), -c * kperp(e3)])
        w2, w3 = np.linalg.solve(m2, -a * omega * kperp(e1))
        rhs = a * omega**2 * e1 + b * w2**2 * e2 - c * w3**2 * e3
        al2, al3 = np.linalg.solve(m2, rhs)
        pos_a, pos_q = np.array([ax, ay]), np.array([d, 0.0])
        pos_b = np.array([bx, by])
        acc_a = -a * omega**2 * e1
        frames = [(np.zeros(2), p, omega, 0.0, np.zeros(2)),
                  (pos_a, t2, w2, al2, acc_a),
                  (pos_q, t3, w3, al3, np.zeros(2))]
        mat = np.zeros((9, 9))
        known = np.zeros(9)
        joints = [(None, 0, np.zeros(2)), (0, 1, pos_a), (1, 2, pos_b), (None, 2, pos_q)]
        for j, (giver, receiver, pt) in enumerate(joints):
            for body, sign in ((receiver, 1.0), (giver, -1.0)):
                if body is None:
                    continue
                lever = pt - frames[body][0]
                mat[3 * body, 2 * j] += sign
                mat[3 * body + 1, 2 * j + 1] += sign
                mat[3 * body + 2, 2 * j] -= sign * lever[1]
                mat[3 * body + 2, 2 * j + 1] += sign * lever[0]
        mat[2, 8] = 1.0
        for k, (_origin, th, w, al, acc_o) in enumerate(frames):
            r = rot(th, props[k].com)
            acc_s = acc_o + al * kperp(r) - w**2 * r
            force = -props[k].mass * acc_s
            known[3 * k : 3 * k + 2] = force
            known[3 * k + 2] = r[0] * force[1] - r[1] * force[0] - props[k].inertia * al
        out[i] = np.linalg.solve(mat, -known)[8]
    return out


def main() -> None:
    """Every family against its closed form at every size, the per-angle loop, then the request and its JSON."""
    keep_freed_memory()  # the allocator as the service's workers set it, for both sides of every ratio
    print_floor(compare_floor())
    print_families(compare_families())
    linkage = linkage_from(AnalysisIn.model_validate({"mechanism": FOURBAR_EXAMPLE}))  # the loop has no gravity
    phi = synth.cycle_angles(SAMPLES)
    engine = synth.analyse(linkage, OMEGA, samples=SAMPLES)
    loop_torque = per_angle_torque(linkage, phi, OMEGA)
    diff = float(np.abs(engine.kinetostatics.driving_torque - loop_torque).max())
    assert diff < 1e-9 * (1 + float(np.abs(loop_torque).max())), f"the per-angle loop disagrees by {diff}"
    t = interleaved({"engine": lambda: synth.analyse(linkage, OMEGA, samples=SAMPLES),
                     "loop": lambda: per_angle_torque(linkage, phi, OMEGA)}, 3)
    print(f"  per-angle closed-form loop (torque only), four-bar, {SAMPLES} angles: {t['loop'][1] * 1e3:7.2f} ms median,"
          f" engine {t['loop'][1] / t['engine'][1]:.0f}x faster")

    client = SynthClient.in_process()
    body = AnalysisIn.model_validate({"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": SAMPLES})
    payload = body.model_dump(mode="json", exclude_none=True)
    # The raw POST: the server's whole work and the transport, not the client's own parsing of the answer.
    t_req = median_of(lambda: client.http.post("/v1/analysis", json=payload).raise_for_status(), 15)
    t_health = median_of(client.health, 15)
    out = analysis_out(engine)
    t_orjson = median_of(lambda: json_bytes(analysis_out(engine)), 15)
    t_pydantic = median_of(lambda: analysis_out(engine).to_lists().model_dump_json(), 5)
    assert json.loads(json_bytes(out)) == json.loads(out.to_lists().model_dump_json())
    asgi = asgi_medians({"analysis": ("POST", "/v1/analysis", payload), "health": ("GET", "/health", None)}, 15)
    print(f"POST /v1/analysis, {SAMPLES} samples, in-process (raw POST, the client does not parse the answer):")
    print(f"  over ASGI from an event loop (the service's work): {asgi['analysis'] * 1e3:.2f} ms "
          f"(GET /health {asgi['health'] * 1e3:.2f} ms)")
    print(f"  through the synchronous client (its thread hand-offs included): {t_req * 1e3:.2f} ms "
          f"(GET /health {t_health * 1e3:.2f} ms)")
    print(f"  response JSON from the engine's arrays: orjson {t_orjson * 1e3:.2f} ms, pydantic model_dump_json "
          f"{t_pydantic * 1e3:.2f} ms ({t_pydantic / t_orjson:.0f}x), same parsed content")


if __name__ == "__main__":
    main()
