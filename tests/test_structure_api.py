"""POST /v1/structure against the seeds' structural cases: pair classes, mobility, Assur groups, determinacy."""

from __future__ import annotations

import pytest

from mechsynth_client.client import InvalidInputError, SynthClient
from mechsynth_client.schemas.structure import SIXBAR_EXAMPLE, StructureIn
from conftest import CASES


def _spatial(classes: list[int], closed: bool, **extra: object) -> StructureIn:
    """A chain frame-1-2-...: one pair of each class in turn, closed back to the frame when ``closed``."""
    n = len(classes) - 1 if closed else len(classes)
    links = ["frame", *(str(i) for i in range(1, n + 1))]
    ends = links + (["frame"] if closed else [])
    pairs = [{"name": f"P{i}", "links": [ends[i], ends[i + 1]], "pair_class": k} for i, k in enumerate(classes)]
    return StructureIn.model_validate({"links": links, "pairs": pairs, "planar": False, **extra})


def test_somov_malyshev_spatial_fourbar(client: SynthClient) -> None:
    # A, B class V; C class IV; D class III around a closed loop of three moving links: W = 18 - 10 - 4 - 3 = 1.
    case = CASES["somov_malyshev_spatial_fourbar"]
    inp = case["inputs"]
    classes = [5] * inp["p5"] + [4] * inp["p4"] + [3] * inp["p3"] + [2] * inp["p2"] + [1] * inp["p1"]
    out = client.structure(_spatial(classes, closed=True, known_mobility=1))
    assert out.moving_links == inp["n_moving"]
    assert out.mobility_somov_malyshev == case["expected"]["W"]
    assert out.redundant_constraints == 0 and out.mobility_chebyshev is None


def test_somov_malyshev_open_chain(client: SynthClient) -> None:
    case = CASES["somov_malyshev_open_chain"]
    inp = case["inputs"]
    out = client.structure(_spatial([3, 4, 5], closed=False))
    assert out.moving_links == inp["n_moving"]
    assert (out.pair_counts["p3"], out.pair_counts["p4"], out.pair_counts["p5"]) == (inp["p3"], inp["p4"], inp["p5"])
    assert out.mobility_somov_malyshev == case["expected"]["W"]


def test_pair_classes(client: SynthClient) -> None:
    # S = 6 - H: a ball on a plane (H = 5) is class I, a cylinder on a plane (2 constraints) class II, H = 4;
    # a point contact with 5 freedoms is a higher pair of class I.
    case = CASES["pair_class_examples_001"]
    point = CASES["pair_class_point_contact_004"]
    body = StructureIn.model_validate({"links": ["frame", "ball", "cylinder", "body"], "planar": False, "pairs": [
        {"name": "ball", "links": ["frame", "ball"], "dof": case["inputs"]["ball_plane_H"]},
        {"name": "cylinder", "links": ["frame", "cylinder"], "pair_class": case["inputs"]["cylinder_plane_constraints"]},
        {"name": "point", "links": ["frame", "body"], "dof": point["inputs"]["W_relative"]},
    ]})
    pairs = {p.name: p for p in client.structure(body).pairs}
    assert pairs["ball"].constraints == case["expected"]["ball_plane_S"]
    assert pairs["ball"].pair_class == case["expected"]["ball_plane_class"]
    assert pairs["cylinder"].dof == case["expected"]["cylinder_plane_H"]
    assert pairs["cylinder"].pair_class == case["expected"]["cylinder_plane_class"]
    assert pairs["point"].constraints == point["expected"]["S"]
    assert pairs["point"].pair_class == point["expected"]["class"]
    assert pairs["point"].higher is point["expected"]["higher_pair"]


def test_rigid_body_with_supports(client: SynthClient) -> None:
    # One body on the frame: one pair of k constraints leaves 6 - k; six single-constraint supports leave 0.
    case = CASES["rigid_body_dof_supports"]
    for constraints, dof in zip(case["inputs"]["constraints"], case["expected"]["dof"]):
        pairs = ([{"name": "S", "links": ["frame", "body"], "pair_class": constraints}] if constraints <= 5 else
                 [{"name": f"rod{i}", "links": ["frame", "body"], "pair_class": 1} for i in range(constraints)])
        out = client.structure(StructureIn.model_validate({"links": ["frame", "body"], "pairs": pairs,
                                                           "planar": False}))
        assert out.mobility_somov_malyshev == dof


