"""The design chain of a whole machine, linkage to motor, checked by simulating the assembled machine.

analysis -> balancing -> the balanced linkage reduced to its crank -> motor from the mean power -> ratio split
and tooth numbers (the real ratio from the teeth is what the rest uses) -> flywheel sized with the chosen
motor's characteristic on the chosen shaft -> the machine run to its steady state -> every shaft's speed, power
and peak and RMS torque. Each stage is one of the engine's own capabilities, called as its endpoint calls it;
what the chain adds is the simulated machine and what every shaft carries over the cycle.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from ..analysis import Analysis, Summary, analyse
from ..balancing import (
    BalanceResult,
    SliderCrankBalance,
    Weights,
    balance_full,
    balance_optimal,
    balance_slider_crank,
    balance_static,
)
from ..counter_rotors import CounterRotor
from ..errors import Infeasible, InvalidInput, SolverFailed
from ..flywheel import (
    FlywheelBody,
    FlywheelResult,
    MethodResult,
    Motor,
    ReducedCycle,
    Shaft,
    SpeedProfile,
    cycle_from_reduced,
    design_flywheel,
    motor_constant_inertia,
    wittenbauer_tangents,
)
from ..gearing import (
    CatalogueMotor,
    DriveResult,
    SizedStage,
    StageLoad,
    ToothResult,
    TrainSizing,
    chain_efficiency,
    design_drive,
    motor_catalogue,
    size_stage,
    tooth_numbers,
)
from ..gearing.sizing import HELICAL_TYPES, SIZED_TYPES
from ..gearing.split import TeethLimit, teeth_limited
from ..gearing.stages import Stage, stage_name
from ..gearing.teeth import ToothRules
from ..kinematics import FourBar, PlanarLinkage, SliderCrank
from ..model import FloatArray, Linkage
from ..warnings import DELTA_RANGE, RIM_SPEED_MARGIN, DesignWarning, check_analysis, check_counterweights
from .foundation import Isolation
from .foundation_chain import (
    check_choices,
    ElasticInDesign,
    Limit,
    RegulationInDesign,
    elastic_limits,
    elastic_of_design,
    elastic_shaft_torques,
    elastic_warnings,
    forcing_of_design,
    foundation_limits,
    foundation_of_design,
    regulation_limits,
    regulation_of_design,
)
from .operating_point import MotorLoad, operating_speed
from ..friction import friction_kinetostatics
from ..dynamics import reduced_model
from .running import MachineRunning, machine_running
from .simulate import MachineCycle, MachineMotion, simulate_machine
from .spec import BALANCING_MODES, BalancingMode, MachineSpec
from .stages import Stage as DesignStage
from .stages import gathered, refuse_likely_mistakes, stage, staged
from .strength import MachineStrength, parts_of_machine, size_machine_links

#: Least mean power [W] worth choosing a motor for: below it the linkage does no work to speak of.
MIN_POWER = 1e-3
#: Catalogue sizes the chain may step up when the cycle overloads the motor chosen from the mean power.
MAX_MOTOR_UPGRADES = 4
#: Relative room the tooth search gets around each free stage's split ratio [-].
TOOTH_RATIO_ROOM = 0.05


@dataclass(frozen=True, slots=True)
class Balancing:
    """The balancing stage of the chain, the same shape for every family.

    ``result`` the counterweights' answer (a four-bar's static or full, any family's optimal), ``slider_crank``
    a slider-crank's static or full (crank counterweight and Lanchester balancers); ``linkage`` the
    balanced linkage (counterweights, pendulum coupler); ``counter_rotors``; ``balancer_inertia`` the
    Lanchester shafts reduced to the crank [kg·m²]; ``after`` RMS and peaks after balancing [N, N·m].
    """

    mode: str
    result: BalanceResult | None
    slider_crank: SliderCrankBalance | None
    linkage: Linkage
    counter_rotors: tuple[CounterRotor, ...]
    balancer_inertia: float
    after: Summary


@dataclass(frozen=True, slots=True)
class MachineShaft:
    """One shaft of the assembled machine in its steady motion, motor shaft first, crank shaft last.

    ``speed_ratio`` shaft over crank speed [-]; ``mean_speed`` [rad/s]; ``mean_power`` it passes on [W];
    ``mean_torque``, ``peak_torque`` (largest magnitude) and ``rms_torque`` (over time) it passes on [N·m];
    ``inertia`` what turns with it, the flywheel included when it sits there [kg·m²].
    """

    name: str
    speed_ratio: float
    mean_speed: float
    mean_power: float
    mean_torque: float
    peak_torque: float
    rms_torque: float
    inertia: float
    carries_flywheel: bool


@dataclass(frozen=True, slots=True)
class MachineCheck:
    """One target of the design against the simulated machine: ``value`` held at most ``limit``, both in
    ``unit`` ("" for a ratio); ``label`` the check's name in words."""

    name: str
    value: float
    limit: float
    passed: bool
    detail: str
    unit: str = ""
    label: str = ""


#: The checks of how the machine starts and stops (the rest judge its steady motion).
RUNNING_CHECKS = ("motor_starts", "startup_time", "rundown_time")


