"""Static balancing of many variants of one linkage at once: the answers of :func:`balance_static`, one per
case, with every array operation run once over the whole batch.

At a few hundred samples a single request's cost is the fixed cost of each of its hundreds of small array
operations, not the samples. So the variants of a batch that share a topology, sample count, crank speed and
gravity are laid end to end along the sample axis (:mod:`synth.kinematics.stacking`; four-bars in one pass of
their closed form): one direct kinetostatic solve with each sample's own mass properties gives every variant's
analysis before balancing, one evaluation of the map's shaking-force rows every variant's rows (its block of
samples; the program needs no other rows), and one direct solve with the counterweights added every variant's
independent re-analysis. Each variant's program is its own (its row space of the force rows, its realisability
cones and budget), built and solved by Clarabel exactly as :func:`balance_static` builds and solves it.

A case the stack cannot take (the fixed-points method, loads or torques on the links, a singular position
anywhere in the stack) is run by :func:`balance_static` itself; an error of one variant is that variant's
answer, as the single request would raise it.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass, fields
from typing import Any, Literal, TypeVar

import numpy as np

from ..analysis import Analysis, Summary
from ..dynamics import reduced_model
from ..errors import Infeasible, SynthError
from ..kinematics import MAX_SAMPLES, FourBar, Motion, PointState, cycle_angles, motion
from ..kinematics.motion import magnitude
from ..kinematics.stacking import motion_block, stack_motions, stacked_fourbar_motion
from ..kinetostatics import (Kinetostatics, LinkArrays, external_loads, link_arrays_per_sample, shaking_force_map,
                             solve_direct, virtual_power_torque)
from ..model import FloatArray, Linkage
from .fourbar import (BalanceResult, _require_turning, _static_columns, _static_result, _static_solution,
                      _static_spec, balance_static)
from .program import CounterweightSolution, CounterweightSpec, counterweight_layout, row_spaces

#: Most samples laid end to end in one stack: past a few tens of thousands the arrays leave the caches and a
#: larger stack gains nothing.
MAX_STACK_SAMPLES = 20_000


@dataclass(frozen=True, slots=True)
class StaticCase:
    """One static-balancing request: the arguments of :func:`balance_static` (same names, same units)."""

    linkage: Linkage
    speed: float
    spec: CounterweightSpec | None = None
    samples: int = 360
    objective: Literal["min_mass", "min_inertia"] = "min_mass"
    mass_budget: float | None = None
    time_limit_s: float = 20.0
    method: Literal["program", "fixed_points"] = "program"


@dataclass(frozen=True, slots=True)
class _Prepared:
    """A case checked and its spec resolved as :func:`balance_static` does before analysing, with its angles."""

    index: int
    case: StaticCase
    spec: CounterweightSpec
    angles: FloatArray


def balance_static_batch(cases: Sequence[StaticCase]) -> list[BalanceResult | SynthError]:
    """:func:`balance_static` of every case: its result, or the engine error it raises, in the cases' order.

    The same results as calling :func:`balance_static` case by case (the same programs, solved the same way;
    the analyses the same plain model, on the stack), computed with one kinetostatic solve per stack.
    """
    out: dict[int, BalanceResult | SynthError] = {}
    groups: list[list[_Prepared]] = []
    for index, case in enumerate(cases):
        try:
            prepared = _prepare(index, case)
        except SynthError as exc:
            out[index] = exc.as_answer()
            continue
        if prepared is None:
            out[index] = _alone(case)
            continue
        for group in groups:
            if _stackable(group[0], prepared):
                group.append(prepared)
                break
        else:
            groups.append([prepared])
    for group in groups:
        per_stack = max(1, MAX_STACK_SAMPLES // len(group[0].angles))
        for start in range(0, len(group), per_stack):
            out.update(_stacked(group[start : start + per_stack]))
    return [out[i] for i in range(len(cases))]


def _alone(case: StaticCase) -> BalanceResult | SynthError:
    try:
        return balance_static(case.linkage, case.speed, case.spec, samples=case.samples, objective=case.objective,
                              mass_budget=case.mass_budget, time_limit_s=case.time_limit_s, method=case.method)
    except SynthError as exc:
        return exc.as_answer()


def _prepare(index: int, case: StaticCase) -> _Prepared | None:
    """The checks of :func:`balance_static` and :func:`synth.analyse` in their order up to the motion; None
    for a case the stack does not take."""
    linkage = case.linkage
    _require_turning(linkage)
    if case.method != "program" or linkage.loads or linkage.torques:
        return None
    spec = _static_spec(linkage, case.spec, case.objective, case.mass_budget)
    angles = cycle_angles(case.samples, 2 * math.pi, MAX_SAMPLES)
    if not (math.isfinite(case.speed) and case.speed > 0):
        return None   # the single request says what is wrong with the speed
    return _Prepared(index, case, spec, angles)


def _stackable(a: _Prepared, b: _Prepared) -> bool:
    ma, mb = a.case.linkage.mechanism, b.case.linkage.mechanism
    return (type(ma) is type(mb) and ma.topology == mb.topology and dict(ma.origins) == dict(mb.origins)
            and np.array_equal(a.angles, b.angles) and a.case.speed == b.case.speed
            and a.case.linkage.gravity == b.case.linkage.gravity)


def _stacked(group: Sequence[_Prepared]) -> dict[int, BalanceResult | SynthError]:
    """The results of one stack; a stack that cannot be solved as one (a dead position somewhere) is run
    case by case."""
    try:
        ready, stack, out = _stack(group)
        if ready and stack is not None:
            out.update(zip((p.index for p in ready), _solve_stack(ready, stack), strict=True))
        return out
    except SynthError:
        return {p.index: _alone(p.case) for p in group}


def _stack(group: Sequence[_Prepared]
           ) -> tuple[list[_Prepared], Motion | None, dict[int, BalanceResult | SynthError]]:
    """The motions of the variants whose loops close, stacked; the others' errors (or answers) as the single
    request gives them."""
    angles, speed = group[0].angles, group[0].case.speed
    out: dict[int, BalanceResult | SynthError] = {}
    mechanisms = [p.case.linkage.mechanism for p in group]
    if all(isinstance(m, FourBar) for m in mechanisms):
        fourbars = [m for m in mechanisms if isinstance(m, FourBar)]
        stack, bad = stacked_fourbar_motion(fourbars, angles, speed)
        if not bad.any():
            return list(group), stack, out
        ready = [p for p, b in zip(group, bad, strict=True) if not b]
        for p in (p for p, b in zip(group, bad, strict=True) if b):
            out[p.index] = _alone(p.case)   # its loop does not close: the single request names the gaps
        kept = [m for m, b in zip(fourbars, bad, strict=True) if not b]
        return ready, stacked_fourbar_motion(kept, angles, speed)[0] if kept else None, out
    motions: list[Motion] = []
    ready = []
    for p in group:
        try:
            motions.append(motion(p.case.linkage.mechanism, angles, speed))
            ready.append(p)
        except SynthError as exc:
            out[p.index] = exc.as_answer()
    return ready, stack_motions(motions) if motions else None, out


_T = TypeVar("_T")


@functools.cache
def _field_names(cls: type) -> tuple[str, ...]:
    return tuple(f.name for f in fields(cls))


def _block(obj: _T, s: slice) -> _T:
    """A dataclass of per-sample arrays (and dicts of them) cut to the samples ``s``."""
    cls: type = type(obj)
    cut: dict[str, Any] = {}
    for name in _field_names(cls):
        value = getattr(obj, name)
        if isinstance(value, np.ndarray):
            value = value[s]
        elif isinstance(value, dict):
            value = {k: v[s] for k, v in value.items()}
        cut[name] = value
    block: _T = cls(**cut)
    return block


def _summaries(kin: Kinetostatics, linkage: Linkage, count: int) -> list[Summary]:
    """:meth:`synth.Analysis.summary` of each of ``count`` equal blocks of the stacked ``kin``, at once."""
    force = magnitude(kin.shaking_force).reshape(count, -1)
    moment = kin.shaking_moment.reshape(count, -1)
    torque = kin.driving_torque.reshape(count, -1)
    revolute = [j.name for j in linkage.mechanism.topology.joints if j.kind == "revolute"]
    bearing = np.stack([magnitude(kin.reactions[j]).reshape(count, -1).max(axis=1) for j in revolute]).max(axis=0)
    columns = (np.sqrt(np.mean(force**2, axis=1)), force.max(axis=1), np.sqrt(np.mean(moment**2, axis=1)),
               np.abs(moment).max(axis=1), np.sqrt(np.mean(torque**2, axis=1)), np.abs(torque).max(axis=1), bearing)
    return [Summary(*(float(c) for c in row)) for row in zip(*columns, strict=True)]


def _analyses(stack: Motion, linkages: Sequence[Linkage], bases: Sequence[Motion],
              wanted: Sequence[bool] | None = None) -> tuple[list[Analysis | None], list[Summary], LinkArrays]:
    """:func:`synth.analyse` of each linkage on its block of ``stack`` (``bases``, each variant's block of the
    mechanism's motion), all in one solve (None for a variant whose figures overflow, the single request says
    why, and for one not ``wanted``), their summaries, and the stack's link arrays."""
    reference = linkages[0]
    count = len(linkages)
    n = stack.samples // count
    params = np.stack([lk.params().reshape(-1, 4) for lk in linkages], axis=1)  # (L, K, 4)
    arrays = link_arrays_per_sample(stack, reference, np.repeat(params, n, axis=1))
    links = reference.mechanism.topology.links
    coms = {f"S_{link}": PointState(arrays.com_pos[i], arrays.com_vel[i], arrays.com_acc[i])
            for i, link in enumerate(links)}
    mot = stack.with_points({}, coms)
    loads = external_loads(mot, reference)
    kin = solve_direct(mot, reference, arrays, loads)
    vp = virtual_power_torque(mot, reference, arrays, loads)
    red = reduced_model(mot, reference, arrays, loads)
    # The finiteness check of synth.analyse, per variant.
    checked = (kin.unknowns, kin.shaking_force, kin.shaking_moment, vp, red.inertia, red.load_torque)
    finite = np.ones(count, dtype=bool)
    for a in checked:
        finite &= np.isfinite(a.reshape(count, -1).sum(axis=1))
    out: list[Analysis | None] = []
    for k, linkage in enumerate(linkages):
        s = slice(k * n, (k + 1) * n)
        out.append(Analysis(linkage=linkage, motion=motion_block(mot, s.start, s.stop),
                            kinetostatics=_block(kin, s), virtual_power_torque=vp[s], reduced=_block(red, s),
                            mechanism_motion=bases[k])
                   if finite[k] and (wanted is None or wanted[k]) else None)
    return out, _summaries(kin, reference, count), arrays


