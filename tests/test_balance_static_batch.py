"""Static balancing in batches: every variant's answer and every variant's error are those of the single
request (the independent computation is `synth.balance_static` called variant by variant)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

import synth
from api.execution.plans import Limits
from api.studies.tasks import ENDPOINTS, batch_function, run_endpoint, run_endpoint_batch, validate_request
from api.translate.linkage import linkage_from
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE
from synth.balancing import batch as batch_module
from synth.errors import SynthError

ENDPOINT = "/v1/balancing/static"
LIMITS = Limits(max_samples=20_000, max_stages=6, solver_time_limit_s=20.0)
RTOL = 1e-9


def _request(crank: float, coupler: float, rocker: float, budget: float | None, **extra: Any) -> dict[str, Any]:
    mechanism = {**FOURBAR_EXAMPLE, "crank_length_m": crank, "coupler_length_m": coupler, "rocker_length_m": rocker}
    body: dict[str, Any] = {"mechanism": mechanism, "speed_rpm": 300, "samples": 90,
                            "max_radius_m": {"crank": 0.1, "rocker": 0.25}, **extra}
    if budget is not None:
        body["mass_budget_kg"] = budget
    return body


def _requests() -> list[dict[str, Any]]:
    """A study-like mix: link lengths and budgets from a seeded draw (some budgets too small, some four-bars
    that do not close), and one each of the cases the stack must leave to the single path or group apart."""
    rng = np.random.default_rng(7)
    out = [_request(float(rng.uniform(0.05, 0.12)), float(rng.uniform(0.30, 0.40)), float(rng.uniform(0.20, 0.30)),
                    float(rng.uniform(2.0, 6.0))) for _ in range(40)]
    out += [
        _request(0.10, 0.25, 0.25, None),                                   # minimum mass, no budget
        _request(0.10, 0.25, 0.25, 4.0, objective="min_inertia"),            # minimum inertia in a budget
        _request(0.10, 0.25, 0.25, None, objective="min_inertia"),           # error: needs a budget
        _request(0.10, 0.25, 0.25, 4.0, samples=36),                         # another stack (sample count)
        _request(0.10, 0.25, 0.25, 4.0, speed_rpm=120),                      # another stack (crank speed)
        _request(0.10, 0.25, 0.25, None, gravity={"g_m_s2": 9.81}),          # gravity, its own stack
        _request(0.10, 0.25, 0.25, None, method="fixed_points"),             # the closed form, alone
        _request(0.20, 0.35, 0.25, 4.0),                                     # error: a change-point four-bar
        _request(0.12, 0.40, 0.20, 4.0),                                     # error: |AQ| < b - c near 0 deg
        _request(0.05, 0.30, 0.20, 4.0, counterweight_links=["crank", "coupler"],
                 max_radius_m={"crank": 0.1, "coupler": 0.2}),               # error or answer: the coupler's radius
        {"mechanism": {"type": "slider_crank", "crank_length_m": 0.1, "rod_length_m": 0.35,
                       "links": {"crank": {"mass_kg": 1.0, "com_m": [0.05, 0.0]},
                                 "rod": {"mass_kg": 2.0, "com_m": [0.1, 0.0]},
                                 "slider": {"mass_kg": 1.0}}},
         "speed_rpm": 300, "samples": 90},                                   # error: static is for four-bars
        {**_request(0.10, 0.25, 0.25, 4.0), "samples": -3},                  # error: the request's field
    ]
    return out


def _close(a: Any, b: Any, scale: float, where: str) -> None:
    """Equal structure, equal strings, numbers within RTOL relative; values at the level of rounding noise
    (residuals of a balanced linkage, ~1e-13 N) within RTOL of the request's largest figure ``scale``."""
    if isinstance(b, dict):
        assert isinstance(a, dict) and a.keys() == b.keys(), where
        for key in b:
            _close(a[key], b[key], scale, f"{where}.{key}")
    elif isinstance(b, list):
        assert isinstance(a, list) and len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            _close(x, y, scale, f"{where}[{i}]")
    elif isinstance(b, float) and not isinstance(a, bool):
        assert a == pytest.approx(b, rel=RTOL, abs=RTOL * scale), where
    else:
        assert a == b, where


