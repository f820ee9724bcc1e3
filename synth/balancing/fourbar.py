"""Counterweight balancing on the linear-in-parameters map: static and full for four-bars, optimal for every
family (four-bar, slider-crank, shaper).

Every answer is re-analysed with the plain kinetostatic model (``synth.analyse`` on the linkage with the
counterweights added), never with the map it was optimised on, and carries the residual shaking force and moment.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Literal

import numpy as np

from ..analysis import Analysis, Summary, analyse
from ..counter_rotors import CounterRotor, rotor_loads
from ..errors import Infeasible, InvalidInput
from ..kinematics import FourBar, Motion, PlanarLinkage, SliderCrank
from ..kinematics.motion import magnitude
from ..kinetostatics import LinearMap, linear_map, shaking_force_map
from ..model import Counterweight, FloatArray, Linkage, MassProps
from ..warnings import link_lengths
from .fixed_points import fixed_point_counterweights
from .program import (
    PARAMS,
    ConeProgram,
    CounterweightLayout,
    CounterweightSolution,
    CounterweightSpec,
    counterweight_layout,
    realisability_block,
    row_space,
    solve,
)


@dataclass(frozen=True, slots=True)
class BalanceResult:
    """Counterweights and what they do, checked by re-analysis with the plain model.

    ``residual_force`` / ``residual_moment``: largest shaking force [N] / moment [N·m] left after balancing
    (counter-rotors included); ``..._rel``: the same over the largest before.
    """

    mode: str
    counterweights: tuple[Counterweight, ...]
    total_added_mass: float
    before: Summary
    after: Summary
    residual_force: float
    residual_force_rel: float
    residual_moment: float
    residual_moment_rel: float
    analysis_before: Analysis
    analysis_after: Analysis
    added_inertia: float = 0.0
    coupler_inertia: float | None = None
    counter_rotors: tuple[CounterRotor, ...] = ()
    objective: float | None = None
    driving_torque_after: FloatArray | None = None
    weights: Weights | None = None
    weight_scale: str | None = None


# A budget is met when the least mass exceeds it by no more than this fraction (the solver's own accuracy).
BUDGET_TOLERANCE = 1e-8

def _require_fourbar(linkage: Linkage, mode: str | None = None) -> FourBar:
    """The four-bar of ``linkage``; for ``mode`` (static, full) an InvalidInput that says what to use instead."""
    mech = linkage.mechanism
    if isinstance(mech, FourBar):
        return mech
    if mode is None:
        raise InvalidInput("counterweight balancing by this mode is for four-bars", field="mechanism.type")
    output = mech.topology.output
    # Rotating counterweights give forces that turn with their links; the output's inertia force stays on the
    # slide's line, so equalities on the force (or moment) over the cycle have no solution in general.
    instead = ("the optimal mode (the best trade-off within a mass budget), or the slider-crank balancing "
               "(a crank counterweight and Lanchester balancers, synth.balance_slider_crank)"
               if isinstance(mech, SliderCrank) else "the optimal mode (the best trade-off within a mass budget)")
    raise InvalidInput(f"{mode} balancing is for four-bars: counterweights on the links that turn cannot cancel "
                       f"the {output}'s reciprocating inertia force at every angle; use {instead}",
                       field="mechanism.type")


def _require_turning(linkage: Linkage) -> None:
    """Static balancing takes four-bars and general linkages whose links all turn (no prismatic pair); for any
    other an InvalidInput that says what to use instead."""
    mech = linkage.mechanism
    if isinstance(mech, PlanarLinkage):
        sliding = [j.name for j in mech.joints if j.kind == "prismatic"]
        if not sliding:
            return
        raise InvalidInput(
            f"static balancing needs a linkage whose links all turn: through its prismatic pairs {sliding} a link "
            f"slides, and counterweights on turning links cannot cancel that link's reciprocating inertia force at "
            "every angle; use the optimal mode (the best trade-off within a mass budget)", field="mechanism.type")
    _require_fourbar(linkage, "static")


def _var_columns(lm: LinearMap, cw: CounterweightLayout) -> list[int]:
    """Columns of the map the counterweight variables add to, in the layout's order."""
    cols: list[int] = []
    for link in cw.links:
        s = lm.columns(link)
        cols += list(range(s.start, s.stop))
    return cols


def _program(cw: CounterweightLayout, extra: int = 0) -> ConeProgram:
    """A cone program over the counterweight variables (and ``extra`` more), realisability rows included."""
    program = ConeProgram(cw.size + extra)
    program.add(realisability_block(cw))
    return program


def _rows(lm: LinearMap, which: Sequence[int]) -> tuple[FloatArray, FloatArray]:
    """Stack rows ``which`` of the map over all angles: (N·rows, params) and (N·rows,)."""
    y = lm.y[:, which, :].reshape(-1, lm.y.shape[2])
    return y, lm.y0[:, which].reshape(-1)


def _check(linkage: Linkage, speed: float, samples: int, counterweights: Sequence[Counterweight],
           before: Analysis, rotor_moment: FloatArray | None = None) -> tuple[Analysis, float, float, float, float]:
    # The re-analysis is the plain model with the counterweights' masses, on the mechanism's motion as the
    # analysis before computed it (one motion per request).
    after = analyse(linkage.with_counterweights(counterweights), speed, samples=samples,
                    base_motion=before.mechanism_motion)
    return (after, *_residuals(after, before, rotor_moment))


