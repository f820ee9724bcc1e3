"""Crank-rocker for a rocker swing and a time ratio: the one-parameter family and its global optimum.

At the rocker's extreme positions B1 and B2 (a chord of length 2·c·sin(psi/2)) the crank and the coupler are
collinear: folded at B1 (|OB1| = b - a), stretched at B2 (|OB2| = b + a), and the chord subtends the overlap angle
theta = pi·(Q - 1)/(Q + 1) at the crank pivot O. So O lies on a circle through B1 and B2 (the chord's own line when
Q = 1), and with r1 = |OB1| the triangle O-B1-B2 gives r2 = r1·cos(theta) + sqrt(s² - r1²·sin²(theta)),
a = (r2 - r1)/2, b = (r2 + r1)/2. The signed parameter u = ±r1/r1_max walks the whole locus: its sign is the side of
the chord O lies on. Every member meets psi and Q exactly; the objective picks one.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Literal, cast

import numpy as np

from ..analysis import analyse
from ..errors import InvalidInput
from ..kinematics import FourBar, Mechanism
from ..model import FloatArray, Linkage, MassProps, ProcessLoad
from .checks import LinkageCheck, check_fourbar
from .family import FamilyValues, Optimality, feasible, maximise_family

Objective = Literal["transmission_angle", "peak_driving_torque", "rms_shaking_force"]
_LINKS = ("crank", "coupler", "rocker", "ground")


@dataclass(frozen=True, slots=True)
class CrankRockerSpec:
    """What the crank-rocker must do and within which limits.

    swing: rocker swing psi [rad]; time_ratio: Q >= 1, slow stroke over fast stroke duration;
    scale_link/scale_length: the one link whose length [m] is given (``rocker``, ``ground`` or ``crank``);
    bounds: link -> (min, max) length [m] for any of crank, coupler, rocker, ground;
    max_length_ratio: no link longer than this many rocker lengths (the family's transmission angle keeps
    improving as the coupler and ground grow without limit when Q = 1);
    pivot_region: (x_min, x_max, y_min, y_max) [m] for the crank pivot in the rocker frame (rocker pivot at the
    origin, mid-swing rocker along +x), or None;
    min_transmission_angle: lowest admissible transmission angle [rad] (0: no limit);
    slow_stroke: +1 or -1 to have the rocker turn counter-clockwise or clockwise during the slow stroke (crank
    turning counter-clockwise), 0 for either; it picks the side of the chord B1-B2 the crank pivot lies on;
    objective: ``transmission_angle`` (largest minimum, the default), ``peak_driving_torque`` or
    ``rms_shaking_force`` (least, for the link masses of ``linear_density`` [kg/m] at ``speed`` [rad/s] with
    ``loads`` on the rocker, over ``samples`` crank angles).
    """

    swing: float
    time_ratio: float = 1.0
    scale_link: Literal["rocker", "ground", "crank"] = "rocker"
    scale_length: float = 1.0
    bounds: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    max_length_ratio: float = 4.0
    pivot_region: tuple[float, float, float, float] | None = None
    min_transmission_angle: float = 0.0
    slow_stroke: int = 0
    objective: Objective = "transmission_angle"
    linear_density: Mapping[str, float] = field(default_factory=dict)
    speed: float = 2 * math.pi
    loads: tuple[ProcessLoad, ...] = ()
    samples: int = 120

    def validate(self) -> None:
        """Raise InvalidInput naming the field that cannot be used."""
        if not (math.isfinite(self.swing) and 0.0 < self.swing < math.pi):
            raise InvalidInput("the rocker swing must lie strictly between 0 and 180 degrees", field="swing_deg")
        if not (math.isfinite(self.time_ratio) and 1.0 <= self.time_ratio < 1e3):
            raise InvalidInput("the time ratio must be at least 1 (slow stroke over fast)", field="time_ratio")
        if not (math.isfinite(self.scale_length) and self.scale_length > 0):
            raise InvalidInput("the scale length must be positive", field="scale_length_m")
        for name, (lo, hi) in self.bounds.items():
            if name not in _LINKS:
                raise InvalidInput(f"unknown link {name!r} in bounds; links are {list(_LINKS)}", field=f"bounds.{name}")
            if not (0.0 <= lo < hi):
                raise InvalidInput(f"bounds of {name}: need 0 <= min < max", field=f"bounds.{name}")
        if not self.max_length_ratio > 1.0:
            raise InvalidInput("max_length_ratio must exceed 1", field="max_length_ratio")
        if self.slow_stroke not in (-1, 0, 1):
            raise InvalidInput("slow_stroke must be -1, 0 or +1", field="slow_stroke")
        if self.objective != "transmission_angle" and not self.linear_density:
            raise InvalidInput(f"objective {self.objective!r} needs link densities", field="linear_density_kg_m")


@dataclass(frozen=True, slots=True)
class CrankRockerResult:
    """The optimal crank-rocker, its place in its family, and the engine's re-analysis.

    ``linkage``: the mechanism in the standard frame with link masses when densities were given;
    ``objective_value``: minimum transmission angle [rad], peak driving torque [N·m] or RMS shaking force [N];
    ``crank_pivot``: crank pivot in the rocker frame (rocker pivot at the origin, mid-swing along +x) [m];
    ``parameter``: the family parameter u of the answer; ``check``: swing, time ratio and transmission angles
    recomputed by the kinematics engine.
    """

    linkage: Linkage
    objective: str
    objective_value: float
    crank_pivot: tuple[float, float]
    parameter: float
    optimality: Optimality
    check: LinkageCheck

    @property
    def fourbar(self) -> FourBar:
        """The synthesised four-bar."""
        mech = self.linkage.mechanism
        assert isinstance(mech, FourBar)
        return mech


def overlap_angle(time_ratio: float) -> float:
    """Crank overlap angle theta = pi·(Q - 1)/(Q + 1) [rad] of a time ratio Q."""
    return math.pi * (time_ratio - 1.0) / (time_ratio + 1.0)


def time_ratio_of(overlap: float) -> float:
    """Time ratio Q = (pi + theta)/(pi - theta) of an overlap angle [rad]."""
    return (math.pi + overlap) / (math.pi - overlap)


@dataclass(frozen=True, slots=True)
class _Family:
    """Members of the family at parameters u, lengths scaled to metres."""

    crank: FloatArray
    coupler: FloatArray
    rocker: FloatArray
    ground: FloatArray
    pivot: FloatArray  # crank pivot O in the rocker frame, (n, 2) [m]
    branch: FloatArray  # assembly branch of each member, (n,)
    folded_branch: FloatArray  # branch side at the folded dead centre times |cross|, (n,); same sign when valid


def _family(spec: CrankRockerSpec, u: FloatArray) -> _Family:
    half, theta = 0.5 * spec.swing, overlap_angle(spec.time_ratio)
    s = 2.0 * math.sin(half)  # chord B1-B2 for a unit rocker
    r1 = np.abs(u) * _r1_max(spec)
    r2 = r1 * math.cos(theta) + np.sqrt(np.clip(s * s - (r1 * math.sin(theta)) ** 2, 0.0, None))
    a, b = 0.5 * (r2 - r1), 0.5 * (r2 + r1)
    gamma = np.arcsin(np.clip(r1 * math.sin(theta) / s, -1.0, 1.0)) * np.sign(u)  # angle at B2 in O-B2-B1
    b1 = np.array([math.cos(half), math.sin(half)])
    b2 = np.array([math.cos(half), -math.sin(half)])
    toward_b1 = np.stack([-np.sin(gamma), np.cos(gamma)], axis=-1)
    o = b2 + r2[:, None] * toward_b1
    d = np.hypot(o[:, 0], o[:, 1])
    # Branch from the stretched position: A on O->B2 at distance a, B at B2, Q at the rocker pivot (origin).
    with np.errstate(invalid="ignore", divide="ignore"):
        a_pt = o + (a / r2)[:, None] * (b2 - o)
    qa, ba = -a_pt, b2 - a_pt
    branch = np.sign(qa[:, 0] * ba[:, 1] - qa[:, 1] * ba[:, 0])
    with np.errstate(invalid="ignore", divide="ignore"):
        a_fold = o - (a / r1)[:, None] * (b1 - o)
    qf, bf = -a_fold, b1 - a_fold
    folded = branch * (qf[:, 0] * bf[:, 1] - qf[:, 1] * bf[:, 0])
    lengths = {"crank": a, "coupler": b, "rocker": np.ones_like(a), "ground": d}
    k = spec.scale_length / lengths[spec.scale_link]
    return _Family(a * k, b * k, k * np.ones_like(a), d * k, o * k[:, None], branch, folded)


def _r1_max(spec: CrankRockerSpec) -> float:
    theta = overlap_angle(spec.time_ratio)
    s = 2.0 * math.sin(0.5 * spec.swing)
    # r1 = b - a < b <= max_length_ratio rockers; past s/(2 sin(theta/2)) the crank length would turn negative.
    limit = float(spec.max_length_ratio)
    return min(limit, s / (2.0 * math.sin(0.5 * theta))) if theta > 0 else limit


def transmission_extremes(a: FloatArray, b: FloatArray, c: FloatArray, d: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Transmission angles [rad] at crank angle 0 and 180° (crank along the ground), where a crank-rocker's
    transmission angle reaches its extremes."""
    with np.errstate(invalid="ignore", divide="ignore"):
        at0 = np.arccos(np.clip((b * b + c * c - (d - a) ** 2) / (2 * b * c), -1.0, 1.0))
        at180 = np.arccos(np.clip((b * b + c * c - (d + a) ** 2) / (2 * b * c), -1.0, 1.0))
    return at0, at180


