"""The design chain as the whole-machine optimisation searches it: its discrete choices alone, or its steady machine.

:func:`design_machine` ends with the start and run-down simulations (most of its time). What the optimisation's
objectives are made of (the motor, the balancing masses, the flywheel body, the shaking force after balancing)
and the steady checks (delta, mean speed, motor heating and breakdown) come before them. The search therefore
runs the chain to its steady machine (:func:`steady_member`) and the optimum's own design runs the whole chain,
start and run-down included, before it is answered.

:func:`discrete_choice` runs the chain only up to its discrete choices, the catalogue motor and the tooth numbers
(analysis, balancing, the drive's split, the tooth search), with the parts of the objectives they fix: the
motor's rated power, the balancing masses and the shaking force after balancing. The flywheel body is what it
leaves out, and it is never negative: the choice's figures bound the objectives from below.
"""

from __future__ import annotations

import math
import pickle
import threading
from collections import OrderedDict
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, fields, replace
from typing import Any, TypeVar

import numpy as np

from ..analysis import Analysis, analyse
from ..flywheel import Motor, ReducedCycle, cycle_from_reduced
from ..friction import friction_kinetostatics
from ..gearing import DriveResult, ToothResult, chain_efficiency, design_drive
from ..gearing.split import teeth_limited
from ..gearing.stages import Stage
from ..gearing.teeth import ToothRules
from ..kinematics import FourBar
from ..errors import InvalidInput
from . import chain as _chain
from .chain import MAX_MOTOR_UPGRADES, MIN_POWER, Balancing, MachineCheck
from .operating_point import MotorLoad, operating_speed
from .optimise_parts import MachineParts, machine_parts
from .simulate import MachineCycle
from .spec import MachineSpec
from .stages import refuse_likely_mistakes

#: Bisections of the face width when the search sizes the wheels for their mass: the width within ln(5)/2^12,
#: a few parts in 1e4, never below the least (the answer's own design sizes them to the chain's precision).
SEARCH_WIDTH_STEPS = 12

#: Crank angles of the stages (a member's analyses and balancing, about 1 kB an angle, or its drive) one
#: optimisation keeps in a process: 133 at 120 samples (half of them analyses), 22 at 720; and optimisations kept
#: at once.
KEPT_SAMPLES = 16_000
KEPT_RUNS = 2

#: A member's discrete choice: the catalogue motor's name and each toothed stage's (pinion, gear) teeth.
Choice = tuple[str, tuple[tuple[int, int], ...]]


@dataclass(frozen=True, slots=True)
class DiscreteChoice:
    """The chain's discrete choices for one member and the objectives' parts they fix: ``choice`` motor and
    teeth, ``motor_power`` rated [W], ``balancing_mass`` counterweights and balancer masses [kg],
    ``rms_shaking_force`` after balancing [N]."""

    choice: Choice
    motor_power: float
    balancing_mass: float
    rms_shaking_force: float


@dataclass(frozen=True, slots=True)
class SteadyMember:
    """One member's steady machine: its discrete ``choice``, objectives [W, kg, N] in the optimisation's order,
    the RMS shaking moment after balancing [N·m], the steady checks failed (by name), the RMS shaking force
    before balancing [N], the balancing masses [kg] and the machine's parts (the gear wheels' mass only when
    sized)."""

    choice: Choice
    values: tuple[float, float, float]
    rms_shaking_moment: float
    failed: tuple[str, ...]
    rms_shaking_force_before: float
    balancing_mass: float
    parts: MachineParts


def balancing_mass(bal: Balancing) -> float:
    """Counterweights and Lanchester balancer masses [kg] of the chain's balancing stage."""
    mass = 0.0
    if bal.result is not None:
        mass += sum(c.mass for c in bal.result.counterweights)
    if bal.slider_crank is not None:
        mass += bal.slider_crank.crank_counterweight.mass
        if bal.mode == "full":
            mass += sum(2 * p.mass for p in bal.slider_crank.pairs)  # each pair: two shafts, each with its mass
    return float(mass)


T = TypeVar("T")
_KEPT: OrderedDict[str, OrderedDict[bytes, Any]] = OrderedDict()
_KEPT_LOCK = threading.Lock()  # a worker of several threads may run two stages of one run at once
_RUN: ContextVar[str | None] = ContextVar("optimisation_run", default=None)


