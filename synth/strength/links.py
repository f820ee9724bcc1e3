"""Links as beams: the cycle's axial force, shear and bending moment along each link, its checks and its least
section.

A link is a straight bar along its x-axis from its rearmost to its foremost load point (joints, a slide's moving
contact, counterweights), loaded at every crank angle by its joint reactions, the driving torque (crank), the
external torques and the process force (working member), and its own weight and d'Alembert inertia spread along
it. The spread load is the link's mass laid out linearly along the bar so that its mass and first moment are
the analysis' ones, plus a uniform force and couple per length that close the rest of its inertial load (an
off-axis centre of mass, the inertia beyond a slender bar's): every link is then in equilibrium exactly as the
kinetostatics has it, and the internal forces at the far end vanish to round-off (``closure``). A point off the
bar's axis hangs on it by a rigid bracket (its force's moment about the axis enters the bar); a ternary link of
far off-axis joints is taken the same way and says so.

Checks at every crank angle and section (all angles at once, every candidate section at once):

- static: the von Mises stress at the outer fibres (axial plus bending) and at the neutral axis (axial with the
  largest shear) against the yield strength;
- fatigue: the stress history over the cycle at each fibre and at the neutral axis, its alternating and mean
  parts against the modified Goodman line with Marin's endurance limit (:mod:`.fatigue`);
- buckling: the largest compression the link ever carries against Euler/Johnson's critical load
  (:mod:`.columns`), in the plane (the revolute joints let the ends turn: pinned-pinned) and out of it (the pins
  hold the ends square to the plane: fixed-fixed by default).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..analysis import Analysis
from ..errors import Infeasible, InvalidInput
from ..kinematics.motion import Motion
from ..kinetostatics import external_loads
from ..model import FloatArray, MassProps
from .columns import END_FACTORS, critical_load
from .fatigue import AXIAL_LOAD_FACTOR, endurance_limit, goodman_safety
from .materials import Material
from .sections import Section, SectionFamily

#: Sections evaluated along a link besides those either side of its load points.
SECTIONS_ALONG = 21
#: A load point farther off the bar's axis than this fraction of its length makes the link a plate taken as a bar
#: with brackets (a named warning).
OFF_AXIS_FRACTION = 0.05


@dataclass(frozen=True, slots=True)
class StrengthLimits:
    """The required factors of safety and the fatigue conditions shared by every link.

    ``static_safety`` against yield, ``fatigue_safety`` on the Goodman line, ``buckling_safety`` on the critical
    load; ``surface`` finish and ``reliability`` for Marin's ka and ke; ``notch_factor`` Kf on every fatigue
    stress; ``in_plane_ends`` and ``out_of_plane_ends`` name the column's end conditions (:data:`END_FACTORS`).
    """

    static_safety: float = 1.5
    fatigue_safety: float = 1.5
    buckling_safety: float = 2.5
    surface: str = "machined"
    reliability: float = 0.9
    notch_factor: float = 1.0
    in_plane_ends: str = "pinned-pinned"
    out_of_plane_ends: str = "fixed-fixed"

    def validate(self) -> StrengthLimits:
        """Raise InvalidInput naming the field of a factor below 1 or an unknown end condition."""
        for name in ("static_safety", "fatigue_safety", "buckling_safety", "notch_factor"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 1.0):
                raise InvalidInput(f"limits.{name} must be at least 1, got {value!r}", field=f"limits.{name}")
        for name in ("in_plane_ends", "out_of_plane_ends"):
            if getattr(self, name) not in END_FACTORS:
                raise InvalidInput(f"limits.{name} must be one of {list(END_FACTORS)}", field=f"limits.{name}")
        return self


@dataclass(frozen=True, slots=True)
class LinkSpec:
    """How one link is made: its material, and either a section family to size or a given ``section``."""

    material: Material
    family: SectionFamily = field(default_factory=SectionFamily)
    section: Section | None = None


@dataclass(frozen=True, slots=True)
class BeamForces:
    """Internal forces of one link at every crank angle (axis 0) and section (axis 1).

    ``x`` the sections in the link frame [m] (S,); ``axial`` tension positive [N], ``shear`` [N] and ``moment``
    [N·m] (N, S); ``start``, ``end`` the bar's ends [m]; ``points`` each load point's place along it [m] (its
    mean for a moving contact); ``closure`` the largest force [N] and moment [N·m] left over at the far end (zero
    for a link in equilibrium); ``off_axis`` the largest distance of a load point from the axis [m].
    """

    link: str
    phi: FloatArray
    x: FloatArray
    axial: FloatArray
    shear: FloatArray
    moment: FloatArray
    start: float
    end: float
    points: dict[str, float]
    closure: tuple[float, float]
    off_axis: float

    @property
    def length(self) -> float:
        """The bar's length [m]."""
        return self.end - self.start


