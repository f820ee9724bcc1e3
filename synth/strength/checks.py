"""One strength check of a part: the value the cycle gives against its limit, with what it means."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class PartCheck:
    """A check of a part: ``value`` held at most ``limit`` (or at least, when ``at_least``), both in ``unit``
    (SI: Pa, m/s, Pa·m/s, h, 1); ``part`` names the joint, shaft or hub; ``meaning`` says it in words."""

    part: str
    name: str
    value: float
    limit: float
    unit: str
    meaning: str
    at_least: bool = False

    @property
    def passed(self) -> bool:
        """The value on the right side of its limit."""
        return self.value >= self.limit if self.at_least else self.value <= self.limit

    @property
    def utilisation(self) -> float:
        """How much of the limit the value uses [-]: value/limit, or limit/value for an at-least check."""
        if self.at_least:
            return self.limit / self.value if self.value > 0 else float("inf")
        return self.value / self.limit if self.limit > 0 else float("inf")