def _quality(mu: FloatArray) -> FloatArray:
    return np.asarray(np.minimum(mu, math.pi - mu))


def _linkage(spec: CrankRockerSpec, fb: FourBar) -> Linkage:
    lengths = {"crank": fb.crank, "coupler": fb.coupler, "rocker": fb.rocker}
    links = {}
    for name, rho in spec.linear_density.items():
        if name in lengths:
            m = rho * lengths[name]
            links[name] = MassProps(m, (0.5 * lengths[name], 0.0), m * lengths[name] ** 2 / 12.0)
    return Linkage(cast(Mechanism, fb), links, loads=spec.loads)


class _Evaluate:
    """The family's objective and constraint slacks at parameters u (a callable object, picklable)."""

    def __init__(self, spec: CrankRockerSpec) -> None:
        self.spec = spec

    def __call__(self, u: FloatArray) -> FamilyValues:
        spec = self.spec
        fam = _family(spec, u)
        a, b, c, d = fam.crank, fam.coupler, fam.rocker, fam.ground
        ref = spec.scale_length
        with np.errstate(invalid="ignore"):
            mu0, mu180 = transmission_extremes(a, b, c, d)
            mu_min = np.minimum(_quality(mu0), _quality(mu180))
            longest = np.maximum(np.maximum(b, c), d)
            slack: dict[str, FloatArray] = {
                "crank_length_positive": a / c - 1e-9,
                "crank_shortest": (np.minimum(np.minimum(b, c), d) - a) / ref,
                "grashof": (b + c + d - longest - (a + longest)) / ref,
                "max_length_ratio": spec.max_length_ratio - longest / c,
                # Both dead centres on one assembly branch; otherwise the rocker turns back before B1 or B2.
                "one_branch": fam.folded_branch,
            }
            lengths = {"crank": a, "coupler": b, "rocker": c, "ground": d}
            for name, (lo, hi) in spec.bounds.items():
                slack[f"{name}_length_min"] = (lengths[name] - lo) / ref
                slack[f"{name}_length_max"] = (hi - lengths[name]) / ref
            if spec.pivot_region is not None:
                x0, x1, y0, y1 = spec.pivot_region
                x, y = fam.pivot[:, 0], fam.pivot[:, 1]
                slack.update(pivot_x_min=(x - x0) / ref, pivot_x_max=(x1 - x) / ref,
                             pivot_y_min=(y - y0) / ref, pivot_y_max=(y1 - y) / ref)
            if spec.min_transmission_angle > 0:
                slack["min_transmission_angle"] = mu_min - spec.min_transmission_angle
        for key, value in slack.items():
            slack[key] = np.where(np.isfinite(value), value, -1.0)
        if spec.objective == "transmission_angle":
            return FamilyValues(mu_min, slack)
        ok = feasible(slack)
        value = np.full(u.shape, -np.inf)
        for i in np.flatnonzero(ok):
            an = analyse(_linkage(spec, FourBar(d[i], a[i], b[i], c[i], int(fam.branch[i]))), spec.speed,
                         samples=spec.samples)
            summary = an.summary()
            value[i] = -(summary.max_driving_torque if spec.objective == "peak_driving_torque"
                         else summary.rms_shaking_force)
        return FamilyValues(value, slack)


