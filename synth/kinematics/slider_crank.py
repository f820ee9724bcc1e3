"""Offset slider-crank O-A-B with the slider on a horizontal guide: closed-form positions and analogues."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..errors import InvalidInput, NotAssemblable, angle_ranges_deg
from ..model import FloatArray
from ..topology import Joint, Topology
from .linkage import JointSpec, LinkSpec, PlanarLinkage
from .motion import AngleAnalogues, PointAnalogues, constant_angle, fixed_point, unit, xy


@dataclass(frozen=True, slots=True)
class SliderCrank:
    """Slider-crank: crank O->A, connecting rod A->B, slider at B on the line y = ``offset``.

    Lengths [m]. ``branch`` +1 puts the slider on the +x side of the crank pin, -1 on the -x side.
    Link frames: crank at O, rod at A toward B, slider at B with its x-axis along the guide (+x).
    """

    crank: float
    rod: float
    offset: float = 0.0
    branch: int = 1

    family: ClassVar[str] = "slider_crank"
    topology: ClassVar[Topology] = Topology(
        links=("crank", "rod", "slider"),
        joints=(
            Joint("O", "revolute", (None, "crank")),
            Joint("A", "revolute", ("crank", "rod")),
            Joint("B", "revolute", ("rod", "slider")),
            Joint("guide", "prismatic", (None, "slider"), axis_link=None, axis_angle=0.0, at="B"),
        ),
        crank="crank",
        output="slider",
        output_motion="translation",
        output_axis_angle=0.0,
    )
    origins: ClassVar[dict[str, str]] = {"crank": "O", "rod": "A", "slider": "B"}

    def __post_init__(self) -> None:
        for name, value in (("crank_length_m", self.crank), ("rod_length_m", self.rod)):
            if not (math.isfinite(value) and value > 0):
                raise InvalidInput(f"{name} must be a positive length, got {value!r}", field=f"mechanism.{name}")
        if not math.isfinite(self.offset):
            raise InvalidInput("offset_m must be finite", field="mechanism.offset_m")
        if self.branch not in (1, -1):
            raise InvalidInput("branch must be +1 or -1", field="mechanism.branch")

    def as_linkage(self) -> PlanarLinkage:
        """The same slider-crank as a linkage of links and joints: the crank and one RRP dyad."""
        return PlanarLinkage(
            frame_points=(("O", (0.0, 0.0)), ("G", (0.0, self.offset))),
            links=(LinkSpec("crank", ("O", "A"), self.crank), LinkSpec("rod", ("A", "B"), self.rod),
                   LinkSpec("slider", ("B",))),
            joints=(JointSpec("O", "revolute", ("frame", "crank")), JointSpec("A", "revolute", ("crank", "rod")),
                    JointSpec("B", "revolute", ("rod", "slider")),
                    JointSpec("guide", "prismatic", ("frame", "slider"), point="B", through="G")),
            crank_link="crank", output="slider", branches=(("B", self.branch),),
        )

    def assembly_gaps_deg(self) -> list[tuple[float, float]]:
        """Exact crank-angle ranges [deg] in [0, 360) where the rod cannot reach the guide: |offset - a·sin(phi)| >= l."""
        a, l_, e = self.crank, self.rod, self.offset
        s_hi, s_lo = (e + l_) / a, (e - l_) / a  # sin(phi) >= s_hi or sin(phi) <= s_lo leaves the rod short
        if s_hi <= -1.0 or s_lo >= 1.0:
            return [(0.0, 360.0)]
        gaps: list[tuple[float, float]] = []
        if s_hi <= 1.0:
            t = math.degrees(math.asin(s_hi))
            gaps.append((t, 180.0 - t) if t >= 0 else (0.0, 180.0 - t))
            if t < 0:
                gaps.append((360.0 + t, 360.0))
        if s_lo >= -1.0:
            t = math.degrees(math.asin(s_lo))
            gaps.append((180.0 - t, 360.0 + t) if t <= 0 else (180.0 - t, 360.0))
            if t > 0:
                gaps.append((0.0, t))
        return sorted((round(lo, 9), round(hi, 9)) for lo, hi in gaps)

    def solve(self, phi: FloatArray) -> tuple[dict[str, PointAnalogues], dict[str, AngleAnalogues]]:
        """Joint positions and link angles with analogues; NotAssemblable where |offset - y_A| > rod."""
        n = len(phi)
        a, l_, e = self.crank, self.rod, self.offset
        pin = a * unit(phi)                     # the crank pin as a complex number: a·cos(phi) + i·a·sin(phi)
        sin2 = (e - pin.imag) / l_
        bad = np.abs(sin2) >= 1.0
        if bad.any():
            raise NotAssemblable(
                f"slider-crank cannot be assembled at {int(bad.sum())} of {n} crank angles: "
                f"|offset - crank pin height| reaches the rod length; exact gaps (deg): {self.assembly_gaps_deg()}",
                phi=phi[bad],
                ranges_deg=self.assembly_gaps_deg() or angle_ranges_deg(phi, bad),
            )
        cos2 = self.branch * np.sqrt(1.0 - sin2 * sin2)
        th2 = np.arctan2(sin2, cos2)
        # sin(th2) = (e - a sin phi)/l differentiated twice in phi.
        l_cos2 = l_ * cos2
        t2d1 = -pin.real / l_cos2
        t2d1_sq = t2d1 * t2d1
        t2d2 = (pin.imag + l_ * sin2 * t2d1_sq) / l_cos2
        xb = pin.real + l_cos2
        xb_d1 = -pin.imag - l_ * sin2 * t2d1
        xb_d2 = -pin.real - l_cos2 * t2d1_sq - l_ * sin2 * t2d2
        zeros = np.zeros(n)
        points = {
            "O": fixed_point((0.0, 0.0), n),
            "A": PointAnalogues(xy(pin), xy(1j * pin), xy(-pin)),
            "B": PointAnalogues(xy(xb + 1j * e), xy(xb_d1 + 0j), xy(xb_d2 + 0j)),
        }
        angles = {
            "crank": AngleAnalogues(np.asarray(phi, dtype=float), np.ones(n), zeros.copy(), pin / a),
            "rod": AngleAnalogues(th2, t2d1, t2d2, cos2 + 1j * sin2),
            "slider": constant_angle(0.0, n),
        }
        return points, angles