@dataclass(frozen=True, slots=True)
class LinkCheck:
    """One check of a link: its factor of safety against the required one, where and when it is least.

    ``name`` is ``static``, ``fatigue``, ``buckling_in_plane`` or ``buckling_out_of_plane``; ``x`` the section
    [m] in the link frame and ``phi`` the crank angle [rad] where the factor is least; ``method`` names the model.
    """

    link: str
    name: str
    safety: float
    required: float
    x: float
    phi: float
    method: str

    @property
    def passed(self) -> bool:
        """The factor of safety meets the required one."""
        return self.safety >= self.required


@dataclass(frozen=True, slots=True)
class LinkSizing:
    """A link's section, its mass properties as built (a uniform bar) and its checks."""

    link: str
    section: Section
    material: Material
    mass_props: MassProps
    checks: tuple[LinkCheck, ...]
    sized: bool
    forces: BeamForces

    @property
    def mass(self) -> float:
        """Mass of the bar [kg]."""
        return self.mass_props.mass

    @property
    def passed(self) -> bool:
        """Every check met."""
        return all(c.passed for c in self.checks)


def beam_links(analysis: Analysis) -> tuple[str, ...]:
    """The links that are bars: two or more load points apart (a slider block is not one)."""
    return tuple(link for link in analysis.linkage.mechanism.topology.links if _span(analysis, link) is not None)


def _local(motion: Motion, link: str, vec: FloatArray) -> FloatArray:
    """Plane vectors (N, 2) in the frame's axes turned into the link's axes."""
    c, s = np.cos(motion.link_angle[link]), np.sin(motion.link_angle[link])
    return np.stack([c * vec[:, 0] + s * vec[:, 1], -s * vec[:, 0] + c * vec[:, 1]], axis=1)


@dataclass(frozen=True, slots=True)
class _PointLoad:
    name: str
    pos: FloatArray     # (N, 2) in the link frame [m]
    force: FloatArray   # (N, 2) in the link's axes [N]
    couple: FloatArray  # (N,) [N·m]


def _point_loads(analysis: Analysis, link: str) -> list[_PointLoad]:
    """Every concentrated load on ``link``: joint reactions, torques, the process force, counterweights."""
    motion, linkage = analysis.motion, analysis.linkage
    topo = linkage.mechanism.topology
    k = analysis.kinetostatics
    origin = motion.point_pos[motion.link_origin[link]]
    n = motion.samples
    zero = np.zeros(n)
    out: list[_PointLoad] = []

    def place(p: FloatArray) -> FloatArray:
        return _local(motion, link, p - origin)

    for joint in topo.joints:
        if link not in joint.bodies:
            continue
        sign = 1.0 if joint.bodies[1] == link else -1.0
        force = sign * k.reactions[joint.name]
        couple = sign * k.couples[joint.name] if joint.name in k.couples else zero
        out.append(_PointLoad(joint.name, place(motion.point_pos[joint.point]), _local(motion, link, force), couple))
    torque = k.driving_torque if link == topo.crank else zero
    loads = external_loads(motion, linkage)
    torque = torque + loads.torques.get(link, zero)
    if link == topo.output and loads.has_force:
        out.append(_PointLoad("process_force", place(loads.point), _local(motion, link, loads.force), zero))
    if np.any(torque != 0.0):
        out.append(_PointLoad("torque", np.zeros((n, 2)), np.zeros((n, 2)), np.asarray(torque, dtype=float)))
    g = linkage.gravity.vector if linkage.gravity is not None else np.zeros(2)
    for i, cw in enumerate(linkage.counterweights):
        if cw.link != link:
            continue
        state = motion.point_on(link, cw.position)
        force = cw.mass * (g - state.acc)
        out.append(_PointLoad(f"counterweight[{i}]", np.broadcast_to(np.asarray(cw.position, float), (n, 2)),
                              _local(motion, link, force), -cw.inertia * motion.link_alpha[link]))
    return out


