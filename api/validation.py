"""Request validation errors told as the client wrote the request: JSON paths, "did you mean", and a body that
is not JSON at all.

Pydantic locates an error in its own model tree: a discriminated union adds its tag (``mechanism.fourbar.
crank_length_m``), a union of types the member's type (``drive.stages.list[...].0``). The client wrote neither, so
each location is walked along the body the client sent and only the keys and indexes that are in it are kept
(``mechanism.crank_length_m``, ``drive.stages[0]``), plus the last key when it is the one missing. A field that
is not allowed where it stands is answered with the fields that are, the closest first, read from the request
schema of the OpenAPI document at the same JSON path.
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Mapping, Sequence
from typing import Any

# Pydantic's names for the members of a union of types: ``function-after[...]``, ``list[...]``, ``int``, ...
_TYPE_TAG = re.compile(r"^[a-z][a-z0-9_-]*(\[.*\])?$")
_TYPE_NAMES = {"str", "int", "float", "bool", "list", "dict", "tuple", "none", "json-or-python", "lax-or-strict",
               "is-instance", "literal", "enum", "union", "nullable", "default", "model", "dataclass"}

Path = list[str | int]


def _is_tag(part: str) -> bool:
    return part in _TYPE_NAMES or ("[" in part and bool(_TYPE_TAG.match(part)))


def json_path(loc: Sequence[Any], body: Any) -> Path:
    """The keys and indexes of pydantic's ``loc`` that the client's ``body`` holds, in order; the last key too
    when it is a field missing from an object. Union tags (discriminator values, type names) are left out."""
    parts = list(loc[1:]) if loc and loc[0] == "body" else list(loc)
    node: Any = body
    out: Path = []
    for i, part in enumerate(parts):
        if isinstance(node, Mapping) and isinstance(part, str) and part in node:
            out.append(part)
            node = node[part]
        elif isinstance(node, list) and isinstance(part, int) and 0 <= part < len(node):
            out.append(part)
            node = node[part]
        elif i == len(parts) - 1 and isinstance(node, Mapping) and isinstance(part, str) and not _is_tag(part):
            out.append(part)  # a required field the object lacks
    return out


def dotted(path: Path) -> str:
    """``mechanism.links.crank.mass_kg``, ``loads[0].torque_Nm``: the path as the engine's errors name fields."""
    text = ""
    for p in path:
        text += f"[{p}]" if isinstance(p, int) else (f".{p}" if text else p)
    return text


def _resolve(schema: Mapping[str, Any], doc: Mapping[str, Any]) -> Mapping[str, Any]:
    seen = 0
    while "$ref" in schema and seen < 32:
        ref = str(schema["$ref"]).removeprefix("#/").split("/")
        node: Any = doc
        for key in ref:
            node = node[key]
        schema, seen = node, seen + 1
    return schema


def _choose(schema: Mapping[str, Any], value: Any, doc: Mapping[str, Any]) -> Mapping[str, Any]:
    """The member of a union that describes ``value``: by its discriminator, else the first of its kind."""
    schema = _resolve(schema, doc)
    members = schema.get("oneOf") or schema.get("anyOf")
    if not members or "properties" in schema:
        # an object's own oneOf/anyOf are rules over its fields (one of two given), not alternatives to it
        return schema
    disc = schema.get("discriminator")
    if isinstance(disc, Mapping) and isinstance(value, Mapping):
        target = disc.get("mapping", {}).get(value.get(disc.get("propertyName")))
        if target:
            return _resolve({"$ref": target}, doc)
    if isinstance(value, Mapping):
        tagged = _by_tag([_choose(m, value, doc) for m in members], value, doc)
        if tagged is not None:
            return tagged
    kind = "object" if isinstance(value, Mapping) else "array" if isinstance(value, list) else None
    for m in members:
        m = _choose(m, value, doc)
        if kind is not None and (m.get("type") == kind or (kind == "object" and "properties" in m)):
            return m
    return _resolve(members[0], doc)


def _tags(member: Mapping[str, Any], doc: Mapping[str, Any]) -> dict[str, tuple[Any, bool]]:
    """A member's tag fields (a property of one constant value): name -> (value, whether it is the default)."""
    out = {}
    for key, sub in member.get("properties", {}).items():
        sub = _resolve(sub, doc)
        enum = sub.get("enum")
        if "const" in sub:
            tag = sub["const"]
        elif isinstance(enum, list) and len(enum) == 1:
            tag = enum[0]
        else:
            continue
        out[key] = (tag, "default" in sub and sub["default"] == tag)
    return out


def _by_tag(members: Sequence[Mapping[str, Any]], value: Mapping[str, Any],
            doc: Mapping[str, Any]) -> Mapping[str, Any] | None:
    """The member whose tag the value carries, or whose tag is the default when the value leaves it out: a union
    told apart by a function (no discriminator mapping in the schema) is still told apart as pydantic did."""
    tags = [_tags(m, doc) for m in members]
    for m, t in zip(members, tags, strict=True):
        if t and all(key in value and value[key] == tag for key, (tag, _) in t.items()):
            return m
    for m, t in zip(members, tags, strict=True):
        if t and all(key not in value and default for key, (_, default) in t.items()):
            return m
    return None


def allowed_fields(schema: Mapping[str, Any], doc: Mapping[str, Any], body: Any, parent: Path) -> list[str]:
    """The field names the request schema allows in the object at JSON path ``parent`` of ``body``."""
    node, value = _choose(schema, body, doc), body
    for part in parent:
        if isinstance(part, int):
            value = value[part] if isinstance(value, list) and part < len(value) else None
            node = _choose(node.get("items", {}), value, doc)
        else:
            value = value.get(part) if isinstance(value, Mapping) else None
            props = node.get("properties", {})
            if part in props:
                node = _choose(props[part], value, doc)
            elif isinstance(node.get("additionalProperties"), Mapping):
                node = _choose(node["additionalProperties"], value, doc)
            else:
                return []
    return sorted(node.get("properties", {}))


def did_you_mean(misspelt: str, allowed: Sequence[str]) -> list[str]:
    """The allowed names closest to ``misspelt``, best first (at most three)."""
    return difflib.get_close_matches(misspelt, list(allowed), n=3, cutoff=0.6)


def request_schema(openapi: Mapping[str, Any], path: str, method: str) -> Mapping[str, Any] | None:
    """The JSON request-body schema of an operation in the OpenAPI document, or None."""
    operation = openapi.get("paths", {}).get(path, {}).get(method.lower(), {})
    content = operation.get("requestBody", {}).get("content", {})
    found = content.get("application/json", {}).get("schema")
    return found if isinstance(found, Mapping) else None
