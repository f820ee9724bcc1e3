"""Crank and slotted lever driving a ram (shaper): closed-form positions and analogues.

Seed: lecture 10 example [000:219-353]: crank O-A, block 2 at A sliding in the slot of rocker 3 (pivot O1),
block 4 at the rocker tip B sliding in a vertical slot of ram 5, which slides on a horizontal guide.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..errors import InvalidInput
from ..model import FloatArray
from ..topology import Joint, Topology
from .linkage import JointSpec, LinkSpec, PlanarLinkage
from .motion import AngleAnalogues, PointAnalogues, constant_angle, crank_point, cross, fixed_point, perp


@dataclass(frozen=True, slots=True)
class SlottedLever:
    """Shaper: crank O->A, rocker O1->B through the block at A, ram on a horizontal guide driven at B.

    O at the origin, rocker pivot O1 at (0, -ground) straight below it, the ram guide horizontal at
    ``ram_height`` above O1; crank angle from +x, counter-clockwise. Lengths [m]; the crank must be shorter
    than O-O1 so that the lever rocks.
    Link frames: crank at O; ``slider`` (block at A) at A along the rocker; ``rocker`` at O1 toward B;
    ``ram_slider`` (block at B) at B; ``ram`` at R = (x_B, height of the guide), x-axis along the guide.
    """

    crank: float
    ground: float
    rocker: float
    ram_height: float

    family: ClassVar[str] = "slotted_lever"
    topology: ClassVar[Topology] = Topology(
        links=("crank", "slider", "rocker", "ram_slider", "ram"),
        joints=(
            Joint("O", "revolute", (None, "crank")),
            Joint("A", "revolute", ("crank", "slider")),
            Joint("A_slot", "prismatic", ("slider", "rocker"), axis_link="rocker", axis_angle=0.0, at="A"),
            Joint("O1", "revolute", (None, "rocker")),
            Joint("B", "revolute", ("rocker", "ram_slider")),
            Joint("B_slot", "prismatic", ("ram_slider", "ram"), axis_link="ram", axis_angle=math.pi / 2, at="B"),
            Joint("R", "prismatic", (None, "ram"), axis_link=None, axis_angle=0.0),
        ),
        crank="crank",
        output="ram",
        output_motion="translation",
        output_axis_angle=0.0,
    )
    origins: ClassVar[dict[str, str]] = {
        "crank": "O", "slider": "A", "rocker": "O1", "ram_slider": "B", "ram": "R",
    }

    def __post_init__(self) -> None:
        for name, value in (
            ("crank_length_m", self.crank),
            ("ground_length_m", self.ground),
            ("rocker_length_m", self.rocker),
            ("ram_height_m", self.ram_height),
        ):
            if not (math.isfinite(value) and value > 0):
                raise InvalidInput(f"{name} must be a positive length, got {value!r}", field=f"mechanism.{name}")
        if self.crank >= self.ground:
            raise InvalidInput(
                f"crank ({self.crank} m) must be shorter than the pivot distance O-O1 ({self.ground} m) "
                "for the lever to rock",
                field="mechanism.crank_length_m",
            )
        if self.rocker <= self.ground + self.crank:
            raise InvalidInput(
                f"rocker ({self.rocker} m) must reach past the crank pin (O1-A up to {self.ground + self.crank} m)",
                field="mechanism.rocker_length_m",
            )

    def as_linkage(self) -> PlanarLinkage:
        """The same shaper as a linkage of links and joints: the crank, an RPR dyad (block and slotted lever) and an
        RPP dyad (block and ram); ``G`` is the frame point of the ram guide straight above O1."""
        half = math.pi / 2
        return PlanarLinkage(
            frame_points=(("O", (0.0, 0.0)), ("O1", (0.0, -self.ground)),
                          ("G", (0.0, -self.ground + self.ram_height))),
            links=(LinkSpec("crank", ("O", "A"), self.crank), LinkSpec("slider", ("A",)),
                   LinkSpec("rocker", ("O1", "B"), self.rocker), LinkSpec("ram_slider", ("B",)),
                   LinkSpec("ram", ("R",))),
            joints=(JointSpec("O", "revolute", ("frame", "crank")), JointSpec("A", "revolute", ("crank", "slider")),
                    JointSpec("A_slot", "prismatic", ("slider", "rocker"), axis_link="rocker"),
                    JointSpec("O1", "revolute", ("frame", "rocker")),
                    JointSpec("B", "revolute", ("rocker", "ram_slider")),
                    JointSpec("B_slot", "prismatic", ("ram_slider", "ram"), axis_link="ram", axis_angle=half,
                              slider_angle=half),
                    JointSpec("R", "prismatic", ("frame", "ram"), through="G")),
            crank_link="crank", output="ram",
        )

    def solve(self, phi: FloatArray) -> tuple[dict[str, PointAnalogues], dict[str, AngleAnalogues]]:
        """Joint positions and link angles with analogues (always assemblable for a valid shaper)."""
        n = len(phi)
        a_pt = crank_point(self.crank, phi)
        o1 = np.array([0.0, -self.ground])
        r, r1, r2 = a_pt.pos - o1, a_pt.d1, a_pt.d2
        rr = np.einsum("ij,ij->i", r, r)
        t3 = np.arctan2(r[:, 1], r[:, 0])
        # theta3 = atan2(r) gives theta3' = (r x r')/|r|^2; differentiate once more (r' x r' = 0).
        t3d1 = cross(r, r1) / rr
        t3d2 = cross(r, r2) / rr - 2 * cross(r, r1) * np.einsum("ij,ij->i", r, r1) / rr**2
        u = np.stack([np.cos(t3), np.sin(t3)], axis=-1)
        k_u = perp(u)
        length = self.rocker
        b_pos = o1 + length * u
        b_d1 = length * t3d1[:, None] * k_u
        b_d2 = length * (t3d2[:, None] * k_u - (t3d1**2)[:, None] * u)
        y_guide = -self.ground + self.ram_height
        zeros = np.zeros(n)
        ram = PointAnalogues(
            np.stack([b_pos[:, 0], np.full(n, y_guide)], axis=-1),
            np.stack([b_d1[:, 0], zeros], axis=-1),
            np.stack([b_d2[:, 0], zeros], axis=-1),
        )
        points = {
            "O": fixed_point((0.0, 0.0), n),
            "A": a_pt,
            "O1": fixed_point((0.0, -self.ground), n),
            "B": PointAnalogues(b_pos, b_d1, b_d2),
            "R": ram,
        }
        rocker = AngleAnalogues(t3, t3d1, t3d2)
        angles = {
            "crank": AngleAnalogues(np.asarray(phi, dtype=float), np.ones(n), zeros.copy()),
            "slider": rocker,
            "rocker": rocker,
            "ram_slider": constant_angle(0.0, n),
            "ram": constant_angle(0.0, n),
        }
        return points, angles
