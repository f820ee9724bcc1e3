"""The lecture-10 shaper's seed cases through POST /v1/analysis: kinematics, the Assur groups' reactions, the
crank's torque and Zhukovsky's lever, at the lecture's position (crank angle 0)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.analysis import AnalysisIn, AnalysisOut
from conftest import CASES

EXACT = CASES["l10_shaper_drive_torque_exact"]


def _shaper(client: SynthClient, inputs: dict[str, Any], *, load: bool = True, gravity: bool = True,
            masses: tuple[str, ...] = ("crank", "rocker", "ram")) -> AnalysisOut:
    # The seed's shaper [000:219-353] as a request: ram guide 0.7 m above O1 and the cutting force 0.1 m below
    # the ram's centre of mass where a case does not give them (from the kinetostatic case).
    links = {
        "crank": {"mass_kg": inputs.get("m1_kg", 0.0)},
        "rocker": {"mass_kg": inputs.get("m3_kg", 0.0), "com_m": [inputs["l_O1S3_m"], 0.0],
                   "inertia_kgm2": inputs.get("J3_kgm2", 0.0)},
        "ram": {"mass_kg": inputs.get("m5_kg", 0.0)},
    }
    body: dict[str, Any] = {
        "mechanism": {"type": "slotted_lever", "crank_length_m": inputs["l_OA_m"],
                      "ground_length_m": inputs["l_O1O_m"], "rocker_length_m": inputs["l_O1B_m"],
                      "ram_height_m": inputs.get("h_m", 0.7),
                      "links": {k: v for k, v in links.items() if k in masses}},
        "speed_rpm": inputs["omega1_rad_s"] * 30 / math.pi,
        "crank_angle_deg": [0.0],
    }
    if gravity:
        body["gravity"] = {"g_m_s2": inputs.get("g_m_s2", 9.81)}
    if load:
        body["loads"] = [{"type": "window", "force_N": inputs["P_cut_N"], "start_deg": -60, "end_deg": 60,
                          "point_m": [0, -inputs["b_m"]]}]
    return client.analysis(AnalysisIn.model_validate(body))


def _xy(values: list[list[float]]) -> np.ndarray:
    return np.asarray(values[0])


@pytest.mark.parametrize("case_id", ["l10_shaper_kinematics_exact", "l10_shaper_kinematics_plan"])
def test_shaper_kinematics(client: SynthClient, case_id: str) -> None:
    case = CASES[case_id]
    inp, exp, rel = case["inputs"], case["expected"], case["tolerance_rel"]
    out = _shaper(client, {**EXACT["inputs"], **inp}, load=False)
    rocker, p = out.links["rocker"], out.points
    psi = math.pi / 2 - math.radians(rocker.angle_deg[0])
    got = {
        "omega3_rad_s": rocker.angular_velocity_rad_s[0],
        "eps3_rad_s2": rocker.angular_acceleration_rad_s2[0],
        "v_ram_m_s": abs(p["R"].velocity_m_s[0][0]),
        "a_ram_m_s2": abs(p["R"].acceleration_m_s2[0][0]),
        "a_S5_m_s2": abs(p["S_ram"].acceleration_m_s2[0][0]),
        "v_S3_m_s": float(np.hypot(*_xy(p["S_rocker"].velocity_m_s))),
        "a_S3_m_s2": float(np.hypot(*_xy(p["S_rocker"].acceleration_m_s2))),
        "l_O1A_m": float(np.hypot(*(_xy(p["A"].position_m) - _xy(p["O1"].position_m)))),
        "psi_deg": math.degrees(psi),
        "v_A3_over_v_A": math.sin(psi),
    }
    for key, value in exp.items():
        assert got[key] == pytest.approx(value, rel=rel), key


def test_shaper_ram_and_rocker_groups(client: SynthClient) -> None:
    out = _shaper(client, EXACT["inputs"])
    r, p = out.joint_reactions_N, out.points
    ram = CASES["l10_shaper_kinetostatics_ram_group"]
    exp, rel = ram["expected"], ram["tolerance_rel"]
    assert abs(r["B_slot"][0][0]) == pytest.approx(exp["R45_N"], rel=rel)
    assert r["R"][0][1] == pytest.approx(exp["R05_N"], rel=rel)
    assert p["S_ram"].position_m[0][1] - p["B"].position_m[0][1] == pytest.approx(exp["d_m"], rel=rel)
    assert out.prismatic_couples_Nm["R"][0] / r["R"][0][1] == pytest.approx(exp["k_m"], rel=rel)
    rocker = CASES["l10_shaper_kinetostatics_rocker_group"]
    exp, rel = rocker["expected"], rocker["tolerance_rel"]
    o1, a, b = (_xy(p[k].position_m) for k in ("O1", "A", "B"))
    assert float(np.hypot(*(a - o1))) == pytest.approx(exp["l_O1A_m"], rel=rel)
    assert b[1] - o1[1] == pytest.approx(exp["h43_m"], rel=rel)
    assert float(np.hypot(*r["A_slot"][0])) == pytest.approx(exp["R23_N"], rel=rel)
    assert float(np.hypot(*r["O1"][0])) == pytest.approx(exp["R03_N_with_Phi3"], rel=rel)


def test_shaper_crank_torque_and_zhukovsky_lever(client: SynthClient) -> None:
    crank = CASES["l10_shaper_crank_drive_torque"]
    out = _shaper(client, EXACT["inputs"])
    assert out.driving_torque_Nm[0] == pytest.approx(crank["expected"]["M_drive_Nm"], rel=crank["tolerance_rel"])
    assert float(np.hypot(*out.joint_reactions_N["O"][0])) == pytest.approx(crank["expected"]["R01_N"],
                                                                            rel=crank["tolerance_rel"])
    # The lecture's lever neglects the rocker's inertia but keeps its weight: by linearity in the loads, the
    # torque with the ram alone plus the rocker's weight alone (its torque with gravity minus without).
    lever = CASES["l10_shaper_zhukovsky_lever"]
    inp = EXACT["inputs"]
    torque = (_shaper(client, inp, masses=("ram",)).driving_torque_Nm[0]
              + _shaper(client, inp, load=False, masses=("rocker",)).driving_torque_Nm[0]
              - _shaper(client, inp, load=False, gravity=False, masses=("rocker",)).driving_torque_Nm[0])
    assert torque == pytest.approx(lever["expected"]["M_drive_Nm"], rel=lever["tolerance_rel"])
