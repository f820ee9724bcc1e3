"""Disc cams in the engine: motion laws against the textbooks and independent derivations, the profile's checks,
the least cam against a brute-force search written here, the pair's forces by virtual power, the optimised laws
against their theoretical bounds, and bad input named."""

from __future__ import annotations

import math

import numpy as np
import pytest

import synth.cams as cams
from synth.errors import Infeasible, InvalidInput

r = math.radians
# Peak acceleration coefficients C_a (peak = C_a h/beta²) as printed in Norton, "Cam Design and Manufacturing
# Handbook" (table of standard laws), and Rothbart, "Cam Design Handbook": 4 significant digits.
TEXTBOOK = {"cycloidal": 6.2832, "simple_harmonic": 4.9348, "polynomial_345": 5.7735, "polynomial_4567": 7.5132,
            "modified_trapezoid": 4.888, "modified_sine": 5.528}
# Peak velocity coefficients C_v from the same tables.
TEXTBOOK_VELOCITY = {"cycloidal": 2.0, "simple_harmonic": 1.5708, "polynomial_345": 1.875,
                     "polynomial_4567": 2.1875, "modified_trapezoid": 2.0, "modified_sine": 1.7596}


def program(law: str = "cycloidal", lift: float = 0.02, rise_deg: float = 120.0, ret_law: str = "polynomial_345"
            ) -> tuple[cams.Segment, ...]:
    dwell = (360.0 - 2 * rise_deg) / 2
    return (cams.Segment("rise", r(rise_deg), lift, law), cams.Segment("dwell", r(dwell)),  # type: ignore[arg-type]
            cams.Segment("return", r(rise_deg), lift, ret_law), cams.Segment("dwell", r(dwell)))  # type: ignore[arg-type]


def angles(n: int = 720) -> np.ndarray:
    return np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)


@pytest.mark.parametrize("name", sorted(TEXTBOOK))
def test_standard_laws_peak_coefficients_match_the_textbooks(name: str) -> None:
    c = cams.law_coefficients(name)
    assert c.acceleration == pytest.approx(TEXTBOOK[name], abs=6e-4)     # the tables' 4-5 digits
    assert c.velocity == pytest.approx(TEXTBOOK_VELOCITY[name], abs=6e-4)
    assert cams.TEXTBOOK_PEAK_ACCELERATION[name] == pytest.approx(TEXTBOOK[name], abs=6e-4)


@pytest.mark.parametrize("name", cams.STANDARD_LAWS)
def test_laws_are_rest_to_rest_rises_whose_derivatives_are_their_own(name: str) -> None:
    # Identity: f(0) = 0, f(1) = 1, f'(0) = f'(1) = 0, and each closed-form derivative is the finite difference
    # of the one before it (central differences on a fine grid; next to a joint of the piecewise laws, where the
    # following derivative jumps, the difference is first order: h times the jump, 2e-4 of the peak here).
    u = np.linspace(0.0, 1.0, 16001)
    f = cams.LAWS[name](u)
    assert (f[0][0], f[0][-1], f[1][0], f[1][-1]) == pytest.approx((0.0, 1.0, 0.0, 0.0), abs=1e-12)
    h = u[1] - u[0]
    for k in range(3):
        fd = (f[k][2:] - f[k][:-2]) / (2 * h)
        assert np.max(np.abs(fd - f[k + 1][1:-1])) < 1e-3 * max(1.0, np.max(np.abs(f[k + 1])))


def test_polynomial_345_peak_from_its_own_roots() -> None:
    # Independent derivation: f'' = 60u - 180u² + 120u³ peaks where f''' = 60 - 360u + 360u² = 0, u = (3 - √3)/6.
    u = (3.0 - math.sqrt(3.0)) / 6.0
    peak = 60 * u - 180 * u**2 + 120 * u**3
    assert peak == pytest.approx(10.0 / math.sqrt(3.0), rel=1e-12)
    assert cams.law_coefficients("polynomial_345").acceleration == pytest.approx(peak, rel=1e-6)


