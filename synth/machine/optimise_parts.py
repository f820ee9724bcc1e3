"""What the optimised machine weighs and costs, part by part.

The machine's mass is the sum of the parts the design chain chooses: the counterweights, the Lanchester balancer
masses, the flywheel body, the gear wheels as sized for strength (solid discs of the reference diameters and the
face width) and the catalogue motor. The linkage's own links and the frame are the same order of mass for every
member of a family and are not counted. The cost prices each part kind by its mass and the motor by its name
(or by its mass when no price is given for it).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

from ..errors import InvalidInput
from ..flywheel import FlywheelBody
from ..gearing import CatalogueMotor
from ..gearing.sizing import TrainSizing
from .chain import Balancing

#: Part kinds in the order every parts tuple holds them.
PART_KINDS = ("counterweights", "balancers", "flywheel", "gears", "motor")


@dataclass(frozen=True, slots=True)
class Prices:
    """Prices in one currency (the defaults are rough figures in euros for a small machine shop's bought-in and
    made parts): ``counterweight``, ``balancer``, ``flywheel`` and ``gears`` per kilogram of that part kind,
    ``motor_per_kg`` per kilogram of a catalogue motor without its own price, ``motors`` catalogue name ->
    price of that motor."""

    counterweight: float = 3.0
    balancer: float = 4.0
    flywheel: float = 2.5
    gears: float = 12.0
    motor_per_kg: float = 6.0
    motors: Mapping[str, float] = field(default_factory=dict)

    def validate(self) -> None:
        """InvalidInput naming the price that is negative or not finite."""
        named = {"counterweight_per_kg": self.counterweight, "balancer_per_kg": self.balancer,
                 "flywheel_per_kg": self.flywheel, "gears_per_kg": self.gears, "motor_per_kg": self.motor_per_kg,
                 **{f"motors.{k}": v for k, v in self.motors.items()}}
        for name, v in named.items():
            if not (math.isfinite(v) and v >= 0):
                raise InvalidInput("a price must be finite and not negative", field=f"prices.{name}")


@dataclass(frozen=True, slots=True)
class MachineParts:
    """The masses [kg] of the parts the chain chooses, in :data:`PART_KINDS` order; ``gears`` None when the
    wheels were not sized (the search leaves the sizing out unless the objective needs it); ``motor_name`` the
    catalogue motor."""

    counterweights: float
    balancers: float
    flywheel: float
    gears: float | None
    motor: float
    motor_name: str

    @property
    def mass(self) -> float:
        """The machine's mass [kg]: NaN when the gears were not sized."""
        return math.nan if self.gears is None else (self.counterweights + self.balancers + self.flywheel
                                                    + self.gears + self.motor)

    @property
    def fixed_mass(self) -> float:
        """What the member's discrete choice and balancing fix: counterweights, balancers and motor [kg]."""
        return self.counterweights + self.balancers + self.motor

    def motor_price(self, prices: Prices) -> float:
        """The motor's own price, else its mass at the price per kilogram of a motor."""
        return float(prices.motors.get(self.motor_name, prices.motor_per_kg * self.motor))

    def cost(self, prices: Prices) -> float:
        """The machine's cost in the prices' currency: NaN when the gears were not sized."""
        if self.gears is None:
            return math.nan
        return (prices.counterweight * self.counterweights + prices.balancer * self.balancers
                + prices.flywheel * self.flywheel + prices.gears * self.gears + self.motor_price(prices))

    def fixed_cost(self, prices: Prices) -> float:
        """The cost of the fixed parts (counterweights, balancers, motor)."""
        return (prices.counterweight * self.counterweights + prices.balancer * self.balancers
                + self.motor_price(prices))


def motor_mass(motor: CatalogueMotor) -> float:
    """The catalogue mass [kg]; NaN when the catalogue does not give it (an optimisation that weighs or prices
    the machine refuses such a catalogue before it starts)."""
    return math.nan if motor.mass is None else float(motor.mass)


def machine_parts(bal: Balancing, placement: FlywheelBody | None, gears: TrainSizing | None, sized: bool,
                  motor: CatalogueMotor) -> MachineParts:
    """The parts of a machine: ``sized`` False when the gear wheels were not sized (their mass unknown), True
    with ``gears`` None when the drive has no stage to size (no wheels counted)."""
    counterweights = 0.0
    balancers = 0.0
    if bal.result is not None:
        counterweights += sum(c.mass for c in bal.result.counterweights)
    if bal.slider_crank is not None:
        counterweights += bal.slider_crank.crank_counterweight.mass
        if bal.mode == "full":
            balancers += sum(2 * p.mass for p in bal.slider_crank.pairs)  # each pair: two shafts, each its mass
    wheels = (0.0 if gears is None else float(gears.mass)) if sized else None
    return MachineParts(float(counterweights), float(balancers), 0.0 if placement is None else float(placement.mass),
                        wheels, motor_mass(motor), motor.name)