def parameter_range(spec: CrankRockerSpec) -> tuple[float, float]:
    """The family parameter's range [-]: the sign of u is the side of the chord the crank pivot is on, and with
    it the way the rocker turns in its slow stroke; at Q = 1 both sides are the chord's own line."""
    lo, hi = (-1.0, 1.0) if spec.time_ratio > 1.0 else (0.0, 1.0)
    if spec.time_ratio > 1.0 and spec.slow_stroke:
        lo, hi = (0.0, 1.0) if spec.slow_stroke > 0 else (-1.0, 0.0)
    return lo, hi


def family_slack(spec: CrankRockerSpec, u: FloatArray) -> Mapping[str, FloatArray]:
    """Named constraint slacks of the members at parameters u, (n,) each, feasible when all exceed the
    degeneracy margin: kinematics only, vectorised over the members."""
    return _Evaluate(replace(spec, objective="transmission_angle"))(u).slack


def member(spec: CrankRockerSpec, u: float) -> Linkage:
    """The family's member at parameter u, with the link masses of ``spec.linear_density`` and its loads."""
    fam = _family(spec, np.array([u]))
    fb = FourBar(float(fam.ground[0]), float(fam.crank[0]), float(fam.coupler[0]), float(fam.rocker[0]),
                 int(fam.branch[0]))
    return _linkage(spec, fb)