def test_modified_trapezoid_and_sine_normalised_by_numerical_integration() -> None:
    # Independent of the closed-form integration: build the acceleration shape on a grid, integrate it twice by
    # the trapezoid rule, and scale so that the rise ends at 1; the scale is the peak coefficient.
    u = np.linspace(0.0, 1.0, 200001)
    w = 4 * math.pi
    trap = np.select([u < 1 / 8, u < 3 / 8, u < 5 / 8, u < 7 / 8],
                     [np.sin(w * u), 1.0, np.cos(w * (u - 3 / 8)), -1.0], -np.cos(w * (u - 7 / 8)))
    sine = np.select([u < 1 / 8, u < 7 / 8], [np.sin(w * u), np.cos(w / 3 * (u - 1 / 8))], -np.cos(w * (u - 7 / 8)))
    for shape, name in ((trap, "modified_trapezoid"), (sine, "modified_sine")):
        v = np.concatenate([[0.0], np.cumsum((shape[1:] + shape[:-1]) / 2 * np.diff(u))])
        s = np.concatenate([[0.0], np.cumsum((v[1:] + v[:-1]) / 2 * np.diff(u))])
        assert cams.law_coefficients(name).acceleration == pytest.approx(1.0 / s[-1], rel=1e-6)


def _brute_least_prime_radius(h: float, beta: float, alpha: float, e: float) -> float:
    """The least prime radius at which a cycloidal rise's pressure angle stays within alpha, by exhaustive search:
    radii every 1e-4 m up to 0.1 m, then every 1e-6 m below the first that passes, each checked at 4001 angles
    of the rise with tan(alpha) = (v - e)/(sqrt(Rp² - e²) + s)."""
    u = np.linspace(0.0, 1.0, 4001)
    s = h * (u - np.sin(2 * np.pi * u) / (2 * np.pi))
    v = h / beta * (1 - np.cos(2 * np.pi * u))

    def first_ok(radii: np.ndarray) -> float:
        y = np.sqrt(radii[:, None] ** 2 - e**2) + s[None, :]
        ok = np.all(np.abs(np.arctan2(v[None, :] - e, y)) <= alpha, axis=1)
        assert ok.any()
        return float(radii[np.argmax(ok)])

    coarse = first_ok(np.arange(abs(e) + 1e-6, 0.1, 1e-4))
    return first_ok(np.arange(coarse - 1e-4, coarse + 1e-6, 1e-6))


@pytest.mark.parametrize("contact,roller,offset", [("knife_edge", 0.0, 0.0), ("roller", 0.008, 0.004)])
def test_least_base_radius_for_a_cycloidal_rise_matches_a_brute_force_search(contact: str, roller: float,
                                                                            offset: float) -> None:
    h, beta, alpha = 0.02, r(100), r(30)
    segments = (cams.Segment("rise", beta, h, "cycloidal"), cams.Segment("dwell", r(80)),
                cams.Segment("return", r(150), h, "cycloidal"), cams.Segment("dwell", r(30)))
    follower = cams.Follower("translating", contact, roller, offset)  # type: ignore[arg-type]
    least = cams.least_cam(segments, follower, cams.CamLimits(alpha, r(89), 0.0, (0.002, 0.2)))
    brute = _brute_least_prime_radius(h, beta, alpha, offset)
    assert least.active == "max_pressure_angle_rise_deg"
    # the brute force's step (1e-6 m) bounds the difference
    assert least.base_radius + roller == pytest.approx(brute, abs=1.5e-6)
    assert least.pressure_rise == pytest.approx(alpha, abs=1e-7)


def test_a_free_offset_beats_every_fixed_one_near_it() -> None:
    segments = program()
    follower = cams.Follower("translating", "roller", 0.01)
    lim = cams.CamLimits(r(30), r(45), 0.0, (0.005, 0.2), (-0.02, 0.02))
    free = cams.least_cam(segments, follower, lim)
    fixed = cams.CamLimits(r(30), r(45), 0.0, (0.005, 0.2))
    for e in (free.offset - 2e-4, free.offset + 2e-4, 0.0):
        other = cams.least_cam(segments, cams.Follower("translating", "roller", 0.01, e), fixed)
        assert other.base_radius >= free.base_radius * (1 - 1e-8)
    assert free.pressure_rise <= r(30) + 1e-9 and free.pressure_return <= r(45) + 1e-9


