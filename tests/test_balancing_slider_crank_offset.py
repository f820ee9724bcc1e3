"""Lanchester balancing of offset (desaxé) slider-cranks: the orders cancelled and those left alone, the limit of
a vanishing offset, the first order against its series in the offset, the balancers' moment, and the endpoint."""

from __future__ import annotations

import io
import math

import matplotlib.image as mpimg
import numpy as np
import pytest

import synth
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.balancing import SLIDER_CRANK_EXAMPLE, SliderCrankBalanceIn

R, L, E = 0.05, 0.2, 0.02  # crank, rod, offset [m]
W = 1500 * math.pi / 30  # 1500 rpm [rad/s]
M_B = 1.2 + 0.8 * 0.06 / L  # the slider plus the rod's static share at B, from the masses below [kg]


def _linkage(offset: float, branch: int = 1) -> synth.Linkage:
    return synth.Linkage(synth.SliderCrank(R, L, offset, branch), {
        "crank": synth.MassProps(1.0, (0.02, 0.0), 0.001),
        "rod": synth.MassProps(0.8, (0.06, 0.0), 0.003),
        "slider": synth.MassProps(1.2),
    })


def _balancers(pairs: list[tuple[int, float, float, float]], phi: np.ndarray, w: float,
               line_y: float) -> tuple[np.ndarray, np.ndarray]:
    """Force (N, 2) and moment about O (N,) of pairs (order, mass, radius, phase [rad]) as the answer documents
    them: at crank angle phi the clockwise shaft's mass points at phase - k·phi, the counter-clockwise one's at
    k·phi - phase, each pulling its shaft outward with m·rho·(k·w)²; the shafts sit in mirror image about the line
    y = line_y, so the y-pulls cancel without a couple and the x-force acts on that line (moment -y·Fx)."""
    force = np.zeros((len(phi), 2))
    for k, m, rho, psi in pairs:
        for angle in (psi - k * phi, k * phi - psi):
            force += m * rho * (k * w) ** 2 * np.stack([np.cos(angle), np.sin(angle)], axis=1)
    return force, -line_y * force[:, 0]


def _orders(force: np.ndarray, orders: int) -> np.ndarray:
    """Complex harmonics (orders, 2) of a force sampled at phi_i = 2·pi·i/N: f ≈ sum Re(H_k·e^{i·k·phi})."""
    return (np.fft.fft(force, axis=0) * 2 / len(force))[1:orders + 1]


def _pairs(result: synth.SliderCrankBalance) -> list[tuple[int, float, float, float]]:
    return [(p.order, p.mass, p.radius, p.phase) for p in result.pairs]


@pytest.mark.parametrize("branch", [1, -1])
def test_offset_orders_one_and_two_cancel_and_the_others_stay(branch: int) -> None:
    # Independent of the module: the plain engine re-run here with the answer's counterweight at 512 samples (the
    # sizing used 360, so this is not its own FFT bins), plus the pairs rebuilt from the documented convention,
    # and the harmonics of both forces by numpy's complex FFT. The counterweight is a pure first order and the
    # pairs pure first and second orders, so orders 3..6 of the force must be those of the unbalanced linkage.
    linkage = _linkage(E, branch)
    result = synth.balance_slider_crank(linkage, W)
    n = 512
    before = synth.analyse(linkage, W, samples=n).kinetostatics.shaking_force
    balanced = synth.analyse(linkage.with_counterweights([result.crank_counterweight]), W, samples=n)
    phi = balanced.motion.phi
    after = balanced.kinetostatics.shaking_force + _balancers(_pairs(result), phi, W, E)[0]
    h_before, h_after = _orders(before, 6), _orders(after, 6)
    size = np.linalg.norm(h_before, axis=1)
    assert size[2] > 10.0  # the offset's third order (13.6 N here); an in-line slider-crank has none
    for k in (1, 2):
        assert np.linalg.norm(h_after[k - 1]) < 1e-6 * size[k - 1]
        assert result.residual_by_order[k - 1] < 1e-6 * size[k - 1]
    for k in range(3, 7):
        assert np.linalg.norm(h_after[k - 1] - h_before[k - 1]) <= 1e-9 * size[k - 1]
        # The module's peak of order k: the major semi-axis of the ellipse Re(H_k·e^{ik·phi}) traces.
        peak = np.linalg.svd(np.stack([h_before[k - 1].real, -h_before[k - 1].imag], axis=1), compute_uv=False)[0]
        assert result.residual_by_order[k - 1] == pytest.approx(peak, rel=1e-9)


