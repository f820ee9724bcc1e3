"""POST /v1/machines/optimise on the executor's workers: the candidates' chains run side by side.

The engine's :func:`synth.optimise_machine` runs its stages one after another in one process (a design study's
variant does that). A request runs the same stages as separate tasks: the kinematic scan; the scan's members in
small tasks the workers take in turn (the chain's own designed, the others bounded), then rounds of the bounded
members that could still win, one task each; rounds of cells (two at a time, each round's chosen against the best
found before it), one task per cell to cut it into plateaus and one per plateau searched; and the conclusion,
which renders the answer in its worker. The members are put back in the order the engine's own loop makes them,
so both give the same answer.

A worker keeps what it computed for a member (analysis, balancing, drive, teeth) for the rest of the run, so a
later stage of the same member asks for that worker (a bound member designed in full, a cell's walk from its
upper end, a plateau searched from the ends its walk found); the pool gives it there when that worker is free,
and to another worker (which computes the member again) rather than let one idle.
"""

from __future__ import annotations

import math
import uuid
from collections.abc import Callable, Iterable, Sequence
from typing import Any, TypeVar

from fastapi import Request, Response

import synth
from synth.machine.optimise import (
    MemberScore,
    Plateau,
    Refinement,
    cell_plateaus,
    conclude_search,
    design_members,
    designed,
    in_run,
    members_to_design,
    next_cells,
    scan_family,
    scan_members,
    search_plateau,
    with_designed,
)

from .admission import RequestSolvers, in_turn
from synth.machine.record import DesignRecord

from .plans import SERVICE_VERSION, Limits, machine_optimise_conclusion
from .work import optimise_s
from api.translate.optimise import machine_optimise_from
from mechsynth_client.schemas.optimise import MachineOptimiseIn


T = TypeVar("T")

#: Members of the scan in one task: the workers take the tasks in turn, so they finish within about one task's
#: work of each other, and each task pays the hand-off to a worker once.
MEMBERS_PER_TASK = 4


def member_tasks(candidates: Sequence[float], sized: float) -> list[list[float]]:
    """The scan's members as tasks for the workers to take in turn: the member ``sized`` (its wheels sized to the
    chain's precision, several members' work) alone and first, then the others in tasks of about
    :data:`MEMBERS_PER_TASK`, each task every k-th member of the family's order (so each spans the family)."""
    others = [u for u in candidates if u != sized]
    k = max(1, math.ceil(len(others) / MEMBERS_PER_TASK))
    return [[sized], *(others[i::k] for i in range(k) if others[i::k])]


def _parameters(scored: tuple[MemberScore, ...]) -> list[float]:
    return [m.parameter for m in scored]


def _plateau_ends(walk: tuple[Refinement, tuple[Plateau, ...]]) -> list[float]:
    return [u for p in walk[1] for u in (p.lo, p.hi)]


def price_optimisation(b: MachineOptimiseIn, lim: Limits, workers: int) -> float:
    """The request's estimated time on ``workers`` workers [s]; TooLarge naming the field that drives most of it
    (``scan_members`` or ``search_cells``) when beyond the service's bound."""
    parts = optimise_s(b, max(1, workers))
    wall = sum(parts.values())
    if wall > lim.max_work_s:
        field = max(("scan_members", "search_cells"), key=lambda k: parts[k])
        raise synth.TooLarge(
            "machine optimisation estimated time [s]", int(lim.max_work_s), math.ceil(wall),
            f"{b.scan_members} scanned members and {b.search_cells} cells searched at {b.samples} crank angles "
            f"take about {wall:.3g} s on the {workers} workers, beyond the bound of {lim.max_work_s:g} s: ask for "
            f"fewer {field.replace('_', ' ')} or fewer crank angles (samples)", field=field)
    return wall


