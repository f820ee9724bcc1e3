"""POST /v1/machines/optimise-linkage on the executor's workers, priced before it starts.

The engine's :func:`~synth.machine.optimise_linkage.optimise_linkage` runs its stages one after another in one
process (a design study's variant does that). A request runs the same stages as separate tasks: the box's sample
and its kinematic check, the kinematically feasible members in one task per worker, one task per refinement
start, and the conclusion, which renders the answer in its worker. The members are put back in the sample's
order and the refinements in their starts' order, as the engine's own loop makes them, so both give the same
answer.
"""

from __future__ import annotations

import math

from fastapi import Request, Response

import synth
from api.translate.optimise import linkage_optimise_from, linkage_optimise_out
from mechsynth_client.schemas.optimise import LinkageOptimiseIn, LinkageOptimiseOut
from synth.machine.optimise_linkage import conclude_linkage, design_sample, refine_start, scan_box

from ..media import Render
from .admission import RequestSolvers, together
from .plans import Limits, Plan
from .work import linkage_member_s, optimise_linkage_s


def price_linkage_optimisation(b: LinkageOptimiseIn, lim: Limits, workers: int) -> float:
    """The request's estimated time on ``workers`` workers [s]; TooLarge naming the field that drives most of
    it (``samples`` or ``refine_runs``) when beyond the service's bound."""
    parts = optimise_linkage_s(b, max(1, workers))
    wall = sum(parts.values())
    if wall > lim.max_work_s:
        field = max(("samples", "refine_runs"), key=lambda k: parts[k])
        raise synth.TooLarge(
            "linkage optimisation estimated time [s]", int(lim.max_work_s), math.ceil(wall),
            f"{b.samples} sampled members and {b.refined} refinements of up to {b.refine_runs} chain runs each "
            f"(a chain run about {linkage_member_s(b):.2g} s for this machine) take about {wall:.3g} s on the "
            f"{workers} workers, beyond the bound of {lim.max_work_s:g} s: ask for fewer "
            f"{field.replace('_', ' ')}{' or fewer refined' if field == 'refine_runs' else ''}, or fewer crank "
            "angles (machine.samples)",
            field=field)
    return wall


async def answer_linkage_optimisation(body: LinkageOptimiseIn, request: Request,
                                      solvers: RequestSolvers) -> Response:
    """Answer the request with the optimised linkage and its machine, the chains spread over the workers."""
    lim = solvers.limits
    workers = solvers.solvers.workers
    spec = linkage_optimise_from(body, lim.max_stages)
    spec.validate()
    price_linkage_optimisation(body, lim, workers)
    t = lim.solver_time_limit_s
    scan = await solvers.run(scan_box, spec)
    feasible = scan.feasible
    n = max(1, min(workers, len(feasible)))
    # interleaved, so every worker gets members from the whole sample
    shares = [feasible[k::n] for k in range(n)]
    designed = await together([solvers.run(design_sample, spec, scan, share, time_limit_s=t)
                                for share in shares])
    members = scan.members([pair for part in designed for pair in part])
    # a start past the feasible members refines nothing: no task for it
    starts = min(spec.refined, sum(m.feasible for m in members))
    refinements = await together([solvers.run(refine_start, spec, scan, members, k, time_limit_s=t)
                                   for k in range(starts)])
    plan = Plan(Render(linkage_optimise_out, model_extra=(body.model_dump(mode="json"),)),
                conclude_linkage, (spec, scan, members, refinements), dict(time_limit_s=t))
    return await solvers.answer_plan(plan, request)