def test_chebyshev_with_a_higher_pair(client: SynthClient) -> None:
    # Four moving links, five lower pairs and a higher pair between 1 and 2 (a cam 1 on a sliding follower 2
    # that drives a four-bar loop): W = 12 - 10 - 1 = 1; the higher pair is replaced by a link with two
    # revolutes for the decomposition, which keeps W.
    case = CASES["chebyshev_mobility_higher_pair"]
    body = StructureIn.model_validate({"links": ["frame", "1", "2", "3", "4"], "pairs": [
        {"name": "a", "links": ["frame", "1"], "kind": "revolute"},
        {"name": "b", "links": ["frame", "2"], "kind": "prismatic"},
        {"name": "h", "links": ["1", "2"], "kind": "higher"},
        {"name": "c", "links": ["2", "3"], "kind": "revolute"},
        {"name": "d", "links": ["3", "4"], "kind": "revolute"},
        {"name": "e", "links": ["4", "frame"], "kind": "revolute"},
    ]})
    out = client.structure(body)
    assert out.moving_links == case["inputs"]["n_moving"]
    assert out.mobility_chebyshev == case["expected"]["W"]
    assert out.replaced_higher_pairs == ["h"]
    assert out.assur_groups is not None and all(g.mobility == 0 for g in out.assur_groups)


def test_sixbar_decomposes_into_two_dyads(client: SynthClient) -> None:
    case = CASES["structural_analysis_sixbar"]
    inp, exp = case["inputs"], case["expected"]
    out = client.structure(StructureIn.model_validate(SIXBAR_EXAMPLE))
    assert out.moving_links == inp["n_moving"] and out.pair_counts["p5"] == inp["p5"]
    assert out.mobility_chebyshev == exp["W"]
    # A planar six-bar built with spatial revolutes: 3 redundant constraints per independent loop (two loops).
    assert out.redundant_constraints == 6
    assert out.primary_mobility == exp["primary_W"]
    assert len(out.primary_links) - 1 == inp["primary"]["n"] and len(out.primary_pairs) == inp["primary"]["p5"]
    groups = out.assur_groups
    assert groups is not None
    assert [{"n": g.n, "p5": g.p5} for g in groups] == inp["groups"]
    assert [g.mobility for g in groups] == exp["group_W"]
    assert [g.group_class for g in groups] == exp["group_class"]
    assert out.mechanism_class == "II"


def _ring_group(n: int) -> StructureIn:
    """A crank and one Assur group of ``n`` links: a dyad for 2, else a closed ring of n links with every other
    one paired outward (to the crank first, then the frame): 3n = 2·(n + n/2)."""
    group = [f"g{i}" for i in range(n)]
    if n == 2:
        pairs = [("g0", "g1"), ("crank", "g0"), ("g1", "frame")]
    else:
        pairs = [(group[i], group[(i + 1) % n]) for i in range(n)]
        pairs += [(group[i], "crank" if i == 0 else "frame") for i in range(0, n, 2)]
    pairs.append(("frame", "crank"))
    return StructureIn.model_validate({"links": ["frame", "crank", *group], "input_links": ["crank"], "pairs": [
        {"name": f"p{i}", "links": list(ab), "kind": "revolute"} for i, ab in enumerate(pairs)]})


def test_static_determinacy_of_groups(client: SynthClient) -> None:
    # Groups of lower pairs are statically determinate when 3n = 2p5: (2, 3), (4, 6), (6, 9), (8, 12).
    case = CASES["static_determinacy_groups"]
    for n, p5 in zip(case["inputs"]["n"], case["expected"]["p5"]):
        out = client.structure(_ring_group(n))
        assert out.assur_groups is not None
        (group,) = out.assur_groups
        assert (group.n, group.p5, group.mobility) == (n, p5, 0)
        assert group.statically_determinate
        # A dyad is class II; a ring of n links has a closed contour of n: class n (IV for four links).
        assert group.group_class == ("II" if n == 2 else ("IV", "VI", "VIII")[n // 2 - 2])


def test_bad_structures_are_named(client: SynthClient) -> None:
    with pytest.raises(InvalidInputError) as err:
        client.structure(StructureIn.model_validate({"links": ["frame", "a"], "pairs": [
            {"name": "x", "links": ["frame", "b"], "kind": "revolute"}]}))
    assert err.value.problem["field"] == "pairs[0].links"
    with pytest.raises(InvalidInputError) as err:
        client.structure(StructureIn.model_validate({"links": ["frame", "a"], "planar": False, "pairs": [
            {"name": "x", "links": ["frame", "a"]}]}))
    assert err.value.problem["field"] == "pairs[0]"


def test_four_link_groups_are_class_iii_or_iv(client: SynthClient) -> None:
    # Seed note on n = 4, p5 = 6: a class III group of the 3rd order (a base link with three pairs, three outer
    # pairs) or a class IV group of the 2nd order (a closed contour of four links, two outer pairs).
    triad = StructureIn.model_validate({"links": ["frame", "crank", "a", "b", "base", "c"], "pairs": [
        {"name": f"p{i}", "links": list(ab), "kind": "revolute"} for i, ab in enumerate(
            [("frame", "crank"), ("crank", "a"), ("a", "base"), ("b", "base"), ("base", "c"), ("b", "frame"),
             ("c", "frame")])]})
    (group,) = client.structure(triad).assur_groups or []
    assert (group.n, group.p5, group.group_class, group.order) == (4, 6, "III", 3)
    (group,) = client.structure(_ring_group(4)).assur_groups or []
    assert (group.n, group.p5, group.group_class, group.order) == (4, 6, "IV", 2)