@pytest.mark.parametrize("branch", [1, -1])
def test_a_vanishing_offset_gives_the_in_line_answer(branch: int) -> None:
    # Continuity: every figure of the answer at e = 1e-9 m equals the in-line one to 1e-6 relative (the first
    # order's phase moves by about e/l = 5e-9 rad, the amplitudes by O(e²)); forces left near round-off are
    # compared on the scale of the unbalanced force, phases as angles.
    inline = synth.balance_slider_crank(_linkage(0.0, branch), W)
    tiny = synth.balance_slider_crank(_linkage(1e-9, branch), W)
    rel = 1e-6
    for field in ("rotating_mass", "reciprocating_mass", "first_order_amplitude", "second_order_amplitude",
                  "residual", "residual_moment"):
        assert getattr(tiny, field) == pytest.approx(getattr(inline, field), rel=rel), field
    assert tiny.crank_counterweight.mass == pytest.approx(inline.crank_counterweight.mass, rel=rel)
    assert np.allclose(tiny.crank_counterweight.position, inline.crank_counterweight.position, rtol=0, atol=rel * R)
    for a, b in zip(tiny.pairs, inline.pairs, strict=True):
        assert (a.order, a.radius) == (b.order, b.radius)
        assert a.mass == pytest.approx(b.mass, rel=rel) and a.amplitude == pytest.approx(b.amplitude, rel=rel)
        assert abs(math.remainder(a.phase - b.phase, 2 * math.pi)) < rel
    scale = inline.before.max_shaking_force
    assert np.allclose(tiny.residual_by_order, inline.residual_by_order, rtol=0, atol=rel * scale)
    assert inline.balancer_moment == 0.0
    assert tiny.balancer_moment < rel * inline.before.max_shaking_moment


def test_the_first_order_of_a_small_offset_follows_its_series() -> None:
    # x_B = r·cos(phi) + sqrt(l² - (e - r·sin(phi))²) (branch +1). (a) Any function of sin(phi) is unchanged by
    # phi -> pi - phi, which turns cos(phi) round, so the cos(phi) coefficient of x_B is r exactly, whatever e.
    # (b) To first order in e, d/de sqrt(l² - (e - r·s)²) at e = 0 is r·s/sqrt(l² - r²s²) = lambda·s·(1 +
    # lambda²s²/2 + 3·lambda⁴s⁴/8 + ...) with lambda = r/l (binomial series), and the sin(phi) coefficients of s³
    # and s⁵ are 3/4 and 10/16 (s³ = (3s - sin 3phi)/4, s⁵ = (10s - 5 sin 3phi + sin 5phi)/16), so the sin(phi)
    # coefficient is b1 = e·lambda·(1 + 3·lambda²/8 + 15·lambda⁴/64) + O(e·lambda⁷) + O(e³/l²). At constant w the
    # slider's inertia force -m_B·a_B has the first harmonic m_B·w²·(r·cos(phi) + b1·sin(phi)).
    # With e = 1 mm the terms left out are 35·lambda⁶/128 = 6.7e-5 and (e/l)²/2 = 1.3e-5 of b1: tolerance 2e-4
    # (the lambda⁴ term, 9.2e-4 of b1, is inside what is checked).
    e = 1e-3
    lam = R / L
    result = synth.balance_slider_crank(_linkage(e), W)
    first = result.pairs[0]
    # The pair points its masses along +x at k·phi = phase, against the force: the force's own phase is phase - pi.
    cos_part = -first.amplitude * math.cos(first.phase)
    sin_part = -first.amplitude * math.sin(first.phase)
    assert cos_part == pytest.approx(M_B * W**2 * R, rel=1e-9)
    assert sin_part == pytest.approx(M_B * W**2 * e * lam * (1 + 3 * lam**2 / 8 + 15 * lam**4 / 64), rel=2e-4)
    # The even orders stay pure cosines with an offset (same symmetry: cos(2·phi) is unchanged by phi -> pi - phi,
    # sin(2·phi) turns round), so the second pair keeps the in-line phase, 180° for branch +1.
    assert math.degrees(result.pairs[1].phase) == pytest.approx(180.0, abs=1e-9)