@dataclass(frozen=True, slots=True)
class MachineDesign:
    """Every stage of a whole-machine design and its independent check.

    ``before`` and ``balanced`` the linkage's analyses (the latter with counterweights, pendulum coupler and
    counter-rotors); ``output_power`` the mean power the crank delivers [W]; ``drive`` the motor choice and
    split; ``teeth`` the tooth numbers (None without toothed stages); ``stage_ratios`` and ``train_ratio`` the
    real ratios from the teeth [-]; ``motor`` the chosen motor's characteristic through them; ``train_inertia``
    the train (rotor excluded) and Lanchester shafts reduced to the crank [kg·m²]; ``flywheel`` its sizing,
    ``placement`` the body on its shaft (None when no flywheel is needed); ``motion`` the simulated machine;
    ``shafts`` motor first; ``checks`` every target against the simulation, the steady motion's and the start,
    run-up and run-down's, in one list that alone decides ``passed``; ``gears`` every cylindrical stage sized
    for the torque its pinion shaft passes on over the simulated cycle (Miner's rule; None when the drive asks
    for no sizing), the elastic link's where it is larger; ``running`` the stages' efficiencies, the start-up
    and the run-down; ``foundation`` the frame on its isolators, ``elastic`` the drive with its elastic link and
    ``regulation`` the load step, each when the machine asks for it (their limits are among ``checks``);
    ``strength`` the parts as built (links sized before balancing, re-checked with everything else on
    ``balanced``; their checks among ``checks``).
    """

    spec: MachineSpec
    before: Analysis
    balancing: Balancing
    balanced: Analysis
    output_power: float
    drive: DriveResult
    teeth: ToothResult | None
    stage_ratios: tuple[float, ...]
    train_ratio: float
    motor: Motor
    train_inertia: float
    flywheel: FlywheelResult
    placement: FlywheelBody | None
    motion: MachineMotion
    shafts: tuple[MachineShaft, ...]
    checks: tuple[MachineCheck, ...]
    warnings: tuple[DesignWarning, ...]
    gears: TrainSizing | None = None
    running: MachineRunning | None = None
    foundation: Isolation | None = None
    elastic: ElasticInDesign | None = None
    regulation: RegulationInDesign | None = None
    strength: MachineStrength | None = None

    @property
    def running_checks(self) -> tuple[MachineCheck, ...]:
        """The start, run-up and run-down checks among ``checks``."""
        return tuple(c for c in self.checks if c.name in RUNNING_CHECKS)

    @property
    def flywheel_inertia(self) -> float:
        """Flywheel inertia reduced to the crank [kg·m²]."""
        return self.flywheel.design.flywheel_inertia

    @property
    def passed(self) -> bool:
        """True when every check meets its target."""
        return all(c.passed for c in self.checks)


@dataclass(frozen=True, slots=True)
class Alternative:
    """The same machine with another balancing mode: its design, or why the mode is not available."""

    mode: str
    design: MachineDesign | None
    reason: str | None


def _summary_with_balancers(summary: Summary, force: np.ndarray, moment: np.ndarray) -> Summary:
    """The balanced linkage's summary with the frame's force and moment once the Lanchester balancers act too
    (their shafts sit off the crank pivot, so they change the moment as well as the force)."""
    magnitude = np.hypot(force[:, 0], force[:, 1])
    return replace(summary, rms_shaking_force=float(np.sqrt(np.mean(magnitude**2))),
                   max_shaking_force=float(magnitude.max()),
                   rms_shaking_moment=float(np.sqrt(np.mean(moment**2))),
                   max_shaking_moment=float(np.abs(moment).max()))


#: Fields of the balancing choice, which the machine request holds under ``balancing``.
_BALANCING_FIELDS = ("counterweight_links", "max_radius_m", "mass_budget_kg", "weights", "rotor_ratios")


def _balancing_field(name: str | None) -> str | None:
    """A balancing field named as the machine request spells it; the linkage's own fields stay as they are."""
    if name is not None and name.split(".")[0] in _BALANCING_FIELDS:
        return f"balancing.{name}"
    return name


def _balance(spec: MachineSpec, before: Analysis | None, time_limit_s: float) -> tuple[Balancing, Analysis]:
    """The balancing stage and the balanced linkage's analysis (counter-rotors included), reusing the
    balancing's own re-analysis where it is the same one. ``before`` the linkage's analysis, None where the
    balancing's own analysis of the linkage serves (a program balancing analyses it as the chain does)."""
    try:
        return _balance_stage(spec, before, time_limit_s)
    except Infeasible as exc:
        raise Infeasible(exc.reason, _balancing_field(exc.constraint), **exc.details) from exc
    except InvalidInput as exc:
        raise InvalidInput(str(exc), field=_balancing_field(exc.field)) from exc


def _balance_stage(spec: MachineSpec, before: Analysis | None,
                   time_limit_s: float) -> tuple[Balancing, Analysis]:
    choice, linkage, speed = spec.balancing, spec.linkage, spec.speed
    mode = choice.mode
    if mode == "none":
        if before is None:
            before = analyse(linkage, speed, samples=spec.samples, friction=spec.friction)
        return Balancing("none", None, None, linkage, (), 0.0, before.summary()), before
    mech = linkage.mechanism
    if mode == "optimal" or isinstance(mech, (FourBar, PlanarLinkage)):
        if mode == "static":
            r = balance_static(linkage, speed, choice.spec, samples=spec.samples, mass_budget=choice.mass_budget,
                               time_limit_s=time_limit_s)
        elif mode == "full":
            r = balance_full(linkage, speed, choice.spec, samples=spec.samples,
                             ratios=dict(choice.rotor_ratios) or None, time_limit_s=time_limit_s)
        else:
            r = balance_optimal(linkage, speed, choice.spec, weights=choice.weights, mass_budget=choice.mass_budget,
                                samples=spec.samples, time_limit_s=time_limit_s)
        balanced = r.analysis_after
        if r.counter_rotors:
            balanced = analyse(balanced.linkage, speed, samples=spec.samples, counter_rotors=r.counter_rotors)
        return Balancing(mode, r, None, balanced.linkage, r.counter_rotors, 0.0, r.after), balanced
    if isinstance(mech, SliderCrank):
        sc = balance_slider_crank(linkage, speed, samples=spec.samples)
        balanced = analyse(linkage.with_counterweights([sc.crank_counterweight]), speed, samples=spec.samples)
        after = balanced.summary()
        if mode == "static":
            return Balancing(mode, None, sc, balanced.linkage, (), 0.0, after), balanced
        # each pair's two shafts carry m at rho turning at k·w: kinetic energy m·rho²·k²·w², so 2·m·rho²·k²
        extra = sum(2 * p.mass * p.radius**2 * p.order**2 for p in sc.pairs)
        return (Balancing(mode, None, sc, balanced.linkage, (), extra, _summary_with_balancers(after, sc.after_force, sc.after_moment)),
                balanced)
    raise InvalidInput(f"{mode} balancing takes four-bars (counterweights) and slider-cranks (a crank counterweight "
                       f"and Lanchester balancers): counterweights turning with a {type(mech).__name__}'s links "
                       f"cannot cancel its {mech.topology.output}'s reciprocating force at every angle; use mode "
                       "optimal (the best trade-off within a mass budget) or none", field="balancing.mode")


