"""Where the isolation model stops: a harmonic passed on undiminished, below sqrt(2) times a natural frequency,
near a mode with little damping, an isolator in tension; each against the one-degree-of-freedom closed form of a
frame driven through its centre (seed 003:762-835)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.foundation import IsolationIn
from synth.machine.foundation import G, Forcing, Frame, Isolator, isolate

MASS, KY = 400.0, 1e5
FRAME = Frame(MASS, 60.0, (0.0, 0.0))
N = 64
PHI = np.arange(N) * 2 * math.pi / N
#: The vertical mode of two equal isolators symmetric about the centre: one degree of freedom, sqrt(2 k_y / m).
W_N = math.sqrt(2 * KY / MASS)


def _isolators(zeta: float) -> tuple[Isolator, ...]:
    return tuple(Isolator((x, 0.0), 5e4, KY, damping_ratio=zeta) for x in (-0.5, 0.5))


def _vertical(amplitude: float, speed: float) -> Forcing:
    force = np.column_stack([np.zeros(N), amplitude * np.cos(PHI)])
    return Forcing(PHI, speed, force, np.zeros(N))


def _transmissibility(r: float, zeta: float) -> float:
    return math.sqrt(1 + (2 * zeta * r) ** 2) / math.sqrt((1 - r * r) ** 2 + (2 * zeta * r) ** 2)


def test_a_frame_at_resonance_is_named_with_its_transmissibility() -> None:
    r = isolate(FRAME, _isolators(0.08), _vertical(100.0, W_N), check=False)
    t = _transmissibility(1.0, 0.08)   # sqrt(1 + 4 zeta²)/(2 zeta) = 6.3
    assert r.harmonics[0].force_transmissibility == pytest.approx(t, rel=1e-9)
    codes = {w.code for w in r.warnings}
    assert {"transmissibility_high", "frequency_ratio_low", "resonance_damping_low"} <= codes
    checks = {c.name: c for c in r.checks}
    assert checks["transmissibility"].value == pytest.approx(t, rel=1e-9) and not checks["transmissibility"].passed
    assert not checks["resonance_damping"].passed
    assert checks["resonance_damping"].value == pytest.approx(0.08, rel=1e-6)


def test_an_undamped_frame_a_hair_off_resonance_is_not_calm() -> None:
    r = isolate(FRAME, _isolators(0.0), _vertical(100.0, W_N * 1.0001), check=False)
    assert r.harmonics[0].force_transmissibility == pytest.approx(_transmissibility(1.0001, 0.0), rel=1e-6)
    assert {"transmissibility_high", "resonance_damping_low"} <= {w.code for w in r.warnings}


def test_a_well_isolated_frame_passes_every_check() -> None:
    # three times the vertical mode and above every other: T = 1/(r² - 1) + damping's share, under 1
    r = isolate(FRAME, _isolators(0.08), _vertical(100.0, 3 * max(W_N, math.sqrt(2 * 5e4 / MASS)) * 1.5),
                check=False)
    assert all(c.passed for c in r.checks) and not r.warnings


def test_an_isolator_lifting_off_is_named_with_its_crank_angles() -> None:
    # each isolator carries m g / 2 and, at r = 3 with little damping, passes on T F / 2 of the harmonic
    speed = 3 * W_N
    t = _transmissibility(3.0, 0.02)
    lift = MASS * G / t * 1.2          # 20 % more than lifts it
    r = isolate(FRAME, _isolators(0.02), _vertical(lift, speed), check=False)
    off = [w for w in r.warnings if w.code == "isolator_lift_off"]
    assert off and off[0].ranges
    least = MASS * G / 2 - t * lift / 2
    assert off[0].value == pytest.approx(least, rel=0.05)   # the rocking mode adds a little to each isolator
    calm = isolate(FRAME, _isolators(0.02), _vertical(lift / 1.5, speed), check=False)
    assert "isolator_lift_off" not in {w.code for w in calm.warnings}


def test_a_centre_outside_its_isolators_is_named(client: SynthClient) -> None:
    example = IsolationIn.model_json_schema()["examples"][0]
    body = IsolationIn.model_validate({**example, "frame": {**example["frame"], "centre_m": [1.0, -0.25]}})
    out = client.isolate_machine(body)
    # statics of a beam on two supports at x = -0.3 and 0.5 with the weight at x = 1.0: the near one pulls
    w = body.frame.mass_kg * G
    tension = w * (1.0 - 0.5) / (0.5 + 0.3)
    warn = [x for x in out.warnings if x.code == "isolator_in_tension"]
    assert len(warn) == 1 and warn[0].field == "isolators.0"
    assert warn[0].value == pytest.approx(-tension, rel=1e-9)
    assert not {c.name: c for c in out.validity}["isolator_compression"].passed
