"""Mass properties, counterweights, gravity and loads: plain dataclasses in SI units, validated once."""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from .errors import InvalidInput
from .mechanism import FloatArray as FloatArray
from .mechanism import Mechanism


def _finite(value: float, field_name: str) -> float:
    if not math.isfinite(value):
        raise InvalidInput(f"{field_name} must be a finite number, got {value!r}", field=field_name)
    return float(value)


@dataclass(frozen=True, slots=True)
class MassProps:
    """Mass [kg], centre of mass in the link frame [m] and inertia about the centre of mass [kg·m²]."""

    mass: float = 0.0
    com: tuple[float, float] = (0.0, 0.0)
    inertia: float = 0.0

    def validate(self, where: str) -> None:
        """Raise InvalidInput naming ``where`` for a negative or non-finite property."""
        _finite(self.mass, f"{where}.mass_kg")
        _finite(self.inertia, f"{where}.inertia_kgm2")
        for i, c in enumerate(self.com):
            _finite(c, f"{where}.com_m[{i}]")
        if self.mass < 0:
            raise InvalidInput(f"{where}: mass must not be negative, got {self.mass} kg", field=f"{where}.mass_kg")
        if self.inertia < 0:
            raise InvalidInput(
                f"{where}: inertia must not be negative, got {self.inertia} kg·m²", field=f"{where}.inertia_kgm2"
            )

    def params(self) -> FloatArray:
        """Inertial parameters (m, m·x, m·y, J about the link's first joint) [kg, kg·m, kg·m, kg·m²]."""
        x, y = self.com
        m = self.mass
        return np.array([m, m * x, m * y, self.inertia + m * (x * x + y * y)])

    @staticmethod
    def from_params(p: Sequence[float] | FloatArray) -> MassProps:
        """Inverse of :meth:`params`; a massless parameter set keeps its joint inertia as its own."""
        m, hx, hy, j_joint = (float(v) for v in p)
        if m <= 0.0:
            return MassProps(0.0, (0.0, 0.0), j_joint)
        x, y = hx / m, hy / m
        return MassProps(m, (x, y), j_joint - m * (x * x + y * y))


@dataclass(frozen=True, slots=True)
class Counterweight:
    """Point-like counterweight on a link: mass [kg], position in the link frame [m], own inertia [kg·m²]."""

    link: str
    mass: float
    position: tuple[float, float]
    inertia: float = 0.0

    def params(self) -> FloatArray:
        """Inertial parameters it adds to its link (m, m·x, m·y, J about the first joint)."""
        return MassProps(self.mass, self.position, self.inertia).params()


@dataclass(frozen=True, slots=True)
class Gravity:
    """Uniform gravity: magnitude [m/s²] and direction angle in the plane [rad] (-pi/2 = down)."""

    g: float = 9.81
    direction: float = -math.pi / 2

    @property
    def vector(self) -> FloatArray:
        """Gravitational acceleration vector [m/s²] (read-only: one array shared by every use)."""
        return _gravity_vector(self.g, self.direction)


@functools.lru_cache(maxsize=64)
def _gravity_vector(g: float, direction: float) -> FloatArray:
    vector = g * np.array([math.cos(direction), math.sin(direction)])
    vector.flags.writeable = False
    return vector


