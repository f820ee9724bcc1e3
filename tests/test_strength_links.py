"""Links sized for strength: each method against a published worked example, the beams' equilibrium, the
stresses recomputed by a second path from the final analysis, and the fixed point of sizing and analysis."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import synth
from synth import JointSpec, LinkSpec as BodySpec, PlanarLinkage
from synth.strength import (MATERIALS, LinkSpec, Material, SectionFamily, StrengthLimits, beam_forces, ipe,
                            size_link, size_links, tube)
from synth.strength.columns import critical_load, euler_load, johnson_load, tangent_slenderness
from synth.strength.fatigue import (endurance_limit, goodman_safety, size_factor, surface_factor,
                                    von_mises_amplitude_mean)
from synth.strength.sections import IPE_TABLE, i_section_properties, round_bar

MPA, GPA, MM = 1e6, 1e9, 1e-3
RPM = 2 * math.pi / 60


# --- columns ---------------------------------------------------------------------------------------------------

def test_euler_tube_column_of_hibbeler_example_13_1() -> None:
    # Hibbeler, Mechanics of Materials, Example 13.1: an A-36 tube of radii 75 and 70 mm, 7.2 m, pin-ended,
    # E = 200 GPa: P_cr = 228.2 kN, sigma_cr = 100 MPa below the yield 250 MPa, so Euler holds.
    sec = tube(150 * MM, 5 * MM)
    p = critical_load(sec.area, sec.radius_of_gyration, 7.2, 200 * GPA, 250 * MPA)
    assert float(p) == pytest.approx(228.2e3, rel=1e-3)
    assert float(p) / sec.area == pytest.approx(100 * MPA, rel=2e-3)
    assert 7.2 / sec.radius_of_gyration > tangent_slenderness(200 * GPA, 250 * MPA)


def test_euler_and_yield_of_hibbeler_example_13_2() -> None:
    # Hibbeler, Example 13.2: W200x46, A = 5890 mm², I_y = 15.3e6 mm⁴, 4 m pin-ended, E = 200 GPa: Euler gives
    # 1887.6 kN (320.5 MPa, above the 250 MPa yield), so the column yields first at 1472.5 kN. Johnson's parabola
    # (the model below the tangent point) stays below both.
    area, i = 5890 * MM**2, 15.3e6 * MM**4
    k = math.sqrt(i / area)
    assert float(euler_load(area, 4.0 / k, 200 * GPA)) == pytest.approx(1887.6e3, rel=1e-3)
    assert area * 250 * MPA == pytest.approx(1472.5e3, rel=1e-4)
    p = float(critical_load(area, k, 4.0, 200 * GPA, 250 * MPA))
    assert p == float(johnson_load(area, 4.0 / k, 200 * GPA, 250 * MPA))
    assert 0 < p < 1472.5e3


def test_round_bar_allowable_load_of_amesweb_example() -> None:
    # AmesWeb column buckling example 1: round bar 50 mm, 2 m, pinned ends, ASTM A588 (Sy 345 MPa, E 205 GPa),
    # design factor 5: allowable load 31.04 kN (a long column: Euler).
    sec = round_bar(50 * MM)
    assert float(critical_load(sec.area, sec.radius_of_gyration, 2.0, 205 * GPA, 345 * MPA)) / 5 == pytest.approx(
        31.04e3, rel=1e-3)


def test_johnson_meets_euler_tangentially_and_yield_at_zero_slenderness() -> None:
    # Identities of Shigley eqs. 4-44..4-48: equal value and slope at (l/k)_1, and A Sy at l/k = 0.
    e, sy, a = 207 * GPA, 500 * MPA, 1e-4
    lk1 = tangent_slenderness(e, sy)
    assert lk1 == pytest.approx(90.4, abs=0.05)   # Shigley Example 4-17's (l/k)_1 for these E and Sy
    assert float(johnson_load(a, lk1, e, sy)) == pytest.approx(float(euler_load(a, lk1, e)), rel=1e-12)
    h = 1e-4 * lk1
    slope_j = (johnson_load(a, lk1 + h, e, sy) - johnson_load(a, lk1 - h, e, sy)) / (2 * h)
    slope_e = (euler_load(a, lk1 + h, e) - euler_load(a, lk1 - h, e)) / (2 * h)
    assert float(slope_j) == pytest.approx(float(slope_e), rel=1e-6)
    assert float(johnson_load(a, 0.0, e, sy)) == pytest.approx(a * sy, rel=1e-12)


# --- fatigue ---------------------------------------------------------------------------------------------------

def test_marin_endurance_limit_of_shigley_problem_6_10() -> None:
    # Shigley (Budynas & Nisbett, 8th ed.) solution of problem 6-10: Sut = 440 MPa, machined: ka = 0.899,
    # axial (kb = 1, kc = 0.85): Se = 0.899 (0.85)(220) = 168.1 MPa.
    assert surface_factor(440 * MPA, "machined") == pytest.approx(0.899, abs=5e-4)
    assert endurance_limit(220 * MPA, 440 * MPA, "machined", 0.0) * 0.85 == pytest.approx(168.1 * MPA, rel=1e-3)


def test_size_factor_of_shigley_problem_6_15() -> None:
    # Shigley solution of problem 6-15: a 1.8 in bar in non-rotating bending, d_e = 0.370 d = 0.666 in,
    # kb = 0.879 (0.666)^-0.107 = 0.92 (the inch fit; eq. 6-20's mm fit is the same curve).
    assert size_factor(round_bar(1.8 * 25.4 * MM).equivalent_diameter) == pytest.approx(0.92, abs=0.005)


@pytest.mark.parametrize(("sigma_a", "tau_m", "tau_a", "expected"), [
    (69.0, 138.0, 0.0, 1.46),   # Shigley 8th ed., solution of problem 6-13: sigma'_a 69, sigma'_m 239 MPa
    (83.0, 103.0, 69.0, 1.18),  # problem 6-14: sigma'_a 145.5, sigma'_m 178.4 MPa
])
def test_goodman_safety_of_shigley_problems_6_13_and_6_14(sigma_a: float, tau_m: float, tau_a: float,
                                                          expected: float) -> None:
    # Both with Se = 276 MPa and Sut = 551 MPa; the histories are the problems' fully reversed bending and the
    # steady plus alternating torsion over one cycle, their von Mises amplitude and mean taken as eqs. 6-55/56.
    t = np.linspace(0, 2 * math.pi, 361)
    sigma = sigma_a * np.sin(t) * MPA
    tau = (tau_m + tau_a * np.sin(t)) * MPA
    sa, sm = von_mises_amplitude_mean(sigma, tau)
    assert float(sa) == pytest.approx(math.hypot(sigma_a, math.sqrt(3) * tau_a) * MPA, rel=1e-4)
    assert float(sm) == pytest.approx(math.sqrt(3) * tau_m * MPA, rel=1e-9)
    assert float(goodman_safety(sa, sm, 276 * MPA, 551 * MPA)) == pytest.approx(expected, abs=0.005)


def test_a_compressive_mean_does_not_lower_the_strength() -> None:
    # Shigley §6-12: for sigma_m <= 0 the Goodman line is replaced by n = Se / sigma_a.
    assert float(goodman_safety(100 * MPA, -200 * MPA, 250 * MPA, 500 * MPA)) == pytest.approx(2.5)


# --- sections and materials -------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", list(IPE_TABLE))
def test_ipe_table_agrees_with_its_dimensions(name: str) -> None:
    # EN 10365's area and I_y against the ones computed from h, b, tw, tf, r (fillets as corner spandrels).
    h, b, tw, tf, r, *_ = IPE_TABLE[name]
    area, i = i_section_properties(h * MM, b * MM, tw * MM, tf * MM, r * MM)
    sec = ipe(name)
    assert area == pytest.approx(sec.area, rel=5e-3)
    assert i == pytest.approx(sec.second_moment, rel=1e-2)
    assert sec.modulus == pytest.approx(sec.second_moment / (h * MM / 2), rel=1e-2)


def test_a_material_without_its_limits_is_refused_naming_the_field() -> None:
    bad = dataclasses.replace(MATERIALS["S355J2"], name="mine", fatigue_limit=math.nan)
    with pytest.raises(synth.InvalidInput) as err:
        bad.validate("links.coupler.material")
    assert err.value.field == "links.coupler.material.fatigue_limit_MPa"
    with pytest.raises(synth.InvalidInput, match="exceeds the ultimate"):
        Material("x", 500 * MPA, 400 * MPA, 200 * MPA, 210 * GPA, 7850).validate()


# --- links -------------------------------------------------------------------------------------------------------

def fourbar() -> synth.Linkage:
    mech = synth.FourBar(0.30, 0.10, 0.25, 0.25)
    return synth.Linkage(mech, {"crank": synth.MassProps(1.0, (0.05, 0.0), 0.001),
                                "coupler": synth.MassProps(2.0, (0.125, 0.01), 0.02),
                                "rocker": synth.MassProps(1.5, (0.125, 0.0), 0.008)},
                         gravity=synth.Gravity(), loads=(synth.ProcessLoad("window", 60.0, 0.0, math.pi),))


def press() -> synth.Linkage:
    def rev(name: str, a: str, b: str) -> JointSpec:
        return JointSpec(name, "revolute", (a, b))
    mech = PlanarLinkage(
        (("O", (0.0, 0.0)), ("Q", (0.3, 0.0)), ("G", (0.45, 0.0))),
        (BodySpec("crank", ("O", "A"), 0.1), BodySpec("coupler", ("A", "B"), 0.35),
         BodySpec("rocker", ("Q", "B"), 0.25, (("C", (0.4, 0.0)),)), BodySpec("rod", ("C", "D"), 0.5),
         BodySpec("ram", ("D",))),
        (rev("O", "frame", "crank"), rev("A", "crank", "coupler"), rev("B", "coupler", "rocker"),
         rev("Q", "frame", "rocker"), rev("C", "rocker", "rod"), rev("D", "rod", "ram"),
         JointSpec("guide", "prismatic", ("frame", "ram"), through="G", axis_angle=math.pi / 2)),
        "crank", "ram")
    props = {"crank": synth.MassProps(1.0, (0.05, 0.0), 0.001), "coupler": synth.MassProps(2.0, (0.175, 0.0), 0.02),
             "rocker": synth.MassProps(3.0, (0.2, 0.0), 0.04), "rod": synth.MassProps(2.5, (0.25, 0.0), 0.05),
             "ram": synth.MassProps(8.0)}
    return synth.Linkage(mech, props, gravity=synth.Gravity(),
                         loads=(synth.ProcessLoad("window", 4000.0, 0.0, math.pi),),
                         counterweights=(synth.Counterweight("crank", 0.8, (-0.04, 0.0)),))


def spec(kind: str = "rectangle", **family: float) -> LinkSpec:
    return LinkSpec(MATERIALS["S355J2"], SectionFamily(kind, **family))   # type: ignore[arg-type]


@pytest.mark.parametrize("linkage", [fourbar(), press()], ids=["fourbar", "press"])
def test_every_bar_is_in_equilibrium_under_the_cycles_loads(linkage: synth.Linkage) -> None:
    # The joint reactions, torques, process force, counterweights and the spread weight and inertia of a link
    # sum to zero force and moment (the kinetostatics' own equations): left over only at round-off.
    analysis = synth.analyse(linkage, 120 * RPM, samples=180)
    for link in synth.strength.beam_links(analysis):
        forces = beam_forces(analysis, link)
        scale = float(np.abs(forces.axial).max() + np.abs(forces.shear).max())
        assert forces.closure[0] <= 1e-10 * scale
        assert forces.closure[1] <= 1e-10 * scale * forces.length


def _moment_from_the_right(analysis: synth.Analysis, link: str, x: float, samples: int = 4001) -> np.ndarray:
    """Bending moment at x from the loads right of it, with the spread load integrated numerically point by
    point from the motion (a path that shares only the reactions with :func:`beam_forces`): the sized bar is
    uniform, mu = m / L, plus the couple per length of its inertia beyond a slender bar's, -m h²/12 alpha / L."""
    motion, linkage = analysis.motion, analysis.linkage
    topo = linkage.mechanism.topology
    theta = motion.link_angle[link]
    e = np.stack([np.cos(theta), np.sin(theta)], axis=1)
    nrm = np.stack([-np.sin(theta), np.cos(theta)], axis=1)
    origin = motion.point_pos[motion.link_origin[link]]
    moment = np.zeros(motion.samples)
    end = 0.0
    for joint in topo.joints:
        if link not in joint.bodies:
            continue
        f = analysis.kinetostatics.reactions[joint.name] * (1.0 if joint.bodies[1] == link else -1.0)
        r = motion.point_pos[joint.point] - origin
        xj = np.sum(r * e, axis=1)
        end = max(end, float(xj.max()))
        right = xj > x
        # moment about the section point of a force at xj on the axis: (xj - x) * (f . n)
        moment += np.where(right, (xj - x) * np.sum(f * nrm, axis=1), 0.0)
    props = linkage.links[link]
    length = end
    mu = props.mass / length
    s = np.linspace(x, end, samples)
    g = linkage.gravity.vector if linkage.gravity is not None else np.zeros(2)
    q = np.stack([mu * (g - motion.point_on(link, (float(si), 0.0)).acc) for si in s])   # (samples, N, 2)
    qn = np.sum(q * nrm[None], axis=2)
    moment += np.trapezoid((s - x)[:, None] * qn, s, axis=0)
    h2 = 12 * props.inertia / props.mass - length**2
    moment += -props.mass * h2 / 12 * motion.link_alpha[link] / length * (end - x)
    # the loads right of the section act on the right part; the internal moment on the left part is their moment
    return np.asarray(moment)


