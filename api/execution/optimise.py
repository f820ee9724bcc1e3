"""POST /v1/machines/optimise on the executor's workers: the candidates' chains run side by side.

The engine's :func:`synth.optimise_machine` runs its stages one after another in one process (a design study's
variant does that). A request runs the same stages as separate tasks: the kinematic scan; the scan's members in
one task per worker; rounds of cells (two at a time, each round's chosen against the best found before it), one
task per cell to cut it into plateaus and one per plateau searched; and the conclusion, which renders the answer
in its worker. The members are put back in the order the engine's own loop makes them, so both give the same
answer.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

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
    next_cells,
    scan_family,
    search_plateau,
)

from .admission import RequestSolvers, together
from synth.machine.record import DesignRecord

from .plans import SERVICE_VERSION, Limits, machine_optimise_conclusion
from .work import optimise_s
from api.translate.optimise import machine_optimise_from
from mechsynth_client.schemas.optimise import MachineOptimiseIn


#: The chain's own member has its wheels sized to the chain's precision: about as much work as this many other
#: members of the scan (measured on the README's crank-rocker with two stages).
SIZED_MEMBER_WEIGHT = 8.0


def member_shares(candidates: Sequence[float], sized: float, n: int) -> list[list[float]]:
    """The scan's members in ``n`` shares of about the same work: each member, in the family's order, to the
    share with the least work so far, so every worker gets members from the whole family and the member
    ``sized`` counts for :data:`SIZED_MEMBER_WEIGHT`."""
    shares: list[list[float]] = [[] for _ in range(n)]
    work = [0.0] * n
    for u in candidates:
        k = min(range(n), key=lambda i: (work[i], i))
        shares[k].append(u)
        work[k] += SIZED_MEMBER_WEIGHT if u == sized else 1.0
    return [s for s in shares if s]


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
    scan = await solvers.run(scan_family, spec)
    n = max(1, min(solvers.solvers.workers, len(scan.candidates)))
    shares = member_shares(scan.candidates, scan.chain_parameter, n)
    parts = await together(solvers.run(design_members, spec, share, time_limit_s=t,
                                       size_gears_at=(scan.chain_parameter,)) for share in shares)
    by_parameter: dict[float, MemberScore] = {m.parameter: m for part in parts for m in part}
    members = tuple(by_parameter[u] for u in scan.candidates)

    async def search(r: Refinement) -> tuple[tuple[Refinement, tuple[Plateau, ...]], list[tuple[MemberScore, ...]]]:
        # a cell's plateaus are searched, one task each, as soon as its walk has found them, beside the other
        # cells' walks
        walk = await solvers.run(cell_plateaus, spec, members, r, time_limit_s=t)
        return walk, await together(solvers.run(search_plateau, spec, scan, members, p, time_limit_s=t)
                                    for p in walk[1])

    walks: list[tuple[Refinement, tuple[Plateau, ...]]] = []
    seen: list[tuple[MemberScore, ...]] = []
    # rounds of cells as the engine runs them, each chosen against the best of every member designed before it
    while todo := await solvers.run(next_cells, spec, scan, members + designed(seen),
                                    tuple((r.lo, r.hi) for r, _ in walks)):
        for walk, found in await together(search(r) for r in todo):
            walks.append(walk)
            seen.extend(found)
    record = DesignRecord.of(body.model_dump(mode="json"), name="machine optimisation", version=SERVICE_VERSION)
    plan = machine_optimise_conclusion(conclude_search, spec, scan, members, tuple(walks), tuple(seen), t,
                                       record=record)
    return await solvers.answer_plan(plan, request, fmt)
