"""What makes a machine design report a design record: who, when, which service, which request, every input.

The request is kept as the client sent it (after validation, defaults included) and identified by the SHA-256 of
its canonical JSON (keys sorted, no spaces; the title block left out, so that signing a revision does not change
the design's identity), so a signed report can be matched to the request that made it and the design repeated.
The title block (project, record number, revision, who designed, checked and approved it and when, its state)
comes from the request's optional ``title_block``: a design library fills it. Every input is listed with its unit, read from the field name's unit suffix (the JSON field
names carry their unit: ``length_m``, ``mass_kg``, ``torque_Nm``, ``speed_rpm``, ``angle_deg``).
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import json
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field
from typing import Any

#: Unit suffixes of the request's field names, longest first so that ``_m_s`` is not read as ``_s``.
_UNITS: tuple[tuple[str, str], ...] = (
    ("_MPa_m_s", "MPa·m/s"), ("_Nm_rad", "N·m/rad"), ("_Ns_m", "N·s/m"), ("_N_m", "N/m"), ("_mm2_s", "mm²/s"), ("_kg_m3", "kg/m³"), ("_m_s2", "m/s²"), ("_kgm2", "kg·m²"), ("_m_s", "m/s"), ("_rad_s2", "rad/s²"),
    ("_rad_s", "rad/s"), ("_rpm", "rpm"), ("_deg", "°"), ("_Nm", "N·m"), ("_Pa", "Pa"), ("_kg", "kg"),
    ("_W", "W"), ("_N", "N"), ("_m", "m"), ("_s", "s"), ("_h", "h"),
)
#: Inputs whose unit their name does not carry.
_NAMED_UNITS = {"viscous": "N·s/m"}
#: Dimensionless inputs and choices, named so that the inputs page says so instead of leaving the unit blank.
_DIMENSIONLESS = ("delta", "speed_tolerance", "reserve_factor", "efficiency", "ratio", "ratio_min", "ratio_max",
                  "tooth_tolerance", "thickness_ratio", "width_ratio", "breakdown_torque_ratio", "weights",
                  "shaking_force", "shaking_moment", "driving_torque", "added_mass", "rotor_ratios",
                  "application_factor", "coefficient", "static_coefficient", "max_face_width_ratio",
                  "min_face_width_ratio", "min_safety_contact", "min_safety_root")
#: The states of a design record, in the order it passes through them.
STATES = ("draft", "checked", "approved", "superseded")
#: The request's key that holds the title block (outside the design's identity).
TITLE_BLOCK = "title_block"
#: The PDF metadata key a record's title block is written under (JSON), so a kept record says how it was signed.
TITLE_BLOCK_KEY = "/MechsynthTitleBlock"


@dataclass(frozen=True, slots=True)
class TitleBlock:
    """Who answers for a record: the project, the record's number and revision, its title, the names and dates
    (ISO 8601) of whoever designed, checked and approved it, and its state (draft, checked, approved,
    superseded). Blank names and dates are left for a pen."""

    project: str = ""
    number: str = ""
    revision: str = ""
    title: str = ""
    designed_by: str = ""
    designed_on: str = ""
    checked_by: str = ""
    checked_on: str = ""
    approved_by: str = ""
    approved_on: str = ""
    state: str = "draft"
    #: Why a design that fails a check is released anyway (blank: it passed, or it is not signed).
    deviation: str = ""

    @staticmethod
    def of(data: Mapping[str, Any] | None) -> TitleBlock:
        """The title block of a request's ``title_block`` (None: a draft with blank names)."""
        if not data:
            return TitleBlock()
        fields = TitleBlock.__dataclass_fields__
        return TitleBlock(**{k: "" if v is None else str(v) for k, v in data.items() if k in fields})


@dataclass(frozen=True, slots=True)
class RevisionRow:
    """One line of a record's revision table: the revision's number, date (UTC), author, message, state,
    checker and approver with their dates, deviation and comments (``who: text``, one a line)."""

    number: str
    date: str
    author: str
    message: str
    state: str
    checked: str = ""
    approved: str = ""
    deviation: str = ""
    comments: str = ""


@dataclass(frozen=True, slots=True)
class ChangeNote:
    """What changed in the design since the previous approved revision: ``against`` says which (blank: there is
    none, this is the first release) and ``rows`` each input that differs as (field, unit, before, after)."""

    against: str = ""
    rows: tuple[tuple[str, str, str, str], ...] = ()


