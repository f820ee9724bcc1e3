"""Dimensional synthesis engine: the crank-rocker and slider-crank families against dense scans written here on a
different parametrisation, their engine checks, and path generation recovering known four-bars."""

from __future__ import annotations

import math

import numpy as np
import pytest

import synth

# Targets are met to rounding: the engine's dead centres are roots found on its own position solution.
EXACT = 1e-9


def _locus(b1: np.ndarray, b2: np.ndarray, theta: float, n: int, reach: float) -> np.ndarray:
    """Every point O from which the chord B1-B2 is seen under the angle theta, (m, 2): two circular arcs, or the
    chord's own line (outside the chord, up to ``reach`` from it) when theta = 0. Written from the inscribed-angle
    theorem, independently of the engine's parametrisation."""
    s = float(np.hypot(*(b2 - b1)))
    mid, along = 0.5 * (b1 + b2), (b2 - b1) / s
    normal = np.array([-along[1], along[0]])
    if theta == 0.0:
        t = np.linspace(0.0, reach, n)[1:]
        return np.concatenate([b1 - t[:, None] * along, b2 + t[:, None] * along])
    radius = s / (2 * math.sin(theta))
    t = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    pts = []
    for side in (1.0, -1.0):
        centre = mid + side * normal * s / (2 * math.tan(theta))
        pts.append(centre + radius * np.stack([np.cos(t), np.sin(t)], axis=-1))
    o = np.concatenate(pts)
    u1, u2 = b1 - o, b2 - o
    seen = np.arctan2(np.abs(u1[:, 0] * u2[:, 1] - u1[:, 1] * u2[:, 0]), np.einsum("ij,ij->i", u1, u2))
    return o[np.abs(seen - theta) < 1e-9]   # the other arc sees the chord under 180° - theta


def _overlap(q: float) -> float:
    return math.pi * (q - 1) / (q + 1)   # seed formula theta = 180(k-1)/(k+1), in radians


