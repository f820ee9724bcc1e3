"""Schemas of POST /v1/structure: a mechanism as links and pairs, its mobility and Assur groups."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator
from pydantic.config import JsonDict

from .common import PlanarLinkageIn, StrictModel

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


DOUBLE_PARALLELOGRAM_EXAMPLE: JsonDict = {
    "type": "linkage",
    "frame_points_m": {"O": [0.0, 0.0], "Q": [0.3, 0.0], "E": [0.15, 0.0]},
    "links": [{"name": "crank", "joints": ["O", "A"], "length_m": 0.1},
              {"name": "coupler", "joints": ["A", "B"], "length_m": 0.3, "points_m": {"C": [0.15, 0.0]}},
              {"name": "crank2", "joints": ["Q", "B"], "length_m": 0.1},
              {"name": "crank3", "joints": ["E", "C"], "length_m": 0.1}],
    "joints": [{"name": "O", "kind": "revolute", "links": ["frame", "crank"]},
               {"name": "A", "kind": "revolute", "links": ["crank", "coupler"]},
               {"name": "B", "kind": "revolute", "links": ["coupler", "crank2"]},
               {"name": "Q", "kind": "revolute", "links": ["frame", "crank2"]},
               {"name": "E", "kind": "revolute", "links": ["frame", "crank3"]},
               {"name": "C", "kind": "revolute", "links": ["coupler", "crank3"]}],
    "crank": "crank",
    "output": "crank2",
}


class StructureIn(StrictModel):
    """A mechanism as links (the frame among them) and the pairs that join them; or a planar linkage with its
    dimensions (`mechanism`), whose mobility is then judged from its geometry too."""

    links: Annotated[list[Name], Field(min_length=2, max_length=40)] | None = Field(
        None, description="Every link by name, the frame included (with `pairs`; or give `mechanism`).")
    pairs: Annotated[list[PairIn], Field(min_length=1, max_length=80)] | None = Field(
        None, description="Every kinematic pair (with `links`).")
    mechanism: PlanarLinkageIn | None = Field(
        None, description="Instead of `links` and `pairs`: a linkage with its dimensions (as `/v1/analysis` takes "
        "it, masses optional). Its mobility is then also judged from the geometry (the rank of the constraint "
        "Jacobian over the cycle), passive links and their redundant pairs are named, and each Assur group says "
        "how it is placed.")
    frame: Name = Field("frame", description="Name of the fixed link.")
    planar: bool = Field(True, description="Planar (Chebyshev's mobility formula) or spatial (Somov-Malyshev).")
    input_links: list[Name] | None = Field(None, max_length=40, description="Driven links of the primary "
                                           "mechanism; default the first W links paired with the frame.")
    known_mobility: int | None = Field(None, ge=-1000, le=1000, description="Spatial: the actual mobility, for "
                                       "the redundant constraints.")

    @model_validator(mode="after")
    def _one_description(self) -> StructureIn:
        if self.mechanism is None and (self.links is None or self.pairs is None):
            raise ValueError("give `links` and `pairs`, or a `mechanism` with its dimensions")
        if self.mechanism is not None and (self.links is not None or self.pairs is not None):
            raise ValueError("give `links` and `pairs`, or a `mechanism`: not both")
        if self.mechanism is not None and (not self.planar or self.input_links is not None):
            raise ValueError("a `mechanism` is planar and driven by its crank: leave `planar` and `input_links` out")
        return self

    model_config = ConfigDict(json_schema_extra={"examples": [
        SIXBAR_EXAMPLE,
        {"mechanism": DOUBLE_PARALLELOGRAM_EXAMPLE},
        {"links": ["frame", "1", "2", "3"], "planar": False, "known_mobility": 1,
         "pairs": [{"name": "A", "links": ["frame", "1"], "pair_class": 5},
                   {"name": "B", "links": ["1", "2"], "pair_class": 5},
                   {"name": "C", "links": ["2", "3"], "pair_class": 4},
                   {"name": "D", "links": ["3", "frame"], "pair_class": 3}]},
    ]})


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
    placement: Literal["closed_form", "numerical"] | None = Field(
        None, description="With `mechanism`: how the analysis places it, `closed_form` (a dyad) or `numerical` "
        "(class III and above: Newton continuation on its loop equations); null without dimensions.")


class MobilityGeometryOut(BaseModel):
    """Mobility from the geometry of a linkage whose pairs repeat constraints (passive links)."""

    mobility_geometric: int = Field(description="W = 3n - rank of the constraint Jacobian (its largest rank over "
                                    "the sampled crank angles).")
    jacobian_rank: int = Field(description="That rank.")
    constraint_rows: int = Field(description="Rows of the Jacobian: 2 per lower pair.")
    samples: int = Field(description="Crank angles over the cycle at which it was judged.")
    passive_links: list[str] = Field(description="The links taken out to place the rest (passive links).")
    redundant_pairs: list[str] = Field(description="Their pairs: the constraints taken as redundant.")
    dependent_pairs: list[str] = Field(description="Every pair whose constraint rows are linearly dependent on the "
                                       "others' (touched by the Jacobian's left null space).")
    max_residual_m: float = Field(description="Largest distance by which the passive links' pins miss their "
                                  "lengths over the sampled angles, with the rest placed [m]: zero to rounding.")
    explanation: str = Field(description="Which pairs are redundant and why, in one sentence.")


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
    note: str = Field(description="Why the mechanism was not decomposed into Assur groups; empty when it was "
                      "(with passive links: which pairs are redundant).")
    geometry: MobilityGeometryOut | None = Field(None, description="With `mechanism` and passive links: the mobility from "
                                         "the geometry and the redundant pairs; null otherwise.")