@dataclass(frozen=True, slots=True)
class ProcessLoad:
    """Process load on the working member, acting against its velocity.

    Magnitude is a force [N] on a sliding member or a torque [N·m] on a turning one. ``kind`` chooses its law:
    ``"window"``: ``magnitude`` while the crank angle is inside [start, end] (radians, wrapping past 2*pi);
    ``"crank_table"``: periodic linear interpolation of ``values`` over crank angles ``table_x`` [rad];
    ``"position_table"``: linear interpolation over the output position ``table_x`` (slide displacement [m]
    or output angle [rad]), zero outside the table.
    ``stroke`` limits it to one direction of the output velocity (+1 or -1); 0 acts in both.
    ``point`` is where a force acts, in the output link frame [m].
    ``direction`` says which way it acts: ``"against_motion"`` (the default: a resistance, magnitude >= 0 resists,
    its sign following the output velocity); ``"output"`` signed and fixed along the output, positive along the
    slide axis or counter-clockwise on a turning output (a spring preload, a constant thrust); ``"frame"`` a force
    of fixed direction in the frame, at ``angle`` [rad] from +x, signed (a weight: magnitude m·g at -90°), on a
    sliding or a turning output at ``point``.
    """

    kind: Literal["window", "crank_table", "position_table"] = "window"
    magnitude: float = 0.0
    start: float = 0.0
    end: float = 2 * math.pi
    table_x: tuple[float, ...] = ()
    values: tuple[float, ...] = ()
    stroke: int = 0
    point: tuple[float, float] = (0.0, 0.0)
    direction: Literal["against_motion", "output", "frame"] = "against_motion"
    angle: float = 0.0

    def validate(self) -> None:
        """Raise InvalidInput for tables of unequal length, unsorted abscissae or a bad stroke."""
        if self.kind == "window":
            _finite(self.magnitude, "load.magnitude")
        else:
            if len(self.table_x) != len(self.values) or len(self.table_x) < 2:
                raise InvalidInput(
                    f"load table needs at least two points and equal lengths, got {len(self.table_x)} abscissae "
                    f"and {len(self.values)} values",
                    field="load.values",
                )
            if np.any(np.diff(self.table_x) <= 0):
                raise InvalidInput("load table abscissae must increase strictly", field="load.table_x")
        if self.stroke not in (-1, 0, 1):
            raise InvalidInput("load.stroke must be -1, 0 or +1", field="load.stroke")
        if self.direction not in ("against_motion", "output", "frame"):
            raise InvalidInput("load.direction must be against_motion, output or frame", field="load.direction")
        _finite(self.angle, "load.angle")

    def magnitude_at(self, phi: FloatArray, output_position: FloatArray) -> FloatArray:
        """Load magnitude at each crank angle, before the direction rule is applied."""
        if self.kind == "window":
            span = (self.end - self.start) % (2 * math.pi) or 2 * math.pi
            inside = (phi - self.start) % (2 * math.pi) <= span + 1e-12
            return np.where(inside, self.magnitude, 0.0)
        x, y = np.asarray(self.table_x), np.asarray(self.values)
        if self.kind == "crank_table":
            return np.asarray(np.interp(phi % (2 * math.pi), x, y, period=2 * math.pi), dtype=float)
        return np.asarray(np.interp(output_position, x, y, left=0.0, right=0.0), dtype=float)


@dataclass(frozen=True, slots=True)
class LinkTorque:
    """A constant external torque on a link [N·m], counter-clockwise positive, reacted by the frame."""

    link: str
    torque: float


@dataclass(frozen=True, slots=True)
class Linkage:
    """A mechanism with its links' mass properties, counterweights, gravity and loads.

    Links not listed in ``links`` are massless. Gravity ``None`` means off.
    """

    mechanism: Mechanism
    links: Mapping[str, MassProps] = field(default_factory=dict)
    counterweights: tuple[Counterweight, ...] = ()
    gravity: Gravity | None = None
    loads: tuple[ProcessLoad, ...] = ()
    torques: tuple[LinkTorque, ...] = ()
    _params: FloatArray | None = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        names = self.mechanism.topology.links
        for name, props in self.links.items():
            if name not in names:
                raise InvalidInput(f"unknown link {name!r}; this mechanism has {list(names)}", field=f"links.{name}")
            props.validate(f"links.{name}")
        for i, cw in enumerate(self.counterweights):
            if cw.link not in names:
                raise InvalidInput(
                    f"counterweight on unknown link {cw.link!r}; this mechanism has {list(names)}",
                    field=f"counterweights[{i}].link",
                )
            MassProps(cw.mass, cw.position, cw.inertia).validate(f"counterweights[{i}]")
        for i, t in enumerate(self.torques):
            if t.link not in names:
                raise InvalidInput(f"torque on unknown link {t.link!r}", field=f"torques[{i}].link")
            _finite(t.torque, f"torques[{i}].torque_Nm")
        for load in self.loads:
            load.validate()
        if self.gravity is not None:
            _finite(self.gravity.g, "gravity.g_m_s2")
            _finite(self.gravity.direction, "gravity.direction")

    def mass_props(self, link: str) -> MassProps:
        """Mass properties of a link with its counterweights included."""
        p = self.params_of(link)
        return MassProps.from_params(p)

    def params_of(self, link: str) -> FloatArray:
        """Inertial parameters of a link including its counterweights (m, m·x, m·y, J about first joint)."""
        links = self.mechanism.topology.links
        if link in links:
            i = 4 * links.index(link)
            return self.params()[i:i + 4].copy()
        return self._own_params(link)

    def _own_params(self, link: str) -> FloatArray:
        p = self.links.get(link, MassProps()).params()
        for cw in self.counterweights:
            if cw.link == link:
                p = p + cw.params()
        return p

    def params(self) -> FloatArray:
        """Stacked inertial parameters of all links in topology order, shape (4 * links,), read-only.

        Computed once per linkage: a balancing request or a study's variant asks for them at every step."""
        cached = self._params
        if cached is None:
            cached = np.concatenate([self._own_params(name) for name in self.mechanism.topology.links])
            cached.flags.writeable = False
            object.__setattr__(self, "_params", cached)
        return cached

    def with_counterweights(self, counterweights: Sequence[Counterweight]) -> Linkage:
        """The same linkage with ``counterweights`` added to the ones it has."""
        return Linkage(
            self.mechanism,
            self.links,
            self.counterweights + tuple(counterweights),
            self.gravity,
            self.loads,
            self.torques,
        )