def _residuals(after: Analysis, before: Analysis, rotor_moment: FloatArray | None = None,
               summary: Summary | None = None) -> tuple[float, float, float, float]:
    """Largest shaking force [N] and moment [N·m] left in the re-analysis ``after``, each also over its largest
    value ``before`` (whose ``summary`` the caller may have already)."""
    force = float(magnitude(after.kinetostatics.shaking_force).max())
    moment_series = after.kinetostatics.shaking_moment + (0.0 if rotor_moment is None else rotor_moment)
    moment = float(np.abs(moment_series).max())
    summary = before.summary() if summary is None else summary
    f0, m0 = summary.max_shaking_force, summary.max_shaking_moment
    return force, force / f0 if f0 > 0 else 0.0, moment, moment / m0 if m0 > 0 else 0.0


def _force_rows(lm: LinearMap) -> tuple[FloatArray, FloatArray]:
    """The shaking-force rows of the map over all angles: (2N, params) and (2N,), x and y of each angle."""
    return _rows(lm, [lm.force_rows.start, lm.force_rows.start + 1])


def _shaking_force_rows(motion: Motion, linkage: Linkage) -> tuple[FloatArray, FloatArray]:
    """The map's shaking-force rows over all angles as :func:`_force_rows` has them, from their definition
    (:func:`synth.kinetostatics.shaking_force_map`): static balancing needs no other row of the map."""
    y = shaking_force_map(motion, linkage)
    return y.reshape(-1, y.shape[-1]), np.zeros(2 * motion.samples)


def _static_system(linkage: Linkage, force: tuple[FloatArray, FloatArray], cw: CounterweightLayout
                   ) -> tuple[FloatArray, FloatArray]:
    a, b0 = force
    rhs = -(a @ linkage.params() + b0)
    return row_space(a[:, _static_columns(linkage, cw)], rhs, "the shaking force", "counterweight_links")


def _static_columns(linkage: Linkage, cw: CounterweightLayout) -> list[int]:
    """The map's columns of the counterweights' variables: (m, h_x, h_y, J) of each of their links."""
    links = linkage.mechanism.topology.links
    return [PARAMS * links.index(link) + c for link in cw.links for c in range(PARAMS)]


def _with_default_radii(spec: CounterweightSpec, linkage: Linkage) -> CounterweightSpec:
    """The spec with the coupler's default largest radius at twice its length.

    Without a crank counterweight the coupler's counterweight must sit beyond B whenever the crank's centre of
    mass lies toward A (seed 001:1394: a2 > l2); the link's own length would exclude it by default.
    """
    if ("coupler" not in spec.links or "coupler" in (spec.max_radius or {}) or "coupler" in (spec.radius or {})
            or not isinstance(linkage.mechanism, FourBar)):
        return spec
    fb = _require_fourbar(linkage)
    return replace(spec, max_radius={**(spec.max_radius or {}), "coupler": 2.0 * fb.coupler})


def _coupler_shift(linkage: Linkage, spec: CounterweightSpec) -> complex | None:
    """D [kg·m] in m_c·(z_c - l2) = D, the condition on a coupler counterweight (mass m_c at z_c in the coupler
    frame) when the crank carries none; None when the crank has a counterweight too.

    From the static condition on the crank's first moment h1 = -(l1/l2)·(m2·l2 - h2) (seed 3.8) with the coupler's
    totals m2 + m_c, h2 + m_c·z_c: D = m2·l2 + (l2/l1)·h1 - h2.
    """
    if "crank" in spec.links or "coupler" not in spec.links or not isinstance(linkage.mechanism, FourBar):
        return None
    fb = _require_fourbar(linkage)
    h1 = complex(*linkage.params_of("crank")[1:3])
    m2, h2 = float(linkage.params_of("coupler")[0]), complex(*linkage.params_of("coupler")[1:3])
    return m2 * fb.coupler + (fb.coupler / fb.crank) * h1 - h2


def _coupler_radius_cause(linkage: Linkage, spec: CounterweightSpec) -> Infeasible | None:
    """The named cause when, with no crank counterweight, the coupler's radius limit excludes every solution."""
    d = _coupler_shift(linkage, spec)
    if d is None or abs(d) == 0:
        return None
    fb = _require_fourbar(linkage)
    r_max = spec.limit(linkage, "coupler")
    m2 = float(linkage.params_of("coupler")[0])
    # z_c = l2 + D/m_c sweeps the open ray from B along D as m_c falls; its nearest approach to A decides.
    l2 = fb.coupler
    nearest = l2 if d.real >= 0 else l2 * abs(d.imag) / abs(d)
    if nearest < r_max:
        return None
    needed = abs(fb.coupler + d / m2) if m2 > 0 else float("inf")
    return Infeasible(
        f"without a crank counterweight the coupler's counterweight must sit beyond B, at l2 + D/m = "
        f"{fb.coupler:.6g} m + ({d.real:.6g}, {d.imag:.6g}) kg·m / m from A; max_radius_m.coupler is {r_max:.6g} m. "
        f"A counterweight of the coupler's own mass ({m2:.6g} kg) needs a radius of {needed:.6g} m",
        constraint="max_radius_m.coupler", required_radius_m=needed if math.isfinite(needed) else None,
    )