def _span(analysis: Analysis, link: str) -> tuple[float, float] | None:
    """The bar's ends along the link's x-axis [m], or None for a link with one load point (a block)."""
    motion = analysis.motion
    topo = analysis.linkage.mechanism.topology
    origin = motion.point_pos[motion.link_origin[link]]
    xs = [_local(motion, link, motion.point_pos[j.point] - origin)[:, 0]
          for j in topo.joints if link in j.bodies]
    if not xs:
        return None
    stacked = np.concatenate(xs)
    lo, hi = float(stacked.min()), float(stacked.max())
    scale = max(abs(lo), abs(hi), analysis.linkage.mechanism.crank)
    if hi - lo <= 1e-9 * scale:
        return None
    return lo, hi


def beam_forces(analysis: Analysis, link: str, sections: int = SECTIONS_ALONG) -> BeamForces:
    """Axial force, shear and bending moment along ``link`` at every crank angle of ``analysis``."""
    span = _span(analysis, link)
    if span is None:
        raise InvalidInput(f"link {link!r} has a single load point (a block): it is not a bar", field=f"links.{link}")
    motion, linkage = analysis.motion, analysis.linkage
    points = _point_loads(analysis, link)
    x0, x1 = span
    for p in points:   # counterweights may hang beyond the joints
        x0, x1 = min(x0, float(p.pos[:, 0].min())), max(x1, float(p.pos[:, 0].max()))
    length = x1 - x0
    eps = 1e-9 * length
    stations = set(np.linspace(x0, x1, sections).tolist())
    for p in points:
        xm = float(p.pos[:, 0].mean())
        if x0 + eps < xm < x1 - eps:
            stations.update((xm - eps, xm + eps))
    stations.discard(x0)
    stations.add(x0 + eps)
    stations.discard(x1)
    stations.add(x1 - eps)
    xs = np.array(sorted(stations))
    n = motion.samples

    # spread weight and inertia: polynomial coefficients of the load per length along x (N, 3) and a couple (N,)
    a_coef, b_coef, couple = _spread_load(analysis, link, x0, x1)

    # loads on the part of the bar left of each section (x < section), reduced to the section's point
    rx = np.zeros((n, xs.size))
    ry = np.zeros((n, xs.size))
    mr = np.zeros((n, xs.size))
    for p in points:
        left = p.pos[:, 0, None] < xs[None, :]
        fx, fy = p.force[:, 0, None], p.force[:, 1, None]
        rx += np.where(left, fx, 0.0)
        ry += np.where(left, fy, 0.0)
        mr += np.where(left, (p.pos[:, 0, None] - xs[None, :]) * fy - p.pos[:, 1, None] * fx + p.couple[:, None], 0.0)
    powers_i = np.stack([(xs ** (j + 1) - x0 ** (j + 1)) / (j + 1) for j in range(3)])   # (3, S)
    powers_k = np.stack([(xs ** (j + 2) - x0 ** (j + 2)) / (j + 2) for j in range(3)])
    rx += a_coef @ powers_i
    ry += b_coef @ powers_i
    mr += b_coef @ (powers_k - xs[None, :] * powers_i) + couple[:, None] * (xs - x0)[None, :]
    closure = _closure(points, a_coef, b_coef, couple, x0, x1)
    off_axis = max(float(np.abs(p.pos[:, 1]).max()) for p in points)
    names = {p.name: float(p.pos[:, 0].mean()) for p in points if p.name != "torque"}
    return BeamForces(link, motion.phi, xs, -rx, -ry, -mr, x0, x1, names, closure, off_axis)


