"""The frame on its isolators: one-degree-of-freedom closed forms, Newton's law on the answer, the rigid-floor
limit, the time-integration check and the refusals."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mechsynth_client.client import InvalidInputError, SynthClient
from mechsynth_client.schemas.foundation import IsolationIn
from synth.errors import InvalidInput
from synth.machine.foundation import Forcing, Frame, Isolator, isolate

N = 240
PHI = np.arange(N) * 2 * math.pi / N
EXAMPLE = IsolationIn.model_json_schema()["examples"][0]


def _vertical(m: float, k: float, zeta: float, speed: float, amplitude: float = 100.0):  # type: ignore[no-untyped-def]
    """Two equal isolators either side of the centre: the vertical motion is one degree of freedom m, 2k, zeta."""
    force = np.column_stack([np.zeros(N), amplitude * np.cos(PHI)])
    isolators = [Isolator((-0.5, 0.0), k, k, damping_ratio=zeta), Isolator((0.5, 0.0), k, k, damping_ratio=zeta)]
    return isolate(Frame(m, 20.0, (0.0, 0.0)), isolators, Forcing(PHI, speed, force, np.zeros(N)))


@pytest.mark.parametrize("r", [0.5, 1.0, 2.0, 4.0])
@pytest.mark.parametrize("zeta", [0.05, 0.3])
def test_one_degree_of_freedom_matches_the_closed_forms(r: float, zeta: float) -> None:
    m, k = 200.0, 5e4
    w0 = math.sqrt(2 * k / m)
    res = _vertical(m, k, zeta, r * w0)
    # transmissibility of a damped single degree of freedom (independent derivation)
    expected = math.sqrt(1 + (2 * zeta * r) ** 2) / math.sqrt((1 - r * r) ** 2 + (2 * zeta * r) ** 2)
    assert res.harmonics[0].force_transmissibility == pytest.approx(expected, rel=1e-9)
    # seed 003:762-835 (with its misprinted extra 1/m corrected): z_max = (F/m)/sqrt((w0²-w²)² + 4n²w²), n = c/2m
    w, n = r * w0, zeta * w0
    z_max = (100.0 / m) / math.sqrt((w0**2 - w**2) ** 2 + 4 * n * n * w * w)
    # the peak over the samples misses the crest by at most half a sample: 1 - cos(pi/N) ~ (pi/N)²/2
    assert res.peak_displacement == pytest.approx(z_max, rel=(math.pi / N) ** 2 / 2)
    assert res.peak_displacement <= z_max * (1 + 1e-12)
    assert res.modes[1].frequency == pytest.approx(w0 / (2 * math.pi), rel=1e-12)
    assert res.modes[1].damping_ratio == pytest.approx(zeta, rel=1e-9)
    assert res.check.relative_diff < 1e-6


def test_newton_holds_on_the_answer_of_a_linkage(client: SynthClient) -> None:
    out = client.isolate_machine(IsolationIn.model_validate(EXAMPLE))
    x = np.asarray(out.displacement_m)
    theta = np.asarray(out.rotation_rad)
    speed = EXAMPLE["speed_rpm"] * math.pi / 30
    # accelerations by spectral differentiation of the periodic samples: m·a = shaking force - force passed on
    orders = np.fft.rfftfreq(x.shape[0], 1.0 / x.shape[0])
    acc = np.fft.irfft(-(orders[:, None] * speed) ** 2 * np.fft.rfft(x, axis=0), n=x.shape[0], axis=0)
    lhs = EXAMPLE["frame"]["mass_kg"] * acc
    rhs = np.asarray(out.shaking_force_N) - np.asarray(out.force_N)
    assert np.max(np.abs(lhs - rhs)) < 1e-6 * out.peak_shaking_force_N
    # the moment balance about the crank pivot: J·theta'' + (C x m·a) = M_shaking - M_foundation
    alpha = np.fft.irfft(-(orders * speed) ** 2 * np.fft.rfft(theta), n=theta.size)
    cx, cy = EXAMPLE["frame"]["centre_m"]
    lhs_m = EXAMPLE["frame"]["inertia_kgm2"] * alpha + cx * lhs[:, 1] - cy * lhs[:, 0]
    rhs_m = np.asarray(out.shaking_moment_Nm) - np.asarray(out.moment_Nm)
    assert np.max(np.abs(lhs_m - rhs_m)) < 1e-6 * np.max(np.abs(out.shaking_moment_Nm))
    # the isolators' forces add up to the total, and the time integration agrees with the harmonic answer
    total = np.sum([np.asarray(i.force_N) for i in out.isolators], axis=0)
    assert np.max(np.abs(total - np.asarray(out.force_N))) < 1e-9 * out.peak_force_N
    assert out.checks.relative_diff < 1e-6


def test_a_rigid_floor_passes_the_shaking_force_on_exactly() -> None:
    rng = np.random.default_rng(3)
    force = rng.normal(size=(N, 2)) * 0 + np.column_stack([300 * np.cos(PHI) + 40 * np.sin(2 * PHI),
                                                           120 * np.sin(PHI) - 30 * np.cos(3 * PHI)])
    moment = 25 * np.cos(PHI) + 5 * np.sin(2 * PHI)
    stiff = 1e11
    isolators = [Isolator((-0.4, -0.3), stiff, stiff, damping_ratio=0.05), Isolator((0.6, -0.3), stiff, stiff),
                 Isolator((0.1, 0.4), stiff, stiff)]
    res = isolate(Frame(300.0, 40.0, (0.1, -0.1)), isolators, Forcing(PHI, 2 * math.pi * 10, force, moment),
                  check=False)
    # the frame's inertia forces scale with (w/w_n)² ~ 1e-6 of the forcing here
    assert np.max(np.abs(res.force - force)) < 1e-5 * np.max(np.abs(force))
    assert np.max(np.abs(res.moment - moment)) < 1e-5 * np.max(np.abs(force))


def test_refusals_name_the_field(client: SynthClient) -> None:
    with pytest.raises(InvalidInputError) as err:
        client.isolate_machine(IsolationIn.model_validate({**EXAMPLE, "isolators": []}))
    assert err.value.problem["field"] == "isolators"
    with pytest.raises(InvalidInputError) as err:
        client.isolate_machine(IsolationIn.model_validate({**EXAMPLE, "isolators": EXAMPLE["isolators"][:1]}))
    assert err.value.problem["field"] == "isolators" and "turns about the point (-0.3, -0.5)" in str(err.value)
    bad = [{**EXAMPLE["isolators"][0], "ky_N_m": -1.0}, EXAMPLE["isolators"][1]]
    response = client.http.post("/v1/machines/isolation", json={**EXAMPLE, "isolators": bad})
    assert response.status_code == 422 and "ky_N_m" in response.text
    with pytest.raises(InvalidInput, match="must be finite and not negative") as engine_err:
        isolate(Frame(1.0, 1.0, (0, 0)), [Isolator((0, 0), -1.0, 1.0)],
                Forcing(PHI, 1.0, np.zeros((N, 2)), np.zeros(N)))
    assert engine_err.value.field == "isolators.0.kx_N_m"


def test_an_undamped_frame_at_resonance_has_no_steady_cycle() -> None:
    m, k = 100.0, 1e4
    with pytest.raises(InvalidInput, match="natural frequency with no damping"):
        _vertical(m, k, 0.0, math.sqrt(2 * k / m))


def test_the_run_up_passes_the_frames_modes(client: SynthClient) -> None:
    motor = {"synchronous_speed_rpm": 1500, "rated_speed_rpm": 1440, "rated_torque_Nm": 30, "gear_ratio": 3.0,
             "rotor_inertia_kgm2": 0.02, "breakdown_torque_Nm": 70}
    body = IsolationIn.model_validate({**EXAMPLE, "samples": 120,
                                       "run_up": {"motor": motor, "constant_inertia_kgm2": 0.5}})
    out = client.isolate_machine(body)
    ru = out.run_up
    assert ru is not None and ru.ratio is not None
    # the record runs on past the run-up at the final speed, so the peak is at least the steady cycle's
    assert ru.peak_amplitude_m >= ru.steady_amplitude_m * (1 - 1e-3)
    # the crank starts from rest, so the first harmonic sweeps every mode below the final speed
    final_hz = ru.crank_speed_rpm[-1] / 60
    assert ru.crossed_frequencies_Hz == pytest.approx(sorted(m.frequency_Hz for m in out.modes
                                                             if m.frequency_Hz <= final_hz * max(
                                                                 h.order for h in out.harmonics)), rel=1e-9)