def balance_static(
    linkage: Linkage,
    speed: float,
    spec: CounterweightSpec | None = None,
    *,
    samples: int = 360,
    objective: Literal["min_mass", "min_inertia"] = "min_mass",
    mass_budget: float | None = None,
    time_limit_s: float = 20.0,
    method: Literal["program", "fixed_points"] = "program",
) -> BalanceResult:
    """Counterweights that make the shaking force identically zero (the total centre of mass fixed).

    ``method="fixed_points"`` moves each link's centre of mass to a fixed point in closed form instead
    (:func:`fixed_point_counterweights`, the seed's 8.3-8.4), re-analysed the same way.

    Posed on the linear map as a few equalities (the row space of the force rows over all angles) with one
    realisability cone per counterweight; minimum total added mass [kg] by default, or minimum added inertia
    about the links' joints [kg·m²] within ``mass_budget`` [kg]. Solved by Clarabel.
    """
    _require_turning(linkage)
    if method == "fixed_points":
        return _fixed_points(linkage, speed, spec, samples)
    spec = _static_spec(linkage, spec, objective, mass_budget)
    before = analyse(linkage, speed, samples=samples)
    cw, program, x = _static_solution(linkage, _shaking_force_rows(before.motion, linkage), spec, objective,
                                      mass_budget, time_limit_s)
    # In a minimum-mass program the inertia variable is free: the counterweights are point masses.
    cws = CounterweightSolution(cw, x).counterweights(point_masses=objective == "min_mass" and not spec.radius)
    after = _check(linkage, speed, samples, cws, before)[0]
    return _static_result(cws, before, after, float(program.q @ x))


def _static_spec(linkage: Linkage, spec: CounterweightSpec | None, objective: str,
                 mass_budget: float | None) -> CounterweightSpec:
    """The static program's spec: resolved on ``linkage``, the coupler's default radius, and the objective's
    need of a budget checked."""
    spec = _with_default_radii((spec or CounterweightSpec()).resolve(linkage), linkage)
    all_fixed = bool(spec.radius) and all(link in (spec.radius or {}) for link in spec.links)
    if objective == "min_inertia" and mass_budget is None and not all_fixed:
        raise InvalidInput("minimum added inertia needs a mass budget: a heavier counterweight nearer the pivot "
                           "always has less inertia", field="mass_budget_kg")
    return spec


def _static_solution(linkage: Linkage, force: tuple[FloatArray, FloatArray], spec: CounterweightSpec,
                     objective: str, mass_budget: float | None, time_limit_s: float,
                     system: tuple[FloatArray, FloatArray] | None = None
                     ) -> tuple[CounterweightLayout, ConeProgram, FloatArray]:
    """The static program on the map's shaking-force rows ``force`` (:func:`_force_rows`) and its solution; an
    infeasible budget says the mass it needs. ``system`` is :func:`_static_system` of these when the caller has
    it already."""
    if objective == "min_mass" and mass_budget is not None:
        # The least mass within a budget is the least mass when the budget allows it: one program answers both
        # whether the budget suffices and, when it does not, how much it would take.
        cw, program, x = _static_solution(linkage, force, spec, "min_mass", None, time_limit_s, system)
        needed = float(cw.mass_columns() @ x)
        if needed > mass_budget * (1.0 + BUDGET_TOLERANCE):
            raise Infeasible(f"static balance needs at least {needed:.6g} kg of counterweights; the budget is "
                             f"{mass_budget:.6g} kg", constraint="mass_budget_kg", required_mass_kg=needed)
        return cw, program, x
    cw = counterweight_layout(spec, linkage)
    ar, br = _static_system(linkage, force, cw) if system is None else system
    program = _program(cw)
    program.equal(ar, br)
    binding = (["angle_deg"] if spec.angle else []) + ["max_radius_m"]
    masses, inertias = cw.mass_columns(), cw.inertia_columns()
    if mass_budget is not None:
        program.at_most(masses[None, :], np.array([mass_budget]))
        binding = ["mass_budget_kg"] + binding
    program.q = masses + 1e-9 * inertias if objective == "min_mass" else inertias + 1e-9 * masses
    try:
        x = solve(program, time_limit_s, "static balancing", binding)
    except Infeasible as exc:
        if mass_budget is None:
            cause = _coupler_radius_cause(linkage, spec)
            if cause is not None:
                raise cause from exc
            raise
        least, _, x_least = _static_solution(linkage, force, spec, "min_mass", None, time_limit_s, (ar, br))
        needed = sum(c.mass for c in CounterweightSolution(least, x_least).counterweights())
        raise Infeasible(f"static balance needs at least {needed:.6g} kg of counterweights; the budget is "
                         f"{mass_budget:.6g} kg", constraint="mass_budget_kg", required_mass_kg=needed) from exc
    return cw, program, x


