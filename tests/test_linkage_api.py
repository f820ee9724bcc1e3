"""A six-bar press given as links and joints, over HTTP: analysis, balancing, flywheel, machine design and a study
of its rod length; bad descriptions answered with problems that name the link, joint or angle range."""

from __future__ import annotations

import copy
import math
from typing import Any

import numpy as np
import pytest

import synth
from api.translate.linkage import linkage_from
from mechsynth_client.client import SynthClient
from api.execution.plans import Limits
from mechsynth_client.schemas.analysis import AnalysisIn
from mechsynth_client.schemas.common import SIX_BAR_PRESS_EXAMPLE
from api.studies.tasks import variant_function
from synth.execution import SerialExecutor
from test_linkage import independent

LOAD = [{"type": "window", "force_N": 2000.0, "start_deg": 200.0, "end_deg": 300.0}]
PRESS: dict[str, Any] = {"mechanism": SIX_BAR_PRESS_EXAMPLE, "speed_rpm": 60 * 10 / (2 * math.pi), "samples": 256,
                         "gravity": {"g_m_s2": 9.81}, "loads": LOAD}


def _post(client: SynthClient, path: str, body: dict[str, Any]) -> Any:
    # full precision: the answers are held to independent solutions at their round-off
    return client.http.post(path, json=body, params={"precision": "full"})


def test_press_analysis_over_http_agrees_with_loop_closure(client: SynthClient) -> None:
    # Independent: loop closure by fsolve and the driving torque by virtual power (tests/test_linkage.py) on the
    # same request as the engine takes it; the service answers from its dyads and reaction solve.
    r = _post(client, "/v1/analysis", PRESS)
    assert r.status_code == 200, r.text
    answer = r.json()
    phi, points, torque = independent(linkage_from(AnalysisIn.model_validate(PRESS)), 256)
    assert np.allclose(answer["crank_angle_deg"], np.degrees(phi), rtol=0, atol=1e-12)
    assert np.abs(np.array(answer["driving_torque_Nm"]) - torque).max() < 1e-9 * np.abs(torque).max()
    for name in ("B", "C", "D"):
        assert np.abs(np.array(answer["points"][name]["position_m"]) - points[name]).max() < 1e-9  # [m]
    assert answer["checks"]["virtual_power_torque_max_diff_Nm"] < 1e-9 * np.abs(torque).max()
    assert set(answer["joint_reactions_N"]) == {"O", "A", "B", "Q", "C", "D", "guide"}


def test_press_balancing_over_http(client: SynthClient) -> None:
    body = {"mechanism": SIX_BAR_PRESS_EXAMPLE, "speed_rpm": 95.5, "samples": 90}
    r = _post(client, "/v1/balancing/optimal", body)
    assert r.status_code == 200, r.text
    out = r.json()
    # Counterweights on the links pivoted on the frame, re-analysed with the plain model: the shaking force falls.
    assert {c["link"] for c in out["counterweights"]} <= {"crank", "rocker"}
    assert out["summary_after"]["rms_shaking_force_N"] < out["summary_before"]["rms_shaking_force_N"]
    for mode in ("static", "full"):
        r = _post(client, f"/v1/balancing/{mode}", body)
        assert r.status_code == 422
        assert "ram" in r.json()["detail"] or "guide" in r.json()["detail"]


def test_press_flywheel_and_machine_design_over_http(client: SynthClient) -> None:
    # A pressing force rising from 200 to 250 degrees and falling to 300, against the ram's motion.
    table = [{"type": "crank_table", "crank_angle_deg": [0, 200, 250, 300], "force_N": [0, 0, 2000, 0]}]
    body = {"mechanism": SIX_BAR_PRESS_EXAMPLE, "speed_rpm": 60, "delta": 0.05, "loads": table}
    r = _post(client, "/v1/flywheel", body)
    assert r.status_code == 200, r.text
    fly = r.json()
    # The service's own check: the equation of motion integrated with this flywheel gives the target delta.
    assert fly["achieved_delta"] == pytest.approx(0.05, rel=1e-3)
    # Work of the load over a turn, summed by hand over a fine grid: force times the ram's travel, step by step.
    phi = np.linspace(0.0, 2 * math.pi, 36001)
    ram = synth.motion(synth.PlanarLinkage(*_engine_args()), phi, 1.0).point_pos["D"][:, 1]
    force = np.interp(np.degrees(0.5 * (phi[1:] + phi[:-1])), [0, 200, 250, 300, 360], [0, 0, 2000, 0, 0])
    work = -float(np.sum(force * np.abs(np.diff(ram))))
    assert fly["cycle_work_J"] == pytest.approx(work, rel=1e-3)  # the service integrates over 360 samples
    machine = {"mechanism": SIX_BAR_PRESS_EXAMPLE, "loads": LOAD, "speed_rpm": 120, "delta": 0.03,
               "drive": {"stages": ["helical", "helical"], "synchronous_rpm": 1500},
               "balancing": {"mode": "optimal"},
               "flywheel": {"placement": "lightest", "geometry": {"density_kg_m3": 7850, "max_rim_speed_m_s": 30}}}
    r = _post(client, "/v1/machines/design", machine)
    assert r.status_code == 200, r.text
    design = r.json()
    assert design["passed"] is True
    delta = next(c for c in design["checks"] if c["name"] == "delta")
    assert delta["value"] == pytest.approx(0.03, rel=1e-3)  # simulated over the cycle, against the target


