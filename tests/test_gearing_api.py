"""POST /v1/gears/split, /teeth, /drive through the in-process client: the examples, the seed drive, and the
problem responses (unknown stage type, unreachable ratio, empty tooth search, too many stages)."""

from __future__ import annotations

import math

import pytest

import synth
from mechsynth_client.client import InfeasibleError, SynthClient
from mechsynth_client.schemas.gearing import DriveIn, SplitIn, TeethIn

from conftest import CASES


@pytest.mark.parametrize("model", [SplitIn, TeethIn, DriveIn])
def test_schema_examples_work(client: SynthClient, model: type) -> None:
    path = {SplitIn: "split", TeethIn: "teeth", DriveIn: "drive"}[model]
    for example in model.model_config["json_schema_extra"]["examples"]:
        response = client.http.post(f"/v1/gears/{path}", json=example)
        assert response.status_code == 200, (example, response.json())


def test_split_from_speeds_matches_the_engine(client: SynthClient) -> None:
    case = CASES["case_task1_total_ratios"]
    n_out, n_motor = case["inputs"]["n_out_rpm"][0], case["inputs"]["n_motor_rpm"][0]
    out = client.gears_split(SplitIn(motor_speed_rpm=n_motor, output_speed_rpm=n_out, stages=3))
    assert out.total_ratio == pytest.approx(case["expected"]["u_total"][0], abs=5e-7)   # printed to 6 places
    engine = synth.split_ratio(n_motor / n_out, synth.make_stages(3, max_stages=6), "min_inertia")
    assert out.stage_ratios == pytest.approx(list(engine.stage_ratios), rel=1e-9)
    assert out.reduced_inertia_kgm2 == pytest.approx(out.checks.objective_model, rel=1e-7)
    assert out.checks.kkt_residual is not None and out.checks.kkt_residual < 1e-4


def test_teeth_response_fields(client: SynthClient) -> None:
    out = client.gears_teeth(TeethIn(total_ratio=5.7, stages=2, max_teeth=45))
    u = math.prod(m.gear_teeth / m.pinion_teeth for m in out.stages)
    assert out.total_ratio == pytest.approx(u, rel=1e-12)
    assert out.ratio_error == pytest.approx(abs(u / 5.7 - 1), rel=1e-9)
    assert out.checks.agrees is True and "exhaustive" in out.method and out.search_time_s >= 0
    warned = client.gears_teeth(TeethIn(total_ratio=4, stages=2, min_teeth=12, max_teeth=40))
    assert warned.warnings and warned.min_pinion_teeth == 12


def test_drive_reproduces_the_seed(client: SynthClient) -> None:
    case = CASES["drive_motor_selection_and_ratio_split"]
    inp, exp, rel = case["inputs"], case["expected"], case["tolerance_rel"]
    body = DriveIn.model_validate({
        "output_power_W": inp["P_out_kW"] * 1e3, "output_speed_rad_s": inp["omega_out_rad_s"],
        "reserve_factor": inp["reserve_factor"], "drive_efficiency": inp["eta_drive_assumed"],
        "torque_basis": "rated",
        "stages": [{"type": "bevel", "ratio": inp["u_bevel"],
                    "efficiency": inp["eta_coupling"] * inp["eta_bevel"] * inp["eta_bearing"]},
                   {"type": "open_spur", "efficiency": inp["eta_open_cyl_gear"] * inp["eta_bearing"]}]})
    out = client.gears_drive(body)
    assert out.motor.name == inp["motor"] and out.motor.rated_rpm == pytest.approx(inp["n_motor_rpm"])
    assert out.required_power_W / 1e3 == pytest.approx(exp["P_motor_req_kW"], rel=rel)
    assert out.output_speed_rpm == pytest.approx(exp["n_out_rpm"], rel=rel)
    assert [s.torque_Nm / 1e3 for s in out.shafts] == pytest.approx(
        [exp["T_I_kNm"], exp["T_II_kNm"], exp["T_III_kNm"]], rel=rel)
    assert out.checks.kinetic_energy_J == pytest.approx(out.checks.reduced_kinetic_energy_J, rel=1e-12)