def _static_result(cws: Sequence[Counterweight], before: Analysis, after: Analysis, objective: float | None,
                   summaries: tuple[Summary, Summary] | None = None) -> BalanceResult:
    """A static answer from its counterweights and the plain analyses before and after (and their summaries
    when the caller has them already)."""
    s_before, s_after = (before.summary(), after.summary()) if summaries is None else summaries
    f, f_rel, m, m_rel = _residuals(after, before, summary=s_before)
    return BalanceResult("static", tuple(cws), sum(c.mass for c in cws), s_before, s_after,
                         f, f_rel, m, m_rel, before, after,
                         added_inertia=sum(c.params()[3] for c in cws), objective=objective)


def _fixed_points(linkage: Linkage, speed: float, spec: CounterweightSpec | None, samples: int) -> BalanceResult:
    before = analyse(linkage, speed, samples=samples)
    cws = fixed_point_counterweights(linkage, spec)
    return _static_result(cws, before, _check(linkage, speed, samples, cws, before)[0], None)


def exact_static_counterweights(linkage: Linkage) -> dict[str, tuple[float, float]]:
    """First moments (m·x, m·y) [kg·m] the crank and rocker counterweights need for static balance, closed form.

    Berkof-Lowen's linearly independent vectors (the seed's principal vectors [001:1345-1397], with (3.9)
    corrected to l2/l3): with z_i = x_i + i·y_i the centre of mass in link i's frame, the total centre of mass
    is fixed iff m1·z1 = -m2·(l1/l2)·(l2 - z2) and m3·z3 = -m2·z2·l3/l2 (coupler unchanged).
    """
    fb = _require_fourbar(linkage)
    p = {name: linkage.params_of(name) for name in ("crank", "coupler", "rocker")}
    m2, h2 = p["coupler"][0], complex(p["coupler"][1], p["coupler"][2])
    crank_total = -(fb.crank / fb.coupler) * (m2 * fb.coupler - h2)
    rocker_total = -h2 * fb.rocker / fb.coupler
    need1 = crank_total - complex(p["crank"][1], p["crank"][2])
    need3 = rocker_total - complex(p["rocker"][1], p["rocker"][2])
    return {"crank": (need1.real, need1.imag), "rocker": (need3.real, need3.imag)}


def pendulum_inertia(linkage: Linkage) -> float:
    """Coupler inertia about its centre of mass [kg·m²] that makes it a physical pendulum: m2·a·(l2 - a).

    Raises Infeasible when the coupler's centre of mass is off the line of its joints or outside them.
    """
    fb = _require_fourbar(linkage)
    props = linkage.mass_props("coupler")
    x, y = props.com
    if props.mass <= 0:
        raise Infeasible("full balancing needs a coupler with mass", constraint="links.coupler.mass_kg")
    if abs(y) > 1e-9 * fb.coupler:
        raise Infeasible(f"the coupler's centre of mass is {y:.4g} m off the line of its joints: it cannot be a "
                         "physical pendulum, so the shaking moment cannot vanish; use the optimal mode",
                         constraint="links.coupler.com_m")
    if not 0 <= x <= fb.coupler:
        raise Infeasible(f"the coupler's centre of mass ({x:.4g} m from A) lies outside its joints: the pendulum "
                         "inertia m·a·(l - a) would be negative; use the optimal mode",
                         constraint="coupler_inertia_kgm2")
    return props.mass * x * (fb.coupler - x)


def _coupler_pendulum_cause(linkage: Linkage, spec: CounterweightSpec) -> None:
    """Infeasible naming the coupler's centre of mass when, with counterweights on the coupler but not the crank,
    static balance puts it where no physical pendulum exists (beyond B or off the line AB)."""
    d = _coupler_shift(linkage, spec)
    if d is None:
        return
    fb = _require_fourbar(linkage)
    # The coupler's total first moment must be m_tot·l2 + (l2/l1)·h1: its centre of mass sits (l2/l1)·h1/m_tot
    # from B, beyond B for any counterweight when the crank's centre of mass lies toward A (h1·x > 0).
    h1 = complex(*linkage.params_of("crank")[1:3])
    if abs(h1.imag) > 1e-12 * max(abs(h1), 1e-300):
        where = f"{abs(h1.imag) * fb.coupler / fb.crank:.6g} kg·m off the line AB"
    elif h1.real > 0:
        where = f"beyond B by (l2/l1)·h1/m = {h1.real * fb.coupler / fb.crank:.6g} kg·m over the coupler's total mass"
    else:
        return
    raise Infeasible(
        f"with counterweights on the coupler but none on the crank, static balance puts the coupler's centre of "
        f"mass {where}, where it cannot be a physical pendulum (m·a·(l - a) >= 0 needs 0 <= a <= l on AB): "
        f"add the crank to counterweight_links", constraint="counterweight_links",
    )