def _ranged(s: Stage, ratio_min: float, ratio_max: float) -> Stage:
    """The stage free within [ratio_min, ratio_max] (a direct construction: the chain asks it of every member)."""
    return Stage(s.type, ratio_min, ratio_max, s.efficiency, s.volume_coefficient, s.toothed, None)


def _teeth(spec: MachineSpec, drive: DriveResult,
           stages: Sequence[Stage]) -> tuple[ToothResult | None, tuple[float, ...], list[DesignWarning]]:
    """Tooth numbers near the split's ratios; where none lie within the room around them, the search over each
    stage's whole range (as POST /v1/gears/teeth searches), so a train the teeth endpoint builds is never refused."""
    ratios = drive.split.stage_ratios
    toothed = [k for k, s in enumerate(stages) if s.toothed]
    if not toothed:
        return None, tuple(ratios), []
    near, whole = [], []
    for k in toothed:
        s, u = stages[k], ratios[k]
        if s.ratio is not None:
            # a fixed (standard) ratio is kept, to rounding
            lo, hi = s.ratio * (1 - 1e-9), s.ratio * (1 + 1e-9)
            whole.append(_ranged(s, lo, hi))
        else:
            lo = max(s.ratio_min, u * (1 - TOOTH_RATIO_ROOM))
            hi = min(s.ratio_max, u * (1 + TOOTH_RATIO_ROOM))
            whole.append(_ranged(s, s.ratio_min, s.ratio_max))
        near.append(_ranged(s, lo, hi))
    target = math.prod(ratios[k] for k in toothed)
    rules, tolerance = spec.drive.tooth_rules, spec.drive.tooth_tolerance
    warnings: list[DesignWarning] = []
    try:
        result = tooth_numbers(target, near, rules, tolerance)
    except Infeasible:
        result = tooth_numbers(target, whole, rules, tolerance)
        far = [k for k, mesh in zip(toothed, result.stages, strict=True)
               if abs(mesh.ratio / ratios[k] - 1) > TOOTH_RATIO_ROOM]
        warnings += [DesignWarning(
            "teeth_far_from_split", f"stages[{k}]", mesh.ratio,
            f"{stage_name(k)} ({stages[k].type}): no tooth pair lies within {TOOTH_RATIO_ROOM:.0%} of the split's ratio "
            f"{ratios[k]:.5g}; the teeth {mesh.pinion_teeth}:{mesh.gear_teeth} give {mesh.ratio:.5g}, the split's "
            "objective no longer holds for this stage")
            for k, mesh in zip(toothed, result.stages, strict=True) if k in far]
    real = list(ratios)
    for k, mesh in zip(toothed, result.stages, strict=True):
        real[k] = mesh.ratio
    return result, tuple(real), warnings


def _teeth_limit_warnings(drive: DriveResult, stages: Sequence[Stage],
                          limits: Sequence[TeethLimit]) -> list[DesignWarning]:
    """The split sits on a bound the tooth rules set, not the stage type's own (that one the split names)."""
    out = []
    for lim in limits:
        u = drive.split.stage_ratios[lim.stage]
        for bound, pair, side in ((lim.ratio_max, lim.largest, "largest"), (lim.ratio_min, lim.smallest, "smallest")):
            if abs(u / bound - 1) <= 1e-6:
                out.append(DesignWarning(
                    "stage_ratio_at_teeth_limit", f"stages[{lim.stage}]", u,
                    f"{stage_name(lim.stage)} ({stages[lim.stage].type}): the split sits at {bound:.5g}, the {side} ratio "
                    f"a tooth pair within the tooth bounds makes ({pair[0]}:{pair[1]}); raise max_teeth, add a "
                    "stage or choose another stage type to move it off"))
    return out


def _shaft_names(n_stages: int) -> list[str]:
    return ["motor"] + [f"shaft {k}" for k in range(1, n_stages)] + ["crank"]


def _profile(motion: MachineMotion) -> SpeedProfile:
    return SpeedProfile(motion.phi, motion.omega, float(motion.omega.min()), float(motion.omega.max()), motion.delta)


def _raise_to_target(cycle: MachineCycle, motor: Motor, inertia: float, motion: MachineMotion,
                     delta: float) -> tuple[float, MachineMotion]:
    """Constant inertia [kg·m²] whose simulated delta is ``delta`` [-], by secant steps on log delta over log J
    (delta falls nearly as 1/J), from ``inertia`` whose ``motion`` swings too far."""
    j0, d0 = inertia, motion.delta
    j1 = j0 * d0 / delta
    for _ in range(12):
        motion = simulate_machine(cycle, j1, motor, start=float(motion.omega[0]))
        d1 = motion.delta
        if abs(d1 / delta - 1) <= 1e-5:
            return j1, motion
        slope = math.log(d1 / d0) / math.log(j1 / j0)
        if not slope < 0:
            break
        j0, d0, j1 = j1, d1, j1 * math.exp(math.log(delta / d1) / slope)
    raise SolverFailed("no_convergence", "the flywheel inertia that meets the target on the simulated machine "
                       "was not found")