def _systems(group: Sequence[_Prepared], rows: FloatArray, wanted: Sequence[bool]
             ) -> list[tuple[FloatArray, FloatArray] | None]:
    """Each wanted variant's static system (:func:`synth.balancing.fourbar._static_system` of its block of the
    shaking-force ``rows``, (K, 2N, params)), the SVDs of all that share their counterweight columns in one call;
    None where it is not wanted or its shaking force cannot be cancelled (the variant's own program then says so,
    as the single request does)."""
    out: list[tuple[FloatArray, FloatArray] | None] = [None] * len(group)
    by_columns: dict[tuple[int, ...], list[int]] = {}
    for k, p in enumerate(group):
        if wanted[k]:
            layout = counterweight_layout(p.spec, p.case.linkage)
            by_columns.setdefault(tuple(_static_columns(p.case.linkage, layout)), []).append(k)
    for columns, members in by_columns.items():
        block = rows[members]
        params = np.stack([group[k].case.linkage.params() for k in members])
        rhs = -np.matmul(block, params[:, :, None])[:, :, 0]
        reduced = row_spaces(block[:, :, list(columns)], rhs, "the shaking force", "counterweight_links")
        for k, system in zip(members, reduced, strict=True):
            out[k] = None if isinstance(system, Infeasible) else system
    return out