def balance_full(
    linkage: Linkage,
    speed: float,
    spec: CounterweightSpec | None = None,
    *,
    samples: int = 360,
    ratios: Mapping[str, float] | None = None,
    time_limit_s: float = 20.0,
) -> BalanceResult:
    """Shaking force and shaking moment identically zero, at any crank speed and acceleration.

    Force: counterweights as in static balancing. Moment: the coupler made a physical pendulum (its inertia
    a variable) and counter-rotating inertias geared to crank and rocker at -``ratios`` times their speed
    (1:1 by default). The moment rows of two motion states (constant speed, and accelerating at eps = w²) are
    imposed, so the balance does not depend on the speed law. Minimum added mass.
    """
    _require_fourbar(linkage, "full")
    spec = (spec or CounterweightSpec()).resolve(linkage)
    ratios = {"crank": 1.0, "rocker": 1.0, **(ratios or {})}
    for link, k in ratios.items():
        if link not in ("crank", "rocker") or not (math.isfinite(k) and k > 0):
            raise InvalidInput(f"counter-rotor ratio for {link!r} must be a positive number on crank or rocker",
                               field=f"rotor_ratios.{link}")
    spec = _with_default_radii(spec, linkage)
    if "coupler" not in spec.links:
        pendulum_inertia(linkage)  # says plainly, before any solve, when the coupler cannot be a pendulum
    _coupler_pendulum_cause(linkage, spec)
    before = analyse(linkage, speed, samples=samples)
    states = [before.motion, analyse(linkage, speed, samples=samples, crank_acceleration=speed**2).motion]
    cw = counterweight_layout(spec, linkage)
    # Variables: the counterweights, then the coupler's inertia j2 and the two counter-rotor inertias.
    program = _program(cw, extra=3)
    n_vars = program.size
    program.at_most(-np.eye(3, n_vars, cw.size), np.zeros(3))
    p0 = linkage.params()
    coupler = linear_map(states[0], linkage).columns("coupler")
    moment_rows, moment_rhs = [], []
    for k, mot in enumerate(states):
        lm = linear_map(mot, linkage)
        cols = _var_columns(lm, cw)
        if k == 0:
            ar, br = _static_system(linkage, _force_rows(lm), cw)
            program.equal(ar, br)
        a, b0 = _rows(lm, [lm.moment_row])
        # The coupler's own inertia is a variable: take its fixed value out of p0, add the variable.
        base = p0.copy()
        base[coupler.start + 3] -= linkage.mass_props("coupler").inertia
        rotor_cols = np.stack([ratios["crank"] * mot.link_alpha["crank"], ratios["rocker"] * mot.link_alpha["rocker"]], axis=1)
        scale = max(1.0, float(np.abs(a @ p0 + b0).max()))
        moment_rows.append(np.hstack([a[:, cols], a[:, [coupler.start + 3]], rotor_cols]) / scale)
        moment_rhs.append(-(a @ base + b0) / scale)
    # Both states' moment rows over all angles have only a few independent directions: impose those.
    mr, mb = row_space(np.vstack(moment_rows), np.concatenate(moment_rhs), "the shaking moment", "counterweight_links")
    program.equal(mr, mb)
    # Added inertia is weighed at the scale of the crank (kg·m² over crank length²) so that the program does
    # not trade a counterweight's own inertia against a counter-rotor's: both cost.
    inertia_weight = 1e-3 / linkage.mechanism.crank ** 2
    program.q[: cw.size] = cw.mass_columns() + inertia_weight * cw.inertia_columns()
    program.q[cw.size + 1:] = inertia_weight
    x = solve(program, time_limit_s, "full balancing",
              ["counterweight_links", "max_radius_m", "a coupler pendulum and counter-rotors of non-negative inertia"])
    cws = CounterweightSolution(cw, x).counterweights()
    j2 = max(float(x[cw.size]), 0.0)
    counter_rotors = tuple(
        CounterRotor(link, max(float(x[cw.size + 1 + i]), 0.0), ratios[link])
        for i, link in enumerate(("crank", "rocker"))
    )
    coupler_props = linkage.mass_props("coupler")
    balanced = Linkage(
        linkage.mechanism,
        {**linkage.links, "coupler": MassProps(coupler_props.mass, coupler_props.com, j2)},
        linkage.counterweights, linkage.gravity, linkage.loads, linkage.torques,
    )
    rotor_moment, rotor_torque = counter_rotor_loads(before, counter_rotors)
    after, f, f_rel, m, m_rel = _check(balanced, speed, samples, cws, before, rotor_moment)
    torque_after = after.kinetostatics.driving_torque + rotor_torque
    added_inertia = sum(c.params()[3] for c in cws) + sum(r.inertia for r in counter_rotors)
    summary_after = replace(
        after.summary(),
        rms_driving_torque=float(np.sqrt(np.mean(torque_after**2))),
        max_driving_torque=float(np.abs(torque_after).max()),
        rms_shaking_moment=float(np.sqrt(np.mean((after.kinetostatics.shaking_moment + rotor_moment) ** 2))),
        max_shaking_moment=m,
    )
    return BalanceResult("full", tuple(cws), sum(c.mass for c in cws), before.summary(), summary_after,
                         f, f_rel, m, m_rel, before, after, added_inertia=added_inertia,
                         coupler_inertia=j2, counter_rotors=counter_rotors,
                         objective=float(program.q @ x), driving_torque_after=torque_after)


def counter_rotor_loads(an: Analysis, rotors: Sequence[CounterRotor]) -> tuple[FloatArray, FloatArray]:
    """Shaking moment on the frame [N·m] and extra driving torque [N·m] of geared counter-rotors, (N,) each.

    A rotor turning at -k·w_i has angular momentum -k·J·w_i: the frame feels -d/dt of it, k·J·alpha_i, and the
    crank supplies the rate of its kinetic energy k²·J·w_i·alpha_i over the crank speed.
    """
    return rotor_loads(an.motion, rotors)