FOLLOWERS = [
    (cams.Follower("translating", "knife_edge", 0.0, 0.004), 0.02),
    (cams.Follower("translating", "roller", 0.01, -0.006), 0.02),
    (cams.Follower("translating", "flat_faced"), 0.02),
    (cams.Follower("oscillating", "roller", 0.008, pivot_distance=0.1, arm_length=0.075), r(18)),
    (cams.Follower("oscillating", "knife_edge", pivot_distance=0.1, arm_length=0.075), r(18)),
    (cams.Follower("oscillating", "flat_faced", pivot_distance=0.12, face_offset=0.01), r(10)),
]


@pytest.mark.parametrize("follower,lift", FOLLOWERS, ids=lambda x: getattr(x, "contact", ""))
def test_the_point_table_gives_back_the_pressure_angle_and_curvature(follower: cams.Follower, lift: float) -> None:
    spec = cams.CamSpec(program(lift=lift), follower, speed=30.0, base_radius=0.04,
                        loads=cams.PairLoads(1.5 if follower.motion == "translating" else 0.004, 30.0,
                                             process=(cams.ProcessLoad(0.0, r(120), 20.0),)))
    an = cams.analyse_cam(spec)
    assert an.table.max_pressure_angle_error < 1e-6        # rad, fourth-order differences at 720 samples
    assert an.table.max_curvature_error < 1e-5
    assert an.derivative_check < 1e-6
    assert an.forces is not None
    assert an.forces.torque_check < 1e-9                   # virtual power: T omega = Q dq/dt
    assert an.forces.least_margin == pytest.approx(0.2, abs=1e-6)   # the designed spring's margin is active


def test_translating_pressure_angle_is_the_textbook_formula() -> None:
    # tan alpha = (ds/dtheta - e)/(sqrt(Rp² - e²) + s) for a cam turning counter-clockwise (Norton, eq. 8.31
    # with his sign of the offset)
    e, rb, rr = 0.006, 0.03, 0.01
    an = cams.analyse_cam(cams.CamSpec(program(), cams.Follower("translating", "roller", rr, e), 10.0, rb))
    m = an.motion
    expected = np.arctan2(m.v - e, np.sqrt((rb + rr) ** 2 - e**2) + m.s)
    assert np.max(np.abs(an.geometry.pressure_angle - expected)) < 1e-12


def test_flat_face_radius_of_curvature_and_face_width_are_the_textbook_ones() -> None:
    # rho = Rb + s + d2s/dtheta2 and the contact lies ds/dtheta from the axis (Norton, eqs. 8.42, 8.43)
    an = cams.analyse_cam(cams.CamSpec(program(), cams.Follower("translating", "flat_faced"), 10.0, 0.03))
    m, g = an.motion, an.geometry
    assert np.max(np.abs(g.rho - (0.03 + m.s + m.a))) < 1e-12
    assert np.max(np.abs(g.face - (-m.v))) < 1e-12 or np.max(np.abs(g.face - m.v)) < 1e-12


def test_the_designed_spring_is_the_least_one() -> None:
    spec = cams.CamSpec(program(), cams.Follower("translating", "roller", 0.01), 40.0, 0.04,
                        loads=cams.PairLoads(3.0, 40.0, stiffness=500.0, margin=0.3))
    f = cams.analyse_cam(spec).forces
    assert f is not None and f.spring_designed and f.stiffness == pytest.approx(500.0, rel=1e-12)
    m = cams.analyse_cam(spec).motion
    need = np.maximum(-(3.0 * 40.0**2 * m.a), 0.0)
    # Independent: the least preload for a fixed rate is the largest (1 + margin) need - k s, in closed form.
    assert f.preload == pytest.approx(float(np.max(1.3 * need - 500.0 * m.s)), rel=1e-6)
    assert f.contact.min() > 0.0