def _solve_stack(group: Sequence[_Prepared], stack: Motion) -> list[BalanceResult | SynthError]:
    n = len(group[0].angles)
    linkages = [p.case.linkage for p in group]
    bases = [motion_block(stack, k * n, (k + 1) * n) for k in range(len(group))]
    before, s_before, arrays = _analyses(stack, linkages, bases)
    # The program needs only the map's shaking-force rows (as balance_static takes them): every variant's from
    # one evaluation on the stack.
    rows = shaking_force_map(stack, linkages[0], arrays)
    rows = rows.reshape(len(group), 2 * n, rows.shape[-1])
    no_offset = np.zeros(2 * n)
    systems = _systems(group, rows, [an is not None for an in before])
    answers: list[tuple[list[Any], float] | SynthError | None] = []
    for k, (p, an) in enumerate(zip(group, before, strict=True)):
        if an is None:
            answers.append(None)
            continue
        case = p.case
        try:
            cw, program, x = _static_solution(case.linkage, (rows[k], no_offset), p.spec, case.objective,
                                              case.mass_budget, case.time_limit_s, systems[k])
        except SynthError as exc:
            answers.append(exc.as_answer())
            continue
        # In a minimum-mass program the inertia variable is free: the counterweights are point masses.
        cws = CounterweightSolution(cw, x).counterweights(
            point_masses=case.objective == "min_mass" and not p.spec.radius)
        answers.append((cws, float(program.q @ x)))
    # The independent check: the plain model again, every variant with its counterweights, in one solve.
    balanced = [lk.with_counterweights(a[0]) if isinstance(a, tuple) else lk
                for lk, a in zip(linkages, answers, strict=True)]
    after, s_after, _ = _analyses(stack, balanced, bases, [isinstance(a, tuple) for a in answers])
    results: list[BalanceResult | SynthError] = []
    for k, (p, an_before, an_after, answer) in enumerate(zip(group, before, after, answers, strict=True)):
        if isinstance(answer, SynthError):
            results.append(answer)
        elif answer is None or an_before is None or an_after is None:
            results.append(_alone(p.case))
        else:
            cws, objective = answer
            results.append(_static_result(cws, an_before, an_after, objective, (s_before[k], s_after[k])))
    return results


__all__ = ["MAX_STACK_SAMPLES", "StaticCase", "balance_static_batch"]
