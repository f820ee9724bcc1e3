"""Flywheel geometry and placement: the seed's rim formula, least mass against brute force, binding limits."""

from __future__ import annotations

import math

import numpy as np
import pytest

import synth
from synth.flywheel.geometry import _roots
from tests.conftest import CASES


def test_rim_diameter_reproduces_seed() -> None:
    # seed case: D = [4 g J/(pi gamma k1 k2)]^(1/5), a = k1 D, b = k2 D; rho = gamma/g
    case = CASES["cw_flywheel_rim_diameter"]
    inp, exp, rel = case["inputs"], case["expected"], case["tolerance_rel"]
    rho = inp["gamma_N_m3"] / inp["g_m_s2"]
    d = synth.rim_diameter(inp["J_M_kgm2"], rho, inp["k1"], inp["k2"])
    assert d == pytest.approx(exp["D_m"], rel=rel)
    assert inp["k1"] * d == pytest.approx(exp["a_m"], rel=rel)
    assert inp["k2"] * d == pytest.approx(exp["b_m"], rel=rel)
    on_crank = synth.rim_diameter(inp["J_M_crank_shaft_kgm2"], rho, inp["k1"], inp["k2"])
    assert on_crank == pytest.approx(exp["D_on_crank_shaft_m"], rel=rel)
    assert on_crank > inp["D_max_m"] > d  # the seed's reason to move it to the motor shaft


def test_placement_on_motor_shaft_reproduces_seed() -> None:
    # seed case: J' = J (w_crank/w_motor)^2 with w_motor = pi n/30; here through the placement search
    case = CASES["cw_flywheel_to_motor_shaft"]
    inp, exp, rel = case["inputs"], case["expected"], case["tolerance_rel"]
    w_motor = inp["n_motor_rpm"] * math.pi / 30
    assert w_motor == pytest.approx(exp["omega_motor_rad_s"], rel=rel)
    spec = synth.GeometrySpec(density=7950.0, max_rim_speed=40.0, max_diameter=0.75,
                              shafts=(synth.Shaft("motor", w_motor / inp["omega_crank_rad_s"]),))
    design = synth.design_flywheel(inp["J_M_kgm2"], spec, inp["omega_crank_rad_s"])
    motor = next(b for b in design.bodies if b.shaft == "motor")
    assert motor.inertia == pytest.approx(exp["J_M_motor_shaft_kgm2"], rel=rel)
    assert design.best.shaft == "motor"  # the faster shaft needs far less mass
    # on the crank shaft the 0.75 m limit binds, as the seed says
    assert [(m.shaft, m.constraint) for m in design.misses] == [("crank", "max_diameter_m")]


@pytest.mark.parametrize("shape", ["rim", "disc"])
def test_least_mass_beats_a_brute_force_grid(shape: str) -> None:
    # independent: scan diameter, thickness and width on a grid; no feasible grid point is lighter than the NLP
    spec = synth.GeometrySpec(shape=shape, density=7200.0, max_rim_speed=30.0, max_diameter=0.9,
                              thickness_ratio=(0.08, 0.25), width_ratio=(0.05, 0.3))
    j, w = 12.0, 40.0
    body = synth.design_flywheel(j, spec, w).best
    assert body.inertia_check == pytest.approx(j, rel=1e-6)
    assert body.rim_speed <= 30.0 * (1 + 1e-6) and body.outer_diameter <= 0.9 * (1 + 1e-6)
    d = np.linspace(0.2, 0.9, 281)[:, None, None]
    ka = np.linspace(0.08, 0.25, 69)[None, :, None] if shape == "rim" else np.zeros((1, 1, 1))
    kb = np.linspace(0.05, 0.3, 101)[None, None, :]
    a, b = ka * d, kb * d
    rho = spec.density
    if shape == "rim":
        inertia, mass = rho * np.pi * b * d * a * (d**2 + a**2) / 4, rho * np.pi * d * a * b
    else:
        inertia, mass = rho * np.pi * b * d**4 / 32, rho * np.pi * d**2 * b / 4 + 0 * a
    outer = d + a
    ok = (inertia >= j) & (outer <= 0.9) & (0.5 * outer * w <= 30.0)
    assert ok.any()
    assert body.mass <= mass[ok].min() * (1 + 1e-6)
    # and a grid fine enough gets within a few per cent of it
    assert body.mass >= mass[ok].min() * 0.95