@pytest.mark.parametrize(("psi_deg", "q"), [(20.0, 1.1), (60.0, 1.15), (30.0, 1.0)])
def test_crank_rocker_dense_scan_finds_nothing_better(psi_deg: float, q: float) -> None:
    psi, ratio = math.radians(psi_deg), 4.0
    answer = synth.synthesise_crank_rocker(synth.CrankRockerSpec(psi, q, "rocker", 1.0, max_length_ratio=ratio))
    # Rocker pivot D at the origin, unit rocker, its extremes B1, B2; every O on the locus gives a four-bar with
    # crank (|OB_far| - |OB_near|)/2, coupler (|OB_far| + |OB_near|)/2 and ground |OD|.
    b1, b2 = np.array([math.cos(psi / 2), math.sin(psi / 2)]), np.array([math.cos(psi / 2), -math.sin(psi / 2)])
    o = _locus(b1, b2, _overlap(q), 40_001, 2 * ratio)
    r1, r2 = np.hypot(*(o - b1).T), np.hypot(*(o - b2).T)
    a, b, d = 0.5 * np.abs(r2 - r1), 0.5 * (r1 + r2), np.hypot(*o.T)
    ok = (a > 1e-9) & (np.maximum(b, d) <= ratio)
    # Law of cosines in triangle A-B-Q with the crank along the ground line (textbook extremes of a crank-rocker).
    mu = [np.arccos(np.clip((b * b + 1 - (d + sgn * a) ** 2) / (2 * b), -1, 1)) for sgn in (-1, 1)]
    quality = np.minimum.reduce([np.minimum(m, math.pi - m) for m in mu])
    better = np.flatnonzero(ok & (quality > answer.objective_value + 1e-7))
    for i in better[:: max(1, better.size // 40)]:
        # Such a member only counts if the analysis engine confirms it is a crank-rocker doing the same job.
        for branch in (1, -1):
            try:
                fb = synth.FourBar(d[i], a[i], b[i], 1.0, branch)
                check = synth.check_fourbar(fb)
            except synth.SynthError:
                continue
            assert not (fb.grashof == "crank-rocker" and abs(check.travel - psi) < 1e-6
                        and abs(check.time_ratio - q) < 1e-6), (fb, quality[i], answer.objective_value)
    assert ok.sum() > 1000   # the scan did cover the family
    assert quality[ok].max() >= answer.objective_value - 1e-6   # and came as near the answer as its spacing allows
    assert answer.optimality.conditions_met


@pytest.mark.parametrize(("stroke", "q"), [(0.1, 1.3), (0.25, 1.0)])
def test_slider_crank_dense_scan_finds_nothing_better(stroke: float, q: float) -> None:
    ratio = 4.0
    answer = synth.synthesise_slider_crank(synth.SliderCrankSpec(stroke, q, max_length_ratio=ratio))
    check = answer.check
    assert check.travel == pytest.approx(stroke, abs=EXACT * stroke)
    assert check.time_ratio == pytest.approx(q, abs=EXACT)
    b1, b2 = np.array([0.0, 0.0]), np.array([stroke, 0.0])
    o = _locus(b1, b2, _overlap(q), 40_001, 2 * ratio * stroke)
    r1, r2 = np.hypot(*(o - b1).T), np.hypot(*(o - b2).T)
    a, b, e = 0.5 * np.abs(r2 - r1), 0.5 * (r1 + r2), np.abs(o[:, 1])
    same_side = (b1[0] - o[:, 0]) * (b2[0] - o[:, 0]) > 0
    ok = (a > 1e-9) & (b <= ratio * stroke) & (a + e < b) & same_side
    # Largest rod inclination: the crank pin farthest from the guide on the far side, sin = (a + e)/b.
    quality = 0.5 * math.pi - np.arcsin(np.clip((a + e) / b, 0, 1))
    assert ok.sum() > 1000
    assert quality[ok].max() <= answer.objective_value + 1e-7
    assert quality[ok].max() >= answer.objective_value - 1e-6


def test_slow_stroke_direction_is_honoured() -> None:
    for sign in (1, -1):
        sc = synth.synthesise_slider_crank(synth.SliderCrankSpec(0.1, 1.4, slow_stroke=sign)).check
        assert np.sign(sc.output_extremes[1] - sc.output_extremes[0]) == sign
        cr = synth.synthesise_crank_rocker(synth.CrankRockerSpec(math.radians(45), 1.3, slow_stroke=sign)).check
        assert np.sign(math.remainder(cr.output_extremes[1] - cr.output_extremes[0], 2 * math.pi)) == sign
        assert cr.time_ratio == pytest.approx(1.3, abs=EXACT)


def test_bounds_shape_the_answer_and_infeasible_names_the_constraint() -> None:
    free = synth.synthesise_crank_rocker(synth.CrankRockerSpec(math.radians(40), 1.1, "rocker", 0.15))
    cap = 0.95 * free.fourbar.ground
    bounded = synth.synthesise_crank_rocker(
        synth.CrankRockerSpec(math.radians(40), 1.1, "rocker", 0.15, bounds={"ground": (0.0, cap)}))
    assert bounded.fourbar.ground <= cap * (1 + 1e-12)
    assert bounded.objective_value <= free.objective_value
    assert bounded.check.travel == pytest.approx(math.radians(40), abs=EXACT)
    with pytest.raises(synth.Infeasible) as err:
        synth.synthesise_crank_rocker(
            synth.CrankRockerSpec(math.radians(40), 1.1, "rocker", 0.15, bounds={"coupler": (1.0, 2.0)}))
    assert err.value.constraint == "coupler_length_min"
    with pytest.raises(synth.Infeasible) as poor:
        synth.synthesise_crank_rocker(synth.CrankRockerSpec(math.radians(170), 1.5,
                                                            min_transmission_angle=math.radians(30)))
    assert poor.value.constraint == "min_transmission_angle"
    with pytest.raises(synth.InvalidInput) as bad:
        synth.synthesise_crank_rocker(synth.CrankRockerSpec(math.radians(40), 0.8))
    assert bad.value.field == "time_ratio"


def test_scale_link_sets_that_length() -> None:
    for link, length in (("ground", 0.4), ("crank", 0.03)):
        r = synth.synthesise_crank_rocker(synth.CrankRockerSpec(math.radians(50), 1.2, link, length))
        assert getattr(r.fourbar, link) == pytest.approx(length, rel=1e-12)
        assert r.check.time_ratio == pytest.approx(1.2, abs=EXACT)


def test_dynamic_objective_beats_the_kinematic_optimum_on_its_own_measure() -> None:
    dens = {"crank": 2.0, "coupler": 2.0, "rocker": 3.0}
    loads = (synth.ProcessLoad("window", 4.0),)
    base = dict(swing=math.radians(40), time_ratio=1.1, scale_length=0.15, linear_density=dens,
                speed=2 * math.pi * 3, loads=loads, samples=90)
    best = synth.synthesise_crank_rocker(synth.CrankRockerSpec(objective="peak_driving_torque", **base))
    kin = synth.synthesise_crank_rocker(synth.CrankRockerSpec(**base))
    peak = synth.analyse(kin.linkage, base["speed"], samples=90).summary().max_driving_torque
    assert best.objective_value <= peak
    # The reported objective is what the analysis engine gives for the answer's own linkage.
    again = synth.analyse(best.linkage, base["speed"], samples=90).summary().max_driving_torque
    assert again == pytest.approx(best.objective_value, rel=1e-12)
    assert best.optimality.conditions_met


def _coupler_targets(fb: synth.FourBar, point: tuple[float, float], phi: np.ndarray,
                     pivot: tuple[float, float], angle: float) -> np.ndarray:
    an = synth.analyse(synth.Linkage(fb), 1.0, phi=phi, points={"P": ("coupler", point)})
    rot = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    return np.asarray(an.motion.point_pos["P"] @ rot.T + np.asarray(pivot))


@pytest.mark.parametrize("timed", [False, True])
def test_path_recovers_a_known_coupler_curve(timed: bool) -> None:
    # Points sampled from a known crank-rocker's coupler curve, placed and turned in the plane; some four-bar
    # (the original or a cognate) passes through all of them, so the best residual must vanish.
    fb = synth.FourBar(0.36, 0.09, 0.30, 0.27, -1)
    phi = np.radians(np.linspace(10.0, 330.0, 9))
    targets = _coupler_targets(fb, (0.12, -0.07), phi, (0.05, 0.10), 0.4)
    bounds, box, cp = synth.default_path_limits(targets)
    spec = synth.PathSpec(targets, phi if timed else None, bounds, box, cp, starts=16, seed=3)
    result = synth.synthesise_path(spec)
    assert result.residuals.max() < 1e-6
    assert result.fourbar.grashof == "crank-rocker"
    assert 1 <= result.starts_at_best <= 16
    if timed:
        steps = np.diff(np.unwrap(result.crank_angles))
        assert steps == pytest.approx(np.diff(phi), abs=1e-6)


def test_path_answer_does_not_depend_on_the_unit_or_origin_of_the_points() -> None:
    # The same nine points in millimetres about another origin: IPOPT works in units of the points' extent about
    # their centre, so the best four-bar is the one in metres, scaled and moved (to round-off, 1e-9 relative).
    fb = synth.FourBar(0.36, 0.09, 0.30, 0.27, -1)
    targets = _coupler_targets(fb, (0.12, -0.07), np.radians(np.linspace(10.0, 330.0, 9)), (0.05, 0.10), 0.4)
    shift = np.array([2.5, -1.0])
    answers = []
    for points in (targets, 1000.0 * targets + shift):
        bounds, box, cp = synth.default_path_limits(points)
        answers.append(synth.synthesise_path(synth.PathSpec(points, None, bounds, box, cp, starts=16, seed=3)))
    metres, millimetres = answers
    assert np.asarray(millimetres.crank_pivot) == pytest.approx(1000.0 * np.asarray(metres.crank_pivot) + shift,
                                                                rel=1e-9, abs=1e-9)
    for name in ("ground", "crank", "coupler", "rocker"):
        assert getattr(millimetres.fourbar, name) == pytest.approx(1000.0 * getattr(metres.fourbar, name), rel=1e-9)
    assert np.asarray(millimetres.coupler_point) == pytest.approx(1000.0 * np.asarray(metres.coupler_point), rel=1e-9)
    assert millimetres.ground_angle == pytest.approx(metres.ground_angle, abs=1e-9)
    assert millimetres.residuals.max() < 1e-3 and metres.residuals.max() < 1e-6   # exact fits, 1e-6 m either way


def test_path_limits_and_deadline() -> None:
    targets = np.array([[0.0, 0.0], [0.1, 0.05], [0.2, 0.0]])
    bounds, box, cp = synth.default_path_limits(targets)
    with pytest.raises(synth.TooLarge):
        synth.PathSpec(np.zeros((synth.synthesis.MAX_POINTS + 1, 2)), None, bounds, box, cp).validate()
    with pytest.raises(synth.SolverTimeout) as late:
        synth.synthesise_path(synth.PathSpec(targets, None, bounds, box, cp, starts=4, time_limit=1e-12))
    assert late.value.reached["starts_completed"] == 0
    with pytest.raises(synth.InvalidInput):
        synth.synthesise_path(synth.PathSpec(targets, np.zeros(2), bounds, box, cp))


def test_path_keeps_the_transmission_angle_it_is_given() -> None:
    targets = np.array([[0.0, 0.0], [0.1, 0.05], [0.2, 0.0]])
    bounds, box, cp = synth.default_path_limits(targets)
    spec = synth.PathSpec(targets, None, bounds, box, cp, starts=8, min_transmission_angle=math.radians(40))
    result = synth.synthesise_path(spec)
    # The engine's transmission angle over 720 crank angles (its extremes at 0 and 180° are on that grid).
    assert result.check.min_transmission_angle >= math.radians(40) - 1e-7
    assert math.pi - result.check.max_transmission_angle >= math.radians(40) - 1e-7
    assert result.residuals.max() < 1e-6   # three points leave room to spare


@pytest.mark.parametrize("chunks", [2, 3])
def test_path_starts_in_chunks_give_the_serial_answer(chunks: int) -> None:
    # The starts are independent: run in chunks (as the service runs them side by side on its workers) and
    # combined, they give exactly what one run of every start in order gives for the same seed.
    from synth.synthesis.path import best_path, path_starts, start_chunks

    fb = synth.FourBar(0.36, 0.09, 0.30, 0.27, -1)
    targets = _coupler_targets(fb, (0.12, -0.07), np.radians(np.linspace(0.0, 300.0, 6)), (0.05, 0.10), 0.4)
    bounds, box, cp = synth.default_path_limits(targets)
    spec = synth.PathSpec(targets + 0.002 * np.cos(np.arange(6))[:, None], None, bounds, box, cp, starts=8, seed=5)
    serial = synth.synthesise_path(spec)
    split = start_chunks(spec, chunks)
    assert sorted(k for chunk in split for k in chunk) == list(range(8)) and len(split) == chunks
    combined = best_path(spec, [path_starts(spec, chunk) for chunk in split])
    assert np.array_equal(combined.start_objectives, serial.start_objectives, equal_nan=True)
    assert np.array_equal(combined.residuals, serial.residuals)
    assert (combined.crank_pivot, combined.coupler_point, combined.ground_angle, combined.starts_at_best,
            combined.status) == (serial.crank_pivot, serial.coupler_point, serial.ground_angle,
                                 serial.starts_at_best, serial.status)


def test_coupler_jacobian_matches_central_differences() -> None:
    # The screening's hand-derived Jacobian against central differences of the coupler point's closed form
    # (step 1e-6: truncation about 1e-12, round-off about 1e-10 on values of order one).
    from synth.synthesis.path import _coupler_points
    from synth.synthesis.path_screening import coupler_jacobian

    rng = np.random.default_rng(7)
    z = np.array([0.1, -0.2, 0.3, 0.3, 1.1, 0.9, 1.0, 0.5, 0.27]) + 0.02 * rng.random((4, 9))
    phi = rng.random((4, 6)) * 2 * math.pi
    branch = np.array([1.0, -1.0, 1.0, -1.0])
    point, jac, jac_phi = coupler_jacobian(z, phi, branch)

    def at(zz: np.ndarray, pp: np.ndarray) -> np.ndarray:
        x, y = _coupler_points(zz.T[:, :, None], pp, branch[:, None])
        return np.asarray(x + 1j * y)

    assert point == pytest.approx(at(z, phi), abs=1e-14)
    h = 1e-6
    for i in range(9):
        dz = np.zeros(9)
        dz[i] = h
        assert jac[:, :, i] == pytest.approx((at(z + dz, phi) - at(z - dz, phi)) / (2 * h), abs=1e-8)
    assert jac_phi == pytest.approx((at(z, phi + h) - at(z, phi - h)) / (2 * h), abs=1e-8)


def test_cognates_follow_roberts_law_and_trace_the_same_points() -> None:
    # Roberts' law: with w = (coupler point)/(coupler length) as a complex number, the crank-driven cognate's
    # crank, coupler, rocker and ground are |1 - w| times the original's crank, rocker, coupler and ground, and the
    # coupler-driven one's are |w| times its coupler, crank, rocker and ground (Hartenberg and Denavit, 1964, 6.7).
    fb = synth.FourBar(0.30, 0.10, 0.35, 0.25, 1)
    point = (0.15, 0.08)
    phi = np.radians(np.linspace(0.0, 324.0, 10))
    targets = _coupler_targets(fb, point, phi, (0.0, 0.0), 0.0)
    w = complex(*point) / fb.coupler
    crank_driven, coupler_driven = synth.cognates(fb, (0.0, 0.0), 0.0, point, phi)
    k = abs(1 - w)
    c = crank_driven.fourbar
    assert (c.crank, c.coupler, c.rocker, c.ground) == pytest.approx((k * 0.10, k * 0.25, k * 0.35, k * 0.30),
                                                                     rel=1e-12)
    assert c.grashof == "crank-rocker"
    # It turns in step with the original's crank: its angles are the original's shifted by one constant.
    assert np.diff(np.unwrap(crank_driven.crank_angles)) == pytest.approx(np.diff(phi), abs=1e-12)
    traced = _coupler_targets(c, crank_driven.coupler_point, crank_driven.crank_angles, crank_driven.crank_pivot,
                              crank_driven.ground_angle)
    assert np.abs(traced - targets).max() < 1e-12
    k = abs(w)
    d = coupler_driven.fourbar
    assert (d.crank, d.coupler, d.rocker, d.ground) == pytest.approx((k * 0.35, k * 0.10, k * 0.25, k * 0.30),
                                                                     rel=1e-12)
    assert d.grashof == "double-rocker"
    first = _coupler_targets(d, coupler_driven.coupler_point, coupler_driven.crank_angles[:1],
                             coupler_driven.crank_pivot, coupler_driven.ground_angle)
    assert np.abs(first - targets[:1]).max() < 1e-12


@pytest.mark.parametrize("rank_by", ["residual", "link_ratio"])
def test_path_answers_its_cognate_and_ranks_its_fits(rank_by: str) -> None:
    # Ten points on the coupler curve of a crank-rocker: the answer passes through them, and so does its
    # crank-driven cognate (Roberts' law), checked by the engine's own residuals; fits are distinct designs.
    fb = synth.FourBar(0.30, 0.10, 0.35, 0.25, 1)
    targets = _coupler_targets(fb, (0.15, 0.08), np.radians(np.linspace(0.0, 324.0, 10)), (0.0, 0.0), 0.0)
    bounds, box, cp = synth.default_path_limits(targets)
    result = synth.synthesise_path(synth.PathSpec(targets, None, bounds, box, cp, starts=32, rank_by=rank_by))
    assert result.residuals.max() < 1e-9
    assert result.fits[0].linkage == result.linkage and result.fits[0].starts == result.starts_at_best >= 1
    exact = [f for f in (*result.fits, *result.cognates) if f.residuals.max() < 1e-9]
    lengths = {tuple(round(getattr(f.fourbar, n), 6) for n in ("crank", "coupler", "rocker", "ground"))
               for f in exact}
    assert len(lengths) >= 2
    assert result.cognates[0].status == "cognate" and result.cognates[0].fourbar.grashof == "crank-rocker"
    assert sum(f.starts for f in result.fits) <= 32
    if rank_by == "link_ratio":
        level = [f for f in result.fits if f.residuals.max() < 1e-9]
        ratios = [max(v) / min(v) for v in ((f.fourbar.crank, f.fourbar.coupler, f.fourbar.rocker, f.fourbar.ground)
                                            for f in level)]
        assert ratios == sorted(ratios)


def test_path_ranks_fits_equally_near_by_the_starts_reaching_them() -> None:
    # Ten points near a crank-rocker's coupler curve (3 mm of deliberate misfit): the best fit and its
    # crank-driven cognate trace the same curve, so their residuals agree to round-off (Roberts' law) and the
    # default ranking orders them by the starts that reached each, not by that round-off.
    fb = synth.FourBar(0.30, 0.10, 0.35, 0.25, 1)
    targets = _coupler_targets(fb, (0.15, 0.08), np.radians(np.linspace(0.0, 324.0, 10)), (0.0, 0.0), 0.0)
    targets = targets + 0.003 * np.sin(np.arange(10))[:, None]
    bounds, box, cp = synth.default_path_limits(targets)
    result = synth.synthesise_path(synth.PathSpec(targets, None, bounds, box, cp, starts=64, seed=2))
    best = result.fits[0].rms_residual
    level = [f for f in result.fits if f.rms_residual <= best * (1 + 1e-6)]
    assert len(level) >= 2 and best > 1e-5
    assert [f.starts for f in level] == sorted((f.starts for f in level), reverse=True)
    assert level[0].starts > level[-1].starts


def test_compiled_screening_ends_where_the_stacked_numpy_one_does() -> None:
    # The screening's compiled loop against its former form in numpy (bench/path_screening_numpy.py: every
    # start's step stacked in array calls, a batched LU solve), an independent implementation of the same
    # iteration: from the same 32 starts both end at the same points, to the round-off forty damped steps
    # amplify (1e-6 in units of the points' extent), and break down on the same starts.
    from bench import path_screening_numpy
    from synth.synthesis.path import GRASHOF_MARGIN, SCREEN_ITERATIONS, _initial_points, _problem
    from synth.synthesis.path_screening import screen

    fb = synth.FourBar(0.30, 0.10, 0.35, 0.25, 1)
    targets = _coupler_targets(fb, (0.15, 0.08), np.radians(np.linspace(0.0, 324.0, 10)), (0.0, 0.0), 0.0)
    bounds, box, cp = synth.default_path_limits(targets)
    spec = synth.PathSpec(targets, None, bounds, box, cp, starts=32)
    points, offsets, timed, frame, _, lim = _problem(spec)
    x0, branches = _initial_points(spec, range(32), frame, points, offsets, timed)
    m = x0.shape[1] - 20
    args = (x0[:, :m], branches, (points - frame.centre) / frame.scale, offsets, timed, lim["lbx"][:m],
            lim["ubx"][:m], 1.0, GRASHOF_MARGIN, SCREEN_ITERATIONS, math.inf, 1.0)
    compiled, stacked = screen(*args), path_screening_numpy.screen(*args)
    ends = np.isfinite(stacked.objectives)
    assert np.array_equal(ends, np.isfinite(compiled.objectives)) and ends.sum() >= 16
    assert compiled.unknowns[ends] == pytest.approx(stacked.unknowns[ends], abs=1e-6)
    assert compiled.objectives[ends] == pytest.approx(stacked.objectives[ends], rel=1e-6, abs=1e-14)
    assert compiled.iterations == stacked.iterations
