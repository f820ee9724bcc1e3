"""Designing the isolators against a brute-force scan of the plain solve; infeasible limits; the run-up passage
against the steady response at every speed of a slow sweep."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mechsynth_client.client import InfeasibleError, SynthClient
from mechsynth_client.schemas.foundation import IsolationDesignIn
from synth.machine.foundation import G, Forcing, Frame, Isolator, isolate, run_up_passage
from synth.machine.foundation_design import IsolationDesignSpec, design_isolation

N = 180
PHI = np.arange(N) * 2 * math.pi / N
FRAME = Frame(300.0, 40.0, (0.05, -0.2))
POSITIONS = ((-0.4, -0.5), (0.5, -0.5))
FORCING = Forcing(PHI, 2 * math.pi * 8, np.column_stack([900 * np.cos(PHI), 250 * np.cos(2 * PHI) + 400 * np.sin(PHI)]),
                  60 * np.cos(PHI))
EXAMPLE = IsolationDesignIn.model_json_schema()["examples"][0]


def _plain(k: float, zeta: float) -> tuple[float, float]:
    res = isolate(FRAME, [Isolator(p, 0.5 * k, k, damping_ratio=zeta) for p in POSITIONS], FORCING, check=False)
    return max(res.peak_displacement, res.peak_isolator_displacement), res.peak_force


@pytest.mark.parametrize("objective", ["amplitude", "force"])
def test_design_is_no_worse_than_a_fine_scan_of_the_plain_solve(objective: str) -> None:
    limits = {"amplitude": dict(max_force=400.0), "force": dict(max_amplitude=0.004)}[objective]
    spec = IsolationDesignSpec(POSITIONS, objective, stiffness_ratio=0.5, min_stiffness=2e4, max_stiffness=2e7,
                               min_damping_ratio=0.1, max_damping_ratio=0.1, max_static_deflection=0.03,
                               **limits)  # type: ignore[arg-type]
    d = design_isolation(FRAME, FORCING, spec)
    amp, force = _plain(d.ky, d.damping_ratio)
    assert (amp, force) == pytest.approx((d.amplitude, d.peak_force), rel=1e-9)
    k_floor = FRAME.mass * G / (2 * 0.03)
    assert d.ky >= k_floor * (1 - 1e-9) and d.static_deflection <= 0.03 * (1 + 1e-9)
    scan = [_plain(k, 0.1) for k in np.geomspace(k_floor, 2e7, 200)]
    if objective == "amplitude":
        assert force <= 400.0 * (1 + 1e-9)
        best = min(a for a, f in scan if f <= 400.0)
        assert amp <= best * (1 + 2e-3)
    else:
        assert amp <= 0.004 * (1 + 1e-9)
        best = min(f for a, f in scan if a <= 0.004)
        assert force <= best * (1 + 2e-3)
    assert d.isolation.check.relative_diff < 1e-6


def test_limits_nothing_meets_answer_422_naming_the_constraint(client: SynthClient) -> None:
    with pytest.raises(InfeasibleError) as err:
        client.design_isolation(IsolationDesignIn.model_validate({**EXAMPLE, "max_force_N": 1.0}))
    assert err.value.problem["constraint"] == "max_force_N"
    with pytest.raises(InfeasibleError) as err:
        client.design_isolation(IsolationDesignIn.model_validate(
            {**EXAMPLE, "max_static_deflection_m": 1e-6, "max_stiffness_N_m": 1e6}))
    assert err.value.problem["constraint"] == "max_static_deflection_m"


def test_a_slow_run_up_follows_the_steady_response_through_resonance() -> None:
    m, k, zeta = 200.0, 2e5, 0.15
    wn = math.sqrt(2 * k / m)
    frame = Frame(m, 20.0, (0.0, 0.0))
    isolators = (Isolator((-0.5, 0.0), k, k, damping_ratio=zeta), Isolator((0.5, 0.0), k, k, damping_ratio=zeta))
    w0 = 2 * wn
    forcing = Forcing(PHI, w0, np.column_stack([np.zeros(N), 100 * np.cos(PHI)]), np.zeros(N))
    # the crank speeds up from 0.3 w_n to 1.6 w_n over 120 natural periods: close to steady at every speed
    t = np.linspace(0.0, 120 * 2 * math.pi / wn, 4001)
    w = 0.3 * wn + 1.3 * wn * t / t[-1]
    phi = np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(t))])
    passage = run_up_passage(frame, isolators, forcing, t, phi, w, 1.0)
    # steady amplitude of m·y'' + c·y' + 2k·y = 100·(w/w0)²·cos(w t), largest over the sweep (independent)
    ws = np.linspace(0.3 * wn, 1.6 * wn, 20001)
    steady = 100 * (ws / w0) ** 2 / m / np.sqrt((wn**2 - ws**2) ** 2 + (2 * zeta * wn * ws) ** 2)
    assert passage.peak_amplitude == pytest.approx(float(steady.max()), rel=0.03)
    assert passage.peak_speed == pytest.approx(float(ws[np.argmax(steady)]), rel=0.05)
    assert passage.crossed and passage.crossed[0] == pytest.approx(wn / (2 * math.pi), rel=1e-9)