def _spread_load(analysis: Analysis, link: str, x0: float, x1: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The link's own weight and inertia as load per length q(x) = sum_j c_j x^j along [x0, x1] (coefficients
    (N, 3) along and across the axis) and a couple per length (N,), equal in resultant and moment to the
    analysis' m (g - a_S) and -J_S alpha."""
    motion, linkage = analysis.motion, analysis.linkage
    n = motion.samples
    props = linkage.links.get(link, MassProps())
    m = props.mass
    if m == 0.0 and props.inertia == 0.0:
        return np.zeros((n, 3)), np.zeros((n, 3)), np.zeros(n)
    length = x1 - x0
    xm = 0.5 * (x0 + x1)
    xc, yc = props.com
    # mass per length mu(x) = m0 + m1 x with the link's mass and first moment along x
    mu1 = 12.0 * m * (xc - xm) / length**3
    m0, m1 = m / length - mu1 * xm, mu1
    g = linkage.gravity.vector if linkage.gravity is not None else np.zeros(2)
    origin = motion.link_origin[link]
    gl = _local(motion, link, np.broadcast_to(g, (n, 2)).copy())
    a0 = _local(motion, link, np.asarray(motion.point_acc[origin]))
    w2, alpha = motion.link_omega[link] ** 2, motion.link_alpha[link]
    cx, cy = gl[:, 0] - a0[:, 0], gl[:, 1] - a0[:, 1]
    # a point at (x, 0) accelerates with a0 + (-w² x, alpha x) in the link's axes
    a_coef = np.stack([m0 * cx, m0 * w2 + m1 * cx, m1 * w2], axis=1)
    b_coef = np.stack([m0 * cy, -m0 * alpha + m1 * cy, -m1 * alpha], axis=1)
    ints = np.array([(x1 ** (j + 1) - x0 ** (j + 1)) / (j + 1) for j in range(3)])
    ints_x = np.array([(x1 ** (j + 2) - x0 ** (j + 2)) / (j + 2) for j in range(3)])
    # the analysis' load on the link's own mass, in its axes
    acc_s = np.stack([a0[:, 0] - w2 * xc - alpha * yc, a0[:, 1] + alpha * xc - w2 * yc], axis=1)
    f_tot = m * (gl - acc_s)
    m_tot = xc * f_tot[:, 1] - yc * f_tot[:, 0] - props.inertia * alpha
    df = (f_tot - np.stack([a_coef @ ints, b_coef @ ints], axis=1)) / length
    a_coef[:, 0] += df[:, 0]
    b_coef[:, 0] += df[:, 1]
    m_spread = b_coef @ ints_x
    couple = (m_tot - m_spread) / length
    return a_coef, b_coef, couple


def _closure(points: list[_PointLoad], a_coef: FloatArray, b_coef: FloatArray, couple: FloatArray,
             x0: float, x1: float) -> tuple[float, float]:
    """Resultant force [N] and moment about the origin [N·m] of every load on the link: zero in equilibrium."""
    ints = np.array([(x1 ** (j + 1) - x0 ** (j + 1)) / (j + 1) for j in range(3)])
    ints_x = np.array([(x1 ** (j + 2) - x0 ** (j + 2)) / (j + 2) for j in range(3)])
    fx = a_coef @ ints
    fy = b_coef @ ints
    mz = b_coef @ ints_x + couple * (x1 - x0)
    for p in points:
        fx = fx + p.force[:, 0]
        fy = fy + p.force[:, 1]
        mz = mz + p.pos[:, 0] * p.force[:, 1] - p.pos[:, 1] * p.force[:, 0] + p.couple
    return float(np.max(np.hypot(fx, fy))), float(np.max(np.abs(mz)))


@dataclass(frozen=True, slots=True)
class _Candidates:
    """Section properties of C candidate sections, each (C,)."""

    area: FloatArray
    modulus: FloatArray
    shear: FloatArray
    gyration_in: FloatArray
    gyration_out: FloatArray
    endurance: FloatArray

    @staticmethod
    def of(sections: tuple[Section, ...], material: Material, limits: StrengthLimits) -> _Candidates:
        return _Candidates(
            np.array([s.area for s in sections]),
            np.array([s.modulus for s in sections]),
            np.array([s.shear_factor for s in sections]),
            np.array([math.sqrt(s.second_moment / s.area) for s in sections]),
            np.array([math.sqrt(s.second_moment_out / s.area) for s in sections]),
            np.array([endurance_limit(material.fatigue_limit, material.ultimate_strength, limits.surface,
                                      s.equivalent_diameter, limits.reliability) for s in sections]))