def _flywheel(spec: MachineSpec, motor: Motor, cycle: ReducedCycle, machine_cycle: MachineCycle,
              ratios: Sequence[float], train_inertia: float,
              time_limit_s: float) -> tuple[FlywheelResult, FlywheelBody | None, MachineMotion]:
    """The least flywheel for the chosen motor (the flywheel's motor NLP), checked and shaped.

    Its check is the simulation of the assembled machine, the same one every other target is checked on;
    the textbook constant-torque methods do not describe a motor-driven machine and are left out.
    """
    reduced = motor.reduced()
    existing = train_inertia + reduced.inertia
    # the motor sets the mean speed: the band is sized around its steady speed, the working speed is a check
    mean_speed = reduced.mean_speed(cycle)
    balanced, driving = cycle.balanced()
    # the Wittenbauer tangents both report the band and give the NLP its start (the closed-form inertia)
    tangents = wittenbauer_tangents(balanced, mean_speed, spec.delta)
    guess = max(tangents.constant_inertia, 1e-9)
    nlp = motor_constant_inertia(cycle, reduced, mean_speed, spec.delta, guess=guess, time_limit_s=time_limit_s)
    used = max(nlp.constant_inertia, existing)
    # the NLP's periodic speed at the first sample starts the shooting next to the answer
    with stage("simulation"):
        motion = simulate_machine(machine_cycle, used, motor, start=float(nlp.omega[0]))
    methods = [MethodResult("motor_nlp", nlp.constant_inertia, used - existing, _profile(motion))]
    if used > existing and motion.delta > spec.delta * (1 + 1e-4):
        # the NLP holds the speed at the samples; between them (a load step, say) the simulated machine can
        # swing a little further: raise the inertia until the simulation itself meets the target
        with stage("simulation"):
            used, motion = _raise_to_target(machine_cycle, motor, used, motion, spec.delta)
        methods.append(MethodResult("simulated", used, used - existing, _profile(motion)))
    method = methods[-1]
    names = _shaft_names(len(ratios))
    speed_ratios = [math.prod(ratios[k:]) for k in range(len(ratios))]
    choice = spec.flywheel
    if choice.placement == "crank":
        shafts: tuple[Shaft, ...] = ()
    elif choice.placement == "motor":
        shafts = (Shaft("motor", speed_ratios[0]),)
    else:
        shafts = tuple(Shaft(n, r) for n, r in zip(names[:-1], speed_ratios, strict=True))
    shape = None
    if method.flywheel_inertia > 0:
        try:
            shape = design_flywheel(method.flywheel_inertia, replace(choice.geometry, shafts=shafts),
                                    float(motion.omega.max()))
        except Infeasible as exc:
            # the machine request holds the geometry under flywheel: name the field as the request spells it
            raise Infeasible(exc.reason, None if exc.constraint is None else f"flywheel.{exc.constraint}",
                             **exc.details) from exc
        except InvalidInput as exc:
            raise InvalidInput(str(exc), field=None if exc.field is None else f"flywheel.{exc.field}") from exc
    result = FlywheelResult(
        cycle=balanced, mean_speed=mean_speed, target_delta=spec.delta, constant_inertia=existing,
        driving_torque=driving, cycle_work=cycle.cycle_work,
        tangents=tangents, methods=tuple(methods),
        design_method=method.method, geometry=shape, motor_mean_speed=mean_speed,
    )
    if shape is None:
        return result, None, motion
    if choice.placement == "lightest":
        return result, shape.best, motion
    wanted = "crank" if choice.placement == "crank" else "motor"
    for body in shape.bodies:
        if body.shaft == wanted:
            return result, body, motion
    miss = next(m for m in shape.misses if m.shaft == wanted)
    raise Infeasible(f"the {wanted} shaft cannot carry the flywheel within the {miss.constraint} limit; "
                     "choose placement lightest or relax the limit", constraint=f"flywheel.geometry.{miss.constraint}",
                     shaft=wanted, max_inertia_kgm2=miss.max_inertia)


def _shaft_torques(design_ratios: Sequence[float], drive: DriveResult, motion: MachineMotion,
                   placement: FlywheelBody | None, flywheel_inertia: float) -> FloatArray:
    """The torque each shaft passes on at the motion's samples, (shafts, M) [N·m], motor shaft first:
    T_k·w_k = eta_0k·T_m·w_m - d/dt(kinetic energy of shafts 0..k)."""
    n = len(design_ratios)
    names = _shaft_names(n)
    r = np.array([math.prod(design_ratios[k:]) for k in range(n)] + [1.0])
    eta = np.concatenate([[1.0], np.cumprod(drive.stage_efficiencies)])
    own = np.array([s.inertia for s in drive.shafts])
    if placement is not None:
        own[names.index(placement.shaft)] += flywheel_inertia / r[names.index(placement.shaft)] ** 2
    upstream = np.cumsum(own * r**2)
    return np.asarray((eta[:, None] * motion.motor_torque[None, :] * r[0] - upstream[:, None] * motion.alpha[None, :])
                      / r[:, None], dtype=float)


def _time_weights(motion: MachineMotion) -> FloatArray:
    """Each sample's share of the period: trapezoid weights in phi over the crank speed (as time_mean)."""
    phi = motion.phi
    w = np.zeros_like(phi)
    step = np.diff(phi) / 2
    w[:-1] += step
    w[1:] += step
    return np.asarray(w / motion.omega / np.sum(w / motion.omega), dtype=float)


