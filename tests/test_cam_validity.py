"""Where a cam's model stops: the follower leaving the cam, the pressure angle and profile radius beyond their
limits, a step in acceleration at a joint, the spring designed as a coil, the least cam on its hub; each edge
against an independent computation."""

from __future__ import annotations

import math

import numpy as np
import pytest

import synth.cams as cams
from api.translate.cams import cam_analysis_spec, cam_spec, limits_from
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.cams import CamAnalysisIn, CamSynthesisIn
from synth.cams.spring import WIRES

SEGMENTS = [{"kind": "rise", "angle_deg": 120, "lift_m": 0.02, "law": "cycloidal"}, {"kind": "dwell", "angle_deg": 60},
            {"kind": "return", "angle_deg": 120, "lift_m": 0.02, "law": "polynomial_345"},
            {"kind": "dwell", "angle_deg": 60}]
BASE = {"segments": SEGMENTS, "follower": {"contact": "roller", "roller_radius_m": 0.01}, "base_radius_m": 0.04,
        "speed_rpm": 1000}
OMEGA = 1000 * math.pi / 30
H, BETA = 0.02, 2 * math.pi / 3


def _analyse(**changes: object) -> cams.CamAnalysis:
    return cams.analyse_cam(cam_analysis_spec(CamAnalysisIn.model_validate({**BASE, **changes})))


def _codes(an: cams.CamAnalysis) -> list[str]:
    return [w.code for w in an.warnings]


def test_the_follower_leaving_the_cam_is_named_with_its_angles(client: SynthClient) -> None:
    body = CamAnalysisIn.model_validate({**BASE, "loads": {"mass_kg": 2, "spring_stiffness_N_m": 2000,
                                                           "spring_preload_N": 20}})
    out = client.cam_analysis(body)
    # independently: the force the cam must supply along the follower, m ω² s'' + k s + F0, on the cycloidal rise
    # s = h(u - sin 2πu / 2π), s'' = 2π h sin 2πu / β², is negative past its middle: the follower lifts off
    u = np.linspace(0, 1, 2001)
    q = 2 * OMEGA**2 * 2 * math.pi * H * np.sin(2 * math.pi * u) / BETA**2 + 2000 * H * (
        u - np.sin(2 * math.pi * u) / (2 * math.pi)) + 20
    assert q.min() < -500
    jump = [w for w in out.warnings if w.code == "follower_jump"]
    assert len(jump) == 1 and jump[0].crank_angle_ranges_deg
    assert out.forces is not None and jump[0].value == pytest.approx(out.forces.min_contact_force_N, rel=1e-12)
    check = {c.name: c for c in out.validity}["follower_contact"]
    assert not check.passed and check.value == pytest.approx(out.forces.min_contact_force_N, rel=1e-12)
    # the least force falls inside the named ranges
    least_at = out.cam_angle_deg[int(np.argmin(out.forces.contact_force_N))]
    assert any(a <= least_at <= b for a, b in jump[0].crank_angle_ranges_deg)


def test_pressure_angle_and_profile_radius_of_a_tiny_knife_edge_cam() -> None:
    an = _analyse(follower={"contact": "knife_edge"}, base_radius_m=0.001)
    m = an.motion
    # a translating knife edge on the cam's centre line: tan α = s' / (r_b + s), at the very samples
    alpha = np.arctan(np.abs(m.v) / (0.001 + m.s))
    rise = m.segment == 0
    high = {w.field: w for w in an.warnings if w.code == "pressure_angle_high"}
    assert high["max_pressure_angle_rise_deg"].value == pytest.approx(float(alpha[rise].max()), rel=1e-9)
    assert math.degrees(float(alpha[rise].max())) > 70
    # on the dwells the profile is the base circle: its radius 1 mm is below the 2 mm default
    small = [w for w in an.warnings if w.code == "profile_radius_small"]
    assert small and small[0].value == pytest.approx(0.001, rel=1e-6)


def test_simple_harmonic_motion_beside_a_dwell_steps_its_acceleration() -> None:
    segments = [dict(SEGMENTS[0], law="simple_harmonic"), *SEGMENTS[1:]]
    an = _analyse(segments=segments)
    # s'' of simple harmonic motion at its ends is ±(π²/2) h/β²; the dwell's is zero: a step of that times ω²
    step = math.pi**2 / 2 * H / BETA**2 * OMEGA**2
    jerks = [w for w in an.warnings if w.code == "jerk_infinite"]
    assert sorted(w.field or "" for w in jerks) == ["segments.0", "segments.1"]
    assert all(w.value == pytest.approx(step, rel=1e-9) for w in jerks)
    # the program of the examples (cycloidal and 3-4-5 between dwells) has none
    assert not {"jerk_infinite", "acceleration_infinite"} & set(_codes(_analyse()))


def test_the_designed_spring_is_a_spring_and_its_coil_holds_together() -> None:
    an = _analyse(loads={"mass_kg": 2, "contact_margin": 0.2})
    f, coil = an.forces, an.coil
    assert f is not None and coil is not None and f.spring_designed
    # a rate, with the preload an initial compression of at most the lift (a zero rate needs an endless spring)
    assert f.stiffness > 0 and f.preload / f.stiffness <= H * (1 + 1e-9)
    # the margin holds where the follower would be thrown off: spring >= 1.2 × -(m ω² s'')
    need = -2 * OMEGA**2 * an.motion.a
    spring = f.stiffness * an.motion.s + f.preload
    sep = need > 0
    assert np.min(spring[sep] / need[sep]) >= 1.2 * (1 - 1e-6)
    assert f.contact.min() > 0 and "follower_jump" not in _codes(an)
    # the coil gives back its rate, k = G d⁴ / (8 D³ n_a), and its lengths close (Shigley ch. 10)
    shear = WIRES["music_wire"][2]
    assert shear * coil.diameter**4 / (8 * coil.mean_diameter**3 * coil.active_coils) == pytest.approx(
        f.stiffness, rel=1e-9)
    assert coil.free_length - coil.installed_length == pytest.approx(f.preload / f.stiffness, rel=1e-9)
    assert coil.solid_length == pytest.approx((coil.active_coils + 2) * coil.diameter, rel=1e-12)
    assert coil.max_stress <= coil.allowable_stress * (1 + 1e-9) and coil.fatigue_factor >= 1 - 1e-9
    mass = 7850 * math.pi**2 * coil.diameter**2 * coil.mean_diameter * coil.active_coils / 4
    assert coil.surge_frequency == pytest.approx(0.5 * math.sqrt(f.stiffness / mass), rel=1e-12)
    checks = {c.name: c for c in an.checks}
    assert checks["spring_surge"].value == pytest.approx(coil.surge_frequency / (OMEGA / (2 * math.pi)), rel=1e-12)


def test_the_least_cam_encloses_its_hub() -> None:
    example = CamSynthesisIn.model_json_schema()["examples"][1]
    free = CamSynthesisIn.model_validate(example)
    r = cams.synthesise_cam(cam_spec(free), limits_from(free))
    # without a hub the least cam with a free offset is smaller than its 10 mm roller, and says so
    assert r.least.base_radius < 0.01 and "hub_radius_missing" in _codes(r.analysis)
    hub = CamSynthesisIn.model_validate({**example, "hub_radius_m": 0.015})
    r = cams.synthesise_cam(cam_spec(hub), limits_from(hub))
    assert r.least.base_radius >= 0.015 and "hub_radius_missing" not in _codes(r.analysis)