@dataclass(frozen=True, slots=True)
class Weights:
    """Weights of the optimal-balancing objective: RMS and peak terms (dimensionless by default, see
    :func:`relative_weights`; else [1/N or 1/(N·m)]) and added mass [1/kg]."""

    shaking_force: float = 1.0
    shaking_moment: float = 0.0
    driving_torque: float = 0.0
    bearing_forces: float = 0.0
    peak_shaking_force: float = 0.0
    peak_shaking_moment: float = 0.0
    added_mass: float = 1e-6

    def validate(self) -> None:
        """InvalidInput for negative or non-finite weights, or all of them zero."""
        values = [getattr(self, f) for f in self.__dataclass_fields__]
        if any(not math.isfinite(v) or v < 0 for v in values):
            raise InvalidInput("weights must be finite and not negative", field="weights")
        if not any(values[:6]):
            raise InvalidInput("at least one of the shaking/torque/bearing weights must be positive", field="weights")


_RMS_TERMS = ("shaking_force", "shaking_moment", "driving_torque", "bearing_forces")
_PEAK_TERMS = ("peak_shaking_force", "peak_shaking_moment")


def _compressed_cone(y: FloatArray, c: FloatArray) -> tuple[FloatArray, FloatArray]:
    """||y @ x + c|| for a tall y (thousands of rows, a few columns) as a cone of a few rows, exactly.

    With [y c] = Q [[R, t], [0, rho]]: ||y x + c||² = ||R x + t||² + rho², so the solver sees columns, not
    angles; one triangular factorisation of the augmented matrix, Q never formed. Returns (G, g) with the
    cone's vector G x + g.
    """
    k = y.shape[1]
    r: FloatArray = np.asarray(np.linalg.qr(np.column_stack([y, c]), mode="r"), dtype=float)
    rest = abs(float(r[k, k])) if r.shape[0] > k else 0.0
    return np.vstack([r[:k, :k], np.zeros((1, k))]), np.concatenate([r[:k, k], [rest]])


@dataclass(frozen=True, slots=True)
class _OptimalProgram:
    """The optimal-balancing SOCP for one set of weighted terms; only the costs depend on the weights.

    Variables: the counterweights, then one bound per weighted term (in ``terms`` order).
    """

    program: ConeProgram
    layout: CounterweightLayout
    terms: tuple[str, ...]
    scale: tuple[float, ...]  # cost of each term's bound per unit weight
    added: FloatArray  # what the added-mass weight multiplies, per counterweight variable (see _added_cost)

    def costs(self, weights: Weights) -> FloatArray:
        """Objective vector for ``weights``: the terms, plus a small weight on added mass and inertia."""
        q = np.zeros(self.program.size)
        n = self.layout.size
        # The added inertia gets a small weight too: where it does not matter (a crank at constant speed) it is
        # pinned.
        q[:n] = weights.added_mass * self.added
        q[n:] = [getattr(weights, key) * s for key, s in zip(self.terms, self.scale, strict=True)]
        return q


def _optimal_program(lm: LinearMap, linkage: Linkage, cw: CounterweightLayout, terms: tuple[str, ...],
                     mass_budget: float) -> _OptimalProgram:
    """Build the SOCP: RMS terms as compressed cones, a peak force as one small cone per angle, a peak moment as
    two inequalities per angle, and the mass budget."""
    n = lm.y.shape[0]
    p0 = linkage.params()
    cols = _var_columns(lm, cw)
    program = _program(cw, extra=len(terms))
    bearings = _bearing_rows(lm, linkage)
    rms_rows = {
        "shaking_force": ([lm.force_rows.start, lm.force_rows.start + 1], n),
        "shaking_moment": ([lm.moment_row], n),
        "driving_torque": ([lm.torque_row], n),
        "bearing_forces": (bearings, n * len(lm.joints)),
    }
    scale = []
    for k, key in enumerate(terms):
        bound = np.zeros(program.size)
        bound[cw.size + k] = 1.0
        if key in rms_rows:
            rows, count = rms_rows[key]
            y, y0 = _rows(lm, rows)
            g, offset = _compressed_cone(y[:, cols], y @ p0 + y0)
            program.cone(np.vstack([bound, np.pad(g, ((0, 0), (0, program.size - cw.size)))]),
                         np.concatenate([[0.0], offset]))
            scale.append(1 / math.sqrt(count))
        elif key == "peak_shaking_force":
            y, y0 = _rows(lm, [lm.force_rows.start, lm.force_rows.start + 1])
            g = np.zeros((n, 3, program.size))
            g[:, 0, :] = bound
            g[:, 1:, : cw.size] = y[:, cols].reshape(n, 2, -1)
            offset = np.concatenate([np.zeros((n, 1)), (y @ p0 + y0).reshape(n, 2)], axis=1)
            program.cone(g.reshape(3 * n, -1), offset.reshape(-1), dim=3)
            scale.append(1.0)
        else:
            y, y0 = _rows(lm, [lm.moment_row])
            g = np.pad(y[:, cols], ((0, 0), (0, program.size - cw.size)))
            c = y @ p0 + y0
            program.at_most(np.vstack([g - bound, -g - bound]), np.concatenate([-c, c]))
            scale.append(1.0)
    program.at_most(cw.mass_columns()[None, :], np.array([mass_budget]))
    return _OptimalProgram(program, cw, terms, tuple(scale), _added_cost(cw, linkage))


