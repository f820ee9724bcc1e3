"""Defects found by independent re-derivation, each checked against a number computed here, through the API."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.balancing import SLIDER_CRANK_EXAMPLE

# The textbook four-bar these checks were derived for (coupler 0.35 m, its centre of mass at 0.175 m).
FOURBAR_EXAMPLE = {
    "type": "fourbar",
    "ground_length_m": 0.30,
    "crank_length_m": 0.10,
    "coupler_length_m": 0.35,
    "rocker_length_m": 0.25,
    "branch": 1,
    "links": {
        "crank": {"mass_kg": 1.0, "com_m": [0.05, 0.0], "inertia_kgm2": 0.001},
        "coupler": {"mass_kg": 2.0, "com_m": [0.175, 0.0], "inertia_kgm2": 0.02},
        "rocker": {"mass_kg": 1.5, "com_m": [0.125, 0.0], "inertia_kgm2": 0.008},
    },
}


def _post(client: SynthClient, path: str, body: dict) -> tuple[int, dict]:
    r = client.http.post(path, json=body)
    return r.status_code, r.json()


def test_lanchester_honours_the_branch_and_the_exact_second_order(client: SynthClient) -> None:
    # The documented slider-crank at 3000 rpm with the slider on the -x side. Independent: the harmonics of the
    # closed-form slider position x_B = r cos(phi) - sqrt(l² - r² sin²(phi)) by quadrature; its acceleration's
    # k-th harmonic is -k²·c_k·w², so the reciprocating force F_k = m_B·k²·w²·c_k·cos(k·phi), and a pair of
    # balancer masses on rho meets it with 2·m·rho·(k·w)² = |F_k|, pointing along +x at k·phi = phase.
    mech = {**SLIDER_CRANK_EXAMPLE, "branch": -1}
    w = 3000 * math.pi / 30
    status, out = _post(client, "/v1/balancing/slider-crank", {"mechanism": mech, "speed_rpm": 3000})
    assert status == 200
    r, l_ = mech["crank_length_m"], mech["rod_length_m"]
    phi = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
    x_b = r * np.cos(phi) - np.sqrt(l_**2 - (r * np.sin(phi)) ** 2)
    c = [2 * np.mean(x_b * np.cos(k * phi)) for k in range(5)]
    m_b = out["reciprocating_mass_kg"]
    first, second = out["lanchester"]
    for pair, k in ((first, 1), (second, 2)):
        f_k = m_b * k**2 * w**2 * c[k]  # the inertia force -m_B·a_B's cos(k·phi) coefficient
        assert pair["amplitude_N"] == pytest.approx(abs(f_k), rel=1e-9)
        assert pair["mass_kg"] * 2 * pair["radius_m"] * (k * w) ** 2 == pytest.approx(abs(f_k), rel=1e-9)
        # The pair cancels: its masses point along -sign(F_k)·x at phi = 0.
        assert math.cos(math.radians(pair["phase_deg"])) == pytest.approx(-math.copysign(1.0, f_k), abs=1e-9)
    assert 0 <= second["phase_deg"] < 360
    # What is left is the 4th order: m_B·16·w²·|c_4|, far below the textbook sizing's uncancelled 2nd order.
    by_order = out["residual_by_order_N"]
    assert by_order[3] == pytest.approx(m_b * 16 * w**2 * abs(c[4]), rel=1e-6)
    assert max(by_order[:3]) < 1e-9 * out["summary_before"]["max_shaking_force_N"]
    assert out["residual_shaking_force_N"] < 1.1 * sum(by_order)


@pytest.mark.parametrize("offset", [0.0, 0.01])
def test_slider_crank_gaps_are_exact(client: SynthClient, offset: float) -> None:
    # Independent: the rod reaches the guide iff |e - r sin(phi)| < l, so the gaps start where sin(phi) = (e ± l)/r.
    r, l_ = 0.1, 0.07
    mech = {**SLIDER_CRANK_EXAMPLE, "crank_length_m": r, "rod_length_m": l_, "offset_m": offset}
    status, out = _post(client, "/v1/analysis", {"mechanism": mech, "speed_rpm": 60, "samples": 72})
    assert status == 422 and out["type"] == "/problems/not-assemblable"
    up = math.degrees(math.asin((offset + l_) / r))
    down = math.degrees(math.asin((offset - l_) / r))
    expected = sorted([(up, 180 - up), (180 - down, 360 + down)])
    assert np.allclose(out["not_assemblable_ranges_deg"], expected, atol=1e-6)


def test_rotor_correction_angles_are_normalised(client: SynthClient) -> None:
    # Independent: one mass of unbalance 0.1 kg·m at 19.107°; the correction sits opposite, at 199.107°.
    body = {"masses": [{"mass_kg": 1.0, "radius_m": 0.1, "angle_deg": 19.107, "axial_position_m": 0.0}],
            "mode": "static", "correction_radius_m": 0.1}
    status, out = _post(client, "/v1/balancing/rotor", body)
    assert status == 200
    (corr,) = out["corrections"]
    assert corr["angle_deg"] == pytest.approx(199.107, abs=1e-9)


def test_coupler_and_rocker_counterweights_work_by_default(client: SynthClient) -> None:
    # The textbook variant (seed 001:1394): no crank counterweight, so the crank's first moment h1 fixes the
    # coupler's: m_c·(x_c - l2) = D with D = m2·l2 + (l2/l1)·h1 - h2 = 2·0.35 + 3.5·0.05 - 0.35 = 0.525 kg·m.
    # With the counterweight on the default largest radius 2·l2, m_c = D/(2·l2 - l2) = 1.5 kg.
    body = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "counterweight_links": ["coupler", "rocker"],
            "samples": 60}
    status, out = _post(client, "/v1/balancing/static", body)
    assert status == 200
    coupler = next(c for c in out["counterweights"] if c["link"] == "coupler")
    assert coupler["mass_kg"] == pytest.approx(0.525 / 0.35, rel=1e-6)
    assert coupler["position_m"][0] == pytest.approx(0.7, rel=1e-6)
    assert out["checks"]["residual_shaking_force_rel"] < 1e-6


def test_coupler_radius_too_small_names_the_radius_needed(client: SynthClient) -> None:
    # As above with max_radius_m.coupler = l2: no counterweight beyond B fits. One of the coupler's own mass
    # (2 kg) would need x_c = l2 + D/m = 0.35 + 0.525/2 = 0.6125 m.
    body = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "counterweight_links": ["coupler", "rocker"],
            "max_radius_m": {"coupler": 0.35}, "samples": 60}
    status, out = _post(client, "/v1/balancing/static", body)
    assert status == 422
    assert out["constraint"] == "max_radius_m.coupler"
    assert out["required_radius_m"] == pytest.approx(0.6125, rel=1e-12)


def test_full_balance_names_the_coupler_beyond_b(client: SynthClient) -> None:
    # Same variant in full mode: the coupler's centre of mass must move beyond B by (l2/l1)·h1/m > 0, where the
    # pendulum inertia m·a·(l - a) is negative; the cause is the missing crank counterweight.
    body = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "counterweight_links": ["coupler", "rocker"],
            "samples": 60}
    status, out = _post(client, "/v1/balancing/full", body)
    assert status == 422
    assert out["constraint"] == "counterweight_links"
    assert "beyond B" in out["detail"]


def test_full_balance_with_the_coupler_mass_at_a(client: SynthClient) -> None:
    # A coupler with its centre of mass at A is a physical pendulum with m·a·(l - a) = 0: zero inertia about it.
    mech = copy.deepcopy(FOURBAR_EXAMPLE)
    mech["links"]["coupler"]["com_m"] = [0.0, 0.0]
    status, out = _post(client, "/v1/balancing/full", {"mechanism": mech, "speed_rpm": 300, "samples": 60})
    assert status == 200
    assert out["coupler_inertia_kgm2"] == pytest.approx(0.0, abs=1e-7)
    assert out["checks"]["residual_shaking_moment_rel"] < 1e-5


@pytest.mark.parametrize("r_max", [0.1, 0.08])
def test_optimal_crank_counterweight_sits_on_its_limit(client: SynthClient, r_max: float) -> None:
    # Independent: with only the shaking force weighed, the crank counterweight's first moment is the least-squares
    # one, and the added-mass term m + J/l1² with J = m·r² (a point mass), i.e. |h|·(1/r + r/l1²), falls with r
    # up to l1 = 0.1 m: the optimum is at min(l1, r_max).
    body = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "counterweight_links": ["crank"],
            "max_radius_m": {"crank": r_max}, "samples": 90}
    status, out = _post(client, "/v1/balancing/optimal", body)
    assert status == 200
    (place,) = out["placements"]
    assert place["radius_m"] == pytest.approx(min(0.1, r_max), rel=1e-12)
