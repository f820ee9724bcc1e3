"""POST /v1/structure: mobility, redundant constraints and Assur groups of a mechanism given as links and pairs."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import Response

import synth

from ..deps import SolverDep
from ..media import render_for
from ..schemas.structure import StructureIn, StructureOut

router = APIRouter(tags=["structure"])


@router.post("/structure", response_model=StructureOut)
async def structure(body: StructureIn, request: Request, solvers: SolverDep) -> Response:
    """Pair classes, mobility by Somov-Malyshev (and Chebyshev when planar), redundant constraints, and for a
    planar linkage the primary mechanism and the Assur groups with their classes, in the order they are added."""
    return await solvers.answer(
        render_for(request, None, (), StructureOut.from_engine), synth.analyse_structure, body.links,
        [p.to_engine() for p in body.pairs], frame=body.frame, planar=body.planar, input_links=body.input_links,
        known_mobility=body.known_mobility)
