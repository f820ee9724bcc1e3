"""One flywheel request end to end: every sizing method side by side, each checked by the equation of motion."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InvalidInput
from .cycle import ReducedCycle
from .geometry import FlywheelDesign, GeometrySpec, design_flywheel
from .motor import Motor, motor_constant_inertia, motor_speed_limits
from .simulate import SpeedProfile, steady_speed, steady_speed_motor
from .sizing import (
    Tangents,
    energy_method_constant_inertia,
    exact_constant_inertia,
    mertsalov_constant_inertia,
    speed_band,
    wittenbauer_tangents,
)


@dataclass(frozen=True, slots=True)
class MethodResult:
    """One sizing method's answer and the steady motion it gives.

    ``required_constant_inertia`` J_c on top of J_red(phi) [kg·m²]; ``flywheel_inertia`` what must be added to
    the constant inertia already there, never negative [kg·m²]; ``speed`` the simulated steady motion with it.
    """

    method: str
    required_constant_inertia: float
    flywheel_inertia: float
    speed: SpeedProfile

    @property
    def achieved_delta(self) -> float:
        """Delta of the simulated steady motion [-]."""
        return self.speed.delta


@dataclass(frozen=True, slots=True)
class FlywheelResult:
    """Flywheel sizing of one machine cycle.

    ``cycle`` the cycle as sized, its torque balanced over the cycle (with a motor: the load torque plus the
    motor's mean torque); ``driving_torque`` the constant driving torque that balances the cycle's work [N·m];
    ``cycle_work`` the work of the given torques before it [J]; ``constant_inertia`` already on the crank (rotor
    included) [kg·m²]; ``methods`` every method with its check; ``design_method`` the one the geometry uses;
    ``motor_mean_speed`` the motor's angle-average steady speed [rad/s] (None without a motor).
    """

    cycle: ReducedCycle
    mean_speed: float
    target_delta: float
    constant_inertia: float
    driving_torque: float
    cycle_work: float
    tangents: Tangents
    methods: tuple[MethodResult, ...]
    design_method: str
    geometry: FlywheelDesign | None
    motor_mean_speed: float | None

    def method(self, name: str) -> MethodResult:
        """The result of the method called ``name`` (exact, mertsalov, energy, motor_nlp)."""
        for m in self.methods:
            if m.method == name:
                return m
        raise KeyError(name)

    @property
    def design(self) -> MethodResult:
        """The method the flywheel is designed with: exact for a constant driving torque, motor_nlp with a motor."""
        return self.method(self.design_method)

    @property
    def speed_band(self) -> tuple[float, float]:
        """Target w_min, w_max [rad/s]."""
        return speed_band(self.mean_speed, self.target_delta)


def size_flywheel(
    cycle: ReducedCycle,
    mean_speed: float,
    delta: float,
    *,
    constant_inertia: float = 0.0,
    motor: Motor | None = None,
    geometry: GeometrySpec | None = None,
    time_limit_s: float = 20.0,
) -> FlywheelResult:
    """Size a flywheel for ``delta`` at ``mean_speed`` [rad/s] by every method and check each one.

    Parameters
    ----------
    cycle
        Reduced cycle: J_red(phi) [kg·m²] and the reduced torque of everything given [N·m]. Without a motor a
        constant driving torque balances its work; with one, ``cycle.torque`` is the load alone.
    mean_speed
        w_m = (w_max + w_min)/2 [rad/s].
    delta
        Target coefficient of speed fluctuation (w_max - w_min)/w_m [-].
    constant_inertia
        Constant inertia already on the crank (rotor, gears reduced) [kg·m²].
    motor
        Static characteristic and gearing of the motor; None for a constant driving torque.
    geometry
        Material, limits and shafts to shape the flywheel; None to size it only.
    time_limit_s
        IPOPT's wall-time limit per NLP [s].
    """
    if constant_inertia < 0:
        raise InvalidInput("constant inertia must not be negative", field="constant_inertia_kgm2")
    speed_band(mean_speed, delta)
    balanced, driving = cycle.balanced()
    existing = constant_inertia
    reduced_motor = None
    if motor is not None:
        reduced_motor = motor.reduced()
        existing += reduced_motor.inertia
        motor_speed_limits(cycle, reduced_motor, mean_speed, delta)  # fail fast, before any simulation

    def simulate(j_c: float) -> SpeedProfile:
        if reduced_motor is None:
            return steady_speed(balanced, j_c, mean_speed)
        return steady_speed_motor(cycle, j_c, reduced_motor)

    def result(name: str, required: float) -> MethodResult:
        used = max(required, existing)
        return MethodResult(name, required, used - existing, simulate(used))

    exact = exact_constant_inertia(balanced, mean_speed, delta)
    methods = [
        result("exact", exact),
        result("mertsalov", mertsalov_constant_inertia(balanced, mean_speed, delta)),
        result("energy", energy_method_constant_inertia(balanced, mean_speed, delta)),
    ]
    design_method = "exact"
    if reduced_motor is not None:
        # the exact method's motion under the motor starts IPOPT close to a periodic solution
        first = methods[0].speed
        start = np.interp(cycle.phi, first.phi, first.omega)
        nlp = motor_constant_inertia(
            cycle, reduced_motor, mean_speed, delta, guess=max(exact, 1e-9), start=start, time_limit_s=time_limit_s
        )
        methods.append(result("motor_nlp", nlp.constant_inertia))
        design_method = "motor_nlp"
    design = next(m for m in methods if m.method == design_method)
    shape = None
    if geometry is not None and design.flywheel_inertia > 0:
        shape = design_flywheel(design.flywheel_inertia, geometry, design.speed.omega_max)
    return FlywheelResult(
        cycle=balanced,
        mean_speed=mean_speed,
        target_delta=delta,
        constant_inertia=existing,
        driving_torque=driving,
        cycle_work=cycle.cycle_work,
        tangents=wittenbauer_tangents(balanced, mean_speed, delta),
        methods=tuple(methods),
        design_method=design_method,
        geometry=shape,
        motor_mean_speed=None if reduced_motor is None else reduced_motor.mean_speed(cycle),
    )
