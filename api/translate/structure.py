"""POST /v1/structure: a linkage's pairs or mechanism in, its structural analysis (groups, mobility) out."""

from __future__ import annotations

import synth

from api.translate.linkage import planar_linkage_from
from mechsynth_client.schemas.structure import (
    AssurGroupOut,
    MobilityGeometryOut,
    PairIn,
    PairOut,
    StructureIn,
    StructureOut,
)


def pair_from(pair: PairIn) -> synth.Pair:
    """Engine pair."""
    return synth.Pair(pair.name, (pair.links[0], pair.links[1]), pair.kind, pair.pair_class, pair.dof, pair.higher)


def structure_of(body: StructureIn) -> synth.Structure:
    """Engine call arguments as one structure analysis."""
    if body.mechanism is not None:
        return synth.linkage_structure(planar_linkage_from(body.mechanism))
    assert body.links is not None and body.pairs is not None
    return synth.analyse_structure(body.links, [pair_from(p) for p in body.pairs], frame=body.frame,
                                   planar=body.planar, input_links=body.input_links,
                                   known_mobility=body.known_mobility)


def structure_out(s: synth.Structure) -> StructureOut:
    """Schema from an engine structure."""
    roman = synth.structure.ROMAN
    return StructureOut(
        moving_links=s.moving_links,
        pairs=[PairOut(name=p.name, links=list(p.links), constraints=p.constraints, dof=p.dof,
                       pair_class=p.pair_class, higher=p.higher) for p in s.pairs],
        pair_counts={f"p{k + 1}": c for k, c in enumerate(s.pair_counts)},
        mobility_somov_malyshev=s.mobility_somov, mobility_chebyshev=s.mobility_chebyshev,
        redundant_constraints=s.redundant_constraints, primary_links=list(s.primary_links),
        primary_pairs=list(s.primary_pairs), primary_mobility=s.primary_mobility,
        assur_groups=None if s.groups is None else [
            AssurGroupOut(links=list(g.links), pairs=list(g.pairs), n=g.n, p5=g.p5, mobility=g.mobility,
                          group_class=roman[g.group_class], order=g.order,
                          statically_determinate=g.statically_determinate,
                          placement=None if s.placements is None else s.placements[i])  # type: ignore[arg-type]
            for i, g in enumerate(s.groups)],
        mechanism_class=None if s.mechanism_class is None else roman[s.mechanism_class],
        replaced_higher_pairs=list(s.replaced_higher_pairs), note=s.note,
        geometry=None if s.geometry is None else MobilityGeometryOut(
            mobility_geometric=s.geometry.mobility_geometric, jacobian_rank=s.geometry.rank,
            constraint_rows=s.geometry.rows, samples=s.geometry.samples,
            passive_links=[p.link for p in s.geometry.passive],
            redundant_pairs=list(s.geometry.redundant_pairs), dependent_pairs=list(s.geometry.dependent_pairs),
            max_residual_m=s.geometry.max_residual, explanation=s.geometry.explanation()),
    )