def _scale(answer: dict[str, Any]) -> float:
    before = answer["summary_before"]
    return max(abs(v) for v in before.values() if isinstance(v, float))


def _single(request: dict[str, Any]) -> dict[str, Any] | Exception:
    try:
        return run_endpoint(ENDPOINT, LIMITS, request)
    except Exception as exc:
        return exc


def test_a_batch_answers_every_variant_as_the_endpoint_does() -> None:
    requests = _requests()
    batched = run_endpoint_batch(ENDPOINT, LIMITS, requests)
    singles = [_single(r) for r in requests]
    assert len(batched) == len(requests)
    kinds: dict[str, int] = {}
    for k, (got, want) in enumerate(zip(batched, singles, strict=True)):
        if isinstance(want, Exception):
            # The same error: its type, its message and what it names (field, constraint, figures).
            assert type(got) is type(want) and str(got) == str(want), k
            if isinstance(want, SynthError):
                assert isinstance(got, SynthError) and got.slug == want.slug and got.extras() == want.extras(), k
            kinds[type(want).__name__] = kinds.get(type(want).__name__, 0) + 1
        else:
            assert isinstance(got, dict), (k, got)
            _close(got, want, _scale(want), f"variant {k}")
            kinds["answer"] = kinds.get("answer", 0) + 1
    # The mix holds answers, infeasible budgets, invalid requests and four-bars that do not close.
    assert kinds["answer"] >= 20 and kinds["Infeasible"] >= 3 and kinds["InvalidInput"] >= 3
    assert kinds.get("NotAssemblable", 0) >= 1


def test_the_engine_batch_carries_the_single_analyses() -> None:
    # Below the answer: the analyses before and after (motion, reactions, virtual-power torque, reduced model)
    # of each variant's block of the stack are those of synth.analyse on the variant alone.
    requests = [_request(0.06 + 0.01 * i, 0.35, 0.25, None) for i in range(5)]
    requests.append(_request(0.08, 0.33, 0.22, None, gravity={"g_m_s2": 9.81}))
    plans = [ENDPOINTS[ENDPOINT][1](validate_request(ENDPOINT, r), LIMITS) for r in requests]
    cases = [synth.StaticCase(*p.args, **p.kwargs) for p in plans]
    results = synth.balance_static_batch(cases)
    for case, got in zip(cases, results, strict=True):
        want = synth.balance_static(case.linkage, case.speed, case.spec, samples=case.samples,
                                    mass_budget=case.mass_budget)
        assert isinstance(got, synth.BalanceResult)
        assert got.total_added_mass == pytest.approx(want.total_added_mass, rel=RTOL)
        for g, w in ((got.analysis_before, want.analysis_before), (got.analysis_after, want.analysis_after)):
            scale = float(np.abs(w.kinetostatics.unknowns).max())
            np.testing.assert_allclose(g.kinetostatics.unknowns, w.kinetostatics.unknowns, rtol=RTOL, atol=RTOL * scale)
            np.testing.assert_allclose(g.virtual_power_torque, w.virtual_power_torque, rtol=RTOL, atol=RTOL * scale)
            np.testing.assert_allclose(g.reduced.inertia, w.reduced.inertia, rtol=RTOL)
            np.testing.assert_allclose(g.reduced.load_torque, w.reduced.load_torque, rtol=RTOL, atol=RTOL * scale)
            np.testing.assert_allclose(g.motion.point_pos["S_coupler"], w.motion.point_pos["S_coupler"], rtol=RTOL)
            assert g.motion.samples == w.motion.samples and g.linkage == w.linkage
        # The independent check figure: the re-analysed shaking force of a static balance is rounding noise.
        assert got.residual_force <= 1e-9 * got.before.max_shaking_force