@contextmanager
def kept(run: str) -> Iterator[None]:
    """Within it, a member's analysis, balancing, drive and teeth are computed once in this process for the
    optimisation ``run`` (a name of its own): the search asks for a member more than once (its bound, then its
    steady machine; a plateau's ends found by the walk's bisection, then searched), and the stages' answers
    depend on the member alone. Another run never sees them."""
    token = _RUN.set(run)
    try:
        yield
    finally:
        _RUN.reset(token)


def forget(run: str) -> None:
    """Let go of what the optimisation ``run`` kept in this process (it has ended)."""
    with _KEPT_LOCK:
        _KEPT.pop(run, None)


def _once(key: tuple[Any, ...], samples: int, compute: Callable[[], T]) -> T:
    run = _RUN.get()
    if run is None:
        return compute()
    name = pickle.dumps(key)
    with _KEPT_LOCK:
        store = _KEPT.get(run)
        if store is None:
            store = _KEPT[run] = OrderedDict()
            while len(_KEPT) > KEPT_RUNS:
                _KEPT.popitem(last=False)
        if name in store:
            store.move_to_end(name)
            return store[name]  # type: ignore[no-any-return]
    out = compute()
    with _KEPT_LOCK:
        store[name] = out
        while len(store) > max(2, KEPT_SAMPLES // samples):
            store.popitem(last=False)
    return out


def _named(machine: MachineSpec) -> tuple[Any, ...]:
    """What a machine's stages depend on: its fields, the linkage's compared ones (not the caches it fills)."""
    link = machine.linkage
    return (tuple(getattr(link, f.name) for f in fields(link) if f.compare),
            tuple(getattr(machine, f.name) for f in fields(machine) if f.name != "linkage"))


def _front(machine: MachineSpec, time_limit_s: float) -> tuple[Analysis, Balancing, Analysis, ReducedCycle, float]:
    """Analysis, balancing and the cycle's mean output power, exactly as the chain makes them."""
    return _once(("front", _named(machine), time_limit_s), machine.samples,
                 lambda: _front_of(machine, time_limit_s))


def _front_of(machine: MachineSpec,
              time_limit_s: float) -> tuple[Analysis, Balancing, Analysis, ReducedCycle, float]:
    machine.validate()
    refuse_likely_mistakes(machine.linkage)
    # a four-bar's static balancing analyses the linkage itself, as the chain's analysis before it does when the
    # pairs have no friction: that analysis is the one before
    own = (machine.balancing.mode == "static" and isinstance(machine.linkage.mechanism, FourBar)
           and not machine.friction)
    before = None if own else analyse(machine.linkage, machine.speed, samples=machine.samples,
                                      friction=machine.friction)
    bal, balanced = _chain._balance(machine, before, time_limit_s)
    if before is None:
        assert bal.result is not None
        before = bal.result.analysis_before
    if machine.friction:
        fr = friction_kinetostatics(balanced.motion, balanced.linkage, balanced.kinetostatics, machine.friction)
        balanced = replace(balanced, friction=fr, reduced=replace(balanced.reduced, friction_torque=fr.loss_torque))
    cycle = cycle_from_reduced(balanced.reduced)
    output_power = -cycle.cycle_work / cycle.period * machine.speed
    if not output_power > MIN_POWER:
        raise InvalidInput("the linkage does no work over the cycle, so there is no power to choose a motor for: "
                           "give its process load", field="loads")
    return before, bal, balanced, cycle, output_power


def _drive(machine: MachineSpec, output_power: float, motor_name: str | None,
           time_limit_s: float) -> tuple[DriveResult, ToothResult | None, tuple[float, ...], list[Stage]]:
    drive, teeth, ratios, stages = _once(("drive", _named(machine), output_power, motor_name, time_limit_s),
                                         machine.samples,
                                         lambda: _drive_of(machine, output_power, motor_name, time_limit_s))
    return drive, teeth, ratios, list(stages)


def _drive_of(machine: MachineSpec, output_power: float, motor_name: str | None,
              time_limit_s: float) -> tuple[DriveResult, ToothResult | None, tuple[float, ...], tuple[Stage, ...]]:
    d = machine.drive
    motor_power = output_power / chain_efficiency(d.stages)
    stages, _ = teeth_limited(d.stages, d.tooth_rules or ToothRules())
    drive = design_drive(output_power, machine.speed, stages, reserve_factor=d.reserve_factor,
                         synchronous_speed=d.synchronous_speed, motor=motor_name, objective=d.objective,
                         torque_basis="load", inertia=d.inertia, time_limit_s=time_limit_s,
                         catalogue=d.catalogue, motor_speed=MotorLoad(motor_power))
    if d.motor is not None:
        operating_speed(drive.motor, motor_power)
    teeth, ratios, _ = _chain._teeth(machine, drive, stages)
    return drive, teeth, tuple(ratios), tuple(stages)


def _choice(drive: DriveResult, teeth: ToothResult | None) -> Choice:
    pairs = () if teeth is None else tuple((s.pinion_teeth, s.gear_teeth) for s in teeth.stages)
    return drive.motor.name, pairs


def discrete_choice(machine: MachineSpec, *, time_limit_s: float = 20.0) -> DiscreteChoice:
    """The motor and teeth the chain chooses from the mean power (before any upgrade the simulated cycle asks)
    and the objectives' parts they fix. Raises as :func:`design_machine` does."""
    _, bal, _, _, power = _front(machine, time_limit_s)
    drive, teeth, _, _ = _drive(machine, power, machine.drive.motor, time_limit_s)
    return DiscreteChoice(_choice(drive, teeth), float(drive.motor.rated_power), balancing_mass(bal),
                          float(bal.after.rms_shaking_force))


def steady_member(machine: MachineSpec, *, time_limit_s: float = 20.0, size_gears: bool = False,
                  width_steps: int | None = SEARCH_WIDTH_STEPS) -> SteadyMember:
    """The chain to its steady machine: motor (stepped up as the chain steps it up on the steady checks),
    teeth, flywheel and the steady checks; no start or run-down simulation. ``size_gears`` sizes the wheels
    for strength on the steady cycle as the chain does (the drive's strength rules; none: no wheels counted),
    for their mass, with ``width_steps`` bisections of the face width (None: the chain's own precision). Raises
    as :func:`design_machine`."""
    before, bal, balanced, cycle, power = _front(machine, time_limit_s)
    d = machine.drive
    motor_name = d.motor
    red = balanced.reduced
    machine_cycle = MachineCycle(red.phi, red.inertia, red.inertia_slope, red.resisting_torque)
    for _ in range(MAX_MOTOR_UPGRADES + 1):
        drive, teeth, ratios, _ = _drive(machine, power, motor_name, time_limit_s)
        train_ratio = math.prod(ratios)
        motor = Motor.from_catalogue(drive.motor, train_ratio, drive.chain_efficiency)
        speed_ratios = [math.prod(ratios[k:]) for k in range(len(ratios))] + [1.0]
        own = np.array([s.inertia for s in drive.shafts])
        train = float(own @ np.square(speed_ratios)) - motor.reduced().inertia + bal.balancer_inertia
        flywheel, placement, motion = _chain._flywheel(machine, motor, cycle, machine_cycle, ratios, train,
                                                       time_limit_s)
        checks: tuple[MachineCheck, ...] = _chain._checks(machine, motion, motor)
        heavy = [c.name for c in checks if c.name in ("motor_rms_torque", "motor_peak_torque") and not c.passed]
        bigger = None if d.motor is not None or not heavy else _chain._next_motor(drive.motor, d.catalogue)
        if bigger is None:
            break
        motor_name = bigger.name
    gears = None
    if size_gears and machine.drive.strength is not None:
        inertia = flywheel.design.flywheel_inertia
        shafts = _chain._shafts(ratios, drive, motion, placement, inertia)
        torques = _chain._shaft_torques(ratios, drive, motion, placement, inertia)
        gears, _ = _chain._gears(machine, teeth, ratios, torques, motion, shafts, width_steps=width_steps)
    parts = machine_parts(bal, placement, gears, size_gears, drive.motor)
    mass = balancing_mass(bal) + (placement.mass if placement is not None else 0.0)
    return SteadyMember(_choice(drive, teeth), (float(drive.motor.rated_power), float(mass),
                                                float(bal.after.rms_shaking_force)),
                        float(bal.after.rms_shaking_moment), tuple(c.name for c in checks if not c.passed),
                        float(before.summary().rms_shaking_force), balancing_mass(bal), parts)
