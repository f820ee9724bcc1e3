"""Static balancing by fixed points (seed 8.3-8.4) through the API, against the seed's recipe computed here."""

from __future__ import annotations

import copy

import pytest

from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE


def _masses(out: dict) -> dict[str, float]:
    return {c["link"]: c["mass_kg"] for c in out["counterweights"]}


def test_three_counterweights_follow_the_corrected_recipe(client: SynthClient) -> None:
    # Seed [003:590-617] with its (6.10) corrected: S1 -> O: m1·l_OS1 = m_P1·r1 (6.8); S2 -> B: m2·l_BS2 = m_P2·d2
    # with d2 the counterweight's distance beyond B (6.9); then the rocker with m2 + m_P2 at B about Q:
    # (m2 + m_P2)·l_QB + m3·l_QS3 = m_P3·r3. The printed (6.10) leaves m_P2 out and does not balance.
    fb = FOURBAR_EXAMPLE
    links = fb["links"]
    l2, l3 = fb["coupler_length_m"], fb["rocker_length_m"]
    r1, r2, r3 = 0.08, 0.6, 0.2  # radii from each link's first joint; the coupler's lies d2 = r2 - l2 beyond B
    m1, m2, m3 = (links[k]["mass_kg"] for k in ("crank", "coupler", "rocker"))
    a1, a2, a3 = (links[k]["com_m"][0] for k in ("crank", "coupler", "rocker"))
    m_p1 = m1 * a1 / r1
    m_p2 = m2 * (l2 - a2) / (r2 - l2)
    m_p3 = ((m2 + m_p2) * l3 + m3 * a3) / r3
    printed = (m2 * l3 + m3 * a3) / r3
    body = {"mechanism": fb, "speed_rpm": 300, "samples": 60, "method": "fixed_points",
            "counterweight_links": ["crank", "coupler", "rocker"],
            "radius_m": {"crank": r1, "coupler": r2, "rocker": r3}}
    r = client.http.post("/v1/balancing/static", json=body)
    assert r.status_code == 200, r.text
    out = r.json()
    got = _masses(out)
    assert got["crank"] == pytest.approx(m_p1, rel=1e-12)
    assert got["coupler"] == pytest.approx(m_p2, rel=1e-12)
    assert got["rocker"] == pytest.approx(m_p3, rel=1e-12)
    assert abs(got["rocker"] / printed - 1) > 0.1  # the printed recipe would leave a shaking force
    # Independent check: the plain re-analysis with these counterweights has no shaking force left.
    assert out["checks"]["residual_shaking_force_rel"] < 1e-9
    com = {p["link"]: p["link_com_m"] for p in out["placements"]}
    mass = {p["link"]: p["link_mass_kg"] for p in out["placements"]}
    assert com["crank"] == pytest.approx([0.0, 0.0], abs=1e-12)
    assert com["coupler"] == pytest.approx([l2, 0.0], abs=1e-12)
    # The rocker and the coupler's mass at B (x = l3 in the rocker's frame) together have their centre at Q.
    assert mass["rocker"] * com["rocker"][0] + mass["coupler"] * l3 == pytest.approx(0.0, abs=1e-12)


def test_two_counterweights_by_point_masses(client: SynthClient) -> None:
    # Seed [003:619-671] (6.14)-(6.21), a coupler whose centre of mass is off AB by y2: first moments as complex
    # numbers, m_A = m2 - h2/l2 at A and m_B = h2/l2 at B; the crank's counterweight first moment is
    # -(h1 + m_A·l1), the rocker's -(h3 + m_B·l3), on radii r1 and r3.
    fb = copy.deepcopy(FOURBAR_EXAMPLE)
    fb["links"]["coupler"]["com_m"] = [0.12, 0.03]
    links = fb["links"]
    l1, l2, l3 = fb["crank_length_m"], fb["coupler_length_m"], fb["rocker_length_m"]
    h = {k: links[k]["mass_kg"] * complex(*links[k]["com_m"]) for k in ("crank", "coupler", "rocker")}
    m_b = h["coupler"] / l2
    m_a = links["coupler"]["mass_kg"] - m_b
    need1, need3 = -(h["crank"] + m_a * l1), -(h["rocker"] + m_b * l3)
    body = {"mechanism": fb, "speed_rpm": 300, "samples": 60, "method": "fixed_points"}
    r = client.http.post("/v1/balancing/static", json=body)
    assert r.status_code == 200, r.text
    out = r.json()
    cw = {c["link"]: c for c in out["counterweights"]}
    for link, need, radius in (("crank", need1, l1), ("rocker", need3, l3)):  # default radii: the link lengths
        assert cw[link]["mass_kg"] == pytest.approx(abs(need) / radius, rel=1e-12)
        pos = complex(*cw[link]["position_m"])
        assert pos * cw[link]["mass_kg"] == pytest.approx(need, rel=1e-12)
    assert out["checks"]["residual_shaking_force_rel"] < 1e-9


def test_fixed_points_reject_given_angles(client: SynthClient) -> None:
    body = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "method": "fixed_points", "angle_deg": {"crank": 180}}
    r = client.http.post("/v1/balancing/static", json=body)
    assert r.status_code == 422 and r.json()["field"] == "angle_deg"