def test_the_balancers_add_the_offset_times_their_force_to_the_moment() -> None:
    # Independent: the pairs' force acts on the slide axis y = e, so about O it adds -e·Fx; what is left is the
    # plain engine's shaking moment with the counterweight (computed here) plus that.
    linkage = _linkage(E)
    result = synth.balance_slider_crank(linkage, W)
    balanced = synth.analyse(linkage.with_counterweights([result.crank_counterweight]), W, samples=360)
    _, moment = _balancers(_pairs(result), balanced.motion.phi, W, E)
    assert result.balancer_line_y == E
    assert result.balancer_moment == pytest.approx(np.abs(moment).max(), rel=1e-9)
    assert result.residual_moment == pytest.approx(np.abs(balanced.kinetostatics.shaking_moment + moment).max(),
                                                   rel=1e-9)
    assert np.allclose(result.after_moment, balanced.kinetostatics.shaking_moment + moment, rtol=0,
                       atol=1e-9 * result.before.max_shaking_moment)
    # With an offset too, the counterweight takes all of the force across the slide: what is left is along it.
    assert np.abs(result.after_force[:, 1]).max() < 1e-9 * result.before.max_shaking_force


def test_offset_endpoint_answers_with_phases_residuals_and_a_figure(client: SynthClient) -> None:
    # The answer's counterweight re-sent to /v1/analysis, plus the pairs rebuilt from mass_kg, radius_m and
    # phase_deg by the convention phase_deg's description states: orders 1 and 2 of what is left are round-off.
    mech = {**SLIDER_CRANK_EXAMPLE, "offset_m": E}
    r = client.http.post("/v1/balancing/slider-crank", json={"mechanism": mech, "speed_rpm": 1500})
    assert r.status_code == 200, r.text
    out = r.json()
    assert out["balancer_line_y_m"] == E and len(out["residual_by_order_N"]) == 6
    first, second = out["lanchester"]
    assert 0 <= first["phase_deg"] < 360 and 0 <= second["phase_deg"] < 360
    # e/l = 0.1 turns the first order by atan(0.1·(1 + 3·lambda²/8)) = 5.84° by the series below; the (e/l)²/2
    # = 0.5 % of it that series leaves out is 0.03°, hence 0.05°.
    assert first["phase_deg"] == pytest.approx(180 + math.degrees(math.atan(E / L * (1 + 3 * (R / L) ** 2 / 8))),
                                               abs=0.05)
    # the analyses in full precision: the residuals below are compared at the engine's round-off
    an = client.http.post("/v1/analysis?precision=full", json={"mechanism": mech, "speed_rpm": 1500,
                                                "counterweights": [out["crank_counterweight"]]}).json()
    phi = np.radians(an["crank_angle_deg"])
    pairs = [(p["order"], p["mass_kg"], p["radius_m"], math.radians(p["phase_deg"])) for p in out["lanchester"]]
    force, moment = _balancers(pairs, phi, W, out["balancer_line_y_m"])
    after = np.asarray(an["shaking_force_N"]) + force
    before = client.http.post("/v1/analysis?precision=full", json={"mechanism": mech, "speed_rpm": 1500}).json()
    size = np.linalg.norm(_orders(np.asarray(before["shaking_force_N"]), 2), axis=1)
    assert np.all(np.linalg.norm(_orders(after, 2), axis=1) < 1e-6 * size)
    assert out["residual_shaking_force_N"] == pytest.approx(np.hypot(*after.T).max(), rel=1e-9)
    assert out["residual_shaking_moment_Nm"] == pytest.approx(
        np.abs(np.asarray(an["shaking_moment_Nm"]) + moment).max(), rel=1e-9)
    assert out["balancer_moment_Nm"] == pytest.approx(np.abs(moment).max(), rel=1e-9)

    png = client.balance_slider_crank_png(SliderCrankBalanceIn.model_validate(
        {"mechanism": mech, "speed_rpm": 1500}))
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    img = np.asarray(mpimg.imread(io.BytesIO(png), format="png"))[:, :, :3]
    h, w, _ = img.shape
    assert w / h == pytest.approx(17 / 10.5, rel=0.15)  # the 2 × 3 panel layout
    cells = [img[i * h // 2:(i + 1) * h // 2, j * w // 3:(j + 1) * w // 3] for i in range(2) for j in range(3)]

    def count(cell: np.ndarray, rgb: tuple[int, int, int]) -> int:
        return int(np.sum(np.abs(cell - np.array(rgb) / 255).max(axis=2) < 0.08))

    # "after" (tab:red) on the polar diagram, the order bars and the moment; the shafts (tab:green) in the drawing.
    assert min(count(c, (0xD6, 0x27, 0x28)) for c in cells[:3]) > 200
    assert count(np.hstack(cells[3:5]), (0x2C, 0xA0, 0x2C)) > 200
    assert client.http.post("/v1/balancing/slider-crank", params={"format": "csv"},
                            json={"mechanism": mech}).status_code == 422