@dataclass(frozen=True, slots=True)
class DesignRecord:
    """The title block of a design report and the request it answers.

    ``name`` a label for people; ``created`` UTC time, ISO 8601 (a library's revision: when it was saved, so
    the record is a document of the revision, not of the download); ``version`` of the service; ``request`` the
    request as JSON-compatible data; ``request_sha256`` the hash of its canonical JSON; ``revisions`` the
    revision table and ``change_note`` the change note a design library adds (none for a plain request).
    """

    name: str
    created: str
    version: str
    request: Mapping[str, Any] = field(default_factory=dict)
    request_sha256: str = ""
    title_block: TitleBlock = field(default_factory=TitleBlock)
    revisions: tuple[RevisionRow, ...] = ()
    change_note: ChangeNote | None = None

    @staticmethod
    def of(request: Mapping[str, Any], *, name: str | None, version: str,
           created: _dt.datetime | None = None) -> DesignRecord:
        """The record of ``request``, hashed without its title block; ``created`` default now (UTC)."""
        when = (created or _dt.datetime.now(_dt.timezone.utc)).astimezone(_dt.timezone.utc)
        design = {k: v for k, v in request.items() if k != TITLE_BLOCK}
        return DesignRecord(name or "machine design", when.strftime("%Y-%m-%d %H:%M:%S UTC"), version,
                            design, request_sha256(design), TitleBlock.of(request.get(TITLE_BLOCK)))


#: The PDF metadata key a record's whole sheet (title block, date, revision table, change note) is written under.
SHEET_KEY = "/MechsynthSheet"


def sheet_metadata(record: DesignRecord) -> str:
    """The part of a record a library may rewrite (title block, date, revision table, change note) as canonical
    JSON: kept in the PDF so that a record already written as the revision stands is given again unchanged."""
    note = None if record.change_note is None else asdict(record.change_note)
    return json.dumps({"title_block": asdict(record.title_block), "created": record.created,
                       "revisions": [asdict(r) for r in record.revisions], "change_note": note},
                      sort_keys=True, separators=(",", ":"), ensure_ascii=False)


def request_sha256(request: Mapping[str, Any]) -> str:
    """SHA-256 of the request's canonical JSON, its title block left out: keys sorted, no spaces, UTF-8 [hex]."""
    design = {k: v for k, v in request.items() if k != TITLE_BLOCK}
    text = json.dumps(design, sort_keys=True, separators=(",", ":"), ensure_ascii=False, allow_nan=False)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def unit_of(key: str) -> str:
    """The unit a field name carries in its suffix; ``-`` for a dimensionless input, blank for a choice or a
    name."""
    if key in _NAMED_UNITS:
        return _NAMED_UNITS[key]
    for suffix, unit in _UNITS:
        if key.endswith(suffix):
            return unit
    return "-" if key in _DIMENSIONLESS else ""


def _value(v: Any) -> str:
    if isinstance(v, bool) or v is None:
        return json.dumps(v)
    if isinstance(v, float):
        return f"{v:.6g}"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    return str(v)


def input_rows(request: Mapping[str, Any]) -> list[tuple[str, str, str]]:
    """Every input of the request as (JSON path, value, unit), in the request's order.

    Objects are walked down to their values; lists of numbers (a centre of mass, a ratio range) stay one row;
    lists of objects (loads, stages) get their index in the path. A value's unit is its own field's, or for a
    map of names (``max_radius_m.crank``) the map's.
    """
    rows: list[tuple[str, str, str]] = []

    def walk(value: Any, path: str, unit_key: str) -> None:
        if isinstance(value, Mapping):
            if not value:
                rows.append((path, "{}", ""))
            for k, v in value.items():
                key = str(k)
                # a map keyed by names (links) carries the unit in its own name
                own = key if unit_of(key) or not unit_of(unit_key) else unit_key
                walk(v, f"{path}.{key}" if path else key, own)
            return
        if isinstance(value, (list, tuple)) and value and any(isinstance(x, (Mapping, list, tuple)) for x in value):
            for i, v in enumerate(value):
                walk(v, f"{path}[{i}]", unit_key)
            return
        rows.append((path, _value(value), unit_of(unit_key)))

    walk(request, "", "")
    return rows