def _added_cost(cw: CounterweightLayout, linkage: Linkage) -> FloatArray:
    """Per counterweight variable, what the added-mass weight multiplies: each mass [1/kg], and each inertia about
    its joint over its link's length squared [1/(kg·m²)].

    A counterweight's inertia then costs as its mass would at the link's length, so at a given first moment h the
    cost m + J/l² >= |h|/r + |h|·r/l² is least with all of the mass at r = l: the lightest counterweight that
    does the same job, on its radius limit by default. One length for every link would pull a long lever's
    counterweight in toward that length, heavier for the same h.
    """
    lengths = link_lengths(linkage.mechanism)
    per_link: FloatArray = np.repeat([1.0 / lengths[link] ** 2 for link in cw.links], PARAMS)
    return cw.mass_columns() + cw.inertia_columns() * per_link


def _bearing_rows(lm: LinearMap, linkage: Linkage) -> list[int]:
    """Rows of the map that are bearing forces: both components of a revolute joint's reaction, the normal force
    of a sliding pair (its couple is a moment, not a force, and :func:`_term_values` leaves it out too)."""
    kinds = {j.name: j.kind for j in linkage.mechanism.topology.joints}
    rows: list[int] = []
    for joint in lm.joints:
        r = lm.reaction_rows(joint)
        rows += list(range(r.start, r.stop if kinds[joint] == "revolute" else r.start + 1))
    return rows


def _term_values(an: Analysis) -> dict[str, float]:
    """Every weighted term of the objective on a plain analysis [N or N·m]."""
    k = an.kinetostatics
    n = an.motion.samples
    f = magnitude(k.shaking_force)
    bearing = np.concatenate([k.reactions[j].reshape(-1) for j in k.reactions])
    terms = {
        "shaking_force": float(np.sqrt(np.mean(f**2))),
        "shaking_moment": float(np.sqrt(np.mean(k.shaking_moment**2))),
        "driving_torque": float(np.sqrt(np.mean(k.driving_torque**2))),
        "bearing_forces": float(np.linalg.norm(bearing) / math.sqrt(n * len(k.reactions))),
        "peak_shaking_force": float(f.max()),
        "peak_shaking_moment": float(np.abs(k.shaking_moment).max()),
    }
    return terms


def relative_weights(an: Analysis, weights: Weights) -> Weights:
    """Dimensionless weights turned into the program's: each term's weight over its value before balancing.

    A weight of 1 on the shaking force then means "one unit per 100 % of the unbalanced RMS force", so terms in
    N and N·m are traded in proportion to what they were; a term that is zero before keeps its weight. The
    added-mass weight stays per kilogram.
    """
    values = _term_values(an)
    scaled = {key: getattr(weights, key) / v if v > 0 else getattr(weights, key) for key, v in values.items()}
    return replace(weights, **scaled)


def objective_value(an: Analysis, weights: Weights, counterweights: Sequence[Counterweight]) -> float:
    """The optimal-balancing objective evaluated on a plain analysis of the linkage with ``counterweights``."""
    terms = _term_values(an)
    lengths = link_lengths(an.linkage.mechanism)
    added = sum(c.mass + c.params()[3] / lengths[c.link] ** 2 for c in counterweights)
    return float(sum(getattr(weights, key) * v for key, v in terms.items()) + weights.added_mass * added)


def balance_optimal(
    linkage: Linkage,
    speed: float,
    spec: CounterweightSpec | None = None,
    *,
    weights: Weights | None = None,
    mass_budget: float | None = None,
    samples: int = 360,
    time_limit_s: float = 20.0,
    motion_map: tuple[Analysis, LinearMap] | None = None,
    weight_scale: Literal["relative", "absolute"] = "relative",
) -> BalanceResult:
    """Counterweights minimising a weighted sum of RMS (and peak) shaking force, shaking moment, driving torque
    and bearing forces, plus a small weight on added mass, within ``mass_budget`` [kg]: one SOCP.

    Any family: counterweights go on links that turn about a pivot (``spec.links``; by default a four-bar's or a
    shaper's crank and rocker, a slider-crank's crank; its rod when named), never on a slider, ram or block.
    The default budget is the linkage's own moving mass. ``weight_scale`` ``relative`` (default) makes the
    weights dimensionless: each term is divided by its value before balancing (:func:`relative_weights`);
    ``absolute`` takes them per N and per N·m. The answer echoes the weights as given.
    """
    return _optimal_points(linkage, speed, spec, [weights or Weights()], mass_budget, samples, time_limit_s,
                           motion_map, weight_scale)[0]


