"""A misspelt field inside a tagged union is answered with the fields of the variant its tag chose.

The expected field lists are read from the variant models themselves (pydantic's ``model_fields``) or from the
variant's own schema, not from the code that picks the variant.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from typing import Any

import pytest

from api import validation
from api.app import app
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.train import TrainMeshIn, TrainPlanetaryIn

DOC = app.openapi()


def _problem(client: SynthClient, body: dict[str, Any]) -> dict[str, Any]:
    r = client.http.post("/v1/gears/train", json=body)
    assert r.status_code == 422
    answer: dict[str, Any] = r.json()
    return answer


def test_a_planetary_element_with_a_wrong_role_field_lists_the_planetary_fields(client: SynthClient) -> None:
    bad = {"type": "planetary", "sun_teeth": 20, "planet_teeth": 30, "ring_teeth": 80, "sun": "input"}
    problem = _problem(client, {"elements": [bad], "input_speed_rad_s": 100.0})
    assert problem["field"] == "elements[0].sun"
    assert problem["valid"] == sorted(TrainPlanetaryIn.model_fields)


def test_a_mesh_without_its_tag_lists_the_mesh_fields(client: SynthClient) -> None:
    # the mesh is the default variant: an element without `type` is a mesh
    problem = _problem(client, {"elements": [{"driving_teeth": 20, "driven_teeth": 30, "internl": True}]})
    assert problem["valid"] == sorted(TrainMeshIn.model_fields)
    assert problem["did_you_mean"][0] == "internal"


def _resolve(node: Mapping[str, Any]) -> Mapping[str, Any]:
    while "$ref" in node:
        target: Any = DOC
        for key in str(node["$ref"]).removeprefix("#/").split("/"):
            target = target[key]
        node = target
    return node


def _unions(node: Any) -> Iterator[Mapping[str, Any]]:
    if isinstance(node, Mapping):
        if isinstance(node.get("oneOf") or node.get("anyOf"), list):
            yield node
        for v in node.values():
            yield from _unions(v)
    elif isinstance(node, list):
        for v in node:
            yield from _unions(v)


def _tagged_variants() -> list[tuple[str, Mapping[str, Any], Mapping[str, Any], dict[str, Any]]]:
    """Every union of the OpenAPI document whose variants each carry a tag field of one constant value."""
    out = []
    seen = set()
    for union in _unions(DOC):
        members = [_resolve(m) for m in (union.get("oneOf") or union.get("anyOf") or [])]
        tags = []
        for m in members:
            props = {k: _resolve(v) for k, v in m.get("properties", {}).items()}
            tag = {k: v["const"] if "const" in v else v["enum"][0] for k, v in props.items()
                   if "const" in v or (isinstance(v.get("enum"), list) and len(v["enum"]) == 1)}
            tags.append(tag)
        if len(members) < 2 or not all(tags):
            continue
        for m, tag in zip(members, tags, strict=True):
            key = (str(m.get("title")), str(sorted(tag.items())))
            if key not in seen:
                seen.add(key)
                out.append((f"{m.get('title')}", union, m, tag))
    return out


VARIANTS = _tagged_variants()


def test_the_document_has_tagged_unions() -> None:
    titles = {t for t, *_ in VARIANTS}
    assert {"TrainPlanetaryIn", "TrainMeshIn", "FourBarIn", "SliderCrankIn", "WindowLoadIn"} <= titles


@pytest.mark.parametrize(("title", "union", "member", "tag"), VARIANTS, ids=[v[0] for v in VARIANTS])
def test_every_tagged_variant_is_the_one_its_tag_chose(title: str, union: Mapping[str, Any],
                                                      member: Mapping[str, Any], tag: dict[str, Any]) -> None:
    value = {**tag, "not_a_field_anywhere": 1}
    assert validation.allowed_fields(union, DOC, value, []) == sorted(member.get("properties", {}))