def test_optimised_laws_sit_between_the_theoretical_bound_and_the_standard_laws() -> None:
    acc = cams.optimise_law("peak_acceleration", 16)
    assert cams.optimal_law.LOWER_BOUND["peak_acceleration"] <= acc.peak_acceleration < 4.888   # beats mod. trapezoid
    assert acc.end_error < 1e-9 and acc.status == "optimal"
    assert acc.peak_acceleration == pytest.approx(acc.objective_value, rel=5e-3)   # sampled vs program
    jerk = cams.optimise_law("peak_jerk", 16)
    assert 32.0 <= jerk.peak_jerk < 1.05 * 32.0            # bang-bang jerk gives exactly 32
    lam = 25.0
    u = np.linspace(0.0, 1.0, 4001)
    cycloidal = cams.optimal_law.residual_vibration(None, lam, second=cams.LAWS["cycloidal"](u)[2])
    vib = cams.optimise_law("residual_vibration", 16, frequency_ratio=lam)
    # the program's quadrature (its constraint samples) and this finer one differ by about 1e-3 of cycloidal's
    assert vib.residual_vibration < 1e-2 * cycloidal
    assert vib.peak_acceleration <= 2 * math.pi * (1 + 1e-3)


def test_segments_that_do_not_close_the_turn_are_named() -> None:
    segs = program()[:3]
    with pytest.raises(InvalidInput) as err:
        cams.analyse_cam(cams.CamSpec(segs, cams.Follower("translating", "knife_edge"), 10.0, 0.04))
    assert err.value.field == "segments" and "300" in str(err.value)


def test_a_rise_with_no_angle_is_named() -> None:
    segs = (cams.Segment("rise", 0.0, 0.01), cams.Segment("dwell", 2 * math.pi))
    with pytest.raises(InvalidInput) as err:
        cams.follower_motion(segs, angles())
    assert err.value.field == "segments.0.angle_deg"


def test_a_roller_larger_than_the_pitch_curves_radius_of_curvature_is_refused() -> None:
    # The pitch curve of a roller follower is the knife-edge cam of the prime radius: its least convex radius
    # of curvature is the largest roller the profile can take.
    segs = program(lift=0.03, rise_deg=60.0, ret_law="cycloidal")
    knife = cams.analyse_cam(cams.CamSpec(segs, cams.Follower("translating", "knife_edge"), 10.0, 0.025))
    limit = float(knife.geometry.rho[knife.geometry.rho > 0].min())
    ok = cams.CamSpec(segs, cams.Follower("translating", "roller", 0.98 * limit), 10.0, 0.025 - 0.98 * limit)
    g = cams.analyse_cam(ok).geometry
    assert g.rho[g.rho_pitch > 0].min() > 0           # the convex profile keeps a positive radius
    with pytest.raises(InvalidInput) as err:
        cams.analyse_cam(cams.CamSpec(segs, cams.Follower("translating", "roller", 1.02 * limit), 10.0,
                                      0.025 - 1.02 * limit))
    assert err.value.field == "follower.roller_radius_m"


def test_a_pressure_limit_no_radius_can_meet_is_infeasible_naming_it() -> None:
    with pytest.raises(Infeasible) as err:
        cams.least_cam(program(), cams.Follower("translating", "roller", 0.01),
                       cams.CamLimits(r(5), r(45), 0.0, (0.005, 0.02)))
    assert err.value.constraint == "max_pressure_angle_rise_deg"


def test_oscillating_roller_pressure_angle_from_the_geometry_drawn_here() -> None:
    # Independent path: place the roller centre by the triangle O-A-P (law of cosines for the start angle), turn
    # it into the cam frame with complex numbers, and take the pitch curve's normal from np.gradient on a dense
    # turn; the pressure angle is then the normal's angle from the roller centre's path square to the arm.
    d, arm, rr, rb = 0.1, 0.075, 0.008, 0.04
    segs = program(lift=r(18))
    n = 20000
    theta = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    an = cams.analyse_cam(cams.CamSpec(segs, cams.Follower("oscillating", "roller", rr, pivot_distance=d,
                                                           arm_length=arm), 10.0, rb, samples=n))
    psi = cams.follower_motion(segs, theta).s
    gamma0 = math.acos((d * d + arm * arm - (rb + rr) ** 2) / (2 * d * arm))
    P = d - arm * np.exp(-1j * (gamma0 + psi))          # = (d - l cos g, l sin g)
    cam_frame = P * np.exp(-1j * theta)
    tangent = np.gradient(cam_frame, theta) * np.exp(1j * theta)    # back in the frame of the follower
    normal = tangent * 1j
    path = 1j * (d - P)                                              # dP/dgamma: square to the arm
    alpha = np.angle(normal / path)
    inner = slice(5, n - 5)
    assert np.max(np.abs(alpha[inner] - an.geometry.pressure_angle[inner])) < 1e-6
