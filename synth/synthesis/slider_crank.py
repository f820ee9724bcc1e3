"""Offset slider-crank for a stroke and a time ratio: the one-parameter family and its global optimum.

At the dead centres the crank and the rod are collinear: folded at B1 (|OB1| = b - a), stretched at B2
(|OB2| = b + a); B1 and B2 lie on the guide a stroke H apart and subtend the overlap angle theta at the crank pivot.
With r1 = |OB1| the triangle O-B1-B2 gives r2 = r1·cos(theta) + sqrt(H² - r1²·sin²(theta)), a = (r2 - r1)/2,
b = (r2 + r1)/2 and the offset e = r1·r2·sin(theta)/H (twice the triangle's area over its base). The parameter
u = r1/r1_max walks the whole family; the mirror image (offset -e) turns the slow stroke the other way.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Literal, cast

import numpy as np

from ..analysis import analyse
from ..errors import InvalidInput
from ..kinematics import Mechanism, SliderCrank
from ..model import FloatArray, Linkage, MassProps, ProcessLoad
from .checks import LinkageCheck, check_slider_crank
from .crank_rocker import overlap_angle
from .family import FamilyValues, Optimality, feasible, maximise_family

SliderObjective = Literal["transmission_angle", "peak_driving_torque", "rms_shaking_force"]
_BOUNDED = ("crank", "rod", "offset")


@dataclass(frozen=True, slots=True)
class SliderCrankSpec:
    """What the offset slider-crank must do and within which limits.

    stroke: slider travel H [m]; time_ratio: Q >= 1; bounds: ``crank``, ``rod`` or ``offset`` (its magnitude)
    -> (min, max) [m]; max_length_ratio: the rod at most this many strokes; min_transmission_angle [rad];
    slow_stroke: +1 or -1 to have the slider move along +x or -x during the slow stroke (crank turning
    counter-clockwise), 0 for either; objective as for the crank-rocker, with ``linear_density`` [kg/m] of crank
    and rod, ``slider_mass`` [kg], ``speed`` [rad/s], ``loads`` (forces on the slider) and ``samples``.
    """

    stroke: float
    time_ratio: float = 1.0
    bounds: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    max_length_ratio: float = 4.0
    min_transmission_angle: float = 0.0
    slow_stroke: int = 0
    objective: SliderObjective = "transmission_angle"
    linear_density: Mapping[str, float] = field(default_factory=dict)
    slider_mass: float = 0.0
    speed: float = 2 * math.pi
    loads: tuple[ProcessLoad, ...] = ()
    samples: int = 120

    def validate(self) -> None:
        """Raise InvalidInput naming the field that cannot be used."""
        if not (math.isfinite(self.stroke) and self.stroke > 0):
            raise InvalidInput("the stroke must be a positive length", field="stroke_m")
        if not (math.isfinite(self.time_ratio) and 1.0 <= self.time_ratio < 1e3):
            raise InvalidInput("the time ratio must be at least 1 (slow stroke over fast)", field="time_ratio")
        for name, (lo, hi) in self.bounds.items():
            if name not in _BOUNDED:
                raise InvalidInput(f"unknown length {name!r} in bounds; use {list(_BOUNDED)}", field=f"bounds.{name}")
            if not (0.0 <= lo < hi):
                raise InvalidInput(f"bounds of {name}: need 0 <= min < max", field=f"bounds.{name}")
        if not self.max_length_ratio > 0.5:
            raise InvalidInput("max_length_ratio must exceed 0.5 (the rod is longer than the crank)",
                               field="max_length_ratio")
        if self.slow_stroke not in (-1, 0, 1):
            raise InvalidInput("slow_stroke must be -1, 0 or +1", field="slow_stroke")
        if self.objective != "transmission_angle" and not (self.linear_density or self.slider_mass > 0):
            raise InvalidInput(f"objective {self.objective!r} needs link densities or a slider mass",
                               field="linear_density_kg_m")


@dataclass(frozen=True, slots=True)
class SliderCrankResult:
    """The optimal offset slider-crank, its certificate and the engine's re-analysis (``travel`` is the stroke)."""

    linkage: Linkage
    objective: str
    objective_value: float
    parameter: float
    optimality: Optimality
    check: LinkageCheck

    @property
    def slider_crank(self) -> SliderCrank:
        """The synthesised slider-crank."""
        mech = self.linkage.mechanism
        assert isinstance(mech, SliderCrank)
        return mech