def test_a_stack_with_a_dead_position_falls_back_to_single_requests(monkeypatch: pytest.MonkeyPatch) -> None:
    # A stack the stacked solve refuses is run variant by variant: the same answers as the single path.
    requests = [_request(0.06, 0.35, 0.25, None), _request(0.07, 0.35, 0.25, 1.0)]
    plans = [ENDPOINTS[ENDPOINT][1](validate_request(ENDPOINT, r), LIMITS) for r in requests]
    cases = [synth.StaticCase(*p.args, **p.kwargs) for p in plans]

    def refuse(group: Any, stack: Any) -> Any:
        raise synth.NotAssemblable("a dead position in the stack", phi=np.array([0.0]), ranges_deg=[])

    monkeypatch.setattr(batch_module, "_solve_stack", refuse)
    got = synth.balance_static_batch(cases)
    assert isinstance(got[0], synth.BalanceResult)
    want = synth.balance_static(cases[0].linkage, cases[0].speed, cases[0].spec, samples=90)
    assert got[0].total_added_mass == pytest.approx(want.total_added_mass, rel=RTOL)
    assert isinstance(got[1], synth.Infeasible) and "needs at least" in str(got[1])


def test_only_endpoints_with_a_batched_engine_have_a_batch_function() -> None:
    assert batch_function(ENDPOINT, LIMITS) is not None
    assert batch_function("/v1/analysis", LIMITS) is None
    assert math.isfinite(batch_module.MAX_STACK_SAMPLES)


@pytest.mark.parametrize("mechanism", ["fourbar", "slider_crank", "six_bar"])
def test_the_shaking_force_rows_from_their_definition_are_the_linear_maps(mechanism: str) -> None:
    # Static balancing takes the map's shaking-force rows from -Σ m·a_S; the independent computation is
    # linear_map's rows, from the reaction solve, with gravity, a process load, a link torque and a crank
    # acceleration that the definition says shake nothing beyond the inertia forces.
    from mechsynth_client.schemas.balancing import SLIDER_CRANK_EXAMPLE
    from mechsynth_client.schemas.common import SIX_BAR_PRESS_EXAMPLE
    from synth.kinematics import cycle_angles, motion
    from synth.kinetostatics import linear_map, shaking_force_map

    body = {"fourbar": FOURBAR_EXAMPLE, "slider_crank": SLIDER_CRANK_EXAMPLE, "six_bar": SIX_BAR_PRESS_EXAMPLE}
    request = {"mechanism": body[mechanism], "speed_rpm": 300, "gravity": {"g_m_s2": 9.81},
               "loads": [{"type": "window", "force_N" if mechanism != "fourbar" else "torque_Nm": 50.0}],
               "torques": [{"link": "crank", "torque_Nm": 3.0}]}
    linkage = linkage_from(validate_request("/v1/analysis", request))  # type: ignore[arg-type]
    mot = motion(linkage.mechanism, cycle_angles(72, 2 * math.pi, 1000), 31.4, 12.0)
    lm = linear_map(mot, linkage)
    want = lm.y[:, lm.force_rows, :]
    np.testing.assert_allclose(shaking_force_map(mot, linkage), want, rtol=0, atol=1e-12 * np.abs(want).max())
    assert np.abs(lm.y0[:, lm.force_rows]).max() <= 1e-12 * np.abs(want).max()


def test_stacked_four_bar_kinematics_are_each_four_bars_own() -> None:
    # Independent computation: synth.kinematics.motion of each four-bar alone (FourBar.solve); a four-bar whose
    # loop does not close is flagged, and alone it raises NotAssemblable.
    from synth.kinematics import FourBar, cycle_angles, motion
    from synth.kinematics.stacking import motion_block, stacked_fourbar_motion

    rng = np.random.default_rng(11)
    fourbars = [FourBar(0.3, float(rng.uniform(0.05, 0.14)), float(rng.uniform(0.28, 0.42)),
                        float(rng.uniform(0.18, 0.3)), int(rng.choice([1, -1]))) for _ in range(30)]
    phi = cycle_angles(60, 2 * math.pi, 1000)
    stack, bad = stacked_fourbar_motion(fourbars, phi, 31.4, 3.0)
    for k, fb in enumerate(fourbars):
        if bad[k]:
            with pytest.raises(synth.NotAssemblable):
                motion(fb, phi, 31.4, 3.0)
            continue
        alone, block = motion(fb, phi, 31.4, 3.0), motion_block(stack, 60 * k, 60 * (k + 1))
        for name in ("point_pos", "point_vel", "point_acc", "link_angle", "link_omega", "link_alpha"):
            for key, want in getattr(alone, name).items():
                np.testing.assert_allclose(getattr(block, name)[key], want, rtol=1e-12, atol=1e-12 * np.abs(want).max())
    assert 0 < int(bad.sum()) < len(fourbars)


