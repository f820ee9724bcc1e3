"""Schemas of POST /v1/structure: a mechanism as links and pairs, its mobility and Assur groups."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field
from pydantic.config import JsonDict

from ._engine import synth
from .common import StrictModel

Name = Annotated[str, Field(min_length=1, max_length=40)]

SIXBAR_EXAMPLE: JsonDict = {
    "links": ["frame", "crank", "coupler", "rocker", "rod", "slider"],
    "pairs": [
        {"name": "O", "links": ["frame", "crank"], "kind": "revolute"},
        {"name": "A", "links": ["crank", "coupler"], "kind": "revolute"},
        {"name": "B", "links": ["coupler", "rocker"], "kind": "revolute"},
        {"name": "C", "links": ["rocker", "frame"], "kind": "revolute"},
        {"name": "D", "links": ["rocker", "rod"], "kind": "revolute"},
        {"name": "E", "links": ["rod", "slider"], "kind": "revolute"},
        {"name": "guide", "links": ["slider", "frame"], "kind": "prismatic"},
    ],
}


class PairIn(StrictModel):
    """A kinematic pair joining two links: by kind (planar), or by class or freedoms (spatial)."""

    name: Name = Field(description="Name of the pair (a joint letter, say).", examples=["A"])
    links: Annotated[list[Name], Field(min_length=2, max_length=2)] = Field(
        description="The two links it joins, by name.", examples=[["crank", "coupler"]])
    kind: Literal["revolute", "prismatic", "higher"] | None = Field(
        None, description="Planar: revolute or prismatic (lower pairs, p5) or higher (p4).")
    pair_class: int | None = Field(None, ge=1, le=5, description="Spatial: constraints S = class (I..V as 1..5).")
    dof: int | None = Field(None, ge=1, le=5, description="Spatial: relative freedoms H = 6 - S.")
    higher: bool | None = Field(None, description="Point or line contact; default: classes I and II, planar "
                                "higher pairs.")

    def to_engine(self) -> synth.Pair:
        """Engine pair."""
        return synth.Pair(self.name, (self.links[0], self.links[1]), self.kind, self.pair_class, self.dof, self.higher)


class StructureIn(StrictModel):
    """A mechanism as links (the frame among them) and the pairs that join them."""

    links: list[Name] = Field(min_length=2, max_length=40, description="Every link by name, the frame included.")
    pairs: list[PairIn] = Field(min_length=1, max_length=80, description="Every kinematic pair.")
    frame: Name = Field("frame", description="Name of the fixed link.")
    planar: bool = Field(True, description="Planar (Chebyshev's mobility formula) or spatial (Somov-Malyshev).")
    input_links: list[Name] | None = Field(None, max_length=40, description="Driven links of the primary "
                                           "mechanism; default the first W links paired with the frame.")
    known_mobility: int | None = Field(None, ge=-1000, le=1000, description="Spatial: the actual mobility, for "
                                       "the redundant constraints.")

    model_config = ConfigDict(json_schema_extra={"examples": [
        SIXBAR_EXAMPLE,
        {"links": ["frame", "1", "2", "3"], "planar": False, "known_mobility": 1,
         "pairs": [{"name": "A", "links": ["frame", "1"], "pair_class": 5},
                   {"name": "B", "links": ["1", "2"], "pair_class": 5},
                   {"name": "C", "links": ["2", "3"], "pair_class": 4},
                   {"name": "D", "links": ["3", "frame"], "pair_class": 3}]},
    ]})

    def run(self) -> synth.Structure:
        """Engine call arguments as one structure analysis."""
        return synth.analyse_structure(self.links, [p.to_engine() for p in self.pairs], frame=self.frame,
                                       planar=self.planar, input_links=self.input_links,
                                       known_mobility=self.known_mobility)


class PairOut(BaseModel):
    """A pair's class S, freedoms H = 6 - S, and contact."""

    name: str = Field(description="The pair's name, as given.")
    links: list[str] = Field(description="The two links it joins.")
    constraints: int = Field(description="Constraints S it imposes, its class number (1..5).")
    dof: int = Field(description="Relative freedoms H = 6 - S.")
    pair_class: str = Field(description="Its class as a Roman numeral, I..V (S).")
    higher: bool = Field(description="A higher pair (point or line contact); false for a lower pair.")


class AssurGroupOut(BaseModel):
    """An Assur group: W = 3n - 2p5 = 0; class (II dyad, III triad, IV...) and order (outer pairs)."""

    links: list[str] = Field(description="The group's links.")
    pairs: list[str] = Field(description="Its pairs: among its links, then those joining it to links already "
                             "placed.")
    n: int = Field(description="Number of links n.")
    p5: int = Field(description="Number of lower pairs p5 (its inner and outer pairs).")
    mobility: int = Field(description="W = 3n - 2p5: always 0 for an Assur group.")
    group_class: str = Field(description="Class as a Roman numeral: II for a dyad; else the most pairs on one link "
                             "or the longest closed contour of its inner pairs, whichever is larger.")
    order: int = Field(description="Order: the number of outer pairs joining it to the links already placed.")
    statically_determinate: bool = Field(description="3n = 2p5.")


class StructureOut(BaseModel):
    """Mobility by Somov-Malyshev and Chebyshev, redundant constraints, the primary mechanism and Assur groups."""

    moving_links: int = Field(description="Number n of moving links (the frame not counted).")
    pairs: list[PairOut] = Field(description="Every pair with its class and freedoms, as given.")
    pair_counts: dict[str, int] = Field(description="p1..p5: pairs by class.")
    mobility_somov_malyshev: int = Field(description="W = 6n - 5p5 - 4p4 - 3p3 - 2p2 - p1.")
    mobility_chebyshev: int | None = Field(description="Planar: W = 3n - 2p5 - p4; null for a spatial mechanism.")
    redundant_constraints: int | None = Field(description="Planar: Chebyshev's W minus Somov-Malyshev's; spatial: "
                                              "known_mobility minus Somov-Malyshev's W, null without it.")
    primary_links: list[str] = Field(description="The primary mechanism: the frame and the input links; empty when "
                                     "not decomposed.")
    primary_pairs: list[str] = Field(description="The pairs joining the input links to the frame; empty when "
                                     "not decomposed.")
    primary_mobility: int | None = Field(description="Mobility of the primary mechanism, 3·inputs - 2·pairs; null "
                                         "when not decomposed.")
    assur_groups: list[AssurGroupOut] | None = Field(description="Assur groups in the order they are added to the "
                                                     "primary mechanism; null when not decomposed (`note` says "
                                                     "why).")
    mechanism_class: str | None = Field(description="Class of the mechanism: the highest class of its groups (I "
                                        "for the primary mechanism alone); null when not decomposed.")
    replaced_higher_pairs: list[str] = Field(description="Higher pairs replaced by a link with two revolutes "
                                             "for the decomposition.")
    note: str = Field(description="Why the mechanism was not decomposed into Assur groups; empty when it was.")

    @classmethod
    def from_engine(cls, s: synth.Structure) -> StructureOut:
        """Schema from an engine structure."""
        roman = synth.structure.ROMAN
        return cls(
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
                              statically_determinate=g.statically_determinate)
                for g in s.groups],
            mechanism_class=None if s.mechanism_class is None else roman[s.mechanism_class],
            replaced_higher_pairs=list(s.replaced_higher_pairs), note=s.note,
        )