def test_nothing_fits_names_the_binding_limit() -> None:
    spec = synth.GeometrySpec(max_rim_speed=None, max_diameter=0.2, shafts=(synth.Shaft("motor", 4.0),))
    with pytest.raises(synth.Infeasible) as err:
        synth.design_flywheel(500.0, spec, 10.0)
    assert err.value.constraint == "geometry.max_diameter_m"
    # under a rim-speed limit the crank-equivalent capacity falls as the shaft ratio cubed: even the crank
    # shaft (a 5 m rim at 10 rad/s) holds less than 1e6 kg·m²
    spec = synth.GeometrySpec(max_rim_speed=25.0, shafts=(synth.Shaft("motor", 4.0),))
    with pytest.raises(synth.Infeasible) as err:
        synth.design_flywheel(1e6, spec, 10.0)
    assert err.value.constraint == "geometry.max_rim_speed_m_s"
    stress = synth.GeometrySpec(max_rim_speed=None, allowable_stress=2e6, density=7200.0)
    speed, name = stress.speed_limit()
    assert name == "allowable_stress_Pa" and speed == pytest.approx(math.sqrt(2e6 / 7200.0), rel=1e-12)


def test_no_limit_at_all_is_invalid() -> None:
    with pytest.raises(synth.InvalidInput) as err:
        synth.design_flywheel(1.0, synth.GeometrySpec(max_rim_speed=None), 10.0)
    assert err.value.field == "geometry.max_diameter_m"


def _least_mass_nlp(spec: synth.GeometrySpec, inertia: float, outer_limit: float) -> float:
    """Independent: the least mass as a nonconvex NLP in (D, a, b) solved by IPOPT from the largest proportions."""
    import casadi as ca

    rho, rim = spec.density, spec.shape == "rim"
    length = (inertia / rho) ** 0.2
    opti = ca.Opti()
    x = opti.variable(3)
    d, a, b = x[0] * length, x[1] * length, x[2] * length
    k1, k2 = spec.thickness_ratio, spec.width_ratio
    if rim:
        j, mass = rho * math.pi * b * d * a * (d**2 + a**2) / 4, rho * math.pi * d * a * b
        opti.subject_to(opti.bounded(k1[0] * x[0], x[1], k1[1] * x[0]))
        opti.subject_to(x[0] + x[1] <= outer_limit / length)
    else:
        j, mass = rho * math.pi * b * d**4 / 32, rho * math.pi * d**2 * b / 4
        opti.subject_to(x[1] == 0)
        opti.subject_to(x[0] <= outer_limit / length)
    opti.subject_to(opti.bounded(k2[0] * x[0], x[2], k2[1] * x[0]))
    opti.subject_to(j / inertia >= 1)
    opti.subject_to(x[0] >= 1e-3)
    opti.minimize(mass / (rho * length**3))
    best = math.inf
    # a nonconvex program: the lightest of several starts across the thickness range
    for t in np.linspace(k1[0], k1[1], 5) if rim else [0.0]:
        d0 = 0.9 * outer_limit / (1 + t) if math.isfinite(outer_limit) else 3 * length
        opti.set_initial(x, [d0 / length, t * d0 / length, k2[1] * d0 / length])
        opti.solver("ipopt", {"print_time": False}, {"print_level": 0, "sb": "yes", "tol": 1e-12})
        try:
            sol = opti.solve()
        except RuntimeError:
            continue
        best = min(best, float(sol.value(mass)))
    return best


