"""The machine around its linkage within the design chain: the frame on its isolators, the elastic drive and the
speed after a load step, each for the designed machine.

Each block is the standalone capability called as its endpoint calls it, fed with what the chain has designed:
the foundation takes the balanced linkage's shaking force and moment at the working speed (the Lanchester
balancers' included); the elastic drive and the regulation take the balanced linkage reduced to its crank, the
chosen motor through the real train and the constant inertia of rotor, train and flywheel. The elastic link sits
between the motor's rotor (with the flywheel when it sits on the motor shaft) and everything after it. Each limit
the request gives becomes one check of the machine's list, passed or not.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import Infeasible, InvalidInput
from ..flywheel import FlywheelBody, Motor
from ..model import FloatArray
from ..warnings import DesignWarning
from .elastic_drive import ElasticDrive, ElasticElement, elastic_drive, link_stiffness
from .foundation import Forcing, Frame, Isolation, Isolator, frame_model, isolate, with_run_up
from .regulation import PIController, Regulation, regulate, tune_pi
from .simulate import MachineCycle
from .startup import StartUp


@dataclass(frozen=True, slots=True)
class FoundationChoice:
    """The machine's frame on isolators (see :func:`synth.machine.foundation.isolate`); limits of the peak force
    to the foundation ``max_force`` [N] and of the frame centre's amplitude ``max_amplitude`` [m] (None: not
    checked); ``run_up`` also follows the frame while the designed machine runs up from rest."""

    frame: Frame
    isolators: tuple[Isolator, ...]
    max_force: float | None = None
    max_amplitude: float | None = None
    run_up: bool = False


@dataclass(frozen=True, slots=True)
class ElasticDriveChoice:
    """The elastic link between the motor's rotor and the train: its ``stiffness`` reduced to the crank
    [N·m/rad] or its ``elements``; ``motor_side_inertia`` on the motor shaft besides the rotor [kg·m²];
    ``damping_ratio`` of the two-mass mode [-]; ``start`` also the run-up with the link; ``max_dynamic_factor``
    the limit of peak elastic over peak rigid torque [-] (None: not checked)."""

    stiffness: float | None = None
    elements: tuple[ElasticElement, ...] = ()
    motor_side_inertia: float = 0.0
    damping_ratio: float = 0.05
    start: bool = True
    max_dynamic_factor: float | None = None


@dataclass(frozen=True, slots=True)
class RegulationChoice:
    """A step ``load_step`` in the process load [N·m at the crank, positive resists]; ``delta`` a band delta·w/2
    the settling is judged in [-] (None: 2 % of the step's dip); a PI ``controller`` with given gains or ``tuning``
    (settling time [s], overshoot [-], filter time [s]), neither: self-regulation; limits ``max_settling_time``
    [s] and ``max_speed_drop`` of the mean crank speed [rad/s] (None: not checked)."""

    load_step: float
    delta: float | None = None
    controller: PIController | None = None
    tuning: tuple[float, float, float] | None = None
    max_settling_time: float | None = None
    max_speed_drop: float | None = None


@dataclass(frozen=True, slots=True)
class ElasticInDesign:
    """The elastic drive of the designed machine: ``drive`` its answer; the inertias it was given, on the motor
    shaft besides the rotor ``motor_side_inertia`` [kg·m²] and on the machine's side reduced to the crank
    ``machine_constant_inertia`` [kg·m²]; ``gear_torque_basis`` "elastic" when a sized gear stage takes the
    elastic link's torque at some crank angle (it is larger there), "rigid" otherwise."""

    drive: ElasticDrive
    motor_side_inertia: float
    machine_constant_inertia: float
    gear_torque_basis: str = "rigid"


@dataclass(frozen=True, slots=True)
class RegulationInDesign:
    """The load step on the designed machine: ``regulation`` its answer, ``constant_inertia`` of rotor, train and
    flywheel reduced to the crank it ran with [kg·m²]."""

    regulation: Regulation
    constant_inertia: float


def check_choices(foundation: FoundationChoice | None, elastic: ElasticDriveChoice | None) -> None:
    """Refuse a frame that cannot stand on its isolators or a link without stiffness before the chain runs
    (InvalidInput naming the field as the machine request spells it)."""
    if foundation is not None:
        try:
            frame_model(foundation.frame, foundation.isolators)
        except InvalidInput as exc:
            raise InvalidInput(str(exc), field=_under("foundation", exc.field)) from exc
    if elastic is not None and elastic.stiffness is None and elastic.elements:
        try:
            link_stiffness(elastic.elements)
        except InvalidInput as exc:
            raise InvalidInput(str(exc), field=_under("elastic_drive", exc.field)) from exc
    if elastic is not None and (elastic.stiffness is None) == (not elastic.elements):
        raise InvalidInput("give the link's stiffness or its elements, one of the two",
                           field="elastic_drive.stiffness_Nm_rad")


def forcing_of_design(phi: FloatArray, speed: float, force: FloatArray, moment: FloatArray) -> Forcing:
    """The balanced machine's pull on its frame at the working ``speed`` [rad/s]: shaking force [N] (N, 2) and
    moment about O [N·m] (N,) at uniform crank angles ``phi`` [rad]."""
    return Forcing(np.asarray(phi, dtype=float), float(speed), np.asarray(force, dtype=float),
                   np.asarray(moment, dtype=float))


def foundation_of_design(choice: FoundationChoice, forcing: Forcing, start: StartUp | None) -> Isolation:
    """The frame on its isolators under the designed machine's ``forcing``; with ``choice.run_up`` also the
    passage while it runs up, on the design's own start-up ``start`` (idling unless it starts under load)."""
    _positive(choice.max_force, "foundation.max_force_N")
    _positive(choice.max_amplitude, "foundation.max_amplitude_m")
    try:
        result = isolate(choice.frame, choice.isolators, forcing)
        if choice.run_up:
            if start is None:
                raise InvalidInput("the design has no start-up to follow", field="run_up")
            result = with_run_up(result, forcing, start)
    except InvalidInput as exc:
        raise InvalidInput(str(exc), field=_under("foundation", exc.field)) from exc
    except Infeasible as exc:
        raise Infeasible(exc.reason, "foundation.run_up", **exc.details) from exc
    return result


def elastic_of_design(choice: ElasticDriveChoice, cycle: MachineCycle, motor: Motor,
                      train_inertia: float, flywheel_inertia: float,
                      placement: FlywheelBody | None, start_cycle: MachineCycle) -> ElasticInDesign:
    """The designed machine driven through the elastic link: the rotor and whatever sits on the motor shaft
    with it (the flywheel there) on one side; the train and the flywheel elsewhere, reduced to the crank
    [kg·m²], on the other. The run-up drives ``start_cycle`` (idling, as the design's start-up does, unless
    the machine starts under load)."""
    if (choice.stiffness is None) == (not choice.elements):
        raise InvalidInput("give the link's stiffness or its elements, one of the two",
                           field="elastic_drive.stiffness_Nm_rad")
    _positive(choice.max_dynamic_factor, "elastic_drive.max_dynamic_factor")
    on_motor = placement is not None and placement.shaft == "motor"
    motor_side = choice.motor_side_inertia + (placement.inertia if on_motor and placement is not None else 0.0)
    machine_side = train_inertia + (0.0 if on_motor else flywheel_inertia)
    try:
        c = choice.stiffness if choice.stiffness is not None else link_stiffness(choice.elements)
        drive = elastic_drive(cycle, motor, c, machine_inertia=machine_side, motor_side_inertia=motor_side,
                              damping_ratio=choice.damping_ratio, start=choice.start, start_cycle=start_cycle)
    except InvalidInput as exc:
        raise InvalidInput(str(exc), field=_under("elastic_drive", exc.field)) from exc
    return ElasticInDesign(drive, motor_side, machine_side)


def regulation_of_design(choice: RegulationChoice, cycle: MachineCycle, motor: Motor,
                         constant_inertia: float) -> RegulationInDesign:
    """The designed machine after the load step, settling judged in 2 % of the dip unless the block gives its
    own delta; a tuned controller is tuned for the machine's mean inertia and the characteristic's slope at
    the crank, as POST /v1/machines/regulation tunes it."""
    _positive(choice.max_settling_time, "regulation.max_settling_time_s")
    _positive(choice.max_speed_drop, "regulation.max_speed_drop_rad_s")
    controller = choice.controller
    try:
        if choice.tuning is not None:
            j_mean = float(np.mean(cycle.inertia)) + constant_inertia
            controller = tune_pi(j_mean, motor.reduced().slope, *choice.tuning)
        target = None if choice.tuning is None else (choice.tuning[0], choice.tuning[1])
        result = regulate(cycle, constant_inertia, motor, choice.load_step, delta=choice.delta,
                          controller=controller, target=target)
    except InvalidInput as exc:
        raise InvalidInput(str(exc), field=_under("regulation", exc.field)) from exc
    except Infeasible as exc:
        raise Infeasible(exc.reason, _under("regulation", exc.constraint), **exc.details) from exc
    return RegulationInDesign(result, constant_inertia)


def elastic_shaft_torques(rigid: FloatArray, phi: FloatArray, elastic: ElasticDrive, ratios: FloatArray,
                          efficiencies: FloatArray, train_efficiency: float) -> FloatArray:
    """The torque each shaft passes on (shafts, M) [N·m] at the simulated machine's angles ``phi`` [rad] with the
    elastic link: the rigid torques ``rigid`` plus the link's excess over the rigid model's torque at the crank,
    carried to shaft k as a motor torque would be, times eta_0k/(eta·r_k) (``ratios`` r_k shaft over crank speed,
    ``efficiencies`` eta_0k from the motor to shaft k, ``train_efficiency`` eta); the larger magnitude of the
    two at every angle and shaft."""
    excess = np.interp(phi, elastic.phi, elastic.steady.elastic_torque - elastic.rigid_torque, period=2 * math.pi)
    carried = rigid + np.outer(efficiencies / (train_efficiency * ratios), excess)
    return np.asarray(np.where(np.abs(carried) > np.abs(rigid), carried, rigid), dtype=float)


@dataclass(frozen=True, slots=True)
class Limit:
    """One limit of a block as a check: ``name``, ``value`` against ``limit`` [``unit``], words."""

    name: str
    value: float
    limit: float
    passed: bool
    detail: str
    unit: str
    label: str


def foundation_limits(choice: FoundationChoice, r: Isolation) -> list[Limit]:
    """The foundation block's limits against the frame's steady cycle."""
    out = []
    if choice.max_force is not None:
        out.append(Limit("foundation_force", r.peak_force, choice.max_force, r.peak_force <= choice.max_force,
                         "largest force all isolators pass to the foundation over the steady cycle [N]", "N",
                         "force to the foundation, peak"))
    if choice.max_amplitude is not None:
        out.append(Limit("foundation_amplitude", r.peak_displacement, choice.max_amplitude,
                         r.peak_displacement <= choice.max_amplitude,
                         "largest displacement of the frame's centre over the steady cycle [m]", "m",
                         "frame amplitude, peak"))
    return out


def elastic_limits(choice: ElasticDriveChoice, e: ElasticDrive) -> list[Limit]:
    """The elastic drive's limit on its dynamic factor."""
    if choice.max_dynamic_factor is None:
        return []
    return [Limit("dynamic_factor", e.dynamic_factor, choice.max_dynamic_factor,
                  e.dynamic_factor <= choice.max_dynamic_factor,
                  "peak torque in the elastic link over the rigid model's peak, steady cycle", "",
                  "elastic drive, dynamic factor")]


def regulation_limits(choice: RegulationChoice, g: Regulation) -> list[Limit]:
    """The load step's limits: the time to settle in the band (not settling within the run fails it) and the
    mean speed's drop."""
    out = []
    if choice.max_settling_time is not None:
        value = g.settling_time if g.settling_time is not None else float(g.time[-1] - g.step_time)
        out.append(Limit("regulation_settling_time", value, choice.max_settling_time,
                         g.settling_time is not None and value <= choice.max_settling_time,
                         "time after the load step until the speed, its cycle's fluctuation taken off, stays in "
                         "the settling band [s]", "s", "settling after the load step"))
    if choice.max_speed_drop is not None:
        drop = g.drop if g.controller is None else g.max_deviation
        out.append(Limit("regulation_speed_drop", abs(drop), choice.max_speed_drop,
                         abs(drop) <= choice.max_speed_drop,
                         "drop of the mean crank speed after the load step (self-regulation), or the largest "
                         "deviation from the reference (with the regulator) [rad/s]", "rad/s",
                         "speed drop after the load step"))
    return out


def elastic_warnings(e: ElasticDrive) -> list[DesignWarning]:
    """A load harmonic near the link's natural frequency, each named."""
    return [DesignWarning("load_harmonic_near_resonance", "elastic_drive.stiffness_Nm_rad", h.ratio,
                          f"harmonic {h.order} of the load torque ({h.frequency:.4g} Hz, {h.amplitude:.4g} N·m) "
                          f"lies within 15 % of the elastic link's natural frequency ({e.natural_frequency:.4g} "
                          "Hz): change the stiffness or the inertias", stage="elastic_drive")
            for h in e.harmonics if h.near]


def _positive(value: float | None, field: str) -> None:
    if value is not None and not (math.isfinite(value) and value > 0):
        raise InvalidInput("a limit must be positive", field=field)


def _under(block: str, field: str | None) -> str:
    """A standalone endpoint's field named as the machine request spells it."""
    if field is None:
        return block
    field = field.removeprefix("run_up.")
    return f"{block}.{field}"