def test_sized_links_stresses_recomputed_from_the_final_reactions_by_a_second_path() -> None:
    result = size_links(press(), 60 * RPM, {n: spec() for n in ("crank", "coupler", "rocker", "rod")},
                        StrengthLimits(), samples=120)
    for link in ("coupler", "rod", "rocker"):
        sizing = result.links[link]
        forces = beam_forces(result.analysis, link)
        j = int(np.argmin(np.abs(forces.x - 0.37 * forces.length)))
        x = float(forces.x[j])
        expected = _moment_from_the_right(result.analysis, link, x)
        scale = float(np.abs(forces.moment).max())
        np.testing.assert_allclose(forces.moment[:, j], expected, atol=1e-6 * scale + 1e-9)
        # and the static check's stress there is the moment over the section modulus plus the axial stress
        stress = np.abs(forces.axial[:, j]) / sizing.section.area + np.abs(expected) / sizing.section.modulus
        static = next(c for c in sizing.checks if c.name == "static")
        assert sizing.material.yield_strength / stress.max() >= static.safety * (1 - 1e-9)


def test_the_fixed_point_masses_are_the_sections_masses_and_resizing_keeps_them() -> None:
    linkage = press()
    specs = {"crank": spec("round"), "coupler": spec("rectangle", ratio=2.5), "rocker": spec("tube", ratio=0.1),
             "rod": spec("rectangle", ratio=3.0)}
    result = size_links(linkage, 60 * RPM, specs, StrengthLimits(), samples=120)
    assert len(result.iterations) >= 2
    assert result.residual == 0.0
    for name, sizing in result.links.items():
        used = result.analysis.linkage.links[name]
        forces = sizing.forces
        # the sizing equation: m = rho A L for the bar between its outer load points
        assert used.mass == pytest.approx(MATERIALS["S355J2"].density * sizing.section.area * forces.length,
                                          rel=1e-12)
        again = size_link(beam_forces(result.analysis, name), specs[name], StrengthLimits())
        assert again.section.label == sizing.section.label
        assert sizing.passed
        # the next smaller section of the family fails a check on the final analysis
        cands = specs[name].family.candidates()
        k = [c.label for c in cands].index(sizing.section.label)
        if k > 0:
            smaller = size_link(beam_forces(result.analysis, name),
                                dataclasses.replace(specs[name], section=cands[k - 1]), StrengthLimits())
            assert not smaller.passed
    # the analysis as built is a plain analysis of the sized linkage
    again = synth.analyse(result.linkage, 60 * RPM, samples=120)
    np.testing.assert_allclose(again.kinetostatics.driving_torque, result.analysis.kinetostatics.driving_torque)


def test_a_family_that_cannot_carry_the_load_is_infeasible_naming_link_check_and_angle() -> None:
    small = LinkSpec(MATERIALS["S235JR"], SectionFamily("round", max_size=4 * MM))
    with pytest.raises(synth.Infeasible) as err:
        size_links(press(), 60 * RPM, {"rod": small}, StrengthLimits(), samples=72)
    extras = err.value.extras()
    assert extras["link"] == "rod" and extras["check"] in ("static", "fatigue", "buckling_in_plane",
                                                           "buckling_out_of_plane")
    assert 0.0 <= extras["crank_angle_deg"] < 360.0
    assert "rod" in str(err.value) and "crank angle" in str(err.value)


def test_a_block_is_not_a_bar() -> None:
    with pytest.raises(synth.InvalidInput, match="not bars"):
        size_links(press(), 60 * RPM, {"ram": spec()}, StrengthLimits(), samples=36)
