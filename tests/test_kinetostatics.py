"""Kinetostatics: the lecture-10 shaper against its seed cases; identities on random linkages; the linear map."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import synth
from conftest import CASES
from helpers import crank_fourbars, lecture_angle, shaper_from_case, slider_cranks, spectral_derivative
from synth.kinematics.motion import cross
from api.translate.linkage import linkage_from

EXACT = CASES["l10_shaper_drive_torque_exact"]


def _shaper_torque(**kw: object) -> float:
    inp = EXACT["inputs"]
    an = synth.analyse(shaper_from_case(inp, **kw), inp["omega1_rad_s"], phi=lecture_angle())  # type: ignore[arg-type]
    assert an.torque_check < 1e-9 * max(1.0, abs(an.kinetostatics.driving_torque[0]))
    return float(an.kinetostatics.driving_torque[0])


def _shaper_exact() -> synth.Analysis:
    inp = EXACT["inputs"]
    return synth.analyse(shaper_from_case(inp), inp["omega1_rad_s"], phi=lecture_angle())


def test_shaper_exact_driving_torque_and_reactions() -> None:
    an, exp, rel = _shaper_exact(), EXACT["expected"], EXACT["tolerance_rel"]
    k = an.kinetostatics
    mag = {name: float(np.hypot(*r[0])) for name, r in k.reactions.items()}
    assert k.driving_torque[0] == pytest.approx(exp["M_drive_Nm"], rel=rel)
    assert an.virtual_power_torque[0] == pytest.approx(exp["M_drive_Nm"], rel=rel)
    assert mag["B_slot"] == pytest.approx(exp["R45_N"], rel=rel)  # ram group: block 4 on ram 5
    assert mag["R"] == pytest.approx(exp["R05_N"], rel=rel)  # guide on ram
    assert mag["A_slot"] == pytest.approx(exp["R23_N"], rel=rel)  # block 2 on rocker 3
    assert mag["O1"] == pytest.approx(exp["R03_N"], rel=rel)
    assert mag["O"] == pytest.approx(exp["R01_N"], rel=rel)
    # k: offset of the guide reaction from S5 is its couple over its force.
    assert k.couples["R"][0] / k.reactions["R"][0, 1] == pytest.approx(exp["k_m"], rel=rel)


def test_shaper_torque_decomposes_into_the_seed_parts() -> None:
    # Linearity of the torque in the loads: each part with only its load present (seed exact case).
    exp, rel = EXACT["expected"], EXACT["tolerance_rel"]
    parts = {
        "M_part_cutting_Nm": _shaper_torque(gravity=False, masses=()),
        "M_part_ram_inertia_Nm": _shaper_torque(with_load=False, gravity=False, masses=("ram",)),
        "M_part_rocker_gravity_Nm": _shaper_torque(with_load=False, masses=("rocker",))
        - _shaper_torque(with_load=False, gravity=False, masses=("rocker",)),
        "M_part_rocker_inertia_Nm": _shaper_torque(with_load=False, gravity=False, masses=("rocker",)),
    }
    for key, value in parts.items():
        assert value == pytest.approx(exp[key], rel=rel), key


def test_shaper_ram_group_seed() -> None:
    case = CASES["l10_shaper_kinetostatics_ram_group"]
    exp, rel = case["expected"], case["tolerance_rel"]
    an = _shaper_exact()
    k, m = an.kinetostatics, an.motion
    assert abs(k.reactions["B_slot"][0, 0]) == pytest.approx(exp["R45_N"], rel=rel)
    assert k.reactions["R"][0, 1] == pytest.approx(exp["R05_N"], rel=rel)
    assert m.point_pos["S_ram"][0, 1] - m.point_pos["B"][0, 1] == pytest.approx(exp["d_m"], rel=rel)
    assert k.couples["R"][0] / k.reactions["R"][0, 1] == pytest.approx(exp["k_m"], rel=rel)


def test_shaper_rocker_group_seed() -> None:
    case = CASES["l10_shaper_kinetostatics_rocker_group"]
    exp, rel = case["expected"], case["tolerance_rel"]
    an = _shaper_exact()
    k, m = an.kinetostatics, an.motion
    o1, a, b = m.point_pos["O1"][0], m.point_pos["A"][0], m.point_pos["B"][0]
    assert float(np.hypot(*(a - o1))) == pytest.approx(exp["l_O1A_m"], rel=rel)
    assert b[1] - o1[1] == pytest.approx(exp["h43_m"], rel=rel)  # arm of the horizontal R43 about O1
    assert float(np.hypot(*k.reactions["A_slot"][0])) == pytest.approx(exp["R23_N"], rel=rel)
    # R23 is normal to the lever (a slot cannot push along itself).
    lever = (b - o1) / np.hypot(*(b - o1))
    assert float(k.reactions["A_slot"][0] @ lever) == pytest.approx(0.0, abs=1e-9)
    assert float(np.hypot(*k.reactions["O1"][0])) == pytest.approx(exp["R03_N_with_Phi3"], rel=rel)


def test_shaper_crank_seed_and_zhukovsky() -> None:
    crank = CASES["l10_shaper_crank_drive_torque"]
    an = _shaper_exact()
    k = an.kinetostatics
    assert k.driving_torque[0] == pytest.approx(crank["expected"]["M_drive_Nm"], rel=crank["tolerance_rel"])
    assert float(np.hypot(*k.reactions["O"][0])) == pytest.approx(crank["expected"]["R01_N"], rel=crank["tolerance_rel"])
    # Zhukovsky's lever in the lecture neglects the rocker's inertia but keeps its weight.
    lever = CASES["l10_shaper_zhukovsky_lever"]
    no_rocker_inertia = (
        _shaper_torque(masses=("ram",)) + _shaper_torque(with_load=False, masses=("rocker",))
        - _shaper_torque(with_load=False, gravity=False, masses=("rocker",))
    )
    assert no_rocker_inertia == pytest.approx(lever["expected"]["M_drive_Nm"], rel=lever["tolerance_rel"])


linkages = st.one_of(crank_fourbars(), slider_cranks())


def _with_loads(linkage: synth.Linkage, gravity: bool, load: float) -> synth.Linkage:
    output = linkage.mechanism.topology.output
    return synth.Linkage(
        linkage.mechanism,
        linkage.links,
        counterweights=(synth.Counterweight(output, 0.3, (-0.05, 0.02), 0.001),),
        gravity=synth.Gravity() if gravity else None,
        loads=(synth.ProcessLoad("window", load, 0.5, 3.5, point=(0.01, -0.02)),),
        torques=(synth.LinkTorque(linkage.mechanism.topology.links[1], 0.7),),
    )


@settings(max_examples=40, deadline=None)
@given(linkages, st.booleans(), st.floats(0.0, 50.0), st.floats(-20.0, 20.0))
def test_virtual_power_equals_kinetostatic_torque(linkage: synth.Linkage, gravity: bool, load: float,
                                                   eps: float) -> None:
    an = synth.analyse(_with_loads(linkage, gravity, load), 7.0, samples=90, crank_acceleration=eps)
    scale = 1.0 + float(np.abs(an.kinetostatics.driving_torque).max())
    assert an.torque_check <= 1e-9 * scale


@settings(max_examples=30, deadline=None)
@given(linkages, st.booleans())
def test_shaking_force_and_moment_equal_momentum_rates(linkage: synth.Linkage, gravity: bool) -> None:
    # Independent: total momentum and angular momentum about O, differentiated spectrally over the cycle.
    w = 3.0
    an = synth.analyse(_with_loads(linkage, gravity, 10.0), w, samples=256)
    m, k = an.motion, an.kinetostatics
    momentum = np.zeros((256, 2))
    ang_momentum = np.zeros(256)
    for link in linkage.mechanism.topology.links:
        props = an.linkage.mass_props(link)
        s = m.point_on(link, props.com)
        momentum += props.mass * s.vel
        ang_momentum += props.mass * cross(s.pos, s.vel) + props.inertia * m.link_omega[link]
    f_scale = 1.0 + float(np.abs(k.shaking_force).max())
    m_scale = 1.0 + float(np.abs(k.shaking_moment).max())
    assert k.shaking_force == pytest.approx(-w * spectral_derivative(momentum), abs=1e-6 * f_scale)
    assert k.shaking_moment == pytest.approx(-w * spectral_derivative(ang_momentum), abs=1e-6 * m_scale)


@settings(max_examples=30, deadline=None)
@given(linkages)
def test_torque_times_speed_is_rate_of_kinetic_energy(linkage: synth.Linkage) -> None:
    # Constant speed, no loads: T*w = dE/dt = w * dE/dphi, E = J_red w^2 / 2 differentiated spectrally.
    w = 5.0
    an = synth.analyse(linkage, w, samples=256)
    energy = an.reduced.kinetic_energy
    scale = 1.0 + float(np.abs(an.kinetostatics.driving_torque).max())
    assert an.kinetostatics.driving_torque * w == pytest.approx(w * spectral_derivative(energy), abs=1e-6 * scale * w)
    assert an.reduced.inertia_slope == pytest.approx(spectral_derivative(an.reduced.inertia), abs=1e-6 * scale)


@settings(max_examples=30, deadline=None)
@given(linkages, st.booleans(), st.floats(-20.0, 20.0))
def test_linear_map_reproduces_the_direct_solve(linkage: synth.Linkage, gravity: bool, eps: float) -> None:
    full = _with_loads(linkage, gravity, 20.0)
    an = synth.analyse(full, 4.0, samples=60, crank_acceleration=eps)
    lm = synth.linear_map(an.motion, full)
    out = lm.evaluate(full.params())
    k = an.kinetostatics
    scale = 1.0 + float(np.abs(k.unknowns).max())
    assert out[:, lm.torque_row] == pytest.approx(k.driving_torque, abs=1e-10 * scale)
    assert out[:, lm.force_rows] == pytest.approx(k.shaking_force, abs=1e-10 * scale)
    assert out[:, lm.moment_row] == pytest.approx(k.shaking_moment, abs=1e-10 * scale)
    assert out[:, : lm.torque_row] == pytest.approx(k.unknowns[:, :-1], abs=1e-10 * scale)
    # A counterweight's columns are its link's columns: adding it changes outputs by Y @ its parameters.
    cw = synth.Counterweight("crank", 0.4, (-0.03, 0.01), 0.002)
    moved = synth.analyse(full.with_counterweights([cw]), 4.0, samples=60, crank_acceleration=eps).kinetostatics
    delta = np.einsum("nrk,k->nr", lm.y[:, :, lm.columns("crank")], cw.params())
    assert moved.driving_torque - k.driving_torque == pytest.approx(delta[:, lm.torque_row], abs=1e-10 * scale)
    point = synth.Counterweight("crank", 0.4, (-0.03, 0.01))
    moved = synth.analyse(full.with_counterweights([point]), 4.0, samples=60, crank_acceleration=eps).kinetostatics
    per_kg = lm.point_mass("crank", point.position)
    assert moved.shaking_moment - k.shaking_moment == pytest.approx(0.4 * per_kg[:, lm.moment_row], abs=1e-10 * scale)


def test_pure_rotor_crank_has_the_textbook_shaking_force() -> None:
    # Independent closed form: a lone crank mass m at r spinning at w shakes the frame with m r w^2 outward.
    fb = synth.FourBar(0.3, 0.1, 0.35, 0.25)
    linkage = synth.Linkage(fb, {"crank": synth.MassProps(2.0, (0.05, 0.0), 0.0)})
    an = synth.analyse(linkage, 10.0, samples=36)
    phi = an.motion.phi
    expected = 2.0 * 0.05 * 100.0 * np.stack([np.cos(phi), np.sin(phi)], axis=-1)
    assert an.kinetostatics.shaking_force == pytest.approx(expected, rel=1e-12)
    assert an.summary().rms_shaking_force == pytest.approx(10.0, rel=1e-12)


def test_dead_position_is_reported_not_nan() -> None:
    # A rocker-crank driven from its rocker toggles: at the toggle the crank cannot drive it.
    fb = synth.FourBar(0.3, 0.25, 0.35, 0.1)
    lo, hi = fb.cos_limits()
    edge = math.acos(max(-1.0, min(1.0, hi))) if hi < 1 else math.acos(lo)
    with pytest.raises(synth.NotAssemblable):
        synth.analyse(synth.Linkage(fb, {"coupler": synth.MassProps(1.0, (0.1, 0), 0.01)}), 1.0, phi=np.array([edge]))


def test_dead_positions_are_judged_as_on_the_full_system(monkeypatch: pytest.MonkeyPatch) -> None:
    # A triple-rocker at the edge of its assembly gap: at crank angle t, |AQ| = |b - c| and the coupler folds
    # onto the rocker (a dead position). The reduced solve must flag exactly the angles whose full 9x9 system has
    # a Hadamard ratio below the threshold, computed here independently with numpy's determinant of the
    # row-normalised matrix. (Change-point four-bars, the classic case, are refused before any analysis.)
    from synth import kinetostatics

    fb = synth.FourBar(0.3, 0.28, 0.35, 0.25)
    linkage = synth.Linkage(fb, {"crank": synth.MassProps(1.0, (0.05, 0.0), 0.001),
                                 "coupler": synth.MassProps(1.0, (0.15, 0.0), 0.01),
                                 "rocker": synth.MassProps(1.0, (0.1, 0.0), 0.004)})
    t = float(np.arccos(fb.cos_limits()[1]))
    phi = np.array([t, t + 1e-4, 0.6, 1.0])
    mot = synth.kinematics.motion(fb, phi, 10.0, 0.0)
    a = kinetostatics.system_matrix(mot, fb.topology)
    ratio = np.abs(np.linalg.det(a / np.linalg.norm(a, axis=2)[..., None]))
    threshold = float(np.sqrt(ratio[0] * ratio[1]))      # between the two smallest: only angle 0 is dead
    monkeypatch.setattr(kinetostatics, "SINGULAR_RATIO", threshold)
    with pytest.raises(synth.NotAssemblable) as err:
        synth.analyse(linkage, 10.0, phi=phi)
    assert np.asarray(err.value.phi) == pytest.approx(phi[ratio < threshold])



@settings(max_examples=20, deadline=None)
@given(linkages, st.booleans(), st.floats(0.0, 50.0))
def test_constant_elimination_equals_the_per_angle_one(linkage: synth.Linkage, gravity: bool, load: float) -> None:
    # Where the kept unknowns' force rows are constant (revolute joints, slides fixed in the frame) F⁻¹·G is
    # formed once per topology; the per-angle product, which a slide turning with a link needs, must give the
    # same unknowns for the same topology.
    from dataclasses import replace

    from synth import kinetostatics

    loaded = _with_loads(linkage, gravity, load)
    red = kinetostatics._reduction(loaded.mechanism.topology)
    assert red is not None and red.g is not None
    mot = synth.analyse(loaded, 7.0, samples=90, crank_acceleration=3.0).motion
    once = kinetostatics.solve_direct(mot, loaded).unknowns
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(kinetostatics, "_reduction", lambda topo: replace(red, g=None))
        per_angle = kinetostatics.solve_direct(mot, loaded).unknowns
    scale = 1.0 + float(np.abs(once).max())
    assert np.abs(once - per_angle).max() <= 1e-12 * scale


@pytest.mark.parametrize("blocked", [True, False])
def test_stacked_solves_of_more_than_three_unknowns_equal_lapack(blocked: bool) -> None:
    # Systems of more than 3 unknowns (linkages of more than three moving links) are solved either block by block
    # (a lower block-triangular pattern, as dyads give) or by vectorised elimination with partial pivoting; both
    # against numpy's LAPACK determinant and solve of the same matrices, angle by angle.
    from synth import kinetostatics

    rng = np.random.default_rng(24)
    k, n = 6, 200
    s = rng.normal(size=(k, k, n))
    if blocked:  # blocks {0, 3}, {1}, {2, 4, 5} in a scrambled order: zero wherever a later block would feed back
        order = [[0, 3], [1], [2, 4, 5]]
        for b, block in enumerate(order):
            for later in order[b + 1 :]:
                s[np.ix_(block, later)] = 0.0
    r = rng.normal(size=(k, 2, n))
    det, x = kinetostatics._det_and_solve(s, r)
    assert (kinetostatics._block_det_and_solve(s, r) is not None) == blocked
    per_angle = np.moveaxis(s, -1, 0)
    expected_x = np.linalg.solve(per_angle, np.moveaxis(r, -1, 0))
    expected_det = np.linalg.det(per_angle)
    assert np.abs(det - expected_det).max() <= 1e-12 * np.abs(expected_det).max()
    assert np.abs(np.moveaxis(x, -1, 0) - expected_x).max() <= 1e-9 * (1 + np.abs(expected_x).max())


def test_a_reanalysis_on_the_shared_motion_equals_a_fresh_one() -> None:
    # Balancing analyses the same mechanism before and after adding counterweights on one motion; the shared
    # motion must give the very numbers a fresh analysis gives (the kinematics are deterministic).
    from mechsynth_client.schemas.analysis import AnalysisIn
    from mechsynth_client.schemas.common import FOURBAR_EXAMPLE

    linkage = linkage_from(AnalysisIn.model_validate({"mechanism": FOURBAR_EXAMPLE, "gravity": {"g_m_s2": 9.81}}))
    before = synth.analyse(linkage, 12.0, samples=90)
    heavier = linkage.with_counterweights([synth.Counterweight("crank", 0.8, (-0.04, 0.01))])
    shared = synth.analyse(heavier, 12.0, samples=90, base_motion=before.mechanism_motion)
    fresh = synth.analyse(heavier, 12.0, samples=90)
    for a, b in ((shared.kinetostatics.unknowns, fresh.kinetostatics.unknowns),
                 (shared.kinetostatics.shaking_moment, fresh.kinetostatics.shaking_moment),
                 (shared.reduced.inertia, fresh.reduced.inertia), (shared.virtual_power_torque, fresh.virtual_power_torque)):
        assert np.array_equal(a, b)
    with pytest.raises(ValueError, match="base_motion"):
        synth.analyse(heavier, 13.0, samples=90, base_motion=before.mechanism_motion)
