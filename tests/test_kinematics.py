"""Kinematics: the lecture-10 shaper against its seed cases, loop closure, analogues, assembly ranges."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings

import synth
from synth.kinematics import motion

from conftest import CASES
from helpers import crank_fourbars, lecture_angle, shaper_from_case, slider_cranks, spectral_derivative


@pytest.mark.parametrize("case_id", ["l10_shaper_kinematics_exact", "l10_shaper_kinematics_plan"])
def test_shaper_matches_seed(case_id: str) -> None:
    case = CASES[case_id]
    inp, exp, rel = case["inputs"], case["expected"], case["tolerance_rel"]
    link = shaper_from_case(inp, with_load=False)
    an = synth.analyse(link, inp["omega1_rad_s"], phi=lecture_angle(), crank_acceleration=inp["eps1_rad_s2"])
    m = an.motion
    s3 = m.point_on("rocker", (inp["l_O1S3_m"], 0.0))
    got = {
        "omega3_rad_s": m.link_omega["rocker"][0],
        "eps3_rad_s2": m.link_alpha["rocker"][0],
        "v_ram_m_s": abs(m.point_vel["R"][0, 0]),
        "a_ram_m_s2": abs(m.point_acc["R"][0, 0]),
        "a_S5_m_s2": abs(m.point_acc["S_ram"][0, 0]),
        "v_S3_m_s": float(np.hypot(*s3.vel[0])),
        "a_S3_m_s2": float(np.hypot(*s3.acc[0])),
        "l_O1A_m": float(np.hypot(*(m.point_pos["A"][0] - m.point_pos["O1"][0]))),
        "psi_deg": math.degrees(math.pi / 2 - m.link_angle["rocker"][0]),
        "v_A3_over_v_A": math.sin(math.pi / 2 - m.link_angle["rocker"][0]),
    }
    for key, value in exp.items():
        assert got[key] == pytest.approx(value, rel=rel), key


@settings(max_examples=30, deadline=None)
@given(crank_fourbars())
def test_fourbar_loop_closes_and_analogues_match_spectral_derivatives(linkage: synth.Linkage) -> None:
    fb = linkage.mechanism
    phi = synth.cycle_angles(512)
    m = motion(fb, phi, 1.0)
    a, b, q = m.point_pos["A"], m.point_pos["B"], m.point_pos["Q"]
    # Identity: link lengths are kept at every angle.
    assert np.hypot(*(b - a).T) == pytest.approx(np.full(512, fb.coupler), abs=1e-12)
    assert np.hypot(*(b - q).T) == pytest.approx(np.full(512, fb.rocker), abs=1e-12)
    # Independent derivative: spectral differentiation of the positions over the full cycle (omega = 1).
    assert m.point_vel["B"] == pytest.approx(spectral_derivative(b), abs=1e-6 * fb.rocker)
    assert m.point_acc["B"] == pytest.approx(spectral_derivative(b, 2), abs=1e-5 * fb.rocker)
    # Branch convention: B to the left of A->Q for +1.
    side = np.sign((q[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1]) - (q[:, 1] - a[:, 1]) * (b[:, 0] - a[:, 0]))
    assert np.all(side == fb.branch)


@settings(max_examples=30, deadline=None)
@given(slider_cranks())
def test_slider_crank_analogues_match_spectral_derivatives(linkage: synth.Linkage) -> None:
    sc = linkage.mechanism
    m = motion(sc, synth.cycle_angles(512), 1.0)
    b = m.point_pos["B"]
    assert np.hypot(*(b - m.point_pos["A"]).T) == pytest.approx(np.full(512, sc.rod), abs=1e-12)
    assert b[:, 1] == pytest.approx(np.full(512, sc.offset), abs=1e-12)
    assert m.point_acc["B"] == pytest.approx(spectral_derivative(b, 2), abs=1e-5 * sc.crank)


def test_crank_acceleration_adds_tangential_terms() -> None:
    # a = w^2 r'' + eps r' (seed 001:966-1006, with the omega^2 correction): compare two runs.
    fb = synth.FourBar(0.3, 0.1, 0.35, 0.25)
    phi = synth.cycle_angles(36)
    m0, m1 = motion(fb, phi, 5.0, 0.0), motion(fb, phi, 5.0, 2.0)
    expected = m0.point_acc["B"] + 2.0 * m0.point_vel["B"] / 5.0
    assert m1.point_acc["B"] == pytest.approx(expected, abs=1e-12)


def test_not_assemblable_reports_the_exact_gap() -> None:
    fb = synth.FourBar(0.2, 0.15, 0.1, 0.12)
    with pytest.raises(synth.NotAssemblable) as err:
        motion(fb, synth.cycle_angles(3600), 1.0)
    (start, end), = err.value.ranges_deg
    # Independent: the loop closes iff |AQ| <= coupler + rocker, |AQ|^2 = a^2 + d^2 - 2 a d cos(phi).
    limit = math.degrees(math.acos((0.15**2 + 0.2**2 - 0.22**2) / (2 * 0.15 * 0.2)))
    assert (start, end) == pytest.approx((limit, 360 - limit), abs=1e-9)
    bad = np.degrees(err.value.phi)
    assert bad.min() >= start and bad.max() <= end


@pytest.mark.parametrize(
    ("lengths", "expected"),
    [
        ((0.3, 0.1, 0.35, 0.25), "crank-rocker"),
        ((0.1, 0.3, 0.35, 0.25), "double-crank"),
        ((0.3, 0.35, 0.1, 0.25), "double-rocker"),
        ((0.3, 0.35, 0.25, 0.1), "rocker-crank"),
        ((0.3, 0.28, 0.35, 0.25), "triple-rocker"),
    ],
)
def test_grashof_classes(lengths: tuple[float, float, float, float], expected: str) -> None:
    assert synth.FourBar(*lengths).grashof == expected


@pytest.mark.parametrize(
    ("lengths", "folded_deg"),
    [
        # |AQ| at phi = 0 is d - a = 0.2 = b - c: the coupler folds onto the rocker there only.
        ((0.3, 0.1, 0.35, 0.15), [0.0]),
        # The parallelogram folds at 0 deg (d - a = b - c = 0.2) and 180 deg (d + a = b + c = 0.4).
        ((0.3, 0.1, 0.3, 0.1), [0.0, 180.0]),
    ],
)
def test_change_point_linkages_are_refused_with_their_collinear_angles(
        lengths: tuple[float, float, float, float], folded_deg: list[float]) -> None:
    with pytest.raises(synth.InvalidInput) as err:
        synth.FourBar(*lengths)
    assert err.value.field == "mechanism" and "change-point" in str(err.value)
    assert str(folded_deg) in str(err.value)


def test_invalid_dimensions_are_named() -> None:
    with pytest.raises(synth.InvalidInput) as err:
        synth.FourBar(0.3, -0.1, 0.35, 0.25)
    assert err.value.field == "mechanism.crank_length_m"
    with pytest.raises(synth.InvalidInput):
        synth.FourBar(1.0, 0.1, 0.2, 0.3)  # longest link longer than the other three together
    with pytest.raises(synth.InvalidInput) as err:
        synth.SlottedLever(0.4, 0.3, 0.9, 0.7)
    assert err.value.field == "mechanism.crank_length_m"


def test_sample_limit() -> None:
    with pytest.raises(synth.TooLarge):
        synth.analyse(synth.Linkage(synth.FourBar(0.3, 0.1, 0.35, 0.25)), 1.0, samples=10, max_samples=5)
