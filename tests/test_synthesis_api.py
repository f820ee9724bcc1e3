"""/v1/synthesis/* in-process: the seed's fish-tail drive (case task 2) in all seven variants, answers that other
endpoints accept as they are, figures, and problem responses."""

from __future__ import annotations

import json
import math
import os
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import synth

from api.translate.synthesis import path_out, path_spec
from mechsynth_client.client import InfeasibleError, InvalidInputError, SynthClient
from mechsynth_client.schemas.analysis import AnalysisIn
from mechsynth_client.schemas.synthesis import CrankRockerIn, PathIn, PathOut, SliderCrankSynthesisIn

from conftest import CASES

TASK2 = CASES["case_task2_fish_tail_crank_rocker"]
VARIANTS = range(len(TASK2["inputs"]["swing_deg"]))


@pytest.mark.parametrize("i", VARIANTS)
def test_seed_task2_fish_tail_variant(client: SynthClient, i: int) -> None:
    inp, exp, rel = TASK2["inputs"], TASK2["expected"], TASK2["tolerance_rel"]
    # N strokes per minute is the crank speed (one double swing per turn); the fin is the rocker.
    body = CrankRockerIn(swing_deg=inp["swing_deg"][i], time_ratio=inp["k_time_ratio"][i],
                         scale_link="rocker", scale_length_m=inp["l_fin_m"][i], speed_rpm=inp["N_per_min"][i])
    out = client.synthesise_crank_rocker(body)
    check = out.check
    # The request met, as the analysis engine re-finds it: to 1e-6 as the issue asks.
    assert check.swing_deg == pytest.approx(inp["swing_deg"][i], abs=1e-6)
    assert check.time_ratio == pytest.approx(inp["k_time_ratio"][i], abs=1e-6)
    # The seed's derived quantities, printed to six places (hence abs 5e-7 beside the case's relative tolerance).
    assert out.crank_speed_rad_s == pytest.approx(exp["omega_crank_rad_s"][i], rel=rel, abs=5e-7)
    assert check.overlap_angle_deg == pytest.approx(exp["crank_overlap_angle_deg"][i], rel=rel, abs=5e-7)
    assert check.cycle_time_s == pytest.approx(exp["t_cycle_s"][i], rel=rel, abs=5e-7)
    assert check.slow_stroke_time_s == pytest.approx(exp["t_work_s"][i], rel=rel, abs=5e-7)
    assert check.rocker_tip_chord_m == pytest.approx(exp["fin_tip_chord_m"][i], rel=rel, abs=5e-7)
    assert out.grashof == "crank-rocker"
    assert out.optimality.conditions_met and out.optimality.gap_bound < 1e-3
    # The answer's minimum transmission angle is the objective it reports.
    assert check.transmission_angle.min_deg == pytest.approx(out.objective_value, abs=1e-9)


def test_crank_rocker_answer_goes_to_analysis_and_balancing(client: SynthClient) -> None:
    example = CrankRockerIn.model_config["json_schema_extra"]["examples"][1]
    out = client.synthesise_crank_rocker(CrankRockerIn.model_validate(example))
    mech = out.mechanism.model_dump()
    assert mech["links"]["coupler"]["mass_kg"] == pytest.approx(2 * mech["coupler_length_m"], rel=1e-12)
    analysis = client.analysis(AnalysisIn.model_validate(
        {"mechanism": mech, "speed_rpm": example["speed_rpm"], "samples": example.get("samples", 120),
         "loads": example["loads"]}))
    # The objective is the analysis engine's peak driving torque of this very linkage and load.
    assert analysis.summary.max_driving_torque_Nm == pytest.approx(out.objective_value, rel=1e-9)
    assert min(analysis.transmission_angle_deg or [0]) >= out.check.transmission_angle.min_deg - 1e-9
    r = client.http.post("/v1/balancing/static", json={"mechanism": mech, "speed_rpm": example["speed_rpm"]})
    assert r.status_code == 200, r.text


def test_slider_crank_answer_goes_to_analysis(client: SynthClient) -> None:
    example = SliderCrankSynthesisIn.model_config["json_schema_extra"]["examples"][0]
    out = client.synthesise_slider_crank(SliderCrankSynthesisIn.model_validate(example))
    assert out.check.stroke_m == pytest.approx(example["stroke_m"], rel=1e-9)
    assert out.check.time_ratio == pytest.approx(example["time_ratio"], rel=1e-9)
    assert out.check.slider_position_m[1] > out.check.slider_position_m[0]   # slow stroke along +x, as asked
    analysis = client.analysis(AnalysisIn.model_validate({"mechanism": out.mechanism.model_dump(), "samples": 720}))
    x = np.array(analysis.points["B"].position_m)[:, 0]
    assert np.ptp(x) == pytest.approx(example["stroke_m"], rel=1e-4)   # 720 samples near flat extremes


