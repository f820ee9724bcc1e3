"""POST /v1/balancing/engine: several slider-cranks on one crankshaft, shaking by orders, against the classic
tables and an independent quadrature of the piston's motion."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from scipy.integrate import quad

from api.translate.engines import engine_from
from mechsynth_client.client import InvalidInputError, SynthClient
import synth
from mechsynth_client.schemas.engines import EngineIn

R, L, M_REC, RPM = 0.045, 0.15, 0.5, 3000.0
W = RPM * math.pi / 30
UNIT = M_REC * R * W**2  # m·r·w², the single cylinder's primary amplitude [N]


def _engine(client: SynthClient, **fields: Any) -> Any:
    body = {"crank_radius_m": R, "rod_length_m": L, "reciprocating_mass_kg": M_REC, "speed_rpm": RPM, **fields}
    return client.balance_engine(EngineIn.model_validate(body))


def _order_amplitude(k: int) -> float:
    """k-th cosine coefficient of the piston's acceleration over r·w²: twice integrating by parts over a period,
    k² times that of the exact position r·cos(t) + sqrt(l² - r²·sin²(t)) over r, by quadrature."""
    def s(t: float) -> float:
        return (R * math.cos(t) + math.sqrt(L**2 - (R * math.sin(t)) ** 2)) / R

    return abs(k**2 * quad(s, 0, 2 * math.pi, weight="cos", wvar=k, epsabs=1e-11)[0] / math.pi)


def test_single_cylinder_orders_and_the_seed_balance_shafts(client: SynthClient) -> None:
    out = _engine(client, cylinders=[{"crank_angle_deg": 0}], orders=4)
    for o in out.force_orders:
        a_k = _order_amplitude(o.order)
        assert o.largest == pytest.approx(UNIT * a_k, rel=1e-6, abs=1e-6 * UNIT)
        # seed 003 (6.32)-(6.33): two counter-rotating shafts at k·w, each m_B·r·A_k/2 (mass times radius)
        assert o.forward_mass_radius == pytest.approx(M_REC * R * a_k / 2 / o.order**2, rel=1e-6, abs=1e-12)
        assert o.backward_mass_radius == pytest.approx(o.forward_mass_radius, rel=1e-9, abs=1e-12)
    assert out.reconstruction_error_N <= 1e-9 * UNIT
    assert out.residual_force_N <= 1e-9 * UNIT


def test_inline_four_has_only_a_secondary_force(client: SynthClient) -> None:
    out = _engine(client, arrangement="inline4", pitch_m=0.09)
    first_f, second_f = out.force_orders[0], out.force_orders[1]
    first_m, second_m = out.moment_orders[0], out.moment_orders[1]
    assert first_f.balanced and first_m.balanced and second_m.balanced and not second_f.balanced
    # the classic table: 4·m·r·w²·(r/l), the first term of the exact order-2 coefficient
    lam = R / L
    assert second_f.largest == pytest.approx(4 * UNIT * lam, rel=lam**2 / 4 * 1.2)
    assert second_f.largest == pytest.approx(4 * UNIT * _order_amplitude(2), rel=1e-6)
    # vertical and reciprocating: a line, equal forward and backward circles, cancelled by two shafts at 2w
    assert second_f.smallest == pytest.approx(0.0, abs=1e-9 * UNIT)
    assert out.residual_force_N <= 1e-9 * UNIT and out.residual_moment_Nm <= 1e-9 * UNIT


def test_inline_six_is_balanced_in_first_and_second_orders(client: SynthClient) -> None:
    out = _engine(client, arrangement="inline6", pitch_m=0.1, orders=6)
    for o in (*out.force_orders[:2], *out.moment_orders[:2]):
        assert o.balanced, o
    # but not in the sixth: every throw's sixth order is in phase
    assert out.force_orders[5].largest == pytest.approx(6 * UNIT * _order_amplitude(6), rel=1e-4)


def test_ninety_degree_v_twin_primary_force_turns_with_the_crank(client: SynthClient) -> None:
    out = _engine(client, cylinders=[{"crank_angle_deg": 0, "bank_angle_deg": -45},
                                     {"crank_angle_deg": 0, "bank_angle_deg": 45}], rotating_mass_kg=0.3)
    first = out.force_orders[0]
    # the two axes' primary forces m·r·w²·cos(phi ∓ 45°) along them add to m·r·w² along the throw: constant
    # magnitude, a forward circle, plus the rotating mass's m_rot·r·w² (both cylinders' pins on one throw)
    expected = UNIT + 2 * 0.3 * R * W**2
    assert first.largest == pytest.approx(expected, rel=1e-9)
    assert first.smallest == pytest.approx(expected, rel=1e-9)
    assert first.backward == pytest.approx(0.0, abs=1e-9 * UNIT)
    # so the crank's own counterweight cancels it: m·r + 2·m_rot·r, opposite the throw (at 180° at phi = 0)
    assert first.forward_mass_radius == pytest.approx(M_REC * R + 2 * 0.3 * R, rel=1e-9)
    assert first.forward_angle_deg == pytest.approx(180.0, abs=1e-6)
    assert first.backward_mass_radius == pytest.approx(0.0, abs=1e-9)


def test_bad_engines_name_the_field(client: SynthClient) -> None:
    with pytest.raises(InvalidInputError) as err:
        _engine(client, crank_radius_m=0.2, arrangement="inline4")
    assert err.value.problem.get("field") == "crank_radius_m" or "crank_radius_m" in str(err.value)
    with pytest.raises(InvalidInputError) as err:
        _engine(client, arrangement="inline4", cylinders=[{"crank_angle_deg": 0}])
    assert "cylinders" in str(err.value)


def test_every_inline_arrangement_is_its_firing_order() -> None:
    from synth.balancing.engines import FIRING_ORDERS

    for name, order in FIRING_ORDERS.items():
        built = [c.crank_phase for c in synth.engine_layout(name)]
        assert built == pytest.approx(list(synth.firing_throws(order)), abs=1e-12), name
    with pytest.raises(synth.InvalidInput):
        synth.firing_throws([1, 2, 2, 4])


def test_the_inline_five_as_built_and_by_its_firing_order() -> None:
    base = {"crank_radius_m": 0.045, "rod_length_m": 0.15, "reciprocating_mass_kg": 0.5, "speed_rpm": 3000,
            "pitch_m": 0.09, "orders": 2}
    built = synth.engine_shaking(engine_from(EngineIn.model_validate({**base, "arrangement": "inline5"})))
    fired = synth.engine_shaking(engine_from(EngineIn.model_validate({**base, "firing_order": [1, 2, 4, 5, 3]})))
    # the primary couple of throws gamma_j at z_j = (j - 3)·a about the middle: m r w² a |sum (j - 3) e^(i gamma_j)|
    # (the reciprocating primary force m r w² cos(phi - gamma) as two counter-rotating halves, each half of it)
    throws = np.radians([0, 144, 216, 288, 72])
    couple = abs(np.sum((np.arange(5) - 2) * np.exp(1j * throws)))
    assert couple == pytest.approx(0.449, abs=5e-4)       # the production engine's figure, 0.449 m r w² a
    m_r_w2_a = 0.5 * 0.045 * (3000 * math.pi / 30) ** 2 * 0.09
    for e in (built, fired):
        assert e.moment_orders[0].largest == pytest.approx(couple * m_r_w2_a, rel=1e-9)
        assert e.force_orders[0].largest < 1e-9 * m_r_w2_a  # no primary force: the throws are even