def test_link_arrays_per_sample_with_one_linkages_masses_are_link_arrays() -> None:
    # Independent computation: link_arrays with the linkage's own (L, 4) parameters.
    from synth.kinematics import cycle_angles, motion
    from synth.kinetostatics import link_arrays, link_arrays_per_sample

    linkage = linkage_from(validate_request(ENDPOINT, _request(0.1, 0.3, 0.25, None)))  # type: ignore[arg-type]
    mot = motion(linkage.mechanism, cycle_angles(40, 2 * math.pi, 1000), 20.0)
    want = link_arrays(mot, linkage)
    params = np.repeat(linkage.params().reshape(-1, 1, 4), 40, axis=1)
    got = link_arrays_per_sample(mot, linkage, params)
    np.testing.assert_allclose(got.mass, np.repeat(want.mass[:, None], 40, axis=1), rtol=1e-15)
    np.testing.assert_allclose(got.inertia, np.repeat(want.inertia[:, None], 40, axis=1), rtol=1e-12)
    for name in ("com_pos", "com_vel", "com_acc"):
        np.testing.assert_allclose(getattr(got, name), getattr(want, name), rtol=1e-12, atol=1e-12)


def test_row_spaces_of_a_stack_are_each_systems_row_space() -> None:
    # Independent computation: row_space of each system alone. The stack holds rank-deficient systems (repeated
    # columns), a consistent right-hand side and one outside the column space, whose error is the same.
    from synth.balancing.program import row_space, row_spaces

    rng = np.random.default_rng(3)
    base = rng.normal(size=(6, 120, 3))
    a = np.concatenate([base, base[:, :, :1] * 2.0, rng.normal(size=(6, 120, 1))], axis=2)  # rank 4 of 5
    b = np.einsum("kmn,kn->km", a, rng.normal(size=(6, 5)))
    b[4] += rng.normal(size=120)   # no x meets it
    got = row_spaces(a, b, "the shaking force", "counterweight_links")
    for k in range(6):
        if k == 4:
            with pytest.raises(synth.Infeasible) as info:
                row_space(a[k], b[k], "the shaking force", "counterweight_links")
            assert isinstance(got[k], synth.Infeasible) and str(got[k]) == str(info.value)
            assert got[k].extras() == info.value.extras()
            continue
        want = row_space(a[k], b[k], "the shaking force", "counterweight_links")
        result = got[k]
        assert not isinstance(result, Exception) and result[0].shape == (4, 5)
        np.testing.assert_allclose(result[0], want[0], rtol=0, atol=1e-13 * np.abs(want[0]).max())
        np.testing.assert_allclose(result[1], want[1], rtol=0, atol=1e-13 * np.abs(want[1]).max())


def test_a_batch_with_errors_leaves_nothing_for_the_cycle_collector() -> None:
    # A variant's error kept with its traceback would hold the frame that caught it, whose lists hold the
    # error: the whole batch's arrays would wait for a full collection. Counted by the collector itself.
    import gc

    requests = _requests()
    run_endpoint_batch(ENDPOINT, LIMITS, requests)  # imports and caches settle first
    gc.collect()
    enabled = gc.isenabled()
    gc.disable()
    try:
        answers = run_endpoint_batch(ENDPOINT, LIMITS, requests)
        assert sum(isinstance(a, synth.Infeasible) for a in answers) >= 3
        del answers
        assert gc.collect() == 0
    finally:
        if enabled:
            gc.enable()