def _gears(machine: MachineSpec, teeth: ToothResult | None, ratios: Sequence[float], torques: FloatArray,
           motion: MachineMotion, shafts: Sequence[MachineShaft],
           width_steps: int | None = None) -> tuple[TrainSizing | None, list[DesignWarning]]:
    """Each cylindrical stage sized for the torque its pinion shaft passes on over the simulated cycle; a stage
    that cannot be sized is reported, not fatal (the machine design stands without it)."""
    rules = machine.drive.strength
    if rules is None:
        return None, []
    stages = machine.drive.stages
    toothed = [k for k, s in enumerate(stages) if s.toothed]
    meshes = dict(zip(toothed, teeth.stages, strict=True)) if teeth is not None else {}
    weights = _time_weights(motion)
    out: list[SizedStage | None] = []
    warnings = []
    for k, s in enumerate(stages):
        if s.type not in SIZED_TYPES or k not in meshes:
            out.append(None)
            continue
        mesh = meshes[k]
        helix = rules.helix_angle if rules.helix_angle is not None else HELICAL_TYPES.get(s.type, 0.0)
        load = StageLoad(torques[k], shafts[k].mean_speed, weights)
        try:
            sized_stage = size_stage(mesh.gear_teeth / mesh.pinion_teeth, load, rules, stage=k, helix_angle=helix,
                                     pinion_teeth=mesh.pinion_teeth, width_steps=width_steps)
            out.append(sized_stage)
            warnings += [replace(w, field=f"drive.stages[{k}]", message=f"{stage_name(k)}: {w.message}",
                                 stage="drive") for w in sized_stage.rating.warnings]
        except (InvalidInput, Infeasible) as exc:
            out.append(None)
            warnings.append(DesignWarning("stage_not_sized", f"drive.stages[{k}]", None,
                                          f"{stage_name(k)} could not be sized for strength: {exc}", stage="drive"))
    sized = [g for g in out if g is not None]
    return (TrainSizing(tuple(out), sum(g.mass for g in sized), sum(g.volume for g in sized),
                        sum(g.centre_distance for g in sized)), warnings)


def _shafts(design_ratios: Sequence[float], drive: DriveResult, motion: MachineMotion,
            placement: FlywheelBody | None, flywheel_inertia: float) -> tuple[MachineShaft, ...]:
    n = len(design_ratios)
    names = _shaft_names(n)
    r = np.array([math.prod(design_ratios[k:]) for k in range(n)] + [1.0])
    own = np.array([s.inertia for s in drive.shafts])
    if placement is not None:
        own[names.index(placement.shaft)] += flywheel_inertia / r[names.index(placement.shaft)] ** 2
    torques = _shaft_torques(design_ratios, drive, motion, placement, flywheel_inertia)
    out = []
    for k in range(n + 1):
        torque = torques[k]
        power = torque * r[k] * motion.omega
        out.append(MachineShaft(
            names[k], float(r[k]), float(r[k] * motion.mean_speed), motion.time_mean(power),
            motion.time_mean(torque), float(np.abs(torque).max()), motion.time_rms(torque), float(own[k]),
            placement is not None and placement.shaft == names[k],
        ))
    return tuple(out)


def _running_checks(spec: MachineSpec, running: MachineRunning) -> list[MachineCheck]:
    up, down = running.startup, running.rundown
    start = up.check
    resisting = float(start.resisting_torque.max())
    checks = [MachineCheck("motor_starts", resisting, start.starting_torque, start.starts,
                           "largest torque holding the crank at rest (gravity, breakaway friction and, starting "
                           "under load, the process load; at the worst crank angle) against the motor's starting "
                           "torque through the train [N·m]", "N·m", "motor starts the machine")]
    if start.starts:
        reached = up.steady_time is not None
        value = up.steady_time if up.steady_time is not None else float(up.run.time[-1]) if up.run else 0.0
        checks.append(MachineCheck("startup_time", value, spec.max_startup_time,
                                   reached and value <= spec.max_startup_time,
                                   "time from rest to within 1 % of the periodic steady speed, idling unless "
                                   "started under load [s]", "s", "start-up time"))
    if spec.max_rundown_time is not None:
        value = down.stop_time if down.stop_time is not None else float(down.run.time[-1])
        checks.append(MachineCheck("rundown_time", value, spec.max_rundown_time,
                                   down.stop_time is not None and value <= spec.max_rundown_time,
                                   "time from the steady state to rest with the motor off (and the brake) [s]",
                                   "s", "run-down time"))
    return checks


def ratio_for_speed(spec: MachineSpec, motion: MachineMotion, motor: Motor) -> float:
    """The train ratio [-] that would turn the crank at the working speed: the motor keeps its speed (its
    operating point moves little with the ratio at a given power), so the ratio scales with the crank's."""
    return motor.gear_ratio * motion.mean_speed / spec.speed


def _checks(spec: MachineSpec, motion: MachineMotion, motor: Motor) -> tuple[MachineCheck, ...]:
    delta_ok = motion.delta <= spec.delta * (1 + 1e-3)
    speed_err = abs(motion.mean_speed / spec.speed - 1)
    speed_ok = speed_err <= spec.speed_tolerance
    speed_detail = "relative distance of the simulated mean crank speed from the working speed"
    if not speed_ok:
        speed_detail += (f": the crank turns at {motion.mean_speed * 30 / math.pi:.4g} rpm for "
                         f"{spec.speed * 30 / math.pi:.4g} rpm; a train ratio of "
                         f"{ratio_for_speed(spec, motion, motor):.4g} (not {motor.gear_ratio:.4g}) would give the "
                         "working speed: free the stage ratios (ratio_min, ratio_max) or choose another speed class")
    rms_ok = motion.motor_rms_torque <= motor.rated_torque
    checks = [
        MachineCheck("delta", motion.delta, spec.delta, delta_ok,
                     "simulated coefficient of speed fluctuation against the target (1e-3 relative)", "",
                     "coefficient of speed fluctuation δ"),
        MachineCheck("mean_speed", speed_err, spec.speed_tolerance, speed_ok, speed_detail, "",
                     "mean crank speed, relative error"),
        MachineCheck("motor_rms_torque", motion.motor_rms_torque, motor.rated_torque, rms_ok,
                     "motor torque RMS over time against its rated torque (heating)", "N·m",
                     "motor torque, RMS (heating)"),
    ]
    if motor.breakdown_torque is not None:
        checks.append(MachineCheck("motor_peak_torque", motion.motor_peak_torque, motor.breakdown_torque,
                                   motion.motor_peak_torque <= motor.breakdown_torque,
                                   "largest motor torque against its breakdown torque (current limit)", "N·m",
                                   "motor torque, peak"))
    return tuple(checks)