_METHODS = {
    "static": "von Mises at the outer fibres and the neutral axis against the yield strength",
    "fatigue": "modified Goodman, Marin factors ka kb ke, Kf on the stresses, axial share over kc = 0.85 "
               "(Shigley ch. 6)",
    "buckling_in_plane": "Euler/Johnson column (Shigley §4-12, 4-13), ends {ends}",
    "buckling_out_of_plane": "Euler/Johnson column (Shigley §4-12, 4-13), ends {ends}",
}
CHECKS = tuple(_METHODS)


def _safeties(forces: BeamForces, cand: _Candidates, material: Material, limits: StrengthLimits
              ) -> dict[str, tuple[FloatArray, FloatArray, FloatArray]]:
    """Per check: the least factor of safety of each candidate (C,), and the crank-angle and section indices
    where it is least (C,)."""
    a = cand.area[:, None, None]
    z = cand.modulus[:, None, None]
    # sections on axis 1 and crank angles last: every reduction over the cycle runs along contiguous memory
    nx = np.ascontiguousarray(forces.axial.T)[None]
    vy = np.ascontiguousarray(forces.shear.T)[None]
    mz = np.ascontiguousarray(forces.moment.T)[None]
    s_axial = nx / a
    s_bend = mz / z
    tau = cand.shear[:, None, None] * vy / a
    # static: the outer fibres (axial + bending) and the neutral axis (axial and the largest shear)
    abs_fibre = np.abs(s_axial) + np.abs(s_bend)
    vm = np.maximum(abs_fibre, np.sqrt(s_axial * s_axial + 3 * tau * tau))
    c_count, s, n = vm.shape
    flat = vm.reshape(c_count, -1)
    where = np.argmax(flat, axis=1)
    peak = flat[np.arange(c_count), where]
    with np.errstate(divide="ignore"):
        static = np.where(peak > 0, material.yield_strength / np.where(peak > 0, peak, 1.0), math.inf)
    out = {"static": (static, where % n, where // n)}

    # fatigue: each fibre's history and the neutral axis', alternating and mean over the crank angles (last axis)
    kf = limits.notch_factor
    alt_axial = s_axial / AXIAL_LOAD_FACTOR
    fatigue = []
    for sign in (1.0, -1.0):
        alt = kf * (alt_axial + sign * s_bend)
        mean = kf * (s_axial + sign * s_bend)
        sa = 0.5 * (alt.max(axis=-1) - alt.min(axis=-1))
        sm = 0.5 * (mean.max(axis=-1) + mean.min(axis=-1))
        fatigue.append(_goodman(sa, sm, cand.endurance, material))
    sa_n = 0.5 * (alt_axial.max(axis=-1) - alt_axial.min(axis=-1)) * kf
    sm_n = 0.5 * (s_axial.max(axis=-1) + s_axial.min(axis=-1)) * kf
    ta = 0.5 * (tau.max(axis=-1) - tau.min(axis=-1)) * kf
    tm = 0.5 * (tau.max(axis=-1) + tau.min(axis=-1)) * kf
    fatigue.append(_goodman(np.sqrt(sa_n**2 + 3 * ta**2), np.sign(sm_n) * np.sqrt(sm_n**2 + 3 * tm**2),
                            cand.endurance, material))
    per_section = np.minimum(np.minimum(fatigue[0], fatigue[1]), fatigue[2])     # (C, S)
    sec = np.argmin(per_section, axis=1)
    least = per_section[np.arange(c_count), sec]
    # the angle where the governing section's stress peaks
    ang = np.argmax(abs_fibre[np.arange(c_count), sec, :], axis=1)
    out["fatigue"] = (least, ang, sec)

    # buckling: the largest compression anywhere along the link at any angle
    flat_c = -nx[0].reshape(-1)
    i_c = int(np.argmax(flat_c))
    p_max = float(flat_c[i_c])
    length = forces.length
    for name, gyration, ends in (("buckling_in_plane", cand.gyration_in, limits.in_plane_ends),
                                 ("buckling_out_of_plane", cand.gyration_out, limits.out_of_plane_ends)):
        if p_max <= 0.0:
            safety = np.full(c_count, math.inf)
        else:
            p_cr = critical_load(cand.area, gyration, END_FACTORS[ends] * length, material.elastic_modulus,
                                 material.yield_strength)
            safety = p_cr / p_max
        out[name] = (safety, np.full(c_count, i_c % n), np.full(c_count, i_c // n))
    return out


def _goodman(sa: FloatArray, sm: FloatArray, endurance: FloatArray, material: Material) -> FloatArray:
    """:func:`.fatigue.goodman_safety` of candidates (C, S) with their own endurance limits (C,)."""
    return goodman_safety(sa / endurance[:, None], sm / material.ultimate_strength, 1.0, 1.0)


def _required(limits: StrengthLimits) -> dict[str, float]:
    return {"static": limits.static_safety, "fatigue": limits.fatigue_safety,
            "buckling_in_plane": limits.buckling_safety, "buckling_out_of_plane": limits.buckling_safety}


def bar_mass_props(section: Section, material: Material, start: float, end: float) -> MassProps:
    """A uniform bar of ``section`` from ``start`` to ``end`` along the link's x-axis [m]: mass [kg], centre
    [m] and inertia about it [kg·m²], m (L² + h²) / 12 (a slender plate's, h the section's height in the plane)."""
    length = end - start
    m = material.density * section.area * length
    return MassProps(m, (0.5 * (start + end), 0.0), m * (length**2 + section.height**2) / 12.0)


def size_link(forces: BeamForces, spec: LinkSpec, limits: StrengthLimits) -> LinkSizing:
    """The least-mass section of ``spec``'s family meeting every check (or ``spec.section`` checked as given).

    Raises Infeasible naming the link, the check and the crank angle when the family's largest section fails.
    """
    sections = (spec.section,) if spec.section is not None else spec.family.candidates()
    required = _required(limits)
    # Candidates lightest first, in blocks that double in size: the least passing section is found at no more
    # than twice the cost of checking the sections up to it.
    start, block = 0, 2
    while True:
        stop = min(len(sections), start + block)
        chunk = sections[start:stop]
        safeties = _safeties(forces, _Candidates.of(chunk, spec.material, limits), spec.material, limits)
        ok = np.ones(len(chunk), dtype=bool)
        for name, (safety, _, _) in safeties.items():
            ok &= safety >= required[name]
        if spec.section is not None or ok.any() or stop == len(sections):
            break
        start, block = stop, 2 * block
    if spec.section is not None:
        chosen = 0
    elif ok.any():
        chosen = int(np.argmax(ok))
    else:
        last = len(chunk) - 1
        worst = min(CHECKS, key=lambda c: safeties[c][0][last] / required[c])
        safety, ang, sec = safeties[worst]
        phi_deg = math.degrees(float(forces.phi[ang[last]]))
        raise Infeasible(
            f"link {forces.link!r}: even the largest {spec.family.kind} section ({chunk[last].label}) fails "
            f"the {worst} check at crank angle {phi_deg:.1f} deg (factor of safety {float(safety[last]):.3g}, "
            f"required {required[worst]:g}); allow a larger section, another shape or a stronger material",
            constraint=f"links.{forces.link}.{worst}", link=forces.link, check=worst,
            crank_angle_deg=phi_deg, safety=float(safety[last]), required=required[worst])
    checks = []
    for name in CHECKS:
        safety, ang, sec = safeties[name]
        ends = limits.in_plane_ends if name == "buckling_in_plane" else limits.out_of_plane_ends
        checks.append(LinkCheck(forces.link, name, float(safety[chosen]), required[name],
                                float(forces.x[sec[chosen]]), float(forces.phi[ang[chosen]]),
                                _METHODS[name].format(ends=ends)))
    section = chunk[chosen]
    return LinkSizing(forces.link, section, spec.material,
                      bar_mass_props(section, spec.material, forces.start, forces.end), tuple(checks),
                      spec.section is None, forces)
