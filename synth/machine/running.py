"""How a designed machine really runs: the efficiency of each stage, its start-up and its run-down.

The linkage's efficiency is its cycle efficiency with friction in the pairs (1 without friction), the gears'
the product of the stage efficiencies, the overall their product. The start-up runs the assembled machine
(linkage reduced to its crank, rotor, train and flywheel) from rest at the crank angle where starting is
hardest, with the motor's starting torque and the pairs' breakaway friction; the run-down switches the motor
off in the steady state, with the request's brake torque. Unless asked to start under load, the machine starts
and runs up idling (its process load engaged once it runs, as a press's clutch does).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from ..analysis import Analysis
from ..dynamics import reduced_model
from ..flywheel import Motor
from ..friction import PairFriction, breakaway_torque, friction_kinetostatics
from ..kinetostatics import solve_direct
from .simulate import MachineCycle
from .startup import RunDown, StartUp, simulate_rundown, simulate_startup


@dataclass(frozen=True, slots=True)
class Efficiency:
    """Efficiency of each stage over the steady cycle [-]: ``linkage`` (None when the drive does no net work on
    it), ``gears`` the train's, ``overall`` their product (None with the linkage's)."""

    linkage: float | None
    gears: float
    overall: float | None


@dataclass(frozen=True, slots=True)
class MachineRunning:
    """The stages' efficiencies, the start-up from rest and the run-down to rest of the assembled machine;
    ``constant_inertia`` rotor, train and flywheel reduced to the crank [kg·m²]."""

    efficiency: Efficiency
    startup: StartUp
    rundown: RunDown
    constant_inertia: float


def machine_running(balanced: Analysis, motor: Motor, constant_inertia: float, gear_efficiency: float,
                    friction: Sequence[PairFriction] = (), brake_torque: float = 0.0,
                    start_under_load: bool = False, steady_start: float | None = None) -> MachineRunning:
    """Efficiencies, start-up and run-down of the machine whose balanced linkage is ``balanced``.

    Parameters
    ----------
    balanced
        The balanced linkage's analysis at the working speed, with friction in its pairs when it has any.
    motor
        The chosen motor through the real train ratio and efficiency.
    constant_inertia
        Rotor, train and flywheel reduced to the crank [kg·m²].
    gear_efficiency
        The train's efficiency [-].
    friction
        Friction per pair (its static coefficients give the breakaway torque).
    brake_torque
        Brake torque at the crank during the run-down [N·m].
    start_under_load
        The machine starts and runs up with its process load on (a press stopped in the stroke); else it starts
        and runs up idling, against gravity, link torques and the friction these cause, to its idle steady
        state (a press's flywheel run up before the clutch engages the stroke). Either way from the crank angle
        where starting is hardest.
    steady_start
        The working steady speed at the first sample when the caller has simulated it [rad/s]: the start-up's
        and the run-down's steady states are shot for from it (fewer integrations, the same states).
    """
    red = balanced.reduced
    cycle = MachineCycle(red.phi, red.inertia, red.inertia_slope, red.load_torque)
    running = None if red.friction_torque is None else np.maximum(red.friction_torque, 0.0)
    if start_under_load:
        start_cycle, start_friction, at_rest = cycle, running, balanced.linkage
    else:
        # idling: gravity and link torques only, the pairs' friction under those alone
        at_rest = replace(balanced.linkage, loads=())
        idle = reduced_model(balanced.motion, at_rest)
        start_cycle = MachineCycle(red.phi, red.inertia, red.inertia_slope, idle.load_torque)
        start_friction = None
        if friction:
            kin = solve_direct(balanced.motion, at_rest)
            start_friction = np.maximum(friction_kinetostatics(balanced.motion, at_rest, kin, friction).loss_torque,
                                        0.0)
    breakaway = breakaway_torque(at_rest, friction, red.phi) if friction else None
    startup = simulate_startup(start_cycle, constant_inertia, motor, friction_torque=start_friction,
                               breakaway_torque=None if breakaway is None else np.maximum(breakaway, 0.0),
                               steady_start=steady_start)
    rundown = simulate_rundown(cycle, constant_inertia, motor, friction_torque=running, brake_torque=brake_torque,
                               steady_start=steady_start)
    linkage = 1.0 if balanced.friction is None else balanced.friction.cycle_efficiency
    overall = None if linkage is None else linkage * gear_efficiency
    return MachineRunning(Efficiency(linkage, gear_efficiency, overall), startup, rundown, constant_inertia)
