"""The elastic drive as a block of POST /v1/flywheel: the same answer as POST /v1/machines/elastic-drive with the
sized flywheel on its side of the link, the two-mass closed form, the rigid limit and the block's refusals."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from mechsynth_client.client import InvalidInputError, SynthClient
from mechsynth_client.schemas.flywheel import FlywheelIn, FlywheelOut
from mechsynth_client.schemas.foundation import ElasticDriveIn

EXAMPLES: list[dict[str, Any]] = FlywheelIn.model_config["json_schema_extra"]["examples"]  # type: ignore[index]
# the schema's example with the elastic block, at fewer samples to keep the integrations short
BODY: dict[str, Any] = {k: v for k, v in EXAMPLES[2].items() if k != "elastic_drive"} | {"samples": 90}
MOTOR = BODY["motor"]


def _flywheel(client: SynthClient, **block: Any) -> FlywheelOut:
    return client.flywheel(FlywheelIn.model_validate({**BODY, "elastic_drive": block}))


def _standalone(client: SynthClient, stiffness: float, machine: float, motor_side: float,
                start: bool = False) -> dict[str, Any]:
    """POST /v1/machines/elastic-drive for the same linkage, loads, motor and samples at the mean speed."""
    body = {k: BODY[k] for k in ("mechanism", "loads", "motor", "samples")}
    answer = client.elastic_drive(ElasticDriveIn.model_validate(
        {**body, "speed_rpm": BODY["mean_speed_rpm"], "stiffness_Nm_rad": stiffness, "machine_inertia_kgm2": machine,
         "motor_side_inertia_kgm2": motor_side, "start": start}))
    return answer.model_dump()


def _same(a: Any, b: Any, path: str = "") -> None:
    """Every number of ``a`` equals ``b``'s to 1e-9 (relative to the array's scale), every other value exactly."""
    if isinstance(a, dict):
        assert a.keys() == b.keys(), path
        for k in a:
            _same(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list) and a and isinstance(a[0], (int, float)) and not isinstance(a[0], bool):
        x, y = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        assert x.shape == y.shape, path
        assert np.max(np.abs(x - y)) <= 1e-9 * max(float(np.max(np.abs(y))), 1e-12), path
    elif isinstance(a, list):
        assert len(a) == len(b), path
        for k, (u, v) in enumerate(zip(a, b)):
            _same(u, v, f"{path}.{k}")
    elif isinstance(a, float):
        assert a == pytest.approx(b, rel=1e-9, abs=1e-12), path
    else:
        assert a == b, path


@pytest.mark.parametrize(("on", "start"), [("crank", False), ("motor_shaft", True)])
def test_the_block_is_the_standalone_drive_with_the_flywheel(client: SynthClient, on: str, start: bool) -> None:
    out = _flywheel(client, stiffness_Nm_rad=2000, flywheel_on=on, motor_side_inertia_kgm2=0.001, start=start)
    assert out.design_method == "motor_nlp" and out.elastic_drive is not None
    j_fw = out.flywheel_inertia_kgm2
    assert j_fw > 0
    constant = BODY.get("constant_inertia_kgm2", 0.0)
    # on the crank the flywheel joins the machine; on the motor shaft its own inertia is the crank's over i²
    machine, motor_side = (constant + j_fw, 0.001) if on == "crank" else (constant,
                                                                         0.001 + j_fw / MOTOR["gear_ratio"] ** 2)
    assert (out.elastic_drive.start is not None) == start
    _same(out.elastic_drive.model_dump(), _standalone(client, 2000, machine, motor_side, start))


def test_the_natural_frequency_is_the_two_mass_closed_form(client: SynthClient) -> None:
    c = 2000.0
    for on in ("crank", "motor_shaft"):
        out = _flywheel(client, stiffness_Nm_rad=c, flywheel_on=on)
        assert out.elastic_drive is not None
        d = out.elastic_drive
        j_fw, i = out.flywheel_inertia_kgm2, MOTOR["gear_ratio"]
        # J1: the rotor reduced to the crank, i²·J_rotor, plus the flywheel when it turns with the rotor;
        # J2: the linkage's mean reduced inertia (the flywheel answer's own samples) plus the flywheel on the crank
        j_red = float(np.mean(out.energy_mass.reduced_inertia_kgm2))
        j1 = i * i * MOTOR["rotor_inertia_kgm2"] + (j_fw if on == "motor_shaft" else 0.0)
        j2 = j_red + (j_fw if on == "crank" else 0.0)
        assert d.rotor_inertia_kgm2 == pytest.approx(j1, rel=1e-12)
        assert d.machine_inertia_kgm2[0] == pytest.approx(j2, rel=1e-12)
        f = math.sqrt(c * (j1 + j2) / (j1 * j2)) / (2 * math.pi)
        assert d.natural_frequency_Hz == pytest.approx(f, rel=1e-9)
        assert d.checks.eigen_frequency_Hz == pytest.approx(f, rel=1e-9)
        assert abs(d.checks.steady_energy_residual) < 1e-6


def test_a_very_stiff_link_is_the_rigid_drive(client: SynthClient) -> None:
    out = _flywheel(client, stiffness_Nm_rad=1e6, flywheel_on="crank")
    assert out.elastic_drive is not None
    d = out.elastic_drive
    # the link's mode lies far above the load's harmonics that carry torque, so the link passes the rigid torque
    assert d.dynamic_factor == pytest.approx(1.0, abs=1e-3)
    assert not d.warnings


def test_the_near_resonance_warnings_are_the_requests(client: SynthClient) -> None:
    # tuned so that the third load harmonic at the mean speed meets the link's natural frequency
    probe = _flywheel(client, stiffness_Nm_rad=2000, flywheel_on="crank")
    assert probe.elastic_drive is not None
    d = probe.elastic_drive
    j1, j2 = d.rotor_inertia_kgm2, d.machine_inertia_kgm2[0]
    w3 = 3 * d.mean_speed_rpm * math.pi / 30
    c = w3**2 * j1 * j2 / (j1 + j2)
    out = _flywheel(client, stiffness_Nm_rad=c, flywheel_on="crank")
    assert out.elastic_drive is not None
    near = [h.order for h in out.elastic_drive.harmonics if h.near_resonance]
    assert 3 in near
    block = [w for w in out.elastic_drive.warnings if w.code == "load_harmonic_near_resonance"]
    top = [w for w in out.warnings if w.code == "load_harmonic_near_resonance"]
    assert len(block) == len(near) == len(top)
    assert all(w.field == "elastic_drive.stiffness_Nm_rad" for w in top)
    assert any("harmonic 3 " in w.message for w in top)


def test_the_block_needs_a_motor_and_a_linkage(client: SynthClient) -> None:
    body = {k: v for k, v in BODY.items() if k != "motor"}
    with pytest.raises(InvalidInputError) as err:
        client.flywheel(FlywheelIn.model_validate({**body, "elastic_drive": {"stiffness_Nm_rad": 2000}}))
    assert err.value.problem["field"] == "elastic_drive" and "motor" in err.value.problem["detail"]
    tables = {**EXAMPLES[0], "motor": MOTOR, "elastic_drive": {"stiffness_Nm_rad": 2000}}
    with pytest.raises(InvalidInputError) as err:
        client.flywheel(FlywheelIn.model_validate(tables))
    assert err.value.problem["field"] == "elastic_drive"
    with pytest.raises(InvalidInputError) as err:
        _flywheel(client)
    assert err.value.problem["field"] == "elastic_drive.stiffness_Nm_rad"
    with pytest.raises(InvalidInputError) as err:
        _flywheel(client, elements=[{"type": "shaft", "diameter_m": 0.03}])
    assert err.value.problem["field"] == "elastic_drive.elements.0.diameter_m"


def test_the_work_estimate_counts_the_block() -> None:
    from api.execution.work import estimate_s

    with_block = FlywheelIn.model_validate({**BODY, "elastic_drive": {"stiffness_Nm_rad": 2000}})
    without = FlywheelIn.model_validate(BODY)
    standalone = ElasticDriveIn.model_validate({k: BODY[k] for k in ("mechanism", "motor", "samples")}
                                               | {"speed_rpm": 298, "stiffness_Nm_rad": 2000})
    # the block costs what the standalone endpoint's request of the same samples is estimated to cost
    assert estimate_s("/v1/flywheel", with_block) == pytest.approx(
        estimate_s("/v1/flywheel", without) + estimate_s("/v1/machines/elastic-drive", standalone), rel=1e-12)


def test_the_link_from_its_shaft_and_coupling(client: SynthClient) -> None:
    shaft = {"type": "shaft", "speed_ratio": 5.0, "diameter_m": 0.02, "length_m": 0.3}
    coupling = {"type": "coupling", "speed_ratio": 5.0, "stiffness_Nm_rad": 500.0}
    out = _flywheel(client, elements=[shaft, coupling])
    assert out.elastic_drive is not None
    # G·pi·d⁴/(32 L) on the motor shaft, each element reduced to the crank by its speed ratio squared, in series
    c_shaft = 81e9 * math.pi * 0.02**4 / (32 * 0.3) * 25
    expected = 1 / (1 / c_shaft + 1 / (500.0 * 25))
    assert out.elastic_drive.stiffness_Nm_rad == pytest.approx(expected, rel=1e-12)