def design_machine(machine: MachineSpec, *, time_limit_s: float = 20.0) -> MachineDesign:
    """Design the whole machine, linkage to motor, and check it by simulating the assembled machine.

    Parameters
    ----------
    machine
        The machine: linkage and load, working speed [rad/s], drive, target delta [-], balancing and flywheel
        choices.
    time_limit_s
        Each solver's time limit [s].

    Raises InvalidInput, NotAssemblable, Infeasible (no motor covers the power, the stages cannot reach the
    ratio, no shaft holds the flywheel, ...), SolverFailed or SolverTimeout, each naming what binds.
    """
    machine.validate()
    check_choices(machine.foundation, machine.elastic_drive)
    notes = refuse_likely_mistakes(machine.linkage)
    # a load or mass typed a hundred orders of magnitude off overflows somewhere down the chain: say so once
    with np.errstate(over="raise"):
        try:
            design = _design(machine, time_limit_s)
            return replace(design, warnings=gathered([*staged(notes, "analysis"), *design.warnings]))
        except FloatingPointError as exc:
            raise InvalidInput("the machine overflows floating point: a load, mass, inertia or speed is far "
                               "outside any physical range") from exc


def _design(machine: MachineSpec, time_limit_s: float) -> MachineDesign:
    sizing = None
    if machine.strength is not None:
        # the links sized first, so that balancing, the flywheel and the drive see the links as built
        with stage("strength"):
            sizing = size_machine_links(machine.strength, machine.linkage, machine.speed, machine.samples)
        machine = replace(machine, linkage=sizing.linkage)
    with stage("analysis"):
        before = analyse(machine.linkage, machine.speed, samples=machine.samples, friction=machine.friction)
    with stage("balancing"):
        bal, balanced = _balance(machine, before, time_limit_s)
    if machine.friction:
        # the balanced linkage with friction in its pairs: its losses are in the power the motor is chosen for
        with stage("analysis"):
            fr = friction_kinetostatics(balanced.motion, balanced.linkage, balanced.kinetostatics, machine.friction)
        balanced = replace(balanced, friction=fr, reduced=replace(balanced.reduced, friction_torque=fr.loss_torque))
    cycle = cycle_from_reduced(balanced.reduced)
    output_power = -cycle.cycle_work / cycle.period * machine.speed
    if not output_power > MIN_POWER:
        with stage("drive"):
            raise InvalidInput("the linkage does no work over the cycle, so there is no power to choose a motor "
                               "for: give its process load", field="loads")
    d = machine.drive
    motor_name = d.motor
    replaced: list[DesignWarning] = []
    for _ in range(MAX_MOTOR_UPGRADES + 1):
        design = _drive_onwards(machine, before, bal, balanced, cycle, output_power, motor_name, time_limit_s)
        heavy = [c.name for c in design.checks
                 if c.name in ("motor_rms_torque", "motor_peak_torque", "motor_starts") and not c.passed]
        bigger = None if d.motor is not None or not heavy else _next_motor(design.drive.motor, d.catalogue)
        if bigger is None:
            break
        # the mean power chose a motor the cycle's peaks or RMS overload: the next size up, same speed class
        replaced.append(DesignWarning(
            "motor_replaced", "drive.motor", bigger.rated_power,
            f"motor {design.drive.motor.name} chosen from the mean power fails {', '.join(heavy)} on the simulated "
            f"cycle; replaced by {bigger.name}", "W", stage="motor"))
        motor_name = bigger.name
    design = _around(machine, replace(design, warnings=tuple(replaced) + design.warnings))
    if machine.strength is None or sizing is None:
        return design
    with stage("strength"):
        parts = parts_of_machine(machine.strength, sizing, design.balanced)
    checks = [MachineCheck(f"{c.name}:{c.part}", c.value, c.limit, c.passed, c.meaning, c.unit,
                           f"{c.part}: {c.name.replace('_', ' ')}") for c in parts.checks]
    return replace(design, checks=design.checks + tuple(checks), warnings=design.warnings + parts.warnings,
                   strength=parts)


#: The request's field each block's limit is given in.
_LIMIT_FIELDS = {"foundation_force": "foundation.max_force_N", "foundation_amplitude": "foundation.max_amplitude_m",
                 "dynamic_factor": "elastic_drive.max_dynamic_factor",
                 "regulation_settling_time": "regulation.max_settling_time_s",
                 "regulation_speed_drop": "regulation.max_speed_drop_rad_s"}


def _limit_checks(limits: Sequence[Limit], block: DesignStage) -> tuple[list[MachineCheck], list[DesignWarning]]:
    """A block's limits as checks of the machine, and a warning for each it fails."""
    checks = [MachineCheck(x.name, x.value, x.limit, x.passed, x.detail, x.unit, x.label) for x in limits]
    warnings = [DesignWarning("check_failed", _LIMIT_FIELDS.get(x.name), x.value,
                              f"the machine fails its {x.name} check ({x.value:.4g} against {x.limit:.4g}): "
                              f"{x.detail}", x.unit, stage=block) for x in limits if not x.passed]
    return checks, warnings


