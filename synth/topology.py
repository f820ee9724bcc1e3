"""How the links of a linkage are joined: the data the generic kinetostatics needs besides the motion."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

JointKind = Literal["revolute", "prismatic"]


@dataclass(frozen=True, slots=True)
class Joint:
    """A lower pair between two links, or between the frame and a link.

    The reaction is reported as the force (and for a prismatic pair also the couple) that ``bodies[0]``
    exerts on ``bodies[1]``; ``None`` as ``bodies[0]`` is the frame.

    Parameters
    ----------
    name : Joint name (by default also the Motion point where the pair acts).
    kind : ``"revolute"`` (reaction: two force components through the point) or ``"prismatic"`` (reaction:
        a force normal to the slide axis through the point, and a couple).
    bodies : (giving link or None for the frame, receiving link).
    axis_link : prismatic only: the link whose angle carries the slide axis (None: fixed in the frame).
    axis_angle : prismatic only: slide axis angle in that link's frame [rad].
    at : Motion point where the pair acts, when it is not the joint's own name.
    """

    name: str
    kind: JointKind
    bodies: tuple[str | None, str]
    axis_link: str | None = None
    axis_angle: float = 0.0
    at: str | None = None

    @property
    def point(self) -> str:
        """Name of the Motion point where the pair acts."""
        return self.at or self.name


@dataclass(frozen=True, slots=True)
class Topology:
    """Links (in parameter order), joints, the driven crank and the working (output) member.

    A linkage with redundant (passive) pairs has more joints than 3·links - 1 (see :attr:`indeterminate`).
    ``output_motion`` says whether the output member turns (its load is a torque) or slides along
    ``output_axis_angle`` in the frame (its load is a force).
    """

    links: tuple[str, ...]
    joints: tuple[Joint, ...]
    crank: str
    output: str
    output_motion: Literal["rotation", "translation"]
    output_axis_angle: float = 0.0

    def __post_init__(self) -> None:
        if 2 * len(self.joints) + 1 < 3 * len(self.links):
            raise ValueError(
                f"a one-degree-of-freedom linkage needs 2 joints + 1 driving torque per 3 link equations; "
                f"got {len(self.links)} links and {len(self.joints)} joints"
            )

    @property
    def indeterminate(self) -> bool:
        """More unknown reactions than equations of equilibrium: redundant pairs make the reactions statically
        indeterminate (the equations fix them only up to self-balanced sets)."""
        return 2 * len(self.joints) + 1 > 3 * len(self.links)
