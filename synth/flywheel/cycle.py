"""The machine reduced to its crank over one cycle: reduced inertia and torque, piecewise linear in the angle.

One model serves every method and every check: between two samples the reduced inertia J(phi) and the reduced
torque M(phi) are linear, so the work A(phi) is piecewise quadratic and exact at any angle. Sizing formulas, the
equation-of-motion check and the NLP all read this one object.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Literal

import numpy as np

from ..dynamics import ReducedModel
from ..errors import InvalidInput, TooLarge
from ..kinematics import MAX_SAMPLES
from ..model import FloatArray


# The closest two crank angles of a table may be, as a fraction of the cycle: closer, the energy's slopes
# between them are dominated by rounding (and a subnormal step divides to infinity).
MIN_STEP = 1e-12

@dataclass(frozen=True, slots=True)
class ReducedCycle:
    """Reduced inertia and reduced torque of one machine cycle at ``N`` samples, periodic in ``period``.

    ``phi`` crank angles [rad], strictly increasing, spanning less than ``period`` (the sample at
    ``phi[0] + period`` is ``phi[0]`` again); ``inertia`` J_red(phi) [kg·m²] of the variable-inertia part;
    ``torque`` reduced torque of every given load and drive [N·m], positive drives the crank; ``period`` [rad];
    ``balance`` the role of the constant torque that balances the cycle's work: ``driving`` (the tables are the
    loads, as in a machine driven by a motor) or ``resisting`` (the tables are the drive, as an engine's gas torque,
    and the constant torque is the consumer's load); ``driving_work`` and ``resisting_work`` the work of each
    given table over the cycle [J] when they came separately (None otherwise), for the sign checks.
    """

    phi: FloatArray
    inertia: FloatArray
    torque: FloatArray
    period: float
    balance: Literal["driving", "resisting"] = "driving"
    driving_work: float | None = None
    resisting_work: float | None = None
    # the work at the closed samples, read by the band, the motor's mean speed and the sizing alike: found once
    _work: FloatArray | None = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        n = self.phi.shape[0]
        if self.phi.ndim != 1 or n < 2:
            raise InvalidInput("a cycle needs at least two crank angles", field="crank_angle_deg")
        for name in ("inertia", "torque"):
            if getattr(self, name).shape != (n,):
                raise InvalidInput(f"{name} must have one value per crank angle ({n})", field=name)
        if not np.all(np.diff(self.phi) > 0) or self.phi[-1] - self.phi[0] >= self.period:
            raise InvalidInput("crank angles must increase strictly within one cycle", field="crank_angle_deg")
        if not np.all(np.diff(self.phi) >= MIN_STEP * self.period):
            raise InvalidInput(f"crank angles closer than {MIN_STEP:g} of the cycle: the slopes between them are "
                               "lost in rounding", field="crank_angle_deg")
        if np.any(self.inertia < 0):
            raise InvalidInput("reduced inertia must not be negative", field="reduced_inertia_kgm2")

    @property
    def samples(self) -> int:
        """Number of samples N."""
        return int(self.phi.shape[0])

    def closed(self) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Angles, inertia and torque with the first sample repeated one period later, (N+1,) each."""
        return (
            np.append(self.phi, self.phi[0] + self.period),
            np.append(self.inertia, self.inertia[0]),
            np.append(self.torque, self.torque[0]),
        )

    def work_nodes(self) -> FloatArray:
        """Work of the torque from ``phi[0]`` to every closed sample [J], (N+1,): exact for linear pieces.
        Read-only: the cycle keeps it."""
        work = getattr(self, "_work", None)
        if work is None:
            phi, _, torque = self.closed()
            work = np.concatenate(([0.0], np.cumsum(0.5 * (torque[1:] + torque[:-1]) * np.diff(phi))))
            work.flags.writeable = False
            object.__setattr__(self, "_work", work)
        return work

    @property
    def cycle_work(self) -> float:
        """Net work of the torque over one cycle [J]; zero in steady motion."""
        return float(self.work_nodes()[-1])

    @property
    def mean_inertia(self) -> float:
        """Mean reduced inertia over the cycle [kg·m²]."""
        phi, inertia, _ = self.closed()
        return float(np.sum(0.5 * (inertia[1:] + inertia[:-1]) * np.diff(phi)) / self.period)

    def with_torque(self, torque: FloatArray) -> ReducedCycle:
        """The same cycle under another torque table [N·m]."""
        return replace(self, torque=np.asarray(torque, dtype=float))

    def balanced(self) -> tuple[ReducedCycle, float]:
        """The cycle with the constant driving torque that makes its work zero, and that torque [N·m]."""
        extra = -self.cycle_work / self.period
        return self.with_torque(self.torque + extra), extra

    def evaluate(self, phi: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Inertia [kg·m²], torque [N·m] and work from ``phi[0]`` [J] at any angles (taken modulo the period)."""
        nodes, inertia, torque = self.closed()
        work = self.work_nodes()
        x = self.phi[0] + np.mod(np.asarray(phi, dtype=float) - self.phi[0], self.period)
        i = np.clip(np.searchsorted(nodes, x, side="right") - 1, 0, self.samples - 1)
        h = nodes[i + 1] - nodes[i]
        s = x - nodes[i]
        t = s / h
        slope_m = (torque[i + 1] - torque[i]) / h
        return (
            inertia[i] + t * (inertia[i + 1] - inertia[i]),
            torque[i] + s * slope_m,
            work[i] + s * torque[i] + 0.5 * slope_m * s**2,
        )

    def dense(self, points: int = 20_000) -> FloatArray:
        """At least ``points`` angles over one cycle [rad] that include every sample, (M,)."""
        nodes, _, _ = self.closed()
        per = max(1, math.ceil(points / self.samples))
        t = np.arange(per) / per
        grid = (nodes[:-1, None] + t[None, :] * np.diff(nodes)[:, None]).reshape(-1)
        return np.append(grid, nodes[-1])


def _table(values: Sequence[float] | None, field: str, n: int) -> FloatArray | None:
    if values is None:
        return None
    arr = np.asarray(values, dtype=float)
    if arr.shape != (n,):
        raise InvalidInput(f"{field} has {arr.size} values but crank_angle_deg has {n}", field=f"tables.{field}")
    if not np.all(np.isfinite(arr)):
        raise InvalidInput(f"{field} must be finite", field=f"tables.{field}")
    return arr


def cycle_from_tables(
    crank_angle: Sequence[float],
    *,
    reduced_inertia: Sequence[float] | None = None,
    reduced_torque: Sequence[float] | None = None,
    driving_torque: Sequence[float] | None = None,
    resisting_torque: Sequence[float] | None = None,
    period: float = 2 * math.pi,
    max_samples: int = MAX_SAMPLES,
    balance: Literal["driving", "resisting"] | None = None,
) -> ReducedCycle:
    """A reduced cycle from tables over crank angle.

    Parameters
    ----------
    crank_angle
        Strictly increasing crank angles [rad] within one cycle; a last angle equal to the first plus
        ``period`` closes the table and must repeat the first sample's values.
    reduced_inertia
        J_red at each angle [kg·m²]; left out, the machine's inertia is all constant (zero here).
    reduced_torque
        Sum of driving and resisting reduced torques [N·m] (positive drives the crank); or give
        ``driving_torque`` and/or ``resisting_torque`` [N·m] (resisting ones negative, as the seeds tabulate
        them); one of the two alone stands for the whole given torque.
    period
        Cycle length [rad]: 2π, or 4π for a four-stroke engine.
    max_samples
        Largest table accepted (TooLarge beyond).
    balance
        Which side the constant balancing torque takes: ``driving`` or ``resisting``. Left out, it is
        ``resisting`` when only ``driving_torque`` is given (an engine: the consumer's load balances its gas
        torque) and ``driving`` otherwise.
    """
    phi = np.asarray(crank_angle, dtype=float)
    if phi.size > max_samples:
        raise TooLarge("table rows", max_samples, phi.size)
    field = "tables.crank_angle_deg"
    if phi.ndim != 1 or phi.size < 3:
        raise InvalidInput("crank_angle_deg needs at least three angles", field=field)
    if not np.all(np.isfinite(phi)) or not np.all(np.diff(phi) > 0):
        raise InvalidInput("crank_angle_deg must increase strictly", field=field)
    if not np.all(np.diff(phi) >= MIN_STEP * 360.0):
        at = int(np.argmin(np.diff(phi))) + 1
        raise InvalidInput(f"crank_angle_deg[{at}] is within {MIN_STEP * 360.0:g}° of the angle before it: the "
                           "slopes between them are lost in rounding", field=f"{field}[{at}]")
    n = phi.size
    inertia = _table(reduced_inertia, "reduced_inertia_kgm2", n)
    total = _table(reduced_torque, "reduced_torque_Nm", n)
    drive = _table(driving_torque, "driving_torque_Nm", n)
    resist = _table(resisting_torque, "resisting_torque_Nm", n)
    if (total is None) == (drive is None and resist is None):
        raise InvalidInput(
            "give reduced_torque_Nm, or driving_torque_Nm and/or resisting_torque_Nm", field="tables.reduced_torque_Nm"
        )
    torque_field = "reduced_torque_Nm"
    if balance is None:
        balance = "resisting" if drive is not None and resist is None else "driving"
    if total is None:
        torque_field = "resisting_torque_Nm" if resist is not None else "driving_torque_Nm"
        total = (np.zeros(n) if drive is None else drive) + (np.zeros(n) if resist is None else resist)
    if inertia is None:
        inertia = np.zeros(n)
    span = phi[-1] - phi[0]
    if span > period * (1 + 1e-12):
        raise InvalidInput(
            f"crank_angle_deg spans {math.degrees(span):g} deg, more than the cycle of {math.degrees(period):g} deg",
            field=field,
        )
    if abs(span - period) <= 1e-9 * period:
        for name, arr in (("reduced_inertia_kgm2", inertia), (torque_field, total)):
            if not math.isclose(arr[-1], arr[0], rel_tol=1e-9, abs_tol=1e-12 * (1 + np.abs(arr).max())):
                raise InvalidInput(
                    f"the table closes the cycle, so its last {name} must repeat the first", field=f"tables.{name}"
                )
        phi, inertia, total = phi[:-1], inertia[:-1], total[:-1]
        drive = None if drive is None else drive[:-1]
        resist = None if resist is None else resist[:-1]
    cycle = ReducedCycle(phi, inertia, total, period, balance)
    # each table's own work, on the same linear pieces as the cycle's, to tell a sign typed wrong from a role
    return replace(
        cycle,
        driving_work=None if drive is None else cycle.with_torque(drive).cycle_work,
        resisting_work=None if resist is None else cycle.with_torque(resist).cycle_work,
    )


def cycle_from_reduced(reduced: ReducedModel) -> ReducedCycle:
    """The reduced cycle of an analysed linkage over one crank revolution (J_red and the reduced load torque,
    less the pairs' friction losses when the analysis has friction)."""
    return ReducedCycle(
        np.asarray(reduced.phi, dtype=float),
        np.asarray(reduced.inertia, dtype=float),
        np.asarray(reduced.resisting_torque, dtype=float),
        2 * math.pi,
    )