@pytest.mark.parametrize("seed", range(12))
def test_closed_form_least_mass_equals_the_nlp(seed: int) -> None:
    # the closed form against IPOPT on the same program, over limits that bind each way: the outer diameter, the
    # least width, thickness ranges on both sides of the rim's peak t ≈ 0.307
    rng = np.random.default_rng(seed)
    shape = "rim" if seed % 3 else "disc"
    t_lo = float(rng.uniform(0.05, 0.5))
    w_lo = float(rng.uniform(0.05, 0.3))
    spec = synth.GeometrySpec(shape=shape, density=7200.0, max_rim_speed=None,
                              max_diameter=float(rng.uniform(0.3, 1.5)),
                              thickness_ratio=(t_lo, t_lo + float(rng.uniform(0.0, 0.6))),
                              width_ratio=(w_lo, w_lo + float(rng.uniform(0.0, 0.4))))
    assert spec.max_diameter is not None
    largest = rng.uniform(0.05, 0.95)
    j = _largest_inertia(spec) * largest
    body = synth.design_flywheel(j, spec, 1.0).best
    assert body.inertia_check == pytest.approx(j, rel=1e-9)
    assert body.outer_diameter <= spec.max_diameter * (1 + 1e-12)
    d = body.diameter
    assert spec.width_ratio[0] * d * (1 - 1e-12) <= body.width <= spec.width_ratio[1] * d * (1 + 1e-12)
    if shape == "rim":
        assert body.thickness is not None
        assert spec.thickness_ratio[0] * (1 - 1e-12) <= body.thickness / d <= spec.thickness_ratio[1] * (1 + 1e-12)
    assert body.mass == pytest.approx(_least_mass_nlp(spec, j, spec.max_diameter), rel=1e-6)


def _largest_inertia(spec: synth.GeometrySpec) -> float:
    """Independent: the most inertia within the outer diameter, by a dense scan of the thickness ratio."""
    assert spec.max_diameter is not None
    k2 = spec.width_ratio[1]
    if spec.shape == "disc":
        return spec.density * math.pi * k2 * spec.max_diameter**5 / 32
    t = np.linspace(*spec.thickness_ratio, 20001)
    d = spec.max_diameter / (1 + t)
    return float(np.max(spec.density * math.pi * k2 * d * t * d * d * d * d * (1 + t * t) / 4))


def test_a_rim_thickness_range_past_the_peak_holds_what_fits() -> None:
    # t(1 + t²)/(1 + t)⁵ peaks inside (0.1, 0.6): the rim at the largest thickness ratio holds 12 % less than the
    # one at the peak, so a flywheel between the two fits and must be designed, not refused
    spec = synth.GeometrySpec(max_rim_speed=None, max_diameter=1.0, thickness_ratio=(0.1, 0.6),
                              width_ratio=(0.1, 0.2))
    most = _largest_inertia(spec)
    at_top = spec.density * math.pi * 0.2 * 0.6 * (1 + 0.36) / (1.6**5) / 4
    assert at_top < 0.9 * most
    body = synth.design_flywheel(0.99 * most, spec, 1.0).best
    assert body.inertia_check == pytest.approx(0.99 * most, rel=1e-9)
    assert body.mass == pytest.approx(_least_mass_nlp(spec, 0.99 * most, 1.0), rel=1e-6)
    with pytest.raises(synth.Infeasible):
        synth.design_flywheel(1.001 * most, spec, 1.0)


def test_rim_quintics_roots_in_one_call_are_numpys_to_the_bit() -> None:
    # the rim's quintics L⁵(t + t³) - C(1 + t)⁵ over a spread of limits and inertias; numpy.roots, one polynomial
    # at a time, is the reference (the same companion matrices, so the same eigenvalues)
    polys = [[-c, -5 * c, l5 - 10 * c, -10 * c, l5 - 5 * c, -c] for c in (1e-6, 0.02, 3.0) for l5 in (1e-4, 0.5, 2.0)]
    for got, row in zip(_roots(polys), polys, strict=True):
        want = np.roots(row)
        assert np.array_equal(got.real, want.real) and np.array_equal(got.imag, want.imag)
    # a zero last coefficient (a root at zero) is left to numpy.roots itself: roots 0, 1 and 2
    np.testing.assert_allclose(np.sort(_roots([[1.0, -3.0, 2.0, 0.0]])[0].real), [0.0, 1.0, 2.0], atol=1e-12)
