"""A disc cam analysed over one turn, and the least cam for pressure-angle and curvature limits.

:func:`analyse_cam` evaluates the follower's program (optimising the laws marked ``optimised``), the cam's pitch
curve and profile, pressure angle and radius of curvature, and the pair's forces; every answer carries its checks:
the pressure angle and curvature recomputed from the point table alone, the motion's derivatives recomputed by
finite differences of the displacement and compared with each law's closed form, each standard law's sampled peak
acceleration against the textbook's coefficient, and the driving torque by virtual power.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import InvalidInput, TooLarge
from ..model import FloatArray
from .forces import PairForces, PairLoads, pair_forces
from .laws import FollowerMotion, Segment, follower_motion, check_segments
from .optimal_law import Objective, OptimisedLaw, optimise_law
from .profile import CamGeometry, Follower, TableCheck, cam_geometry, table_check
from .spring import CoilSpring, coil_spring
from .synthesis import CamLimits, LeastCam, least_cam
from .validity import MIN_PROFILE_RADIUS, contact_validity, geometry_validity, joint_validity
from ..warnings import DesignWarning, ValidityCheck

#: Peak acceleration coefficients C_a (peak = C_a h/beta²) as the textbooks print them (Norton, Cam Design and
#: Manufacturing Handbook, table of standard laws; Rothbart, Cam Design Handbook): independent of the closed forms
#: here, which the answer's law check compares with them.
TEXTBOOK_PEAK_ACCELERATION = {
    "cycloidal": 2.0 * math.pi,
    "simple_harmonic": math.pi**2 / 2.0,
    "polynomial_345": 10.0 / math.sqrt(3.0),
    "polynomial_4567": 7.5132,
    "modified_trapezoid": 4.8881,
    "modified_sine": 5.5280,
}
MIN_SAMPLES = 72
MAX_SEGMENTS = 24


@dataclass(frozen=True, slots=True)
class LawOptions:
    """How segments with the ``optimised`` law are optimised: the objective, knot intervals of the spline, the
    follower's natural frequency [rad/s] (residual vibration), and the cap on the peak acceleration coefficient
    with the residual-vibration objective."""

    objective: Objective = "peak_acceleration"
    intervals: int = 16
    natural_frequency: float = 0.0
    max_acceleration: float = 2.0 * math.pi


@dataclass(frozen=True, slots=True)
class CamSpec:
    """A cam to analyse: the follower's program, the follower, the cam ``speed`` [rad/s, counter-clockwise], the
    base circle radius [m] (the profile's least radius; ignored by the least-cam search), samples per turn, the
    pair's loads (None: kinematics only), the optimised laws' options, and the limits the answer is held to:
    pressure angles in rises and returns [rad], the profile's least radius of curvature [m]."""

    segments: tuple[Segment, ...]
    follower: Follower
    speed: float
    base_radius: float = 0.0
    samples: int = 720
    loads: PairLoads | None = None
    law_options: LawOptions = field(default_factory=LawOptions)
    max_pressure_rise: float = math.radians(30.0)
    max_pressure_return: float = math.radians(45.0)
    min_curvature_radius: float = MIN_PROFILE_RADIUS


@dataclass(frozen=True, slots=True)
class LawCheck:
    """One rise or return: its law and the sampled peak velocity, acceleration and jerk per radian against the
    law's closed-form coefficients (C h/beta^k), with the textbook's acceleration coefficient when there is one."""

    index: int
    kind: str
    law: str
    angle: float
    lift: float
    peak_velocity: float
    peak_acceleration: float
    peak_jerk: float
    coefficient_velocity: float
    coefficient_acceleration: float
    coefficient_jerk: float
    textbook_acceleration: float | None


@dataclass(frozen=True, slots=True)
class CamAnalysis:
    """A cam over one turn: the resolved program (optimised laws in place), motion, geometry and forces, with
    the checks. ``derivative_check`` is the largest relative difference between the law's v, a, jerk and the
    fourth-order finite differences of s, v, a over the samples (segment joints left out); ``coil`` the designed
    spring as a coil (translating followers); ``warnings`` and ``checks`` where the model stops
    (:mod:`synth.cams.validity`)."""

    spec: CamSpec
    motion: FollowerMotion
    geometry: CamGeometry
    table: TableCheck
    laws: tuple[LawCheck, ...]
    optimised: tuple[OptimisedLaw, ...]
    forces: PairForces | None
    derivative_check: float
    coil: CoilSpring | None = None
    warnings: tuple[DesignWarning, ...] = ()
    checks: tuple[ValidityCheck, ...] = ()


@dataclass(frozen=True, slots=True)
class CamSynthesis:
    """The least cam with its certificate, and its full analysis."""

    least: LeastCam
    limits: CamLimits
    analysis: CamAnalysis


def _check_spec(spec: CamSpec, max_samples: int) -> None:
    if len(spec.segments) > MAX_SEGMENTS:
        raise TooLarge("segments", MAX_SEGMENTS, len(spec.segments))
    if spec.samples > max_samples:
        raise TooLarge("samples", max_samples, spec.samples)
    if spec.samples < MIN_SAMPLES:
        raise InvalidInput(f"at least {MIN_SAMPLES} samples per turn", field="samples")
    if not spec.speed > 0.0:
        raise InvalidInput("the cam speed must be positive", field="speed_rpm")
    check_segments(spec.segments)


def resolve_laws(spec: CamSpec) -> tuple[tuple[Segment, ...], tuple[OptimisedLaw, ...]]:
    """The program with each ``optimised`` segment's law solved; a peak objective is solved once for all."""
    opts = spec.law_options
    out: list[Segment] = []
    solved: list[OptimisedLaw] = []
    shared: OptimisedLaw | None = None
    for seg in spec.segments:
        if seg.kind == "dwell" or seg.law != "optimised":
            out.append(seg)
            continue
        if opts.objective == "residual_vibration":
            ratio = opts.natural_frequency * seg.angle / spec.speed
            law = optimise_law(opts.objective, opts.intervals, ratio, opts.max_acceleration)
        else:
            shared = shared or optimise_law(opts.objective, opts.intervals)
            law = shared
        solved.append(law)
        out.append(replace(seg, shape=law.law))
    return tuple(out), tuple(solved)


def _periodic_derivative(y: FloatArray, h: float) -> FloatArray:
    r = [np.roll(y, -k) for k in (-2, -1, 1, 2)]
    return np.asarray((r[0] - 8.0 * r[1] + 8.0 * r[2] - r[3]) / (12.0 * h))


def _derivative_check(m: FollowerMotion) -> float:
    n = len(m.theta)
    h = 2.0 * math.pi / n
    idx = np.arange(n)
    smooth = np.ones(n, dtype=bool)
    for k in (-2, -1, 1, 2):
        smooth &= m.segment[(idx + k) % n] == m.segment
    worst = 0.0
    for y, dy in ((m.s, m.v), (m.v, m.a), (m.a, m.j)):
        scale = float(np.max(np.abs(dy)))
        if scale > 0.0:
            worst = max(worst, float(np.max(np.abs(_periodic_derivative(y, h) - dy)[smooth], initial=0.0)) / scale)
    return worst


def _law_checks(segments: tuple[Segment, ...], m: FollowerMotion) -> tuple[LawCheck, ...]:
    out = []
    u = np.linspace(0.0, 1.0, 8001)
    for i, seg in enumerate(segments):
        if seg.kind == "dwell":
            continue
        inside = m.segment == i
        _, f1, f2, f3 = seg.normalised()(u)
        out.append(LawCheck(
            i, seg.kind, seg.law, seg.angle, seg.lift,
            float(np.max(np.abs(m.v[inside]), initial=0.0)), float(np.max(np.abs(m.a[inside]), initial=0.0)),
            float(np.max(np.abs(m.j[inside]), initial=0.0)),
            float(np.max(np.abs(f1))), float(np.max(np.abs(f2))), float(np.max(np.abs(f3))),
            TEXTBOOK_PEAK_ACCELERATION.get(seg.law)))
    return tuple(out)


def _check_finite(g: CamGeometry) -> None:
    """A follower placed so that its geometry degenerates (the pitch curve stops, an arm folds over) is named,
    never answered with a number that is not one."""
    bad = ~(np.isfinite(g.pressure_angle) & np.isfinite(g.kappa) & np.all(np.isfinite(g.profile), axis=1)
            & np.all(np.isfinite(g.pitch), axis=1))
    if bad.any():
        at = np.degrees(g.motion.theta[bad])
        raise InvalidInput(f"the follower's geometry degenerates at cam angles {at.min():.1f}..{at.max():.1f} deg",
                           field="follower", code="degenerate")


def analyse_cam(spec: CamSpec, max_samples: int = 20_000) -> CamAnalysis:
    """The cam of ``spec`` over one turn at ``spec.samples`` uniformly spaced cam angles, with its checks."""
    _check_spec(spec, max_samples)
    segments, optimised = resolve_laws(spec)
    spec = replace(spec, segments=segments)
    theta = np.linspace(0.0, 2.0 * math.pi, spec.samples, endpoint=False)
    motion = follower_motion(segments, theta)
    geometry = cam_geometry(spec.follower, spec.base_radius, motion)
    _check_finite(geometry)
    forces = pair_forces(geometry, spec.loads) if spec.loads is not None else None
    if forces is not None and not all(np.all(np.isfinite(a)) for a in (forces.contact, forces.torque)):
        raise InvalidInput("the contact force has no finite value at some cam angle: the follower locks there",
                           field="follower", code="locks")
    unit = "m" if spec.follower.motion == "translating" else "rad"
    notes, checks = geometry_validity(segments, geometry, spec.max_pressure_rise, spec.max_pressure_return,
                                      spec.min_curvature_radius)
    more, joints = joint_validity(segments, motion, spec.speed, unit)
    notes, checks = notes + more, checks + joints
    coil = None
    if forces is not None and spec.loads is not None:
        more, contact = contact_validity(motion.theta, forces)
        notes, checks = notes + more, checks + contact
        if forces.spring_designed and spec.follower.motion == "translating" and forces.stiffness > 0:
            coil, more, coil_checks = coil_spring(forces.stiffness, forces.preload, float(np.ptp(motion.s)),
                                                  spec.speed, motion.a, spec.loads.wire, spec.loads.spring_index)
            notes, checks = notes + more, checks + coil_checks
    return CamAnalysis(spec, motion, geometry, table_check(geometry), _law_checks(segments, motion), optimised,
                       forces, _derivative_check(motion), coil, tuple(notes), tuple(checks))


def synthesise_cam(spec: CamSpec, limits: CamLimits, max_samples: int = 20_000) -> CamSynthesis:
    """The least cam for ``limits`` (base radius, and the offset when its range is given), then analysed."""
    _check_spec(spec, max_samples)
    segments, _ = resolve_laws(spec)
    least = least_cam(segments, spec.follower, limits, spec.samples)
    follower = replace(spec.follower, offset=least.offset)
    spec = replace(spec, follower=follower, base_radius=least.base_radius, max_pressure_rise=limits.max_pressure_rise,
                   max_pressure_return=limits.max_pressure_return,
                   min_curvature_radius=limits.min_curvature_radius or spec.min_curvature_radius)
    an = analyse_cam(spec, max_samples)
    if limits.hub_radius == 0.0:
        note = DesignWarning(
            "hub_radius_missing", "hub_radius_m", least.base_radius,
            f"the least cam was searched without the shaft or hub it is made on: its base circle of "
            f"{least.base_radius:.4g} m may not enclose them; give hub_radius_m", "m")
        an = replace(an, warnings=(*an.warnings, note))
    return CamSynthesis(least, limits, an)