def test_problem_responses(client: SynthClient) -> None:
    r = client.http.post("/v1/gears/split", json={"total_ratio": 10, "stages": ["spur", "cycloidal"]})
    assert r.status_code == 422 and r.json()["type"] == "/problems/invalid-input"
    assert r.json()["field"] == "stages[1].type" and "planetary" in r.json()["detail"]
    r = client.http.post("/v1/gears/split", json={"total_ratio": 100, "stages": 2})
    assert r.status_code == 422 and r.json()["type"] == "/problems/infeasible"
    assert r.json()["constraint"] == "stage_ratio_max" and r.json()["reachable_max"] == pytest.approx(6.3**2)
    r = client.http.post("/v1/gears/split", json={"total_ratio": 10, "stages": 7})
    assert r.status_code == 413 and r.json()["type"] == "/problems/too-large" and r.json()["limit"] == 6
    r = client.http.post("/v1/gears/split", json={"total_ratio": 10, "motor_speed_rpm": 1500, "output_speed_rpm": 150})
    assert r.status_code == 422 and r.json()["type"] == "/problems/invalid-input"
    r = client.http.post("/v1/gears/split", json={"total_ratio": 10, "objective": "cheapest"})
    assert r.status_code == 422 and r.json()["field"] == "objective"
    r = client.http.post("/v1/gears/teeth", json={"total_ratio": 4.3, "stages": 2, "max_teeth": 40,
                                                  "tolerance": 1e-4})
    assert r.status_code == 422 and r.json()["type"] == "/problems/infeasible"
    assert r.json()["constraint"] == "tolerance"
    r = client.http.post("/v1/gears/teeth", json={"total_ratio": 4, "stages": ["worm"]})
    assert r.status_code == 422 and r.json()["field"] == "stages[0].type"
    r = client.http.post("/v1/gears/teeth", json={"total_ratio": 4, "stages": 2, "max_teeth": 5000})
    assert r.status_code == 413
    with pytest.raises(InfeasibleError) as err:
        client.gears_drive(DriveIn(output_power_W=1e6, output_speed_rpm=100))
    assert err.value.problem["constraint"] == "motor_power"


def test_catalogues(client: SynthClient) -> None:
    types = {t.name: t for t in client.gears_stage_types()}
    assert set(types) == set(synth.stage_types())
    assert types["bevel"].efficiency == CASES["drive_motor_selection_and_ratio_split"]["inputs"]["eta_bevel"]
    motors = client.gears_motors()
    assert len(motors) == len(synth.motor_catalogue())
    assert [m.rated_power_W for m in motors] == sorted(m.rated_power_W for m in motors)


def test_drive_chooses_from_the_users_catalogue(client: SynthClient) -> None:
    # Two motors of the user's own: the smaller does not cover P_out*xi/eta = 3000*1.1/0.9 = 3667 W, the larger does.
    own = [
        {"name": "small", "rated_power_W": 3000, "synchronous_rpm": 1500, "rated_rpm": 1420},
        {"name": "large", "rated_power_W": 4000, "synchronous_rpm": 1500, "rated_rpm": 1430, "rotor_inertia_kgm2": 0.01},
    ]
    body = {"output_power_W": 3000, "output_speed_rpm": 60, "stages": ["helical", "helical"], "drive_efficiency": 0.9}
    out = client.gears_drive(DriveIn.model_validate({**body, "motor_catalogue": own}))
    assert out.motor.name == "large"
    assert out.motor.rated_rpm == pytest.approx(1430, rel=1e-12)
    assert not any(w.code == "representative_catalogue" for w in out.warnings)
    default = client.gears_drive(DriveIn.model_validate(body))
    assert any(w.code == "representative_catalogue" for w in default.warnings)
    too_small = {**body, "motor_catalogue": own[:1]}
    r = client.http.post("/v1/gears/drive", json=too_small)
    assert r.status_code == 422 and r.json()["type"] == "/problems/infeasible"