def _members(spec: SliderCrankSpec, u: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Crank, rod, offset and folded dead-centre slide position [m] of the members at parameters u."""
    theta, h = overlap_angle(spec.time_ratio), spec.stroke
    r1_max = spec.max_length_ratio * h
    if theta > 0:
        r1_max = min(r1_max, h / (2.0 * math.sin(0.5 * theta)))
    r1 = u * r1_max
    r2 = r1 * math.cos(theta) + np.sqrt(np.clip(h * h - (r1 * math.sin(theta)) ** 2, 0.0, None))
    e = r1 * r2 * math.sin(theta) / h
    x_folded = np.sqrt(np.clip(r2 * r2 - e * e, 0.0, None)) - h
    return 0.5 * (r2 - r1), 0.5 * (r2 + r1), e, x_folded


def _linkage(spec: SliderCrankSpec, sc: SliderCrank) -> Linkage:
    lengths = {"crank": sc.crank, "rod": sc.rod}
    links = {}
    for name, rho in spec.linear_density.items():
        if name in lengths:
            m = rho * lengths[name]
            links[name] = MassProps(m, (0.5 * lengths[name], 0.0), m * lengths[name] ** 2 / 12.0)
    if spec.slider_mass > 0:
        links["slider"] = MassProps(spec.slider_mass)
    return Linkage(cast(Mechanism, sc), links, loads=spec.loads)


class _Evaluate:
    """The family's objective and constraint slacks at parameters u."""

    def __init__(self, spec: SliderCrankSpec) -> None:
        self.spec = spec

    def __call__(self, u: FloatArray) -> FamilyValues:
        spec = self.spec
        a, b, e, x_folded = _members(spec, u)
        h = spec.stroke
        with np.errstate(invalid="ignore", divide="ignore"):
            mu_min = 0.5 * math.pi - np.arcsin(np.clip((a + e) / b, -1.0, 1.0))
            slack: dict[str, FloatArray] = {
                "crank_length_positive": a / h - 1e-9,
                "assembly": (b - a - e) / h,  # the rod reaches the guide from every crank position
                "dead_centres_one_side": x_folded / h,
                "max_length_ratio": spec.max_length_ratio - b / h,
            }
            lengths = {"crank": a, "rod": b, "offset": e}
            for name, (lo, hi) in spec.bounds.items():
                slack[f"{name}_length_min"] = (lengths[name] - lo) / h
                slack[f"{name}_length_max"] = (hi - lengths[name]) / h
            if spec.min_transmission_angle > 0:
                slack["min_transmission_angle"] = mu_min - spec.min_transmission_angle
        for key, value in slack.items():
            slack[key] = np.where(np.isfinite(value), value, -1.0)
        if spec.objective == "transmission_angle":
            return FamilyValues(mu_min, slack)
        ok = feasible(slack)
        value = np.full(u.shape, -np.inf)
        for i in np.flatnonzero(ok):
            an = analyse(_linkage(spec, SliderCrank(a[i], b[i], e[i], 1)), spec.speed, samples=spec.samples)
            summary = an.summary()
            value[i] = -(summary.max_driving_torque if spec.objective == "peak_driving_torque"
                         else summary.rms_shaking_force)
        return FamilyValues(value, slack)


def family_slack(spec: SliderCrankSpec, u: FloatArray) -> Mapping[str, FloatArray]:
    """Named constraint slacks of the members at parameters u in [0, 1], (n,) each, feasible when all exceed
    the degeneracy margin: kinematics only, vectorised over the members."""
    return _Evaluate(replace(spec, objective="transmission_angle"))(u).slack


def member(spec: SliderCrankSpec, u: float) -> Linkage:
    """The family's member at parameter u, turned to the requested slow stroke, with its masses and loads."""
    a, b, e, _ = (float(v[0]) for v in _members(spec, np.array([u])))
    sc = SliderCrank(a, b, e, 1)
    return _linkage(spec, _slow_stroke_side(spec, sc))


def _slow_stroke_side(spec: SliderCrankSpec, sc: SliderCrank) -> SliderCrank:
    if spec.slow_stroke:
        check = check_slider_crank(sc)
        if np.sign(check.output_extremes[1] - check.output_extremes[0]) != spec.slow_stroke:
            # The mirror image about the guide line, run the same way round, moves the slider the other way in
            # its slow stroke; every objective here is symmetric under that reflection.
            return replace(sc, offset=-sc.offset)
    return sc


def synthesise_slider_crank(spec: SliderCrankSpec) -> SliderCrankResult:
    """The offset slider-crank with stroke ``spec.stroke`` and time ratio ``spec.time_ratio`` that is best for
    ``spec.objective`` over the whole one-parameter family, with its certificate and the engine's check.

    Raises InvalidInput for unusable targets and Infeasible (naming the closest-missed constraint) when the
    bounds exclude the whole family.
    """
    spec.validate()
    evaluate = _Evaluate(spec)
    if spec.objective == "transmission_angle":
        u, optimality = maximise_family(evaluate, 0.0, 1.0, grid=256, tol=1e-6, max_evaluations=8_000)
    else:
        u, optimality = maximise_family(evaluate, 0.0, 1.0, grid=48, tol=0.0, rel_tol=1e-6, max_evaluations=240)
    a, b, e, _ = (float(v[0]) for v in _members(spec, np.array([u])))
    sc = _slow_stroke_side(spec, SliderCrank(a, b, e, 1))
    check = check_slider_crank(sc)
    value = float(evaluate(np.array([u])).value[0])
    return SliderCrankResult(
        linkage=_linkage(spec, sc),
        objective=spec.objective,
        objective_value=value if spec.objective == "transmission_angle" else -value,
        parameter=u,
        optimality=optimality,
        check=check,
    )
