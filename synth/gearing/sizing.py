"""Sizing a train's pairs for strength: the module from the ISO 54 series and the face width per stage.

Once the stage ratios and the torques are fixed, the stages do not interact, so the train's least mass (or least
sum of centre distances) is the sum of each stage's least. Per stage the module is discrete and few (ISO 54 first
choice, or first and second), and for each module the least face width meeting S_H >= S_Hmin and S_F >= S_Fmin
on both wheels is one monotone root-find (the stresses fall as the face widens), so enumerating the series with
a bisection per module finds the exact optimum of this mixed-integer program with no MINLP solver; a
branch-and-bound would search the same dozen modules. A module's bisection runs only as far as the choice needs:
its width, and so its mass, lies between the ends it has reached, so a module those bounds show to lose is left
there, and the module chosen is bisected to the end (the answer is the full search's to the last bit). The face
width lies between ``min_face_width_ratio`` and ``max_face_width_ratio`` pinion diameters; the constraint that
fixes it is reported as the binding one.

The ratio split agrees with this sizing: :func:`split_for_strength` sizes the stages, reads each stage's volume
coefficient c_k = V_k / (T_k (u + 1)(u² + 1)/u) off the sized pair and splits again with those coefficients
(the ``min_volume`` geometric program), until the ratios settle.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np

from ..errors import Infeasible, InvalidInput
from ..model import FloatArray
from .involute import BasicRack, min_profile_shift
from .life import SpectrumLanes
from .materials import gear_material
from .rating import MM, Duty, GearPairSpec, PairModel, RatingResult, _result
from .split import InertiaModel, SplitResult, gear_volume, split_ratio
from .stages import Stage, stage_name

ISO54_FIRST = (1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0, 16.0, 20.0, 25.0, 32.0, 40.0, 50.0)
ISO54_SECOND = (1.125, 1.375, 1.75, 2.25, 2.75, 3.5, 4.5, 5.5, 7.0, 9.0, 11.0, 14.0, 18.0, 22.0, 28.0, 36.0, 45.0)
Series = Literal["first", "first_and_second"]
SizingObjective = Literal["mass", "centre_distance"]
HELICAL_TYPES = {"helical": math.radians(15.0)}
SIZED_TYPES = ("spur", "helical", "open_spur")
_WIDTH_STEPS = 26
_SPLIT_PASSES = 4


def module_series(series: Series = "first") -> tuple[float, ...]:
    """ISO 54 normal modules [m], ascending."""
    values = ISO54_FIRST if series == "first" else tuple(sorted(ISO54_FIRST + ISO54_SECOND))
    return tuple(v * MM for v in values)


@dataclass(frozen=True, slots=True)
class SizingRules:
    """How pairs are sized.

    ``materials`` grade names (pinion, gear); ``helix_angle`` [rad], None: 0 for spur stages, 15° for helical;
    ``pinion_teeth`` of every pinion [-]; ``accuracy_grade`` ISO 1328-1; ``oil_viscosity_40`` [m²/s];
    ``flank_roughness_Ra`` [m]; ``root_roughness_Rz`` [m]; ``duty`` K_A, life and minimum safety factors;
    ``series`` of modules; face width between ``min_face_width_ratio`` and ``max_face_width_ratio`` pinion
    diameters [-]; ``objective`` least ``mass`` or least ``centre_distance``.
    """

    materials: tuple[str, str] = ("through_hardened_alloy_MQ", "through_hardened_alloy_MQ")
    helix_angle: float | None = None
    pinion_teeth: int = 19
    accuracy_grade: int = 7
    oil_viscosity_40: float = 220e-6
    flank_roughness_Ra: float = 0.8e-6
    root_roughness_Rz: float = 10e-6
    duty: Duty = dataclasses.field(default_factory=Duty)
    series: Series = "first"
    min_face_width_ratio: float = 0.2
    max_face_width_ratio: float = 1.0
    objective: SizingObjective = "mass"


@dataclass(frozen=True, slots=True)
class StageLoad:
    """The load on a stage's pinion: a nominal ``torque`` [N·m] (times K_A), or torques sampled over the
    machine cycle (an array, Miner's rule) with each sample's share of the time in ``weights`` (None: equal),
    at the mean ``speed`` [rad/s]."""

    torque: float | FloatArray
    speed: float
    weights: FloatArray | None = None


@dataclass(frozen=True, slots=True)
class SizedStage:
    """One sized pair.

    ``module`` normal module [m]; teeth; ``ratio`` z2/z1 [-]; ``face_width``, ``centre_distance``, reference
    ``diameters`` and ``tip_diameters`` [m]; ``mass`` of both wheels as solid discs [kg]; ``volume`` [m³];
    ``safety_contact``/``safety_root`` per wheel [-] (on the spectrum when the load is one); ``binding`` the
    constraint that fixes the face width (``contact_pinion``, ``contact_gear``, ``root_pinion``, ``root_gear``
    or ``min_face_width``); ``margins`` S/S_min - 1 of each strength constraint; ``rating`` the full rating at
    the (peak) torque; ``modules_examined``; ``smaller_module`` the next smaller module of the series at the
    same face width and what fails there (None when the series has none).
    """

    stage: int
    module: float
    pinion_teeth: int
    gear_teeth: int
    ratio: float
    helix_angle: float
    face_width: float
    centre_distance: float
    diameters: tuple[float, float]
    tip_diameters: tuple[float, float]
    mass: float
    volume: float
    safety_contact: tuple[float, float]
    safety_root: tuple[float, float]
    binding: str
    margins: dict[str, float]
    rating: RatingResult
    modules_examined: int
    smaller_module: tuple[float, str] | None


@dataclass(frozen=True, slots=True)
class TrainSizing:
    """A sized train: ``stages`` (None for a stage type that is not a cylindrical pair), ``mass`` [kg],
    ``volume`` [m³], ``sum_centre_distance`` [m]."""

    stages: tuple[SizedStage | None, ...]
    mass: float
    volume: float
    sum_centre_distance: float


_CONSTRAINTS = ("contact_pinion", "contact_gear", "root_pinion", "root_gear")


def _spec(rules: SizingRules, z1: int, z2: int, module: float, width: float, helix: float) -> GearPairSpec:
    return GearPairSpec(z1, z2, module, width, helix, (0.0, 0.0), None, rules.accuracy_grade, rules.materials,
                        rules.oil_viscosity_40, rules.flank_roughness_Ra, rules.root_roughness_Rz,
                        max_face_width_ratio=rules.max_face_width_ratio * (1 + 1e-9))


def _model(rules: SizingRules, spec: GearPairSpec, load: StageLoad) -> tuple[PairModel, SpectrumLanes | None]:
    """The pair's model and, for a load spectrum, its Miner lanes: both hold at every face width."""
    model = PairModel(spec, rules.duty, load.speed)
    if isinstance(load.torque, np.ndarray):
        return model, SpectrumLanes.of(model, np.abs(load.torque), load.weights)
    return model, None


def _safeties(model: PairModel, lanes: SpectrumLanes | None, load: StageLoad) -> FloatArray:
    """S_H1, S_H2, S_F1, S_F2 (on the spectrum when the load is one)."""
    if lanes is not None:
        return lanes.safety(model)
    _, sh, sf, _ = model.stresses(np.array([float(load.torque)]))
    return np.concatenate([model.sigma_hg / sh[0], model.sigma_fg / sf[0]])


def _feasible(model: PairModel, lanes: SpectrumLanes | None, load: StageLoad) -> bool:
    """Every safety factor reaches its minimum (for a spectrum without finding the factors themselves)."""
    if lanes is not None:
        return lanes.feasible(model)
    return bool(np.min(_margins(_safeties(model, lanes, load), model.duty)) >= 0)


def _margins(s: FloatArray, duty: Duty) -> FloatArray:
    need = np.array([duty.min_safety_contact] * 2 + [duty.min_safety_root] * 2)
    return np.asarray(s / need - 1, dtype=float)


def size_stage(ratio: float, load: StageLoad, rules: SizingRules | None = None, *, stage: int = 0,
               helix_angle: float | None = None, pinion_teeth: int | None = None,
               width_steps: int | None = None) -> SizedStage:
    """Least-mass (or least centre distance) pair of about ``ratio`` [-] for ``load``.

    ``width_steps`` bisections in log face width locate the least width each module needs: the default (26) finds it
    to a few parts in 1e8; fewer give a mass figure (the width found is never below the least one, and lies
    within ln(5)/2^steps of it) at less cost.

    The gear gets round(ratio z1) teeth. Raises Infeasible when no module of the series carries the load
    within the face width limits (naming the stage), InvalidInput for bad rules.
    """
    rules = rules or SizingRules()
    for i, name in enumerate(("pinion_material", "gear_material")):
        gear_material(rules.materials[i], f"strength.{name}")
    if not 0 < rules.min_face_width_ratio <= rules.max_face_width_ratio:
        raise InvalidInput("face width ratios need 0 < min <= max", field="strength.min_face_width_ratio")
    helix = (rules.helix_angle or 0.0) if helix_angle is None else helix_angle
    z1 = rules.pinion_teeth if pinion_teeth is None else pinion_teeth
    if min_profile_shift(z1, helix, BasicRack()) > 1e-9:
        raise InvalidInput(f"{z1} pinion teeth are undercut without profile shift at this helix angle",
                           field="strength.pinion_teeth")
    z2 = max(int(round(ratio * z1)), z1)
    torque_peak = float(np.max(np.abs(load.torque))) if isinstance(load.torque, np.ndarray) else float(load.torque)
    if not (math.isfinite(torque_peak) and torque_peak > 0):
        raise InvalidInput(f"{stage_name(stage)} carries no torque", field=f"stages[{stage}]")
    examined = 0
    modules = module_series(rules.series)
    rho = np.array([gear_material(n).density for n in rules.materials])

    def key_of(m: float) -> Callable[[float], float]:
        d = np.array([z1, z2]) * m / math.cos(helix)
        a = float(d.sum() / 2)

        def key(b: float) -> float:
            mass = float(np.sum(rho * math.pi / 4 * b * d**2))
            return mass if rules.objective == "mass" else a + 1e-9 * mass
        return key

    found: list[_WidthSearch] = []       # the modules that carry the load, in the series' order
    steps = _WIDTH_STEPS if width_steps is None else width_steps
    for m in modules:
        d1 = z1 * m / math.cos(helix)
        b_lo, b_hi = rules.min_face_width_ratio * d1, rules.max_face_width_ratio * d1
        if found and rules.objective == "mass":
            # the least mass this module could have (the narrowest face) grows as the module cubed: once it
            # reaches the best found, no larger module can beat it
            d = np.array([z1, z2]) * m / math.cos(helix)
            if _at_least_least(float(np.sum(rho * math.pi / 4 * b_lo * d**2)), found):
                break
        examined += 1
        # one model and one set of Miner lanes per module: the width search changes only the width's terms
        wide, lanes = _model(rules, _spec(rules, z1, z2, m, b_hi, helix), load)
        if not _feasible(wide, lanes, load):
            continue                     # even the widest face fails: a larger module is needed
        narrow = wide.at_width(b_lo)
        if _feasible(narrow, lanes, load):
            found.append(_WidthSearch(m, key_of(m), wide, lanes, load, 0.0, 0.0, 0, (b_lo, narrow)))
            break                        # larger modules only add mass and centre distance from here
        found.append(_WidthSearch(m, key_of(m), wide, lanes, load, math.log(b_lo), math.log(b_hi), steps))
    if not found:
        raise Infeasible(
            f"{stage_name(stage)}: no ISO 54 module up to {modules[-1] / MM:g} mm carries the load with a face width "
            f"up to {rules.max_face_width_ratio:g} pinion diameters",
            constraint="strength", stage_index=stage, pinion_torque_Nm=torque_peak)
    best = _least(found)
    m, b, at_b, lanes = best.module, best.width(), best.model(), best.lanes
    narrowest = best.narrowest is not None
    s = _safeties(at_b, lanes, load)
    binding = "min_face_width" if narrowest else _CONSTRAINTS[int(np.argmin(_margins(s, rules.duty)))]
    r = _result(at_b, torque_peak)      # the full rating at the peak torque, on the model the search found
    d = np.array([z1, z2]) * m / math.cos(helix)
    rho = np.array([gear_material(n).density for n in rules.materials])
    vol = float(np.sum(math.pi / 4 * b * d**2))
    smaller = None
    i = modules.index(m)
    if i > 0:
        ms = modules[i - 1]
        try:
            small, small_lanes = _model(rules, _spec(rules, z1, z2, ms, b, helix), load)
            # one Miner sum per lane says which fall short; their factors are needed only to rank two or more
            failing = small_lanes.failing(small) if small_lanes is not None else None
            if failing is not None and len(failing) <= 1:
                smaller = (ms, _CONSTRAINTS[failing[0]] if failing else "none")
            else:
                marg = _margins(_safeties(small, small_lanes, load), rules.duty)
                smaller = (ms, _CONSTRAINTS[int(np.argmin(marg))] if np.min(marg) < 0 else "none")
        except InvalidInput as exc:
            smaller = (ms, f"geometry: {exc.field}")
    margins = dict(zip(_CONSTRAINTS, map(float, _margins(s, rules.duty)), strict=True))
    g = r.geometry
    return SizedStage(stage, m, z1, z2, z2 / z1, helix, b, g.a, (float(d[0]), float(d[1])), g.da,
                      float(np.sum(rho * math.pi / 4 * b * d**2)), vol, (float(s[0]), float(s[1])),
                      (float(s[2]), float(s[3])), binding, margins, r, examined, smaller)


class _WidthSearch:
    """One module's bisection for its least face width, run only as far as the sizing's decisions need it.

    The bisection halves [ln b_lo, ln b_hi] ``steps`` times and answers the upper end. Its answer lies above
    every lower end it passes and below every upper end, so the key (mass, or centre distance) of the width it
    will answer lies in [key(e^lo), key(e^hi)] at every step: a module that loses (or wins) on those bounds is
    settled without its remaining steps, and the module chosen is bisected to the end as before."""

    def __init__(self, module: float, key: Callable[[float], float], wide: PairModel, lanes: SpectrumLanes | None,
                 load: StageLoad, lo: float, hi: float, steps: int,
                 narrowest: tuple[float, PairModel] | None = None) -> None:
        """``narrowest``: the least width and its model when the narrowest face carries the load (no search)."""
        self.module, self.key, self.wide, self.lanes, self.load = module, key, wide, lanes, load
        self.lo, self.hi, self.steps, self.narrowest = lo, hi, steps, narrowest
        if narrowest is not None:
            self.bounds = (key(narrowest[0]),) * 2
        else:
            self.bounds = (key(math.exp(hi)),) * 2 if steps == 0 else (key(math.exp(lo)), key(math.exp(hi)))

    def step(self) -> None:
        mid = (self.lo + self.hi) / 2
        if _feasible(self.wide.at_width(math.exp(mid)), self.lanes, self.load):
            self.hi = mid
        else:
            self.lo = mid
        self.steps -= 1
        self.bounds = ((self.key(math.exp(self.hi)),) * 2 if self.steps == 0
                       else (self.key(math.exp(self.lo)), self.key(math.exp(self.hi))))

    def width(self) -> float:
        if self.narrowest is not None:
            return self.narrowest[0]
        while self.steps:
            self.step()
        return math.exp(self.hi)

    def model(self) -> PairModel:
        return self.narrowest[1] if self.narrowest is not None else self.wide.at_width(self.width())


def _at_least_least(value: float, found: list[_WidthSearch]) -> bool:
    """Whether ``value`` >= the least key of the modules found, stepping their searches only until that is known."""
    while True:
        if value >= min(f.bounds[1] for f in found):
            return True
        if value < min(f.bounds[0] for f in found):
            return False
        # undecided: the least lower bound belongs to a search still running (a finished one has equal bounds)
        min((f for f in found if f.steps), key=lambda f: f.bounds[0]).step()


def _least(found: list[_WidthSearch]) -> _WidthSearch:
    """The first module of least key (a later one must be strictly lighter to replace an earlier one)."""
    while True:
        alive = [i for i, f in enumerate(found) if not any(
            (j < i and g.bounds[1] <= f.bounds[0]) or (j > i and g.bounds[1] < f.bounds[0])
            for j, g in enumerate(found))]
        if len(alive) == 1:
            return found[alive[0]]
        running = [found[i] for i in alive if found[i].steps]
        if not running:                  # every key known: one module survives
            return found[alive[0]]
        min(running, key=lambda f: f.bounds[0]).step()


def size_train(ratios: Sequence[float] | FloatArray, loads: Sequence[StageLoad], stages: Sequence[Stage] | None = None,
               rules: SizingRules | None = None) -> TrainSizing:
    """Size every cylindrical stage of a train (motor side first) for its pinion load; other stage types get
    None. The stages are independent once ratios and loads are fixed, so each stage's optimum is the train's."""
    rules = rules or SizingRules()
    if len(ratios) != len(loads):
        raise InvalidInput("one load per stage", field="stages")
    out: list[SizedStage | None] = []
    for k, (u, load) in enumerate(zip(ratios, loads, strict=True)):
        kind = stages[k].type if stages is not None else "spur"
        if kind not in SIZED_TYPES:
            out.append(None)
            continue
        helix = rules.helix_angle if rules.helix_angle is not None else HELICAL_TYPES.get(kind, 0.0)
        out.append(size_stage(u, load, rules, stage=k, helix_angle=helix))
    sized = [s for s in out if s is not None]
    return TrainSizing(tuple(out), sum(s.mass for s in sized), sum(s.volume for s in sized),
                       sum(s.centre_distance for s in sized))


@dataclass(frozen=True, slots=True)
class StrengthSplit:
    """A split whose volume model is the strength sizing's: ``split`` the final split, ``sizing`` the train
    sized at its ratios, ``coefficients`` c_k read off the sized stages [m³/(N·m)], ``passes`` made and
    ``volume_agreement`` |V_split/V_sized - 1| of the final pass [-]."""

    split: SplitResult
    sizing: TrainSizing
    coefficients: tuple[float, ...]
    passes: int
    volume_agreement: float


def _stage_loads(ratios: FloatArray, stages: Sequence[Stage], input_torque: float | FloatArray,
                 input_speed: float) -> list[StageLoad]:
    gain = np.concatenate([[1.0], np.cumprod(ratios * np.array([s.efficiency for s in stages]))[:-1]])
    speed = input_speed / np.concatenate([[1.0], np.cumprod(ratios)[:-1]])
    t = np.asarray(input_torque, dtype=float)
    return [StageLoad(t * g if t.ndim else float(t) * float(g), float(w)) for g, w in zip(gain, speed, strict=True)]


def split_for_strength(total: float, stages: Sequence[Stage], input_torque: float | FloatArray,
                       input_speed: float, rules: SizingRules | None = None, *, inertia: InertiaModel | None = None,
                       time_limit_s: float = 20.0) -> StrengthSplit:
    """Split ``total`` between ``stages`` for least gear volume with each stage's volume coefficient taken
    from the strength sizing, and size the train at the answer.

    ``input_torque`` on the motor shaft [N·m] (an array: sampled over the machine cycle); ``input_speed``
    [rad/s]. Every stage must be a cylindrical pair type.
    """
    rules = rules or SizingRules()
    if not stages:
        raise InvalidInput("a drive needs at least one stage", field="stages")
    for k, s in enumerate(stages):
        if s.type not in SIZED_TYPES:
            raise InvalidInput(f"the strength split sizes cylindrical pairs ({', '.join(SIZED_TYPES)}); stage {k} "
                               f"is {s.type}", field=f"stages[{k}].type")
    current = list(stages)
    ref_torque = float(np.max(np.abs(np.asarray(input_torque, dtype=float))))
    effs = np.array([s.efficiency for s in stages])
    previous: FloatArray | None = None
    for passes in range(1, _SPLIT_PASSES + 1):
        split = split_ratio(total, current, "min_volume", inertia=inertia, input_torque=ref_torque,
                            time_limit_s=time_limit_s)
        u = np.array(split.stage_ratios)
        sizing = size_train(u, _stage_loads(u, current, input_torque, input_speed), current, rules)
        # The split's own prediction of the volume against the volume the sizing finds at its ratios.
        agreement = abs((split.gear_volume or 0.0) / sizing.volume - 1)
        pin = ref_torque * np.concatenate([[1.0], np.cumprod(u * effs)[:-1]])
        coeff = tuple(float(st.volume / (p * (st.ratio + 1) * (st.ratio**2 + 1) / st.ratio)) if st else 0.0
                      for st, p in zip(sizing.stages, pin, strict=True))
        settled = previous is not None and float(np.max(np.abs(np.log(u / previous)))) < 1e-3
        if settled:
            break
        previous = u
        current = [dataclasses.replace(s, volume_coefficient=c) for s, c in zip(stages, coeff, strict=True)]
    return StrengthSplit(split, sizing, coeff, passes, agreement)