def synthesise_crank_rocker(spec: CrankRockerSpec) -> CrankRockerResult:
    """The crank-rocker with rocker swing ``spec.swing`` and time ratio ``spec.time_ratio`` that is best for
    ``spec.objective`` over the whole one-parameter family, with the certificate of that and the engine's check.

    Raises InvalidInput for targets no crank-rocker can meet and Infeasible (naming the closest-missed
    constraint) when the bounds exclude the whole family.
    """
    spec.validate()
    evaluate = _Evaluate(spec)
    lo, hi = parameter_range(spec)
    if spec.objective == "transmission_angle":
        u, optimality = maximise_family(evaluate, lo, hi, grid=256, tol=1e-6, max_evaluations=8_000)
    else:
        # Each member costs an analysis; a millionth of the objective is far inside any design margin.
        u, optimality = maximise_family(evaluate, lo, hi, grid=48, tol=0.0, rel_tol=1e-6, max_evaluations=240)
    fam = _family(spec, np.array([u]))
    fb = FourBar(float(fam.ground[0]), float(fam.crank[0]), float(fam.coupler[0]), float(fam.rocker[0]),
                 int(fam.branch[0]))
    value = float(evaluate(np.array([u])).value[0])
    return CrankRockerResult(
        linkage=_linkage(spec, fb),
        objective=spec.objective,
        objective_value=value if spec.objective == "transmission_angle" else -value,
        crank_pivot=(float(fam.pivot[0, 0]), float(fam.pivot[0, 1])),
        parameter=u,
        optimality=optimality,
        check=check_fourbar(fb),
    )
