"""A drive from motor to output: motor choice, ratio split, and what every shaft carries.

Procedure of seed 004:730-830: the required motor power is the output power times a reserve factor over the
drive efficiency; the smallest catalogue motor covering it is chosen; the total ratio is its rated speed over
the output speed; the ratio is split between the stages; speeds, powers and torques follow downstream through
the stage efficiencies; every shaft's inertia is reduced to the motor shaft by the square of its ratio.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import Literal

import numpy as np

from ..errors import Infeasible, InvalidInput
from ..warnings import DesignWarning
from .motors import CatalogueMotor, find_motor, select_motor
from .sizing import SIZED_TYPES, SizingRules, StageLoad, TrainSizing, size_train, split_for_strength
from .split import InertiaModel, SplitResult, split_ratio
from .stages import Stage, chain_efficiency, stage_name

TorqueBasis = Literal["load", "rated"]


@dataclass(frozen=True, slots=True)
class DriveShaft:
    """One shaft, 0 = motor shaft: ``speed`` [rad/s], ``power`` [W], ``torque`` [N·m], ``inertia`` of what
    it carries [kg·m²], ``reduced_inertia`` that inertia on the motor shaft [kg·m²]."""

    speed: float
    power: float
    torque: float
    inertia: float
    reduced_inertia: float


@dataclass(frozen=True, slots=True)
class DriveChecks:
    """Independent check figures: ``power_balance_error`` |P_out - P_0 * prod(eta)|/P_out [-] from the shaft
    torques and speeds; ``kinetic_energy`` sum of 1/2 J_k w_k² over the shafts and ``reduced_kinetic_energy``
    1/2 J_red w_0² at the motor speed the drive uses [J], which must agree."""

    power_balance_error: float
    kinetic_energy: float
    reduced_kinetic_energy: float


@dataclass(frozen=True, slots=True)
class DriveResult:
    """A drive design.

    ``required_power`` P_out * reserve / eta [W]; ``drive_efficiency`` the eta used there [-];
    ``chain_efficiency`` product of stage efficiencies [-]; ``total_ratio`` motor speed (rated, or the one given
    by ``motor_speed``) / output speed [-];
    ``stage_efficiencies`` [-]; ``shafts`` motor shaft first; ``reduced_inertia`` everything on the motor shaft
    [kg·m²]; ``output_speed`` reached [rad/s]; ``torque_basis``: ``rated`` (motor's rated power, as the seed
    does) or ``load`` (the power the output needs); ``gears`` every cylindrical stage sized for strength from
    its shaft torque (None when no strength rules were given); ``volume_agreement`` |V_split/V_sized - 1| of
    a strength-based split (None otherwise).
    """

    motor: CatalogueMotor
    required_power: float
    drive_efficiency: float
    chain_efficiency: float
    total_ratio: float
    split: SplitResult
    stage_efficiencies: tuple[float, ...]
    shafts: tuple[DriveShaft, ...]
    reduced_inertia: float
    output_speed: float
    torque_basis: str
    checks: DriveChecks
    warnings: tuple[DesignWarning, ...] = field(default=())
    gears: TrainSizing | None = None
    volume_agreement: float | None = None


def _reachable(stages: Sequence[Stage], output_speed: float,
               motor_speed: Callable[[CatalogueMotor], float]) -> Callable[[CatalogueMotor], bool]:
    lo = math.prod(s.ratio if s.ratio is not None else s.ratio_min for s in stages)
    hi = math.prod(s.ratio if s.ratio is not None else s.ratio_max for s in stages)
    return lambda m: lo <= motor_speed(m) / output_speed <= hi


def _rated_speed(motor: CatalogueMotor) -> float:
    return motor.rated_speed


def design_drive(
    output_power: float,
    output_speed: float,
    stages: Sequence[Stage],
    *,
    reserve_factor: float = 1.1,
    drive_efficiency: float | None = None,
    synchronous_speed: float | None = None,
    motor: str | None = None,
    objective: str = "min_inertia",
    torque_basis: TorqueBasis = "load",
    inertia: InertiaModel | None = None,
    snap_r20: bool = False,
    snap_tolerance: float | None = None,
    time_limit_s: float = 20.0,
    catalogue: Sequence[CatalogueMotor] | None = None,
    strength: SizingRules | None = None,
    motor_speed: Callable[[CatalogueMotor], float] | None = None,
) -> DriveResult:
    """Choose the motor, split the ratio and find every shaft's speed, power, torque and reduced inertia.

    Parameters
    ----------
    output_power : power the output shaft delivers [W].
    output_speed : output shaft speed [rad/s].
    stages : the layout, motor side first (fixed ratios, efficiencies).
    reserve_factor : xi in P_req = P_out xi / eta [-].
    drive_efficiency : eta assumed for the motor choice [-]; default the product of the stage efficiencies.
    synchronous_speed : restrict the motor to one speed class [rad/s]; ``motor`` names one instead.
    objective : how free stage ratios are split (see :func:`split_ratio`).
    torque_basis : ``load`` (torques for the output power) or ``rated`` (from the motor's rated power).
    inertia : pinion, load and shaft inertias of the reduced-inertia model [kg·m²] (the motor rotor is added).
    time_limit_s : the split solver's time limit [s].
    catalogue : the motors to choose from (a vendor's data); default the shipped representative catalogue.
    strength : size every cylindrical stage for strength (ISO 6336) from its shaft torque and speed; with the
        ``min_volume`` objective and only cylindrical stages, the split's volume model is the sizing's.
    motor_speed : the speed a motor runs at in this drive [rad/s], which the total ratio is taken from;
        default its rated speed (the seed's rule). A machine passes the speed on the motor's characteristic
        under its mean load.

    Raises InvalidInput, Infeasible (no motor covers the power; the stages cannot reach the ratio), solver errors.
    """
    for name, v in (("output_power_W", output_power), ("output_speed", output_speed),
                    ("reserve_factor", reserve_factor)):
        if not (math.isfinite(v) and v > 0):
            raise InvalidInput(f"{name} must be positive, got {v}", field=name)
    eta_chain = chain_efficiency(stages)
    eta = eta_chain if drive_efficiency is None else drive_efficiency
    if not 0 < eta <= 1:
        raise InvalidInput(f"drive efficiency must lie in (0, 1], got {eta}", field="drive_efficiency")
    required = output_power * reserve_factor / eta
    warnings: list[DesignWarning] = []
    if catalogue is None:
        warnings.append(DesignWarning(
            "representative_catalogue", "motor_catalogue", None,
            "motor chosen from the shipped representative 4A-series catalogue; check its rated data "
            "against the manufacturer's datasheet, or send your own catalogue"))
    elif not catalogue:
        raise InvalidInput("the motor catalogue is empty", field="motor_catalogue")
    if motor is not None:
        chosen = find_motor(motor, catalogue)
        if chosen.rated_power < required * (1 - 1e-12):
            raise Infeasible(f"motor {motor} ({chosen.rated_power:.4g} W) does not cover the required "
                             f"{required:.4g} W", constraint="motor_power", required_power_W=required)
    else:
        ok = _reachable(stages, output_speed, motor_speed or _rated_speed)
        chosen = select_motor(required, synchronous_speed=synchronous_speed, acceptable=ok, catalogue=catalogue)
    running = (motor_speed or _rated_speed)(chosen)
    total = running / output_speed
    model = inertia or InertiaModel()
    if chosen.rotor_inertia is None:
        warnings.append(DesignWarning(
            "rotor_inertia_missing", "motor_catalogue", None,
            f"the catalogue gives no rotor inertia for {chosen.name}; the reduced inertia leaves it out"))
    model = InertiaModel(model.pinion_inertia, model.load_inertia, model.shaft_inertias,
                         model.motor_inertia + (chosen.rotor_inertia or 0.0))
    p0 = chosen.rated_power if torque_basis == "rated" else output_power / eta_chain
    strength_split = None
    if (strength is not None and objective == "min_volume" and not snap_r20
            and all(s.type in SIZED_TYPES and s.ratio is None for s in stages)):
        strength_split = split_for_strength(total, stages, p0 / running, running, strength,
                                            inertia=model, time_limit_s=time_limit_s)
        split = strength_split.split
    else:
        split = split_ratio(total, stages, objective, inertia=model, snap_r20=snap_r20,
                            snap_tolerance=snap_tolerance, time_limit_s=time_limit_s)
    u = np.array(split.stage_ratios)
    etas = np.array([s.efficiency for s in stages])
    speeds = running / np.concatenate([[1.0], np.cumprod(u)])
    powers = p0 * np.concatenate([[1.0], np.cumprod(etas)])
    torques = powers / speeds
    n = len(stages)
    own = np.zeros(n + 1)
    own[0] = model.pinion_inertia + model.motor_inertia
    own[1:] = model.pinion_inertia * u**4
    own[1:n] += model.pinion_inertia
    own[n] += model.load_inertia
    if model.shaft_inertias:
        own += np.asarray(model.shaft_inertias, dtype=float)
    reduced = own * (speeds / speeds[0]) ** 2
    shafts = tuple(DriveShaft(float(w), float(p), float(t), float(j), float(jr))
                   for w, p, t, j, jr in zip(speeds, powers, torques, own, reduced, strict=True))
    delivered = float(torques[-1] * speeds[-1])
    checks = DriveChecks(
        power_balance_error=abs(delivered - p0 * float(np.prod(etas))) / delivered,
        kinetic_energy=float(0.5 * np.sum(own * speeds**2)),
        reduced_kinetic_energy=0.5 * split.reduced_inertia * float(speeds[0]) ** 2,
    )
    if torque_basis == "rated" and delivered > output_power * (1 + 1e-9):
        warnings.append(DesignWarning(
            "rated_power_exceeds", "torque_basis", delivered,
            f"torques follow the motor's rated power: the output carries {delivered:.4g} W, "
            f"more than the {output_power:.4g} W required", "W"))
    gears = None
    if strength_split is not None:
        gears = strength_split.sizing
    elif strength is not None:
        gears = size_train(split.stage_ratios, [StageLoad(float(t), float(w)) for t, w in
                                                zip(torques[:-1], speeds[:-1], strict=True)], stages, strength)
    if gears is not None:
        warnings += [DesignWarning("stage_not_sized", f"stages[{k}]", None,
                                   f"{stage_name(k)} ({stages[k].type}) is not a cylindrical pair; it is not sized")
                     for k, g in enumerate(gears.stages) if g is None]
        # a sized stage's rating says where it stops too (its mesh resonance)
        warnings += [replace(w, field=f"stages[{k}]", message=f"{stage_name(k)}: {w.message}")
                     for k, g in enumerate(gears.stages) if g is not None for w in g.rating.warnings]
    return DriveResult(chosen, required, eta, eta_chain, total, split, tuple(map(float, etas)), shafts,
                       split.reduced_inertia, float(speeds[-1]), torque_basis, checks,
                       tuple(warnings) + split.warnings, gears,
                       None if strength_split is None else strength_split.volume_agreement)
