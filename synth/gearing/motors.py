"""The shipped motor catalogue (``motors.json``) and the choice of the smallest motor that covers a power."""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cache
from importlib import resources

from ..errors import Infeasible, InvalidInput

RPM = math.pi / 30.0


@dataclass(frozen=True, slots=True)
class CatalogueMotor:
    """A catalogue motor: ``rated_power`` [W], ``synchronous_speed`` and ``rated_speed`` [rad/s],
    ``rotor_inertia`` [kg·m²] or None when the catalogue does not give it, ``breakdown_ratio`` breakdown over
    rated torque [-] (2.2 is typical of four-pole induction motors of this size), ``starting_ratio`` locked-rotor
    (starting) torque over rated torque [-] (2.0 is typical of the series up to 11 kW); ``mass`` the catalogue
    mass of the motor [kg], or None when the catalogue does not give it.

    Its static characteristic is linear from zero torque at synchronous speed through the rated point, up to the
    breakdown torque: the one motor model the flywheel NLP, the drive and the machine simulation share. Below
    the breakdown speed (only a start passes there) the torque runs linearly from the breakdown torque down to
    the starting torque at standstill.
    """

    name: str
    rated_power: float
    synchronous_speed: float
    rated_speed: float
    rotor_inertia: float | None
    breakdown_ratio: float = 2.2
    starting_ratio: float = 2.0
    mass: float | None = None

    @property
    def rated_torque(self) -> float:
        """Rated torque P/w_rated [N·m]."""
        return self.rated_power / self.rated_speed

    @property
    def breakdown_torque(self) -> float:
        """Largest torque of the linear branch [N·m]."""
        return self.breakdown_ratio * self.rated_torque

    @property
    def starting_torque(self) -> float:
        """Locked-rotor torque at standstill [N·m]."""
        return self.starting_ratio * self.rated_torque


@cache
def motor_catalogue() -> tuple[CatalogueMotor, ...]:
    """The shipped catalogue, ascending in rated power then synchronous speed (speeds converted to rad/s)."""
    text = resources.files(__package__).joinpath("motors.json").read_text(encoding="utf-8")
    rows = json.loads(text)["motors"]
    motors = [CatalogueMotor(r["name"], float(r["rated_power_W"]), r["synchronous_rpm"] * RPM, r["rated_rpm"] * RPM,
                             r["rotor_inertia_kgm2"], float(r.get("breakdown_torque_ratio", 2.2)),
                             float(r.get("starting_torque_ratio", 2.0)),
                             None if r.get("mass_kg") is None else float(r["mass_kg"])) for r in rows]
    return tuple(sorted(motors, key=lambda m: (m.rated_power, m.synchronous_speed)))


def find_motor(name: str, catalogue: Sequence[CatalogueMotor] | None = None) -> CatalogueMotor:
    """The catalogue motor called ``name``; InvalidInput (field ``motor``) when there is none."""
    for m in catalogue or motor_catalogue():
        if m.name == name:
            return m
    raise InvalidInput(f"no motor {name!r} in the catalogue", field="motor")


def select_motor(
    required_power: float,
    *,
    synchronous_speed: float | None = None,
    catalogue: Sequence[CatalogueMotor] | None = None,
    acceptable: Callable[[CatalogueMotor], bool] | None = None,
) -> CatalogueMotor:
    """The smallest catalogue motor whose rated power covers ``required_power`` [W].

    ``synchronous_speed`` [rad/s] restricts the choice to one speed class. Among motors of the smallest
    sufficient rating, those ``acceptable`` says the drive can use (its stages reach the total ratio) come
    first, then the fastest (the smallest frame for the power). Raises Infeasible naming the power limit.
    """
    motors = list(catalogue or motor_catalogue())
    if synchronous_speed is not None:
        motors = [m for m in motors if math.isclose(m.synchronous_speed, synchronous_speed, rel_tol=1e-6)]
        if not motors:
            classes = sorted({round(m.synchronous_speed / RPM) for m in catalogue or motor_catalogue()})
            raise InvalidInput(f"no catalogue motors at this synchronous speed; classes [rpm]: {classes}",
                               field="synchronous_rpm")
    least = required_power * (1 - 1e-12)
    covering = [m for m in motors if m.rated_power >= least]
    if not covering:
        largest = max(m.rated_power for m in motors)
        raise Infeasible(f"no catalogue motor covers the required {required_power:.4g} W (largest {largest:.4g} W)",
                         constraint="motor_power", required_power_W=required_power, largest_power_W=largest)
    smallest = min(m.rated_power for m in covering)
    tied = [m for m in covering if m.rated_power == smallest]
    return min(tied, key=lambda m: (not (acceptable or (lambda _: True))(m), -m.synchronous_speed))
