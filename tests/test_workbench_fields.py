"""Every field of a panel's request, as the manual describes it, has its widget in the workbench (Playwright, the
system's Chromium, a live server).

The walk over the request schemas here is the test's own, in Python over the service's /openapi.json: an
independent path past the page's JavaScript, which finds the same fields its own way.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from typing import Any

import httpx
import pytest
from playwright.sync_api import Browser, Page

from test_workbench import SHOTS, base_url, browser, open_page  # noqa: F401  (the service and the browser, per module)

# The linkage part of a request is the editor's (its own form on the left), not the panel's.
LINKAGE = ["mechanism", "speed_rpm", "crank_acceleration_rad_s2", "samples", "crank_angle_deg", "gravity", "loads",
           "torques", "counterweights"]
# panel -> (request model, fields filled from the design rather than the panel)
PANELS = {
    "machine": ("MachineIn", LINKAGE),
    "drive": ("DriveIn", []),
    # the flywheel's mean speed is the design's crank speed; its tables are the alternative to a linkage
    "flywheel": ("FlywheelIn", [*LINKAGE, "mean_speed_rpm", "mean_speed_rad_s", "tables", "cycle_deg"]),
}
PREFIX = {"machine": "mac", "drive": "drv", "flywheel": "fly"}
FORM_UNITS = {"m": "mm", "kg": "kg"}    # the form's default units for SI lengths and masses


@pytest.fixture
def page(browser: Browser, base_url: str) -> Iterator[Page]:
    yield from open_page(browser, base_url)


@pytest.fixture(scope="module")
def schemas(base_url: str) -> dict[str, Any]:
    doc: dict[str, Any] = httpx.get(f"{base_url}/openapi.json", timeout=30).json()
    return dict(doc["components"]["schemas"])


def _shapes(schema: dict[str, Any], schemas: dict[str, Any]) -> list[dict[str, Any]]:
    """The concrete shapes of a schema: $ref followed, anyOf/oneOf members, allOf merged, null dropped."""
    while "$ref" in schema:
        schema = schemas[schema["$ref"].rsplit("/", 1)[1]]
    if "allOf" in schema:
        merged: dict[str, Any] = {k: v for k, v in schema.items() if k != "allOf"}
        for part in schema["allOf"]:
            for shape in _shapes(part, schemas):
                merged.setdefault("properties", {}).update(shape.get("properties", {}))
                for k, v in shape.items():
                    merged.setdefault(k, v)
        return _shapes(merged, schemas)
    out = []
    props = {k: v for k, v in schema.get("properties", {}).items() if set(v) != {"not"}}
    if props or "enum" in schema or "const" in schema or schema.get("type") not in (None, "null"):
        out.append({**schema, "properties": props} if "properties" in schema else schema)
    for member in schema.get("anyOf", []) + schema.get("oneOf", []):
        out += _shapes(member, schemas)
    return out


def _leaves(model: str, skip: list[str], schemas: dict[str, Any]) -> list[tuple[str, list[dict[str, Any]], dict[str, Any]]]:
    """(path, shapes, the property as written) of every leaf field, nested objects walked."""
    out = []

    def walk(schema: dict[str, Any], prefix: str, depth: int) -> None:
        props: dict[str, Any] = {}
        for shape in _shapes(schema, schemas):
            for k, v in shape.get("properties", {}).items():
                props.setdefault(k, v)
        for name, prop in props.items():
            path = prefix + name
            if any(path == s or path.startswith(s + ".") for s in skip):
                continue
            shapes = _shapes(prop, schemas)
            nested = any(s.get("properties") and not s.get("additionalProperties") for s in shapes)
            if nested and depth < 4 and not any(s.get("type") == "array" for s in shapes):
                walk(prop, path + ".", depth + 1)
            else:
                out.append((path, shapes, prop))

    walk({"$ref": f"#/components/schemas/{model}"}, "", 0)
    return out


def _bracket_unit(text: str) -> str | None:
    found = re.findall(r"\[([^\],]+)\]", text or "")
    return found[-1] if found else None


def panel_rows(page: Page, root: str) -> list[dict[str, Any]]:
    """Every field row under ``root`` (a selector) as the page shows it: its field, range, unit and widget."""
    return list(page.evaluate(f"""[...document.querySelectorAll("{root} .row[data-field]")].map(r => {{
        const w = r.querySelector('input, select, textarea');
        return {{ field: r.dataset.field, range: r.dataset.range || '', unit: r.querySelector('.unit')?.textContent || '',
                 tag: w && w.tagName, placeholder: w && w.placeholder, options: w && w.tagName === 'SELECT' ?
                 [...w.options].map(o => o.value) : [] }}; }})"""))


def check_rows(rows: list[dict[str, Any]], leaves: list[tuple[str, list[dict[str, Any]], dict[str, Any]]]
               ) -> tuple[list[str], list[tuple[str, str, dict[str, Any]]]]:
    """The leaves with no widget, and the widgets that show a leaf wrongly (choices, unit, range, default)."""
    by_field = {r["field"]: r for r in rows}
    missing, wrong = [], []
    for path, shapes, prop in leaves:
        row = by_field.get(path) or next((r for f, r in by_field.items() if f.startswith(path + ".")), None)
        if row is None:
            missing.append(path)
            continue
        choices = [c for s in shapes for c in (s.get("enum") or ([s["const"]] if "const" in s else []))]
        types = {s.get("type") for s in shapes}
        if "boolean" in types:
            choices = [True, False]
        if choices and row["field"] == path:
            # an enumeration or a yes/no: a drop-down offering every value the schema admits
            want = {str(c).lower() for c in choices}
            if row["tag"] != "SELECT" or not want <= {o.lower() for o in row["options"]}:
                wrong.append((path, "choices", row))
        elif types & {"number", "integer"} and row["field"] == path:
            text = prop.get("description") or next((s.get("description") for s in shapes if s.get("description")), "")
            unit = _bracket_unit(text)
            named = unit or re.search(r"_(rpm|deg|m|mm|kg|kgm2|Nm|N|W|s|h|Hz|Pa|MPa|m_s|rad_s|kg_m3)$", path)
            if not row["unit"].strip() and (row["tag"] != "SELECT" or named):
                # a number typed has its unit (– for a pure number); a choice among counts has none to show
                wrong.append((path, "no unit", row))
            elif unit and unit != "-" and row["tag"] != "SELECT" and row["unit"] != FORM_UNITS.get(unit, unit):
                wrong.append((path, f"unit {unit}", row))
            bounded = any(k in s for s in shapes for k in ("minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum"))
            if bounded and row["tag"] != "SELECT" and not row["range"]:
                wrong.append((path, "no range", row))
            default = prop.get("default")
            if isinstance(default, (int, float)) and not isinstance(default, bool) and row["tag"] == "INPUT":
                scale = 1e3 if unit == "m" else 1.0
                shown = float(row["placeholder"]) if row["placeholder"] else math.nan
                # the placeholder is the schema's default in the form's unit, rounded for reading (4 digits)
                if not shown == pytest.approx(default * scale, rel=1e-3, abs=1e-12):
                    wrong.append((path, f"default {default}", row))
    return missing, wrong


@pytest.mark.parametrize("panel", list(PANELS))
def test_every_field_of_the_request_has_a_widget_with_its_unit(page: Page, panel: str, schemas: dict[str, Any]) -> None:
    model, skip = PANELS[panel]
    page.click(f"button[data-panel={panel}]")
    page.wait_for_selector(f"#panel-{panel} .row")
    leaves = _leaves(model, skip, schemas)
    assert len(leaves) > 10, leaves     # the walk found the request's fields (the machine's are over a hundred)
    missing, wrong = check_rows(panel_rows(page, f"#panel-{panel}"), leaves)
    page.locator(f"#panel-{panel}").screenshot(path=str(SHOTS / f"fields-{panel}.png"))
    assert not missing, f"{panel}: fields with no widget: {missing}"
    assert not wrong, f"{panel}: {wrong}"


def test_machine_strength_switches_on_and_materials_are_the_catalogues(page: Page, base_url: str) -> None:
    page.click("button[data-panel=machine]")
    page.click("#mac-more-drive summary")
    # a yes/no the schema types as a boolean: a drop-down, sent as true (typing "yes" was refused before)
    page.select_option("[id='mac-drive.size_gears']", "true")
    materials = [m["name"] for m in httpx.get(f"{base_url}/v1/gears/materials", timeout=30).json()]
    offered = page.eval_on_selector("[id='mac-drive.strength.pinion_material']", "s => [...s.options].map(o => o.value)")
    assert offered[0] == "" and offered[1:] == materials     # "" keeps the API's default
    page.select_option("[id='mac-drive.strength.pinion_material']", materials[0])
    page.fill("[id='mac-delta']", "0.02")
    with page.expect_request("**/v1/machines/design") as sent:
        page.click("#mac-run")
    body = sent.value.post_data_json
    assert body["drive"]["size_gears"] is True and body["drive"]["strength"]["pinion_material"] == materials[0]