async def answer_optimisation(body: MachineOptimiseIn, request: Request, solvers: RequestSolvers,
                              fmt: str | None = None) -> Response:
    """Answer the request with the optimised machine, its chains spread over the workers; ``fmt`` pdf: the
    chosen machine's design record with the certificate's page."""
    lim = solvers.limits
    price_optimisation(body, lim, solvers.solvers.workers)
    spec = machine_optimise_from(body, lim.max_stages)
    t = lim.solver_time_limit_s
    # the stages run as one optimisation: a worker that analysed, balanced and geared a member for an earlier
    # stage takes them as they were (the scan's bound, then its steady machine; a walk's bisection, then a search),
    # and a stage goes to the worker that ran the one before it for the same members, when that worker is free
    run = uuid.uuid4().hex
    scan = await solvers.run(scan_family, spec)
    workers = solvers.solvers.workers
    where: dict[float, str | None] = {}

    async def stage(prefer: float | None, fn: Callable[..., T], *args: Any,
                    kept: Callable[[T], Iterable[float]] | None = None) -> T:
        # a member's stages up to its drive stay in the worker that computed them (in_run): the stage that needs
        # them again goes there when it is free; ``kept`` the members whose stages this one computed
        out: T
        out, worker = await solvers.run_on(where.get(prefer) if prefer is not None else None,
                                           in_run, run, fn, spec, *args, time_limit_s=t)
        for u in kept(out) if kept is not None else ():
            where.setdefault(u, worker)
        return out

    tasks = member_tasks(scan.candidates, scan.chain_parameter)
    parts = await in_turn([lambda share=share: stage(  # type: ignore[misc]
                               None, scan_members, share, scan.chain_parameter, kept=_parameters)
                           for share in tasks], workers)
    by_parameter: dict[float, MemberScore] = {m.parameter: m for part in parts for m in part}
    members = tuple(by_parameter[u] for u in scan.candidates)
    # a round's tasks go to the pool together, so that each worker takes first those whose members it kept, within
    # the service's slots left to them (the request never holds more slots than the service has: a service of one
    # worker and no queue runs them in turn)
    at_once = max(1, solvers.solvers.capacity // max(1, workers))
    # rounds of the bounded members that could still win, as the engine runs them, one member a task
    while bound_round := await solvers.run(members_to_design, spec, scan, members):
        found = await in_turn([lambda u=u: stage(u, design_members, [u])  # type: ignore[misc]
                               for u in bound_round], at_once)
        members = with_designed(members, (m for part in found for m in part))

    async def search(r: Refinement) -> tuple[tuple[Refinement, tuple[Plateau, ...]], list[tuple[MemberScore, ...]]]:
        # the cells' walks side by side on the workers; a cell's plateaus are searched, one task each, as soon as
        # its walk has found them, beside the other cells' walks. A walk asks for its upper end's choice (kept where
        # that member was designed) and leaves its plateaus' ends where it ran
        walk = await stage(r.hi, cell_plateaus, members, r, kept=_plateau_ends)
        return walk, await in_turn([lambda p=p: stage(p.hi, search_plateau, scan, members, p)  # type: ignore[misc]
                                    for p in walk[1]], at_once)

    walks: list[tuple[Refinement, tuple[Plateau, ...]]] = []
    seen: list[tuple[MemberScore, ...]] = []
    # rounds of cells as the engine runs them, each chosen against the best of every member designed before it
    while todo := await solvers.run(next_cells, spec, scan, members + designed(seen),
                                    tuple((r.lo, r.hi) for r, _ in walks)):
        for walk, found in await in_turn([lambda r=r: search(r) for r in todo], workers):  # type: ignore[misc]
            walks.append(walk)
            seen.extend(found)
    record = DesignRecord.of(body.model_dump(mode="json"), name="machine optimisation", version=SERVICE_VERSION)
    plan = machine_optimise_conclusion(conclude_search, spec, scan, members, tuple(walks), tuple(seen), t,
                                       record=record)
    return await solvers.answer_plan(plan, request, fmt)