def _around(machine: MachineSpec, d: MachineDesign) -> MachineDesign:
    """The machine around its linkage, when the request asks for it: the frame on its isolators, the elastic
    drive (the gear stages then sized for its torque where it is larger) and the load step; each block's limits
    join the one list of checks."""
    if machine.foundation is None and machine.elastic_drive is None and machine.regulation is None:
        return d
    red = d.balanced.reduced
    cycle = MachineCycle(red.phi, red.inertia, red.inertia_slope, red.resisting_torque)
    constant = d.train_inertia + d.motor.reduced().inertia + d.flywheel_inertia
    checks, warnings = list(d.checks), list(d.warnings)
    foundation = elastic = regulation = None
    gears = d.gears
    if machine.foundation is not None:
        with stage("foundation"):
            ks, sc = d.balanced.kinetostatics, d.balancing.slider_crank
            force, moment = ks.shaking_force, ks.shaking_moment
            if sc is not None and d.balancing.mode == "full":
                # the Lanchester balancers act on the frame too
                force, moment = sc.after_force, sc.after_moment
            forcing = forcing_of_design(d.balanced.motion.phi, d.balanced.motion.omega_crank, force, moment)
            foundation = foundation_of_design(machine.foundation, forcing,
                                              None if d.running is None else d.running.startup)
        more, notes = _limit_checks(foundation_limits(machine.foundation, foundation), "foundation")
        checks += more
        warnings += notes + [replace(w, stage="foundation", field=f"foundation.{w.field}" if w.field else None)
                             for w in foundation.warnings]
    if machine.elastic_drive is not None:
        with stage("elastic_drive"):
            start_cycle = cycle
            if not machine.start_under_load:
                # it runs up idling, as the design's start-up does (gravity and link torques, no friction)
                idle = reduced_model(d.balanced.motion, replace(d.balanced.linkage, loads=()))
                start_cycle = MachineCycle(red.phi, red.inertia, red.inertia_slope, idle.load_torque)
            elastic = elastic_of_design(machine.elastic_drive, cycle, d.motor, d.train_inertia, d.flywheel_inertia,
                                        d.placement, start_cycle)
        if d.gears is not None:
            n = len(d.stage_ratios)
            r = np.array([math.prod(d.stage_ratios[k:]) for k in range(n)] + [1.0])
            eta = np.concatenate([[1.0], np.cumprod(d.drive.stage_efficiencies)])
            rigid = _shaft_torques(d.stage_ratios, d.drive, d.motion, d.placement, d.flywheel_inertia)
            torques = elastic_shaft_torques(rigid, d.motion.phi, elastic.drive, r, eta, d.motor.efficiency)
            if np.any(torques != rigid):
                gears, not_sized = _gears(machine, d.teeth, d.stage_ratios, torques, d.motion, d.shafts)
                elastic = replace(elastic, gear_torque_basis="elastic")
                warnings += not_sized
        more, notes = _limit_checks(elastic_limits(machine.elastic_drive, elastic.drive), "elastic_drive")
        checks += more
        warnings += notes + elastic_warnings(elastic.drive)
    if machine.regulation is not None:
        with stage("regulation"):
            regulation = regulation_of_design(machine.regulation, cycle, d.motor, constant)
        more, notes = _limit_checks(regulation_limits(machine.regulation, regulation.regulation), "regulation")
        checks += more
        warnings += notes + [replace(w, stage="regulation", field=f"regulation.{w.field}" if w.field else None)
                             for w in regulation.regulation.warnings]
    return replace(d, checks=tuple(checks), warnings=tuple(warnings), gears=gears, foundation=foundation,
                   elastic=elastic, regulation=regulation)


def _next_motor(motor: CatalogueMotor, catalogue: Sequence[CatalogueMotor] | None) -> CatalogueMotor | None:
    """The smallest catalogue motor of the same speed class rated above ``motor``, or None."""
    same = [m for m in catalogue or motor_catalogue()
            if math.isclose(m.synchronous_speed, motor.synchronous_speed, rel_tol=1e-6)
            and m.rated_power > motor.rated_power]
    return min(same, key=lambda m: (m.rated_power, -m.rated_speed)) if same else None


