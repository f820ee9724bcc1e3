"""The OpenAPI manual works offline and reads as a manual: descriptions, readable names, realistic examples."""

from __future__ import annotations

import re
from collections.abc import Iterator
from typing import Any

import pytest

from api.app import create_app
from mechsynth_client.client import SynthClient
from mechsynth_client.library import AsyncLibraryClient, LibraryClient
from mechsynth_client.studies import StudyHandle

DOC: dict[str, Any] = create_app().openapi()
SCHEMAS: dict[str, dict[str, Any]] = DOC["components"]["schemas"]


def _refs(node: object) -> Iterator[str]:
    if isinstance(node, dict):
        if isinstance(node.get("$ref"), str):
            yield node["$ref"].rsplit("/", 1)[-1]
        for value in node.values():
            yield from _refs(value)
    elif isinstance(node, list):
        for value in node:
            yield from _refs(value)


def _request_schemas() -> set[str]:
    """Every schema a request body reaches, directly or through other schemas."""
    todo = [name for ops in DOC["paths"].values() for op in ops.values() for name in _refs(op.get("requestBody"))]
    seen: set[str] = set()
    while todo:
        name = todo.pop()
        if name not in seen:
            seen.add(name)
            todo.extend(_refs(SCHEMAS[name]))
    return seen


REQUEST_SCHEMAS = sorted(_request_schemas())


@pytest.mark.parametrize("page", ["/docs", "/redoc"])
def test_manual_pages_load_everything_from_the_app(client: SynthClient, page: str) -> None:
    html = client.http.get(page)
    assert html.status_code == 200 and "text/html" in html.headers["content-type"]
    urls = re.findall(r'(?:src|href|spec-url)="([^"]+)"', html.text) + re.findall(r"url: '([^']+)'", html.text)
    assert len(urls) >= 3, urls      # script, icon and the OpenAPI document at least
    # Nothing from outside: every script, style, icon and the document itself come from this app.
    assert not re.search(r"(?:src|href|url)\s*[=:]\s*[\"']?(?:https?:)?//", html.text)
    for url in urls:
        asset = client.http.get(url)
        assert asset.status_code == 200 and len(asset.content) > 100, url


def test_root_is_the_workbench_and_links_the_manual(client: SynthClient) -> None:
    r = client.http.get("/", follow_redirects=False)
    assert r.status_code == 200 and "text/html" in r.headers["content-type"]
    assert 'href="/docs"' in r.text


def test_operation_ids_are_readable_and_unique() -> None:
    ids = [op["operationId"] for ops in DOC["paths"].values() for op in ops.values()]
    assert len(ids) == len(set(ids))
    assert all(re.fullmatch(r"[a-z][a-z0-9_]*", i) and not i.endswith(("_post", "_get")) for i in ids), ids
    assert DOC["paths"]["/v1/balancing/static"]["post"]["operationId"] == "balance_static"


def test_every_operation_id_is_a_client_method() -> None:
    # A study's own operations are methods of the handle client.study() returns: study_<method>.
    ids = {op["operationId"] for ops in DOC["paths"].values() for op in ops.values()}
    handle = {f"study_{name}" for name in dir(StudyHandle) if not name.startswith("_")}
    # The library's operations are methods of client.library, named for what they do to a design.
    library = {op["operationId"]: LIBRARY_METHODS.get(op["operationId"]) for path, ops in DOC["paths"].items()
               for op in ops.values() if path.startswith("/v1/library")}
    assert all(m in dir(LibraryClient) and m in dir(AsyncLibraryClient) for m in library.values()), library
    ids -= set(library)
    assert ids <= set(dir(SynthClient)) | handle, ids - set(dir(SynthClient)) - handle


LIBRARY_METHODS = {
    "import_project": "import_project", "list_projects": "projects", "design_history": "history",
    "diff_revisions": "diff", "save_revision": "save", "get_revision": "revision", "approve_revision": "approve",
    "check_revision": "check", "get_record": "record_pdf", "restore_revision": "restore",
    "export_project": "export", "search_revisions": "search", "return_revision": "return_revision",
    "comment_revision": "comment",
}


def test_schema_names_are_readable() -> None:
    assert SCHEMAS and not [name for name in SCHEMAS if "__" in name or "-" in name]


DESCRIBED_SCHEMAS = sorted(SCHEMAS)


def test_described_schemas_cover_requests_and_answers() -> None:
    # What is checked includes every request schema and the answers.
    assert set(REQUEST_SCHEMAS) <= set(DESCRIBED_SCHEMAS)
    assert {"AnalysisOut", "BalanceOut", "FlywheelOut", "MachineDesignOut", "Problem"} <= set(DESCRIBED_SCHEMAS)


@pytest.mark.parametrize("name", DESCRIBED_SCHEMAS)
def test_every_field_is_described(name: str) -> None:
    props = SCHEMAS[name].get("properties", {})
    assert not [field for field, spec in props.items() if not spec.get("description")]


def _numbers(spec: dict[str, Any]) -> list[dict[str, Any]]:
    """The numeric alternatives of a property (itself, its array items, its anyOf branches)."""
    out = []
    for s in [spec, *spec.get("anyOf", [])]:
        item = s.get("items", s) if s.get("type") == "array" else s
        if item.get("type") in ("number", "integer"):
            out.append(item)
    return out


@pytest.mark.parametrize("name", REQUEST_SCHEMAS)
def test_bounded_numbers_show_a_realistic_example(name: str) -> None:
    """Swagger UI fills a field without default or example with its bound (a mass of 1e7 kg): give an example."""
    for field, spec in SCHEMAS[name].get("properties", {}).items():
        bounded = any({"minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum"} & set(n) for n in _numbers(spec))
        required = field in SCHEMAS[name].get("required", [])
        if bounded and required:
            assert spec.get("examples"), f"{name}.{field}"
        for example in spec.get("examples", []):
            values = example if isinstance(example, list) else [example]
            for n in _numbers(spec):
                for v in (x for x in values if isinstance(x, (int, float))):
                    assert n.get("minimum", -1e300) <= v <= n.get("maximum", 1e300), f"{name}.{field}"
                    assert n.get("exclusiveMinimum", -1e300) < v < n.get("exclusiveMaximum", 1e300), f"{name}.{field}"