def _optimal_points(linkage: Linkage, speed: float, spec: CounterweightSpec | None, weight_sets: Sequence[Weights],
                    mass_budget: float | None, samples: int, time_limit_s: float,
                    motion_map: tuple[Analysis, LinearMap] | None,
                    weight_scale: Literal["relative", "absolute"]) -> list[BalanceResult]:
    """Optimal balancing for each weight set: one program and one solver per set of weighted terms, re-solved
    with new costs for each set, and every point re-analysed with the plain model."""
    if weight_scale not in ("relative", "absolute"):
        raise InvalidInput("weight_scale must be relative or absolute", field="weight_scale")
    spec = _with_default_radii((spec or CounterweightSpec()).resolve(linkage), linkage)
    for weights in weight_sets:
        weights.validate()
    if mass_budget is None:
        mass_budget = float(sum(linkage.params_of(link)[0] for link in linkage.mechanism.topology.links))
    if not (math.isfinite(mass_budget) and mass_budget >= 0):
        raise InvalidInput("mass_budget_kg must be a non-negative number", field="mass_budget_kg")
    before, lm = motion_map or _motion_map(linkage, speed, samples)
    given = list(weight_sets)
    if weight_scale == "relative":
        weight_sets = [relative_weights(before, w) for w in weight_sets]
    cw = counterweight_layout(spec, linkage)
    solutions: dict[int, FloatArray] = {}
    groups: dict[tuple[str, ...], list[int]] = {}
    for i, weights in enumerate(weight_sets):
        terms = tuple(key for key in _RMS_TERMS + _PEAK_TERMS if getattr(weights, key) > 0)
        groups.setdefault(terms, []).append(i)
    for terms, members in groups.items():
        built = _optimal_program(lm, linkage, cw, terms, mass_budget)
        built.program.q = built.costs(weight_sets[members[0]])
        solver = built.program.solver(time_limit_s)
        for i in members:
            if i != members[0]:
                solver.update(q=built.costs(weight_sets[i]))
            solutions[i] = solve(solver, time_limit_s, "optimal balancing", ["mass_budget_kg"])
    results = []
    for i, weights in enumerate(weight_sets):
        cws = CounterweightSolution(cw, solutions[i]).counterweights()
        if weights.bearing_forces == 0 or linkage.gravity is None:  # else the mass weighs on the crank's bearing
            cws = _crank_on_limit(cws, spec, linkage)
        after, f, f_rel, m, m_rel = _check(linkage, speed, samples, cws, before)
        results.append(BalanceResult("optimal", tuple(cws), sum(c.mass for c in cws), before.summary(),
                                     after.summary(), f, f_rel, m, m_rel, before, after,
                                     added_inertia=sum(c.params()[3] for c in cws),
                                     objective=objective_value(after, weights, cws), weights=given[i],
                                     weight_scale=weight_scale))
    return results


def _crank_on_limit(cws: Sequence[Counterweight], spec: CounterweightSpec, linkage: Linkage) -> list[Counterweight]:
    """The crank's counterweight as a point mass on its radius limit when that limit is at most the crank length.

    At constant crank speed, with bearing forces unweighted or no gravity, nothing but the added-mass term depends
    on the crank counterweight's mass or inertia once its first moment h is fixed, and that term, m + J/l1² with J >= |h|²/m, falls as the radius grows up to
    l1: its minimum is on the limit. The term is so flat there that the solver stops short of it by up to a few
    tenths of a per cent; this is its exact minimiser for the same h (same forces, moments and torques).
    """
    crank = linkage.mechanism.topology.crank  # a general linkage names its crank as it likes
    if crank not in spec.links:
        return list(cws)
    r_max = spec.limit(linkage, crank)
    if r_max > linkage.mechanism.crank or (spec.radius and crank in spec.radius):
        return list(cws)
    out = []
    for c in cws:
        h = c.params()[1:3]
        if c.link == crank and np.hypot(*h) > 0:
            mass = float(np.hypot(*h)) / r_max
            c = replace(c, mass=mass, position=(float(h[0]) / mass, float(h[1]) / mass), inertia=0.0)
        out.append(c)
    return out


def _motion_map(linkage: Linkage, speed: float, samples: int) -> tuple[Analysis, LinearMap]:
    before = analyse(linkage, speed, samples=samples)
    return before, linear_map(before.motion, linkage)


def tradeoff(
    linkage: Linkage,
    speed: float,
    spec: CounterweightSpec | None,
    weight_sets: Sequence[Weights],
    *,
    mass_budget: float | None = None,
    samples: int = 360,
    time_limit_s: float = 20.0,
    weight_scale: Literal["relative", "absolute"] = "relative",
) -> list[BalanceResult]:
    """Optimal balancing for each weight set (one motion, map and program shared), each point re-analysed."""
    return _optimal_points(linkage, speed, spec, weight_sets, mass_budget, samples, time_limit_s, None, weight_scale)


def least_squares_crank_counterweight(linkage: Linkage, speed: float, samples: int = 360) -> tuple[float, float]:
    """First moment (m·x, m·y) [kg·m] of the crank counterweight minimising the RMS shaking force, closed form.

    The crank turns about a fixed pivot, so its counterweight's first moment enters the shaking force linearly:
    an ordinary least-squares problem over all angles (numpy.linalg.lstsq).
    """
    before, lm = _motion_map(linkage, speed, samples)
    a, b0 = _rows(lm, [lm.force_rows.start, lm.force_rows.start + 1])
    cols = lm.columns("crank")
    rhs = -(a @ linkage.params() + b0)
    h, *_ = np.linalg.lstsq(a[:, [cols.start + 1, cols.start + 2]], rhs, rcond=None)
    return float(h[0]), float(h[1])