def test_path_answer_traces_the_targets_in_analysis(client: SynthClient) -> None:
    example = PathIn.model_config["json_schema_extra"]["examples"][0]
    out = client.synthesise_path(PathIn.model_validate(example))
    # The example's points are a coupler curve rounded to 0.1 mm: the best residual is of that order.
    assert out.max_residual_m < 2e-4 and out.starts_at_best >= 1
    analysis = client.analysis(AnalysisIn.model_validate(
        {"mechanism": out.mechanism.model_dump(), "crank_angle_deg": out.crank_angle_deg,
         "trace_points": [out.trace_point.model_dump()]}))
    g = math.radians(out.ground_angle_deg)
    rot = np.array([[math.cos(g), -math.sin(g)], [math.sin(g), math.cos(g)]])
    world = np.array(analysis.points["P"].position_m) @ rot.T + np.array(out.crank_pivot_m)
    dist = np.hypot(*(world - np.array(example["points_m"])).T)
    assert dist == pytest.approx(out.residuals_m, abs=1e-12)


@pytest.mark.parametrize(("path", "model"), [("crank-rocker", CrankRockerIn), ("slider-crank", SliderCrankSynthesisIn)])
def test_examples_and_figures(client: SynthClient, path: str, model: Any) -> None:
    for example in model.model_config["json_schema_extra"]["examples"]:
        r = client.http.post(f"/v1/synthesis/{path}?format=png", json=example)
        assert r.status_code == 200 and r.headers["content-type"] == "image/png"
        assert r.content[:8] == b"\x89PNG\r\n\x1a\n"


def test_problems(client: SynthClient) -> None:
    with pytest.raises(InfeasibleError) as inf:
        client.synthesise_crank_rocker(CrankRockerIn(swing_deg=40, time_ratio=1.1, scale_length_m=0.15,
                                                     bounds_m={"coupler": {"min_m": 1.0, "max_m": 2.0}}))
    assert inf.value.problem["constraint"] == "coupler_length_min"
    with pytest.raises(InvalidInputError) as bad:
        client.synthesise_crank_rocker(CrankRockerIn(swing_deg=40, time_ratio=1.1, scale_length_m=0.15,
                                                     objective="peak_driving_torque"))
    assert bad.value.problem["field"] == "linear_density_kg_m"
    both = client.http.post("/v1/synthesis/slider-crank", json={"stroke_m": 0.1, "time_ratio": 1.2,
                                                                "overlap_angle_deg": 10})
    assert both.status_code == 422
    many = client.http.post("/v1/synthesis/path", json={"points_m": [[0.01 * i, 0.0] for i in range(41)]})
    assert many.status_code == 422


_BASES = [("/v1/synthesis/crank-rocker", CrankRockerIn.model_config["json_schema_extra"]["examples"][0]),
          ("/v1/synthesis/slider-crank", SliderCrankSynthesisIn.model_config["json_schema_extra"]["examples"][0]),
          ("/v1/synthesis/path", {**PathIn.model_config["json_schema_extra"]["examples"][0], "starts": 2})]
_ODD = [0, -1, 1e-300, 1e300, 2.5, 179.999, 1.0, "x", None, [], {}]


@st.composite
def _mutated(draw: st.DrawFn) -> tuple[str, Any]:
    path, body = draw(st.sampled_from(_BASES))
    body = json.loads(json.dumps(body))
    key = draw(st.sampled_from(sorted(body)))
    value = draw(st.sampled_from(_ODD))
    if isinstance(body[key], list) and body[key] and draw(st.booleans()):
        body[key][draw(st.integers(0, len(body[key]) - 1))] = value
    else:
        body[key] = value
    return path, body


@settings(max_examples=int(os.environ.get("SYNTH_FUZZ_EXAMPLES", "40")), deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(_mutated())
def test_mutated_requests_never_answer_500(client: SynthClient, case: tuple[str, Any]) -> None:
    path, body = case
    r = client.http.post(path, json=body)
    assert r.status_code in (200, 413, 422, 504), (path, body, r.status_code, r.text[:500])


def test_path_over_two_workers_answers_what_one_run_of_all_starts_does() -> None:
    # The service deals the starts to its workers and keeps the best; the answer must be the engine's serial one
    # for the same seed, number for number.
    from fastapi.testclient import TestClient

    from api.app import create_app
    from api.settings import Settings

    example = PathIn.model_config["json_schema_extra"]["examples"][0]
    body = PathIn.model_validate(example)
    serial = path_out(synth.synthesise_path(path_spec(body, 60.0)))
    with TestClient(create_app(Settings(executor="pool", workers=2))) as http:
        assert http.get("/ready").json()["workers"] == 2
        answer = http.post("/v1/synthesis/path", json=example)
    assert answer.status_code == 200
    assert answer.json() == json.loads(serial.model_dump_json())
