"""Four-bar linkage O-A-B-Q: closed-form positions, velocity and acceleration analogues, Grashof class."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import numpy.typing as npt

from ..errors import InvalidInput, NotAssemblable, angle_ranges_deg
from ..model import FloatArray
from ..topology import Joint, Topology
from .linkage import JointSpec, LinkSpec, PlanarLinkage
from .motion import AngleAnalogues, PointAnalogues, cross_c, dot_c, fixed_point, unit, xy


def _positive(value: float, name: str) -> None:
    if not (math.isfinite(value) and value > 0):
        raise InvalidInput(f"{name} must be a positive length, got {value!r}", field=f"mechanism.{name}")


@dataclass(frozen=True, slots=True)
class FourBar:
    """Four-bar: crank O->A (link ``crank``), coupler A->B, rocker Q->B; O at the origin, Q at (ground, 0).

    Lengths [m]. ``branch`` is +1 when B lies to the left of the directed line A->Q, -1 to the right.
    """

    ground: float
    crank: float
    coupler: float
    rocker: float
    branch: int = 1

    family: ClassVar[str] = "fourbar"
    topology: ClassVar[Topology] = Topology(
        links=("crank", "coupler", "rocker"),
        joints=(
            Joint("O", "revolute", (None, "crank")),
            Joint("A", "revolute", ("crank", "coupler")),
            Joint("B", "revolute", ("coupler", "rocker")),
            Joint("Q", "revolute", (None, "rocker")),
        ),
        crank="crank",
        output="rocker",
        output_motion="rotation",
    )

    def __post_init__(self) -> None:
        for name in ("ground", "crank", "coupler", "rocker"):
            _positive(getattr(self, name), f"{name}_length_m")
        if self.branch not in (1, -1):
            raise InvalidInput("branch must be +1 or -1", field="mechanism.branch")
        lengths = sorted((self.ground, self.crank, self.coupler, self.rocker))
        if lengths[3] >= lengths[0] + lengths[1] + lengths[2]:
            raise InvalidInput(
                f"the longest link ({lengths[3]} m) must be shorter than the sum of the others "
                f"({lengths[0] + lengths[1] + lengths[2]} m)",
                field="mechanism",
            )
        if self.grashof == "change-point":
            raise InvalidInput(
                f"a change-point four-bar (shortest + longest link = sum of the other two): at crank angle(s) "
                f"{self.change_point_angles_deg()} deg all four joints are collinear, the motion can switch "
                "assembly branch and the joint forces are unbounded; change one length slightly",
                field="mechanism",
            )

    def change_point_angles_deg(self) -> list[float]:
        """Crank angles [deg] where the coupler and rocker fold onto the ground line (the loop triangle A-B-Q
        degenerates): at 0 deg |AQ| = |d - a|, at 180 deg |AQ| = d + a."""
        a, d, b, c = self.crank, self.ground, self.coupler, self.rocker
        folded = (b + c, abs(b - c))
        return [angle for angle, dist in ((0.0, abs(d - a)), (180.0, d + a))
                if any(math.isclose(dist, f, rel_tol=1e-9, abs_tol=1e-15) for f in folded)]

    @property
    def grashof(self) -> str:
        """Grashof class: crank-rocker, double-crank, double-rocker, rocker-crank, change-point or triple-rocker."""
        lengths = {"ground": self.ground, "crank": self.crank, "coupler": self.coupler, "rocker": self.rocker}
        s, l_ = min(lengths.values()), max(lengths.values())
        p_q = sum(lengths.values()) - s - l_
        if math.isclose(s + l_, p_q, rel_tol=1e-12):
            return "change-point"
        if s + l_ > p_q:
            return "triple-rocker"
        shortest = min(lengths, key=lambda k: lengths[k])
        return {
            "crank": "crank-rocker",
            "ground": "double-crank",
            "coupler": "double-rocker",
            "rocker": "rocker-crank",
        }[shortest]

    def cos_limits(self) -> tuple[float, float]:
        """Range of cos(phi) inside which the loop closes: |b - c| <= |AQ| <= b + c."""
        a, d, b, c = self.crank, self.ground, self.coupler, self.rocker
        lo = (a * a + d * d - (b + c) ** 2) / (2 * a * d)
        hi = (a * a + d * d - (b - c) ** 2) / (2 * a * d)
        return lo, hi

    def assembly_gaps_deg(self) -> list[tuple[float, float]]:
        """Exact crank-angle ranges [deg] in [0, 360) where the linkage cannot be assembled."""
        lo, hi = self.cos_limits()
        gaps: list[tuple[float, float]] = []
        if hi < 1.0:  # near phi = 0 the loop is too short
            t = math.degrees(math.acos(max(-1.0, hi)))
            if hi <= -1.0:
                return [(0.0, 360.0)]
            gaps += [(0.0, t), (360.0 - t, 360.0)]
        if lo > -1.0:  # near phi = 180 the loop is too long
            if lo >= 1.0:
                return [(0.0, 360.0)]
            t = math.degrees(math.acos(lo))
            gaps.append((t, 360.0 - t))
        return sorted((round(a, 9), round(b, 9)) for a, b in gaps)

    def solve(self, phi: FloatArray) -> tuple[dict[str, PointAnalogues], dict[str, AngleAnalogues]]:
        """Joint positions and link angles with their analogues; NotAssemblable where the loop cannot close."""
        n = len(phi)
        moving, angles, bad = loop_closure(self.crank, self.ground, self.coupler, self.rocker, self.branch, phi)
        if np.logical_or.reduce(bad):
            raise NotAssemblable(
                f"four-bar cannot be assembled at {int(bad.sum())} of {n} crank angles; "
                f"exact gaps (deg): {self.assembly_gaps_deg()}",
                phi=phi[bad],
                ranges_deg=self.assembly_gaps_deg() or angle_ranges_deg(phi, bad),
            )
        points = {"O": fixed_point((0.0, 0.0), n), **moving, "Q": fixed_point((self.ground, 0.0), n)}
        return points, angles

    origins: ClassVar[dict[str, str]] = {"crank": "O", "coupler": "A", "rocker": "Q"}

    def as_linkage(self) -> PlanarLinkage:
        """The same four-bar as a linkage of links and joints: the crank and one RRR dyad."""
        return PlanarLinkage(
            frame_points=(("O", (0.0, 0.0)), ("Q", (self.ground, 0.0))),
            links=(LinkSpec("crank", ("O", "A"), self.crank), LinkSpec("coupler", ("A", "B"), self.coupler),
                   LinkSpec("rocker", ("Q", "B"), self.rocker)),
            joints=tuple(JointSpec(j.name, "revolute", (j.bodies[0] or "frame", j.bodies[1]))
                         for j in self.topology.joints),
            crank_link="crank", output="rocker", branches=(("B", self.branch),),
        )


def transmission_angle(coupler_angle: FloatArray, rocker_angle: FloatArray) -> FloatArray:
    """Angle between coupler and rocker [rad] in [0, pi]; its distance from pi/2 measures force transmission."""
    diff = np.mod(rocker_angle - coupler_angle, 2 * np.pi)
    return np.asarray(np.where(diff > np.pi, 2 * np.pi - diff, diff))


def loop_closure(a: float | FloatArray, ground: float | FloatArray, b: float | FloatArray, c: float | FloatArray,
                 branch: float | FloatArray, phi: FloatArray
                 ) -> tuple[dict[str, PointAnalogues], dict[str, AngleAnalogues], npt.NDArray[np.bool_]]:
    """The four-bar's closed form at crank angles ``phi`` [rad]: joints A and B and the three links' angles with
    their analogues, and where the loop fails to close (the values there are meaningless). Each length [m] and
    the branch is one number, or one per angle (a stack of four-bars, :mod:`synth.kinematics.stacking`)."""
    n = len(phi)
    # Plane vectors as complex numbers: a turn by 90 degrees is a product by i, and each vector operation is
    # one array operation instead of two.
    pin = a * unit(phi)
    to_q = ground - pin
    # |to_q| from its squared length, which the circle intersection needs anyway (np.abs of a complex number is
    # a slower hypot)
    dist2 = to_q.real * to_q.real + to_q.imag * to_q.imag
    dist = np.sqrt(dist2)
    bad = (dist > b + c + 1e-12) | (dist < np.abs(b - c) - 1e-12) | (dist == 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = (b * b - c * c + dist2) / (2 * dist)
        h = np.sqrt(np.maximum(b * b - x * x, 0.0))          # np.clip's result, without its Python layers
        bpos = pin + (to_q / dist) * (x + (1j * branch) * h)
        e2 = (bpos - pin) / b
        e3 = (bpos - ground) / c
        # Loop A + b·e2 = Q + c·e3 differentiated once and twice in phi; each a 2x2 solve by Cramer's rule, with
        # det = cross(b·i·e2, -c·i·e3) = -b·c·cross(e2, e3).
        # A product with i turns a cross product into a scalar one: cross(u, i·v) = u·v.
        det = -b * c * cross_c(e2, e3)
        pin_d1 = 1j * pin
        t2d1 = c * dot_c(pin_d1, e3) / det
        t3d1 = b * dot_c(e2, pin_d1) / det
        rhs2 = pin + b * (t2d1 * t2d1) * e2 - c * (t3d1 * t3d1) * e3
        t2d2 = -c * dot_c(rhs2, e3) / det
        t3d2 = -b * dot_c(e2, rhs2) / det
    k3 = 1j * e3
    points = {
        "A": PointAnalogues(xy(pin), xy(pin_d1), xy(-pin)),
        "B": PointAnalogues(xy(bpos), xy((c * t3d1) * k3), xy(c * (t3d2 * k3 - (t3d1 * t3d1) * e3))),
    }
    angles = {
        "crank": AngleAnalogues(np.asarray(phi, dtype=float), np.ones(n), np.zeros(n), pin / a),
        "coupler": AngleAnalogues(np.arctan2(e2.imag, e2.real), t2d1, t2d2, e2),     # np.angle, one call
        "rocker": AngleAnalogues(np.arctan2(e3.imag, e3.real), t3d1, t3d2, e3),
    }
    return points, angles, bad
