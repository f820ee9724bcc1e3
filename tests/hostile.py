"""What a hostile or careless caller sends, and the checks every answer to it must pass: a 2xx whose JSON keeps the
operation's documented answer schema (so no null where a number is promised, no NaN), or a problem response that
keeps the Problem schema of the OpenAPI document."""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from functools import cache
from typing import Any

import httpx
import jsonschema_rs

#: Text that has broken figure, PDF, CSV, DXF or HTML writers somewhere: mathtext, markup, control characters,
#: bidirectional overrides, combining marks, characters no font of the figures has, quoting and path tricks.
HOSTILE_TEXT = [
    "$\\foo{$", "$x^2$", "a$b$c", "\\", "\\\\n", "$", "<svg onload=alert(1)>", "</text><script>x</script>",
    "&amp;&lt;&#0;", "]]><!--", "\x00", "\x01\x1b[31m", "\x7f", "a\nb\r\nc", "\t", "\u202eevil\u202c",
    "\u200f\u200e", "\u2066x\u2069", "e\u0301\u0301", "\u5317\u4eac", "\U0001f527", "\ufeff", "%s%n%x", "{0}{}",
    "' OR 1=1 --", '"quoted"', ";:|*?<>=/", "CON", "..", "../../etc/passwd", "-", " ", "=cmd|' /C calc'!A0",
    "\U0001d518\u0338", "\u0000\u0000",
]
#: Floats at the edges of what a double holds: tiny, huge, subnormal, negative zero.
EXTREME_FLOATS = [1e-300, -1e-300, 1e300, -1e300, 5e-324, 2.2250738585072014e-308, 1e-310, -0.0, 1.7976931348623157e308]


def finite_json(text: str) -> Any:
    """The JSON of an answer; NaN or Infinity in it fail the test (JSON has no such numbers)."""
    def refuse(token: str) -> Any:
        raise AssertionError(f"non-finite number {token} in an answer")
    return json.loads(text, parse_constant=refuse)


@cache
def _validators(doc_json: str) -> tuple[Any, dict[tuple[str, str, str], Any]]:
    doc = json.loads(doc_json)
    components = {"components": doc["components"]}
    problem = jsonschema_rs.Draft202012Validator({"$ref": "#/components/schemas/Problem", **components})
    answers: dict[tuple[str, str, str], Any] = {}
    for path, item in doc["paths"].items():
        for method, op in item.items():
            for status, response in op.get("responses", {}).items():
                schema = response.get("content", {}).get("application/json", {}).get("schema")
                if schema and status.startswith("2"):
                    answers[(method.upper(), path, status)] = jsonschema_rs.Draft202012Validator(
                        {**schema, **components})
    return problem, answers


def checker(http: httpx.Client) -> Callable[[httpx.Response, str], Any]:
    """A check of answers to ``http``'s app against its own OpenAPI document."""
    problem, answers = _validators(json.dumps(http.get("/openapi.json").json()))

    def check(r: httpx.Response, path: str) -> Any:
        """Assert ``r`` (an answer to POST ``path``) is a 2xx keeping its schema or a problem keeping Problem's."""
        ctype = r.headers.get("content-type", "")
        assert r.status_code != 500 and r.status_code < 600, (path, r.status_code, r.text[:500])
        if r.status_code < 300:
            if ctype.startswith("application/json"):
                body = finite_json(r.text)
                validator = answers.get(("POST", path, str(r.status_code)))
                if validator is not None:
                    errors = [f"{e.instance_path}: {e.message[:200]}" for e in validator.iter_errors(body)]
                    assert not errors, (path, errors[:3])
                return body
            assert r.content, (path, "an empty answer")
            return r.content
        assert ctype == "application/problem+json", (path, r.status_code, ctype, r.text[:300])
        assert r.status_code in (400, 408, 413, 415, 422, 504), (path, r.status_code, r.text[:300])
        body = finite_json(r.text)
        errors = [f"{e.instance_path}: {e.message[:200]}" for e in problem.iter_errors(body)]
        assert not errors, (path, errors, body)
        assert body["status"] == r.status_code and body["detail"], body
        return body

    return check


def is_finite_number(value: Any) -> bool:
    """A JSON number that is finite (booleans are not numbers here)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