def test_study_varies_a_link_length_by_a_dotted_path() -> None:
    # Three rod lengths of the press through /v1/analysis; each row's RMS torque is the engine's for that rod.
    spec = {"endpoint": "/v1/analysis",
            "base": {"mechanism": SIX_BAR_PRESS_EXAMPLE, "speed_rpm": 60, "samples": 72, "loads": LOAD},
            "parameters": [{"path": "mechanism.links.3.length_m", "values": [0.45, 0.5, 0.55]}],
            "metrics": ["summary.rms_driving_torque_Nm"]}
    rows: list[synth.VariantRow] = []
    executor = SerialExecutor()
    try:
        synth.run_study(synth.study_from_dict(spec), variant_function("/v1/analysis", Limits(20_000, 6, 20.0)),
                        executor, rows.extend)
    finally:
        executor.shutdown()
    for row in sorted(rows, key=lambda r: r.index):
        body = copy.deepcopy(spec["base"])
        body["mechanism"]["links"][3]["length_m"] = row.values[0]
        an = synth.analyse(linkage_from(AnalysisIn.model_validate(body)), 2 * math.pi, samples=72)
        assert row.metrics is not None
        assert row.metrics[0] == pytest.approx(an.summary().rms_driving_torque, rel=1e-12)
    assert len({row.metrics[0] for row in rows if row.metrics}) == 3


def _engine_args() -> tuple[Any, ...]:
    mech = linkage_from(AnalysisIn.model_validate(PRESS)).mechanism
    assert isinstance(mech, synth.PlanarLinkage)
    return mech.frame_points, mech.links, mech.joints, mech.crank_link, mech.output


def _mechanism(**change: Any) -> dict[str, Any]:
    mech = copy.deepcopy(SIX_BAR_PRESS_EXAMPLE)
    mech.update(change)
    return mech


def test_bad_linkages_are_problems_naming_what_is_wrong(client: SynthClient) -> None:
    def problem(mech: dict[str, Any]) -> dict[str, Any]:
        r = _post(client, "/v1/analysis", {"mechanism": mech, "speed_rpm": 60, "samples": 36})
        assert r.status_code == 422, r.text
        assert r.headers["content-type"].startswith("application/problem+json")
        body: dict[str, Any] = r.json()
        return body

    links = SIX_BAR_PRESS_EXAMPLE["links"]
    joints = SIX_BAR_PRESS_EXAMPLE["joints"]
    assert isinstance(links, list) and isinstance(joints, list)
    loose = problem(_mechanism(links=[*links, {"name": "loose", "joints": ["X", "Y"], "length_m": 0.1}]))
    assert loose["field"] == "mechanism.links.loose"
    ghost = problem(_mechanism(joints=[*joints[:-1], {"name": "guide", "kind": "prismatic",
                                                      "links": ["frame", "slide"], "through": "G"}]))
    assert ghost["field"] == "mechanism.joints.guide.links" and "'slide'" in ghost["detail"]
    free = problem(_mechanism(joints=joints[:-1]))
    assert "W = 3n - 2p" in free["detail"] and free["field"] == "mechanism.joints"
    short = copy.deepcopy(links)
    short[3]["length_m"] = 0.3
    gap = problem(_mechanism(links=short))
    assert gap["type"] == "/problems/not-assemblable" and "RRP dyad of links ['rod', 'ram']" in gap["detail"]
    assert gap["not_assemblable_ranges_deg"] and gap["failing_samples"] > 0
    class_three = {
        "type": "linkage", "frame_points_m": {"O": [0, 0], "Q1": [0.4, 0], "Q2": [0.2, 0.5]},
        "links": [{"name": "crank", "joints": ["O", "A"], "length_m": 0.1},
                  {"name": "l1", "joints": ["A", "B"], "length_m": 0.3},
                  {"name": "t", "joints": ["B", "C"], "length_m": 0.2, "points_m": {"E": [0.1, 0.15]}},
                  {"name": "l2", "joints": ["Q1", "C"], "length_m": 0.3},
                  {"name": "l3", "joints": ["S", "E"], "length_m": 0.3}],
        "joints": [{"name": n, "kind": "revolute", "links": ls} for n, ls in
                   (("O", ["frame", "crank"]), ("A", ["crank", "l1"]), ("B", ["l1", "t"]), ("C", ["t", "l2"]),
                    ("Q1", ["frame", "l2"]), ("E", ["t", "l3"]))]
        + [{"name": "Q2", "kind": "prismatic", "links": ["frame", "l3"], "through": "Q2", "point": "S"}],
        "crank": "crank", "output": "l2"}
    # A class-III group is placed numerically when its pairs all turn; with a slide in it, it is refused.
    group = problem(class_three)
    assert "class-3 Assur group" in group["detail"] and "'t'" in group["detail"] and "['Q2']" in group["detail"]
