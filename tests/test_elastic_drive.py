"""The drive with an elastic link: the linear two-mass response in closed form, the rigid limit, the shafts'
stiffness, the energy balance and the resonance warning."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mechsynth_client.client import InvalidInputError, SynthClient
from mechsynth_client.schemas.foundation import ElasticDriveIn
from synth.flywheel import Motor
from synth.machine.elastic_drive import elastic_drive
from synth.machine.simulate import MachineCycle

EXAMPLE = ElasticDriveIn.model_json_schema()["examples"][0]
N = 120
PHI = np.arange(N) * 2 * math.pi / N


def test_linear_two_mass_response_matches_the_closed_form() -> None:
    # constant machine inertia, a mean load and one harmonic: a heavy machine keeps the speed so even that the
    # system is linear to ~1e-6, and the harmonic of the torque in the link has a closed form
    j1, j2, c, zeta, order, amp = 1.0, 50.0, 2e4, 0.05, 3, 20.0
    motor = Motor(1500 * math.pi / 30, 1440 * math.pi / 30, 100.0, rotor_inertia=j1)
    cycle = MachineCycle(PHI, np.full(N, j2), np.zeros(N), -50.0 + amp * np.cos(order * PHI))
    d = elastic_drive(cycle, motor, c, damping_ratio=zeta, start=False)
    assert d.natural_frequency == pytest.approx(math.sqrt(c * (j1 + j2) / (j1 * j2)) / (2 * math.pi), rel=1e-12)
    s = motor.rated_torque / (motor.synchronous_speed - motor.rated_speed)  # the motor's slope damps mass 1
    b = 2 * zeta * math.sqrt(c * j1 * j2 / (j1 + j2))
    w = order * d.mean_speed
    z = np.array([[-j1 * w * w + 1j * w * (s + b) + c, -(1j * w * b + c)],
                  [-(1j * w * b + c), -j2 * w * w + 1j * w * b + c]])
    x = np.linalg.solve(z, np.array([0.0, amp]))
    # the load is linear between the samples: its harmonic is the cosine's times sinc²(k·h/2), h the step
    half = order * math.pi / N
    expected = abs((c + 1j * w * b) * (x[0] - x[1])) * (math.sin(half) / half) ** 2
    measured = 2 * abs(np.fft.rfft(d.steady.elastic_torque)[order]) / N
    assert measured == pytest.approx(expected, rel=1e-4)
    # the mean torque in the link carries the mean load
    assert float(np.mean(d.steady.elastic_torque)) == pytest.approx(50.0, rel=1e-4)
    assert abs(d.steady.energy_residual) < 1e-6


def test_a_stiff_link_passes_the_rigid_models_torque() -> None:
    # a slow crank behind a 20:1 train: the link's natural frequency lies ~50 times above the second harmonic,
    # so the elastic model's extra torque, ~(2w/w_n)², is below 1e-3
    motor = Motor(1500 * math.pi / 30, 1440 * math.pi / 30, 10.0, gear_ratio=20.0, rotor_inertia=0.5)
    j2 = 2.0 + 0.5 * np.cos(2 * PHI)
    cycle = MachineCycle(PHI, j2, -1.0 * np.sin(2 * PHI), -50.0 + 10 * np.sin(PHI))
    d = elastic_drive(cycle, motor, 1e6, start=False)
    assert (2 * d.mean_speed / (2 * math.pi * d.natural_frequency)) ** 2 < 1e-3
    assert d.dynamic_factor == pytest.approx(1.0, abs=2e-3)
    assert np.max(np.abs(d.steady.elastic_torque - d.rigid_torque)) < 2e-3 * np.max(np.abs(d.rigid_torque))


def test_the_answer_through_the_service(client: SynthClient) -> None:
    out = client.elastic_drive(ElasticDriveIn.model_validate({**EXAMPLE, "samples": 120}))
    shaft, coupling = EXAMPLE["elements"]
    # shaft G·pi·d⁴/(32 L) on the motor shaft, reduced by its speed ratio squared, in series with the coupling
    c_shaft = 81e9 * math.pi * shaft["diameter_m"] ** 4 / (32 * shaft["length_m"]) * shaft["speed_ratio"] ** 2
    expected = 1 / (1 / c_shaft + 1 / coupling["stiffness_Nm_rad"])
    assert out.stiffness_Nm_rad == pytest.approx(expected, rel=1e-12)
    j1 = EXAMPLE["motor"]["gear_ratio"] ** 2 * EXAMPLE["motor"]["rotor_inertia_kgm2"]
    j2 = out.machine_inertia_kgm2[0]
    assert out.natural_frequency_Hz == pytest.approx(math.sqrt(expected * (j1 + j2) / (j1 * j2)) / (2 * math.pi),
                                                     rel=1e-12)
    assert out.checks.closed_form_diff < 1e-12 and abs(out.checks.steady_energy_residual) < 1e-6
    assert out.start is not None and abs(out.start.energy_residual) < 1e-6
    near = [h.order for h in out.harmonics if h.near_resonance]
    assert near and all(str(k) in w.message for k, w in zip(near, out.warnings))
    for h in out.harmonics:
        assert h.near_resonance == (abs(h.frequency_ratio - 1) <= 0.15 and h.amplitude_Nm >= 0.02 * max(
            g.amplitude_Nm for g in out.harmonics))


def test_a_link_needs_its_stiffness(client: SynthClient) -> None:
    body = {k: v for k, v in EXAMPLE.items() if k != "elements"}
    with pytest.raises(InvalidInputError) as err:
        client.elastic_drive(ElasticDriveIn.model_validate(body))
    assert err.value.problem["field"] == "stiffness_Nm_rad"
    with pytest.raises(InvalidInputError) as err:
        client.elastic_drive(ElasticDriveIn.model_validate({**EXAMPLE, "elements": [{"type": "shaft"}]}))
    assert err.value.problem["field"] == "elements.0.diameter_m"
