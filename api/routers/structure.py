"""POST /v1/structure: mobility, redundant constraints and Assur groups of a mechanism given as links and pairs."""

from __future__ import annotations

from fastapi import APIRouter

from ..schemas.structure import StructureIn, StructureOut

router = APIRouter(tags=["structure"])


@router.post("/structure", response_model=StructureOut)
def structure(body: StructureIn) -> StructureOut:
    """Pair classes, mobility by Somov-Malyshev (and Chebyshev when planar), redundant constraints, and for a
    planar linkage the primary mechanism and the Assur groups with their classes, in the order they are added."""
    return StructureOut.from_engine(body.run())