def _drive_onwards(machine: MachineSpec, before: Analysis, bal: Balancing, balanced: Analysis,
                   cycle: ReducedCycle, output_power: float, motor_name: str | None,
                   time_limit_s: float) -> MachineDesign:
    d = machine.drive
    # the motor runs where its characteristic gives the machine's mean power, not at its rated point:
    # the ratio is taken from that speed, so the crank turns at its working speed
    motor_power = output_power / chain_efficiency(d.stages)
    # the split works within the ratios the tooth pairs make, so the tooth search can meet what it asks
    stages, limits = teeth_limited(d.stages, d.tooth_rules or ToothRules())
    try:
        with stage("drive"):
            drive = design_drive(output_power, machine.speed, stages, reserve_factor=d.reserve_factor,
                                 synchronous_speed=d.synchronous_speed, motor=motor_name, objective=d.objective,
                                 torque_basis="load", inertia=d.inertia, time_limit_s=time_limit_s,
                                 catalogue=d.catalogue, motor_speed=MotorLoad(motor_power))
            if d.motor is not None:
                operating_speed(drive.motor, motor_power)  # a named motor too small for the mean power says so
        with stage("teeth"):
            teeth, ratios, teeth_notes = _teeth(machine, drive, stages)
    except InvalidInput as exc:
        # the machine request holds these fields under drive: name them as the request spells them
        again = InvalidInput(str(exc), field=None if exc.field is None else f"drive.{exc.field}", code=exc.code)
        again.stage = exc.stage
        raise again from exc
    train_ratio = math.prod(ratios)
    motor = Motor.from_catalogue(drive.motor, train_ratio, drive.chain_efficiency)
    speed_ratios = [math.prod(ratios[k:]) for k in range(len(ratios))] + [1.0]
    own = np.array([s.inertia for s in drive.shafts])
    train = float(own @ np.square(speed_ratios)) - motor.reduced().inertia + bal.balancer_inertia
    red = balanced.reduced
    machine_cycle = MachineCycle(red.phi, red.inertia, red.inertia_slope, red.resisting_torque)
    with stage("flywheel"):
        flywheel, placement, motion = _flywheel(machine, motor, cycle, machine_cycle, ratios, train, time_limit_s)
    shafts = _shafts(ratios, drive, motion, placement, flywheel.design.flywheel_inertia)
    steady_checks = _checks(machine, motion, motor)
    torques = _shaft_torques(ratios, drive, motion, placement, flywheel.design.flywheel_inertia)
    gears, not_sized = _gears(machine, teeth, ratios, torques, motion, shafts)
    # a bound the tooth rules set is named with its pair; the split's own note of that bound is then redundant
    teeth_bound = _teeth_limit_warnings(drive, stages, limits)
    held = {w.field for w in teeth_bound}
    drive_notes = [w for w in drive.warnings if not (w.code == "stage_ratio_at_limit" and w.field in held)]
    warnings = [*staged(check_analysis(before), "analysis"), *_balancing_warnings(before, bal),
                *staged(drive_notes, "drive", "drive"), *staged(teeth_bound, "drive", "drive")]
    if teeth is not None:
        warnings += staged([*teeth.warnings, *teeth_notes], "teeth", "drive")
    constant = train + motor.reduced().inertia + flywheel.design.flywheel_inertia
    with stage("simulation"):
        running = machine_running(balanced, motor, constant, drive.chain_efficiency, machine.friction,
                                  machine.brake_torque, machine.start_under_load,
                                  steady_start=float(motion.omega[0]))
    running_checks = tuple(_running_checks(machine, running))
    checks = (*steady_checks, *running_checks)
    warnings += _flywheel_warnings(machine, flywheel, placement) + _check_warnings(steady_checks) + not_sized
    warnings += _check_warnings([c for c in running_checks if c.name != "motor_starts"])
    if not running.startup.check.starts:
        warnings.append(DesignWarning(
            "motor_cannot_start", "drive.motor", running.startup.check.starting_torque,
            f"motor {drive.motor.name} cannot start the machine: its starting torque through the train is below the "
            f"torque holding the crank at rest at {math.degrees(running.startup.check.worst_angle):.4g} deg",
            "N·m", stage="simulation"))
    return MachineDesign(machine, before, bal, balanced, output_power, drive, teeth, ratios, train_ratio, motor,
                         train, flywheel, placement, motion, shafts, checks, tuple(warnings), gears,
                         running)


def _balancing_warnings(before: Analysis, bal: Balancing) -> list[DesignWarning]:
    """Counterweights the balancing placed beyond their links (a max_radius_m longer than the link)."""
    if bal.result is None:
        return []
    return staged(check_counterweights(before.linkage, bal.result.counterweights, "max_radius_m"), "balancing",
                  "balancing")


def _flywheel_warnings(spec: MachineSpec, flywheel: FlywheelResult,
                       placement: FlywheelBody | None) -> list[DesignWarning]:
    """A target delta outside every machine type's range; the flywheel's rim near its speed limit."""
    lo, hi = DELTA_RANGE
    out = []
    if not lo <= spec.delta <= hi:
        out.append(DesignWarning(
            "delta_out_of_range", "delta", spec.delta,
            f"a target delta of {spec.delta:.3g} lies outside the usual {lo:.3g}–{hi:.3g} of machines (the machine "
            "types' table lists them); the flywheel grows as 1/delta", "1", stage="flywheel"))
    limit = spec.flywheel.geometry.max_rim_speed
    if placement is not None and limit is not None and placement.rim_speed >= RIM_SPEED_MARGIN * limit:
        out.append(DesignWarning(
            "rim_speed_near_limit", "flywheel.geometry.max_rim_speed_m_s", placement.rim_speed,
            f"the flywheel's rim on the {placement.shaft} shaft runs at {placement.rim_speed:.3g} m/s, "
            f"{placement.rim_speed / limit:.0%} of the {limit:g} m/s limit: no margin for overspeed; a larger "
            "width or another shaft gives one", "m/s", stage="flywheel"))
    return out


def _check_warnings(checks: Sequence[MachineCheck]) -> list[DesignWarning]:
    """A check the simulated machine fails, as a warning of the simulation stage with what to change."""
    fields = {"delta": "delta", "mean_speed": "speed_tolerance", "motor_rms_torque": "drive.motor",
              "motor_peak_torque": "drive.motor", "startup_time": "max_startup_time_s",
              "rundown_time": "max_rundown_time_s"}
    return [DesignWarning("check_failed", fields.get(c.name), c.value,
                          f"the simulated machine fails its {c.name} check ({c.value:.4g} against {c.limit:.4g}): "
                          f"{c.detail}", stage="simulation")
            for c in checks if not c.passed]


def alternatives(machine: MachineSpec, *, time_limit_s: float = 20.0,
                 modes: Sequence[BalancingMode] | None = None) -> tuple[Alternative, ...]:
    """The same machine designed with each balancing mode in ``modes`` (default: the modes it does not use):
    what each choice costs.

    A mode the linkage cannot take (a shaper's static or full mode, a coupler that cannot be a pendulum, a
    budget too small) is reported with the reason instead of a design. The optimal mode without weights of
    its own weighs the RMS shaking force and moment alike (dimensionless).
    """
    if modes is None:
        modes = [m for m in BALANCING_MODES if m != machine.balancing.mode]
    out = []
    for mode in modes:
        choice = replace(machine.balancing, mode=mode)
        if mode == "optimal" and choice.weights is None:
            choice = replace(choice, weights=Weights(shaking_force=1.0, shaking_moment=1.0))
        try:
            out.append(Alternative(mode, design_machine(replace(machine, balancing=choice),
                                                        time_limit_s=time_limit_s), None))
        except (InvalidInput, Infeasible, SolverFailed) as exc:
            out.append(Alternative(mode, None, str(exc)))
    return tuple(out)

