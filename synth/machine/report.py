"""The design record of a whole machine: a multi-page A4 PDF (reportlab's platypus for the pages and tables,
matplotlib for the figures) and a one-page PNG summary.

The PDF opens with a title block (project, record number, revision, title, designed/checked/approved with names
and dates, state, date, service version, the request's SHA-256) and the verdict, then the key figures, every
check with its unit, every warning, every input with its unit, each stage of the chain with its independent
check figure, the counterweights (mass, radius, angle and the steel disc that realises each), the gear train,
the flywheel where it sits, the motor and its operating point, every shaft, and the alternatives when asked; then
the dimensioned drawings to scale (the linkage with its counterweights, the gear pairs, the flywheel) and the
diagrams (mechanism, driving torque, simulated speed, shaking force and moment, energy-mass diagram, motor
torque, start-up and run-down). Every page is A4 landscape; text is set in embedded TrueType fonts so it can be
extracted; tables wrap their cells to fit the page; a value smaller than 1e-9 of its column's (or quantity's)
scale is printed as 0.
"""

from __future__ import annotations

import io
import json
import math
import re
import textwrap
from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict
from pathlib import Path
from typing import Any
from xml.sax.saxutils import escape as xml_escape

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.backends.backend_pdf import PdfPages  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.patches import Circle, Rectangle  # noqa: E402
from pypdf import PdfReader, PdfWriter  # noqa: E402
from reportlab.lib import colors  # noqa: E402
from reportlab.lib.enums import TA_RIGHT  # noqa: E402
from reportlab.lib.pagesizes import A4 as _A4_PT  # noqa: E402
from reportlab.lib.pagesizes import landscape  # noqa: E402
from reportlab.lib.styles import ParagraphStyle  # noqa: E402
from reportlab.lib.units import mm  # noqa: E402
from reportlab.pdfbase import pdfmetrics  # noqa: E402
from reportlab.pdfbase.ttfonts import TTFont  # noqa: E402
from reportlab.platypus import (  # noqa: E402
    BaseDocTemplate, CondPageBreak, Flowable, Frame, KeepTogether, PageTemplate, Paragraph, Spacer, Table,
    TableStyle)

from ..gearing import SizedStage  # noqa: E402
from ..model import Counterweight  # noqa: E402
from ..kinematics import motion as solve_motion  # noqa: E402
from ..plots import draw_linkage, draw_mechanism, figure_png, literal_text, shaking_polar  # noqa: E402
from .chain import Alternative, MachineCheck, MachineDesign  # noqa: E402
from .record import SHEET_KEY, TITLE_BLOCK_KEY, DesignRecord, input_rows, sheet_metadata  # noqa: E402
from .running_plots import running_figure  # noqa: E402
from .foundation_plots import foundation_record_pages  # noqa: E402
from .strength_plots import joint_rows, link_rows, shaft_rows, strength_record_page  # noqa: E402
from .label_layout import OFFSETS, Labels, freeze, mm_axes, scale_bar  # noqa: E402
from ..gearing.stages import stage_name  # noqa: E402

#: A4 landscape [in]: every page of the report.
A4 = (11.69, 8.27)
RPM = np.pi / 30
#: Relative size below which a value is printed as 0: solver noise, not a quantity.
ZERO = 1e-9
#: Steel of the counterweight discs [kg/m³].
STEEL = 7850.0
_MONO = "DejaVu Sans Mono"
# TrueType fonts embedded whole (not Type 3): text a PDF reader can extract and search
_STYLE: Any = {"pdf.fonttype": 42, "ps.fonttype": 42}


def num(value: float | None, scale: float | None = None, digits: int = 4) -> str:
    """``value`` to ``digits`` significant digits, 0 when it is below 1e-9 of ``scale`` (default its own size
    against nothing: only an exact 0); ``-`` for None."""
    if value is None:
        return "-"
    if not math.isfinite(value):
        return str(value)
    if value == 0 or (scale is not None and abs(value) <= ZERO * abs(scale)):
        return "0"
    return f"{value:.{digits}g}"


# ---------------------------------------------------------------------------------------------------------------
# Pages: reportlab's platypus flows headings, paragraphs and tables over A4 landscape pages; the first page opens
# with the title block, every page ends with the record's footer.

_PAGE = landscape(_A4_PT)
_MARGIN = 14 * mm
_FRAME_W = _PAGE[0] - 2 * _MARGIN
_FONTS_READY: list[bool] = []


def _fonts() -> tuple[str, str, str]:
    """DejaVu Sans, its bold and DejaVu Sans Mono (matplotlib's own TrueType files), embedded: every unit sign
    (·, ², °, δ) prints and the text can be extracted."""
    if not _FONTS_READY:
        ttf = Path(matplotlib.get_data_path()) / "fonts" / "ttf"
        for name, file in (("DejaVu", "DejaVuSans.ttf"), ("DejaVu-Bold", "DejaVuSans-Bold.ttf"),
                           ("DejaVuMono", "DejaVuSansMono.ttf")):
            pdfmetrics.registerFont(TTFont(name, str(ttf / file)))
        _FONTS_READY.append(True)
    return "DejaVu", "DejaVu-Bold", "DejaVuMono"


def _styles() -> dict[str, ParagraphStyle]:
    regular, bold, mono = _fonts()
    return {
        "title": ParagraphStyle("title", fontName=bold, fontSize=16, leading=19),
        "h": ParagraphStyle("h", fontName=bold, fontSize=11, leading=14, spaceBefore=8, spaceAfter=4),
        "p": ParagraphStyle("p", fontName=regular, fontSize=8, leading=10, spaceAfter=3),
        "cell": ParagraphStyle("cell", fontName=regular, fontSize=7.5, leading=9),
        "num": ParagraphStyle("num", fontName=regular, fontSize=7.5, leading=9, alignment=TA_RIGHT),
        "head": ParagraphStyle("head", fontName=bold, fontSize=7.5, leading=9),
        "label": ParagraphStyle("label", fontName=regular, fontSize=6.5, leading=8, textColor=colors.grey),
        "value": ParagraphStyle("value", fontName=bold, fontSize=9, leading=11),
        "mono": ParagraphStyle("mono", fontName=mono, fontSize=7.5, leading=9),
    }


def _numeric(text: str) -> bool:
    try:
        float(text.split(" ")[0])
    except ValueError:
        return text in ("-", "")
    return True


def _para(text: str, style: ParagraphStyle) -> Paragraph:
    return Paragraph(xml_escape(text), style)


def _table(header: Sequence[str], rows: Sequence[Sequence[str]], st: dict[str, ParagraphStyle],
           weights: Sequence[float] | None = None) -> Table:
    """A table as wide as the page at most: columns shared out by their longest cell (or ``weights``), text
    wrapped inside its cell, numbers right-aligned, the header repeated on every page it runs over."""
    n = len(header)
    numeric = [len(rows) > 0 and all(_numeric(r[c]) for r in rows) for c in range(n)]
    if weights is not None:
        widths = [_FRAME_W * w / sum(weights) for w in weights]
    else:
        # each column as wide as its longest cell (its header's longest word at least), about 4.7 pt a character
        # at 7.5 pt plus the padding; columns of long text give way when the table is wider than the page
        # (a header's words are bold: about a third wider than the cells' characters, and never broken)
        need = [max(max((len(r[c]) for r in rows), default=0), *(math.ceil(1.35 * len(w)) for w in header[c].split()))
                for c in range(n)]
        widths = [4.7 * min(k, 70) + 14 for k in need]
        if sum(widths) > _FRAME_W:
            fixed = sum(w for w in widths if w <= 100)
            wide = sum(w for w in widths if w > 100)
            squeeze = max((_FRAME_W - fixed) / wide, 0.2) if wide else _FRAME_W / sum(widths)
            widths = [w if w <= 100 and wide else w * squeeze for w in widths]
    data = [[_para(h, st["head"]) for h in header]]
    data += [[_para(v, st["num"] if numeric[c] else st["cell"]) for c, v in enumerate(r)] for r in rows]
    t = Table(data, colWidths=widths, repeatRows=1, hAlign="LEFT")
    t.setStyle(TableStyle([("LINEBELOW", (0, 0), (-1, 0), 0.8, colors.black),
                           ("LINEBELOW", (0, 1), (-1, -1), 0.25, colors.lightgrey),
                           ("VALIGN", (0, 0), (-1, -1), "TOP"),
                           ("TOPPADDING", (0, 0), (-1, -1), 1.5), ("BOTTOMPADDING", (0, 0), (-1, -1), 1.5)]))
    return t


def _section(title: str, body: Sequence[Flowable], st: dict[str, ParagraphStyle]) -> list[Flowable]:
    """A heading kept on the page of what it heads: a short section whole on one page, a long one (a table of
    many rows) starting on this page when a few of its rows fit, its header repeated where it runs over."""
    head = _para(title, st["h"])
    rows = sum(len(getattr(b, "_cellvalues", ())) for b in body)
    if rows > 14:
        return [CondPageBreak(90), head, *body]
    return [KeepTogether([head, *body])]


def _footer(canvas: Any, record: DesignRecord) -> None:
    regular, _, _ = _fonts()
    tb = record.title_block
    canvas.saveState()
    canvas.setFont(regular, 7)
    canvas.setFillColor(colors.grey)
    ident = " ".join(x for x in (tb.number, f"rev. {tb.revision}" if tb.revision else "") if x)
    left = "  ·  ".join(x for x in (tb.title or record.name, ident, tb.state, record.created,
                                    f"mechsynth {record.version}",
                                    f"request SHA-256 {record.request_sha256[:16]}…") if x)
    canvas.drawString(_MARGIN, 8 * mm, left)
    canvas.drawRightString(_PAGE[0] - _MARGIN, 8 * mm, f"page {canvas.getPageNumber()}")
    canvas.restoreState()


# ---------------------------------------------------------------------------------------------------------------
# The record's content.

def _verdict(d: MachineDesign) -> str:
    if d.passed:
        return "every check met"
    return "FAILS: " + ", ".join(c.name for c in d.checks if not c.passed)


#: What the record calls each linkage family.
_FAMILIES = {"FourBar": "four-bar", "SliderCrank": "slider-crank", "SlottedLever": "shaper (slotted lever)"}


def _family(d: MachineDesign) -> str:
    """The linkage family in words (a class name split into words for a family the table does not know)."""
    cls = type(d.spec.linkage.mechanism).__name__
    return _FAMILIES.get(cls) or " ".join(w.lower() for w in re.findall(r"[A-Z][a-z0-9]*", cls)) or cls


def _title_block(record: DesignRecord, d: MachineDesign, st: dict[str, ParagraphStyle]) -> list[Flowable]:
    """The first page's title block: what the record is, who answers for it, where it stands, and its verdict."""
    tb = record.title_block

    def box(label: str, value: str, style: str = "value") -> list[Paragraph]:
        return [_para(label, st["label"]), _para(value or " ", st[style])]

    def signed(role: str, who: str, when: str) -> list[Paragraph]:
        return box(role, f"{who or '—'}    {when}" if when else (who or "—"))

    rows = [
        [box("project", tb.project or "—"), box("title", tb.title or record.name), "", box("state", tb.state)],
        [box("record number", tb.number or "—"), box("revision", tb.revision or "—"),
         box("date of this revision" if record.revisions else "date of this answer", record.created),
         box("service", f"mechsynth {record.version}")],
        [signed("designed", tb.designed_by, tb.designed_on), signed("checked", tb.checked_by, tb.checked_on),
         signed("approved", tb.approved_by, tb.approved_on), box("result", _verdict(d))],
        [box("request SHA-256 (the design's identity; the title block is not part of it)", record.request_sha256,
             "mono"), "", "", ""],
    ]
    spans = [("SPAN", (1, 0), (2, 0)), ("SPAN", (0, 3), (-1, 3))]
    if tb.deviation:
        rows.append([box("DEVIATION: released although it fails a check, for this reason", tb.deviation), "", "", ""])
        spans.append(("SPAN", (0, 4), (-1, 4)))
    widths = [_FRAME_W * w for w in (0.25, 0.3, 0.25, 0.2)]
    t = Table(rows, colWidths=widths, hAlign="LEFT")
    t.setStyle(TableStyle([("BOX", (0, 0), (-1, -1), 1.0, colors.black),
                           ("INNERGRID", (0, 0), (-1, -1), 0.4, colors.grey), *spans,
                           ("VALIGN", (0, 0), (-1, -1), "TOP"),
                           ("BACKGROUND", (3, 2), (3, 2), colors.HexColor("#eaf5ec" if d.passed else "#fbe9e7"))]))
    return [_para("Machine design record", st["title"]), Spacer(1, 4 * mm), t, Spacer(1, 3 * mm)]


def _revision_pages(record: DesignRecord, st: dict[str, ParagraphStyle]) -> list[Flowable]:
    """The revision table (every revision of the design up to this one) and the change note (each input that
    differs from the previous approved revision, with its unit): what a design library adds to its records."""
    out: list[Flowable] = []
    if record.revisions:
        out += _section("Revisions", [_table(
            ["rev.", "date (UTC)", "author", "message", "state", "checked", "approved", "deviation", "comments"],
            [[r.number, r.date, r.author, r.message, r.state, r.checked, r.approved, r.deviation, r.comments]
             for r in record.revisions], st, [4, 9, 7, 14, 9, 10, 10, 14, 23])], st)
    note = record.change_note
    if note is not None:
        if not note.against:
            body: list[Flowable] = [_para("No earlier revision of this design was approved: this is its first "
                                          "release, every input is as listed under Inputs.", st["p"])]
        elif not note.rows:
            body = [_para(f"The inputs are those of {note.against}.", st["p"])]
        else:
            body = [_para(f"Inputs that differ from {note.against}:", st["p"]),
                    _table(["field", "unit", "before", "after"], [list(r) for r in note.rows], st, [40, 10, 25, 25])]
        out += _section("Change note", body, st)
    return out


def _key_figures(d: MachineDesign) -> list[list[str]]:
    motor, body = d.drive.motor, d.placement
    return [
        ["mechanism", _family(d)],
        ["working speed", f"{num(d.spec.speed / RPM)} rev/min"],
        ["mean crank power", f"{num(d.output_power)} W"],
        ["motor", f"{motor.name}: {num(motor.rated_power)} W, {num(motor.rated_speed / RPM)} rev/min rated, runs "
                  f"at {num(d.drive.shafts[0].speed / RPM)} rev/min under the mean load"],
        ["train ratio (teeth)", num(d.train_ratio, digits=5) + ("" if len(d.stage_ratios) < 2 else " = " + " × ".join(
            num(u, digits=5) for u in d.stage_ratios))],
        ["balancing", d.balancing.mode],
        ["flywheel", "none needed" if body is None else
         f"{num(body.inertia)} kg·m² on the {body.shaft} shaft ({num(d.flywheel_inertia)} kg·m² "
         f"crank-equivalent), {body.shape}, outer diameter {num(body.outer_diameter)} m, {num(body.mass)} kg"],
        ["simulated delta", f"{num(d.motion.delta)} (target {num(d.spec.delta)})"],
        ["simulated mean crank speed", f"{num(d.motion.mean_speed / RPM)} rev/min"],
        *_efficiency_rows(d),
        ["warnings", str(len(d.warnings))],
    ]


def _efficiency_rows(d: MachineDesign) -> list[list[str]]:
    """Each stage's efficiency, the start and the run-down, when the design has them."""
    r = d.running
    if r is None:
        return []
    e, up, down = r.efficiency, r.startup, r.rundown
    return [["efficiency linkage / gears / overall", f"{num(e.linkage)} / {num(e.gears)} / {num(e.overall)}"],
            ["start", f"starting torque {num(up.check.starting_torque)} N·m at the crank against "
                      f"{num(float(up.check.resisting_torque.max()), up.check.starting_torque)} N·m at rest; "
                      f"steady after {num(up.steady_time)} s"],
            ["run-down", f"at rest after {num(down.stop_time)} s (brake {num(down.brake_torque)} N·m)"]]


def _stage_rows(d: MachineDesign) -> list[list[str]]:
    """Each stage: what it decided and its independent check figure."""
    before, bal = d.before, d.balancing
    rows = [["analysis", f"RMS shaking force {num(before.summary().rms_shaking_force)} N, RMS driving torque "
                         f"{num(before.summary().rms_driving_torque)} N·m",
             "driving torque against virtual power (Zhukovsky)",
             f"{num(before.torque_check, before.summary().max_driving_torque)} N·m"]]
    if bal.result is not None:
        r = bal.result
        rows.append(["balancing", f"{bal.mode}: {len(r.counterweights)} counterweights, "
                                  f"{num(r.total_added_mass)} kg added",
                     "shaking force / moment re-analysed",
                     f"{num(r.residual_force, r.before.max_shaking_force)} N / "
                     f"{num(r.residual_moment, r.before.max_shaking_moment)} N·m"])
    elif bal.slider_crank is not None:
        sc = bal.slider_crank
        rows.append(["balancing", f"{bal.mode}: crank counterweight {num(sc.crank_counterweight.mass)} kg, "
                                  f"{len(sc.pairs) if bal.mode == 'full' else 0} Lanchester pairs",
                     "largest shaking force left", f"{num(bal.after.max_shaking_force, sc.before.max_shaking_force)} N"])
    else:
        rows.append(["balancing", "none", "-", "-"])
    rows.append(["drive", f"{d.drive.motor.name}, total ratio {num(d.drive.total_ratio, digits=5)}",
                 "power balance over the shafts", num(d.drive.checks.power_balance_error, 1.0)])
    if d.teeth is not None:
        rows.append(["teeth", " ".join(f"{m.pinion_teeth}:{m.gear_teeth}" for m in d.teeth.stages),
                     "real ratio against the split's", num(d.teeth.ratio_error, 1.0)])
    rows.append(["flywheel", f"{num(d.flywheel_inertia)} kg·m² crank-equivalent ({d.flywheel.design_method})",
                 "delta of the simulated machine", f"{num(d.motion.delta)} for {num(d.spec.delta)}"])
    rows.append(["motor", f"operating point {num(d.drive.shafts[0].speed / RPM)} rpm",
                 "simulated mean motor speed", f"{num(d.motor.gear_ratio * d.motion.mean_speed / RPM)} rpm"])
    rows.append(["simulation", f"period {num(d.motion.period)} s", "mean crank speed against the working speed",
                 f"{num(d.motion.mean_speed / RPM)} rpm for {num(d.spec.speed / RPM)} rpm"])
    return rows + _around_rows(d)


def _around_rows(d: MachineDesign) -> list[list[str]]:
    """The foundation, the elastic drive and the load step, when asked: what each found and its check figure."""
    rows = []
    if (f := d.foundation) is not None:
        rows.append(["foundation", f"modes {', '.join(num(m.frequency, digits=3) for m in f.modes)} Hz; peak force "
                                   f"{num(f.peak_force)} N (shaking {num(f.peak_shaking_force)} N), amplitude "
                                   f"{num(f.peak_displacement * 1e3, digits=3)} mm",
                     "time integration against the harmonic answer", f"{f.check.relative_diff:.1e} of the peaks"])
    if d.elastic is not None:
        e = d.elastic.drive
        rows.append(["elastic drive", f"link {num(e.stiffness)} N·m/rad at the crank, {num(e.natural_frequency)} Hz, "
                                      f"dynamic factor {num(e.dynamic_factor)}; gears sized for the "
                                      f"{d.elastic.gear_torque_basis} torque",
                     "eigenvalues against sqrt(c(J₁+J₂)/(J₁J₂)); energy over the cycle",
                     f"{abs(e.eigen_frequency / e.natural_frequency - 1):.1e}; {e.steady.energy_residual:.1e}"])
    if d.regulation is not None:
        g = d.regulation.regulation
        settle = "not within the run" if g.settling_time is None else f"settles in {num(g.settling_time, digits=3)} s"
        rows.append(["regulation", f"{num(g.load_step)} N·m step: drop {num(g.drop / RPM)} rpm, {settle}",
                     "drop against the closed form ΔM/s", f"{num(g.drop_closed_form / RPM)} rpm"])
    return rows


def counterweight_disc(cw: Counterweight, density: float = STEEL) -> tuple[float, float]:
    """Diameter and thickness [m] of a solid disc of ``density`` [kg/m³] that realises a counterweight.

    A disc of mass m and radius a has the own inertia m·a²/2: the disc that has the counterweight's own inertia,
    unless that disc would be thicker than its radius (a point-like counterweight); then the disc as thick as
    its radius, whose own inertia is a little more than the balance assumed.
    """
    if cw.mass <= 0:
        return 0.0, 0.0
    compact = (cw.mass / (density * math.pi)) ** (1 / 3)
    a = max(math.sqrt(2 * max(cw.inertia, 0.0) / cw.mass), compact)
    return 2 * a, cw.mass / (density * math.pi * a * a)


def _counterweights(d: MachineDesign) -> list[Counterweight]:
    bal = d.balancing
    if bal.result is not None:
        return list(bal.result.counterweights)
    if bal.slider_crank is not None:
        return [bal.slider_crank.crank_counterweight]
    return []


def _counterweight_rows(d: MachineDesign) -> list[list[str]]:
    cws = _counterweights(d)
    scale = max((c.mass for c in cws), default=0.0)
    rows = []
    for c in cws:
        radius = math.hypot(*c.position)
        dia, thick = counterweight_disc(c)
        angle = math.degrees(math.atan2(c.position[1], c.position[0])) if radius > ZERO * max(scale, 1e-300) else 0.0
        rows.append([c.link, num(c.mass, scale), num(radius, scale), num(angle, 360.0), num(c.inertia, scale),
                     num(dia, scale), num(thick, scale)])
    return rows


#: Columns of the gear table, one row per stage (motor side first): header and the cell of stage k. The
#: strength rating appends its columns here (module, face width, centre distance, diameters).
GearColumn = tuple[str, Callable[[MachineDesign, int], str]]


def _mesh(d: MachineDesign, k: int) -> tuple[int, int] | None:
    stages = d.spec.drive.stages
    if d.teeth is None:
        return None
    toothed = [i for i, s in enumerate(stages) if s.toothed]
    if k not in toothed:
        return None
    m = d.teeth.stages[toothed.index(k)]
    return m.pinion_teeth, m.gear_teeth


GEAR_COLUMNS: list[GearColumn] = [
    ("stage", lambda d, k: str(k + 1)),
    ("type", lambda d, k: d.spec.drive.stages[k].type),
    ("pinion teeth", lambda d, k: "-" if (m := _mesh(d, k)) is None else str(m[0])),
    ("gear teeth", lambda d, k: "-" if (m := _mesh(d, k)) is None else str(m[1])),
    ("split ratio", lambda d, k: num(d.drive.split.stage_ratios[k], digits=5)),
    ("real ratio", lambda d, k: num(d.stage_ratios[k], digits=5)),
    ("efficiency", lambda d, k: num(d.spec.drive.stages[k].efficiency, digits=3)),
    ("input speed [rpm]", lambda d, k: num(d.shafts[k].mean_speed / RPM)),
    ("input torque peak [N·m]", lambda d, k: num(d.shafts[k].peak_torque)),
]


def _sized(d: MachineDesign, k: int) -> SizedStage | None:
    return None if d.gears is None else d.gears.stages[k]


def _gear_cell(fmt: Callable[[SizedStage], str]) -> Callable[[MachineDesign, int], str]:
    return lambda d, k: "-" if (g := _sized(d, k)) is None else fmt(g)


#: The strength sizing's table, one row per stage (ISO 6336, Miner's rule on the pinion shaft's cyclic torque).
STRENGTH_COLUMNS: list[GearColumn] = [
    ("stage", lambda d, k: str(k + 1)),
    ("module [mm]", _gear_cell(lambda g: f"{g.module * 1e3:g}")),
    ("face width [mm]", _gear_cell(lambda g: num(g.face_width * 1e3))),
    ("centre distance [mm]", _gear_cell(lambda g: num(g.centre_distance * 1e3))),
    ("d1 / d2 [mm]", _gear_cell(lambda g: f"{num(g.diameters[0] * 1e3)} / {num(g.diameters[1] * 1e3)}")),
    ("S_H pinion / gear", _gear_cell(lambda g: f"{num(g.safety_contact[0], digits=3)} / "
                                               f"{num(g.safety_contact[1], digits=3)}")),
    ("S_F pinion / gear", _gear_cell(lambda g: f"{num(g.safety_root[0], digits=3)} / "
                                               f"{num(g.safety_root[1], digits=3)}")),
    ("binding", _gear_cell(lambda g: g.binding)),
    ("mass [kg]", _gear_cell(lambda g: num(g.mass))),
]


def _sizing_paragraph(d: MachineDesign) -> str:
    """What sized the gears and which constraint binds at each stage."""
    if d.gears is None:
        return "Gears not sized for strength (drive.size_gears false)."
    rules = d.spec.drive.strength
    head = ("Module (ISO 54) and least face width per stage for S_H and S_F on the cyclic torque of its pinion "
            "shaft (ISO 6336 method B, Miner's rule over the required life")
    if rules is not None:
        head += (f" of {rules.duty.life:g} h, S_Hmin {rules.duty.min_safety_contact:g}, S_Fmin "
                 f"{rules.duty.min_safety_root:g}, {rules.materials[0]} / {rules.materials[1]}")
    return head + "); binding: the constraint that fixes the face width; - : a stage that is not a spur or " \
        "helical pair, or could not be sized (see the warnings)."


def _flywheel_rows(d: MachineDesign) -> list[list[str]]:
    b = d.placement
    if b is None:
        return [["flywheel", "none needed: the machine's own inertia meets the target"]]
    rows = [
        ["shaft", f"{b.shaft} (speed {num(b.speed_ratio, digits=5)} × crank)"],
        ["inertia on its shaft", f"{num(b.inertia)} kg·m²"],
        ["crank-equivalent inertia", f"{num(d.flywheel_inertia)} kg·m² (= inertia × speed ratio²)"],
        ["shape", b.shape],
        ["mean diameter" if b.shape == "rim" else "diameter", f"{num(b.diameter)} m"],
        ["outer diameter", f"{num(b.outer_diameter)} m"],
    ]
    if b.thickness is not None:
        rows.append(["rim radial thickness", f"{num(b.thickness)} m"])
    rows += [["width", f"{num(b.width)} m"], ["mass", f"{num(b.mass)} kg"],
             ["rim speed", f"{num(b.rim_speed)} m/s"],
             ["inertia from the dimensions (check)", f"{num(b.inertia_check)} kg·m²"]]
    return rows


def _motor_rows(d: MachineDesign) -> list[list[str]]:
    m, c = d.drive.motor, d.motor
    return [
        ["name", m.name], ["rated power", f"{num(m.rated_power)} W"],
        ["synchronous speed", f"{num(m.synchronous_speed / RPM)} rpm"], ["rated speed", f"{num(m.rated_speed / RPM)} rpm"],
        ["rated torque", f"{num(c.rated_torque)} N·m"], ["breakdown torque", f"{num(c.breakdown_torque)} N·m"],
        ["rotor inertia", f"{num(m.rotor_inertia)} kg·m²"],
        ["operating speed under the mean load", f"{num(d.drive.shafts[0].speed / RPM)} rpm (the ratio is taken "
                                                f"from it)"],
        ["simulated mean speed", f"{num(c.gear_ratio * d.motion.mean_speed / RPM)} rpm"],
        ["required power", f"{num(d.drive.required_power)} W (mean crank power × reserve / efficiency)"],
        ["train ratio, efficiency", f"{num(c.gear_ratio, digits=5)}, {num(c.efficiency, digits=4)}"],
        ["torque peak / RMS", f"{num(d.motion.motor_peak_torque)} / {num(d.motion.motor_rms_torque)} N·m"],
    ]


def _check_rows(d: MachineDesign) -> list[list[str]]:
    """Every check, in words, its value and limit in its unit."""
    def with_unit(v: float, c: MachineCheck) -> str:
        return f"{num(v, c.limit)} {c.unit}".strip()

    return [[c.label or c.name.replace("_", " "), with_unit(c.value, c), "≤ " + with_unit(c.limit, c),
             "yes" if c.passed else "NO", c.detail] for c in d.checks]


def _record_flowables(record: DesignRecord, d: MachineDesign, alternatives: Sequence[Alternative],
                      st: dict[str, ParagraphStyle]) -> list[Flowable]:
    """The text of the record: key figures, checks, warnings, inputs, stages, counterweights, gears, flywheel,
    motor, shafts and the alternatives."""
    out: list[Flowable] = [*_title_block(record, d, st), *_revision_pages(record, st)]
    out += _section("Design", [_table(["quantity", "value"], _key_figures(d), st)], st)
    deviation = ([_para(f"Deviation: this revision is released although it fails a check, for this reason: "
                        f"{record.title_block.deviation}", st["p"])] if record.title_block.deviation else [])
    out += _section("Checks against the simulated machine",
                    [*deviation, _table(["check", "value", "limit", "met", "what it compares"], _check_rows(d), st)],
                    st)
    warn = [_para(f"[{w.stage or '-'}] {w.code}" + (f" ({w.field})" if w.field else "") + f": {w.message}", st["p"])
            for w in d.warnings] or [_para("none", st["p"])]
    out += _section(f"Warnings ({len(d.warnings)})", warn, st)
    if record.request:
        out += _section("Inputs: the request as received, defaults included",
                        [_table(["field", "value", "unit"], [list(r) for r in input_rows(record.request)], st,
                                [50, 60, 10])], st)
    out += _section("Stages and their check figures",
                    [_table(["stage", "result", "check", "check figure"], _stage_rows(d), st)], st)
    cw = _counterweight_rows(d)
    out += _section("Counterweights", [
        _para("Radius and angle in the link frame (origin at the link's first joint, x toward its second); each "
              "realised as a steel disc of its own inertia, or as thick as its radius when that inertia is smaller "
              "(drawn to scale on the drawings page).", st["p"]),
        _table(["link", "mass [kg]", "radius [m]", "angle [°]", "own inertia [kg·m²]", "steel disc diameter [m]",
                "disc thickness [m]"], cw, st) if cw else _para("none", st["p"])], st)
    nstages = range(len(d.spec.drive.stages))
    out += _section("Gear train, motor side first", [_table([h for h, _ in GEAR_COLUMNS],
                                                            [[cell(d, k) for _, cell in GEAR_COLUMNS] for k in nstages],
                                                            st)], st)
    strength: list[Flowable] = [_para(_sizing_paragraph(d), st["p"])]
    if d.gears is not None:
        strength.append(_table([h for h, _ in STRENGTH_COLUMNS],
                               [[cell(d, k) for _, cell in STRENGTH_COLUMNS] for k in nstages], st))
    out += _section("Gears sized for strength", strength, st)
    out += _section("Flywheel", [_table(["quantity", "value"], _flywheel_rows(d), st)], st)
    out += _section("Motor", [_table(["quantity", "value"], _motor_rows(d), st)], st)
    peak = max((s.peak_torque for s in d.shafts), default=0.0)
    out += _section("Shafts in the simulated steady motion (the torque each passes on)", [_table(
        ["shaft", "speed [rev/min]", "power [W]", "mean T [N·m]", "peak T [N·m]", "RMS T [N·m]", "inertia [kg·m²]",
         "flywheel"],
        [[s.name, num(s.mean_speed / RPM), num(s.mean_power, d.output_power), num(s.mean_torque, peak),
          num(s.peak_torque, peak), num(s.rms_torque, peak), num(s.inertia), "yes" if s.carries_flywheel else ""]
         for s in d.shafts], st)], st)
    if d.strength is not None:
        s = d.strength
        out += _section("Parts sized for strength", [
            _para(f"Links sized to the fixed point of their own masses in {len(s.sizing.iterations)} passes before "
                  "balancing, then checked on the machine as built: static (von Mises vs yield), fatigue (modified "
                  "Goodman, Marin factors), buckling in and out of the plane (Euler/Johnson); least factors of "
                  "safety over the cycle (drawn on the parts page).", st["p"]),
            _table(["link", "material", "section", "length [mm]", "mass [kg]", "static", "fatigue",
                    "buckling in plane", "buckling out of plane", "passed"], link_rows(s), st),
            _table(["joint", "pin [mm]", "pin governed by", "load", "bearing", "passed"], joint_rows(s), st),
            _table(["part", "size", "figure", "passed"], shaft_rows(s), st)], st)
    if alternatives:
        rows = []
        for a in [Alternative(d.balancing.mode + " (this design)", d, None), *alternatives]:
            if a.design is None:
                rows.append([a.mode, "not available", "", "", "", "", ""])
                continue
            x = a.design
            rows.append([a.mode, num(x.balancing.after.rms_shaking_force, d.before.summary().rms_shaking_force),
                         num(x.balancing.after.rms_shaking_moment, d.before.summary().rms_shaking_moment),
                         num(x.flywheel_inertia), "-" if x.placement is None else
                         f"{num(x.placement.mass)} ({x.placement.shaft})", x.drive.motor.name,
                         "yes" if x.passed else "no"])
        body: list[Flowable] = [_table(["mode", "RMS force [N]", "RMS moment [N·m]", "flywheel, crank-eq. [kg·m²]",
                                        "flywheel mass [kg]", "motor", "passed"], rows, st)]
        body += [_para(f"{a.mode}: {a.reason}", st["p"]) for a in alternatives if a.design is None]
        out += _section("What each balancing choice costs", body, st)
    return out


# ---------------------------------------------------------------------------------------------------------------
# Diagrams.

def _grid(ax: Axes, title: str, xlabel: str, ylabel: str) -> None:
    ax.set_title(title, fontsize=10)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)


def _include(ax: Axes, values: Iterable[float]) -> None:
    """Widen the y-axis so that every reference line in ``values`` lies inside it, with a margin."""
    lo, hi = ax.get_ylim()
    vals = [v for v in values if math.isfinite(v)]
    lo, hi = min([lo, *vals]), max([hi, *vals])
    pad = 0.06 * (hi - lo) if hi > lo else 1.0
    ax.set_ylim(lo - pad, hi + pad)


def _torque(ax: Axes, d: MachineDesign) -> None:
    deg = np.degrees(d.before.motion.phi)
    ax.plot(deg, d.before.kinetostatics.driving_torque, label="as given")
    if d.balancing.mode != "none":
        ax.plot(deg, d.balanced.kinetostatics.driving_torque, "--", label=f"after {d.balancing.mode} balancing")
    ax.legend(fontsize=7)
    _grid(ax, "driving torque at constant speed", "crank angle [deg]", "torque [N·m]")


def _speed(ax: Axes, d: MachineDesign) -> None:
    m = d.motion
    mid = 0.5 * (float(m.omega.max()) + float(m.omega.min())) / RPM
    ax.plot(np.degrees(m.phi), m.omega / RPM, lw=1.4, label=f"simulated: delta {m.delta:.4g}")
    band = (mid * (1 + d.spec.delta / 2), mid * (1 - d.spec.delta / 2))
    working = d.spec.speed / RPM
    ax.axhline(band[0], color="k", ls=":", lw=1)
    ax.axhline(band[1], color="k", ls=":", lw=1, label=f"target band, delta {d.spec.delta:.4g}")
    ax.axhline(working, color="tab:red", ls="-.", lw=1, label=f"working speed {working:.4g} rpm")
    _include(ax, [*band, working])
    ax.legend(fontsize=7)
    _grid(ax, "crank speed, simulated machine", "crank angle [deg]", "crank speed [rpm]")


def _polar(ax: Axes, d: MachineDesign) -> None:
    shaking_polar(ax, d.before.kinetostatics.shaking_force, "as given")
    if d.balancing.mode != "none":
        after = d.balanced.kinetostatics.shaking_force
        if d.balancing.slider_crank is not None and d.balancing.mode == "full":
            after = d.balancing.slider_crank.after_force
        shaking_polar(ax, after, f"after {d.balancing.mode}", ls="--")
    ax.legend(fontsize=7)


def _moment(ax: Axes, d: MachineDesign) -> None:
    deg = np.degrees(d.before.motion.phi)
    ax.plot(deg, d.before.kinetostatics.shaking_moment, label="as given")
    if d.balancing.mode != "none":
        ax.plot(deg, d.balanced.kinetostatics.shaking_moment, "--", label=f"after {d.balancing.mode}")
    ax.legend(fontsize=7)
    _grid(ax, "shaking moment about O", "crank angle [deg]", "moment [N·m]")


def _energy_mass(ax: Axes, d: MachineDesign) -> None:
    f = d.flywheel
    cycle, tan = f.cycle, f.tangents
    phi = cycle.dense(4000)
    inertia, _, work = cycle.evaluate(phi)
    ax.plot(inertia, work, lw=1.5, label="energy-mass curve")
    x = np.linspace(min(0.0, float(inertia.min())), float(inertia.max()) * 1.05 + 1e-12, 50)
    ax.plot(x, tan.slope_max * x + tan.intercept_max, "r--", lw=1, label="tangent w_max²/2")
    ax.plot(x, tan.slope_min * x + tan.intercept_min, "b--", lw=1, label="tangent w_min²/2")
    # both tangents inside the axes over the drawn range of J
    ends = [tan.slope_max * x[0] + tan.intercept_max, tan.slope_max * x[-1] + tan.intercept_max,
            tan.slope_min * x[0] + tan.intercept_min, tan.slope_min * x[-1] + tan.intercept_min]
    _include(ax, ends)
    ax.set_xlim(float(x[0]), float(x[-1]))
    ax.legend(fontsize=7)
    _grid(ax, "energy-mass diagram", "reduced inertia J_red [kg·m²]", "excess work [J]")


def _motor(ax: Axes, d: MachineDesign) -> None:
    m, motor = d.motion, d.motor
    ax.plot(np.degrees(m.phi), m.motor_torque, label="motor torque")
    refs = [motor.rated_torque, m.motor_rms_torque]
    ax.axhline(motor.rated_torque, color="g", ls=":", label=f"rated {motor.rated_torque:.4g} N·m")
    ax.axhline(m.motor_rms_torque, color="g", ls="--", lw=1, label=f"RMS {m.motor_rms_torque:.4g} N·m")
    if motor.breakdown_torque is not None:
        ax.axhline(motor.breakdown_torque, color="r", ls=":", label=f"breakdown {motor.breakdown_torque:.4g} N·m")
        refs.append(motor.breakdown_torque)
    _include(ax, refs)
    ax.legend(fontsize=7)
    _grid(ax, f"motor {d.drive.motor.name} on its shaft", "crank angle [deg]", "torque [N·m]")


def _summary_figure(d: MachineDesign) -> Figure:
    fig, axes = plt.subplots(2, 3, figsize=A4)
    # a third of the way round, where no linkage is folded flat on its line of centres
    phi = d.before.motion.phi
    draw_mechanism(axes[0, 0], d.balanced, float(phi[len(phi) // 6]))
    _torque(axes[0, 1], d)
    _speed(axes[0, 2], d)
    _polar(axes[1, 0], d)
    _motor(axes[1, 1], d)
    ax = axes[1, 2]
    ax.axis("off")
    ax.set_title("design", loc="left", fontsize=10)
    text = "\n".join(f"{k}: {v}" for k, v in _key_figures(d)[1:8])
    ax.text(0.0, 1.0, "\n".join(textwrap.fill(line, 48) for line in text.split("\n")), va="top", fontsize=7,
            family=_MONO, transform=ax.transAxes)
    fig.suptitle(f"machine design: {_verdict(d)}")
    literal_text(fig).tight_layout(rect=(0, 0.03, 1, 1))
    return fig


def _dimension(ax: Axes, labels: Labels, a: Sequence[float], b: Sequence[float], text: str, **kw: Any) -> None:
    """A dimension line from ``a`` to ``b`` [m] with arrows at both ends, its text placed by measure beside its
    middle."""
    ax.annotate("", xy=(b[0], b[1]), xytext=(a[0], a[1]), arrowprops={"arrowstyle": "<->", "lw": 0.8, "color": "0.15"})
    mid = (0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]))
    near = ((0.0, 0.0), (0.0, 8.0), (0.0, -8.0), (10.0, 0.0), (-10.0, 0.0), (0.0, 18.0), (0.0, -18.0), (24.0, 0.0),
            (-24.0, 0.0), *OFFSETS)
    labels.place(mid, text, near, fontsize=7, bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.85},
                 **kw)


def _linkage_drawing(ax: Axes, d: MachineDesign) -> None:
    """The balanced linkage at a third of a turn, to scale, each counterweight drawn as its steel disc and
    dimensioned: radius and angle in its link's frame, disc diameter and thickness."""
    an = d.balanced
    phi = float(an.motion.phi[len(an.motion.phi) // 6])
    draw_linkage(ax, an.linkage, an, phi, counterweights=[])
    mech = an.linkage.mechanism
    single = solve_motion(mech, np.array([phi]), an.motion.omega_crank)
    discs = []
    for cw in _counterweights(d):
        if cw.mass <= 0:
            continue
        origin = single.point_pos[mech.origins[cw.link]][0]
        ang = float(single.link_angle[cw.link][0])
        c, s = math.cos(ang), math.sin(ang)
        centre = origin + np.array([c * cw.position[0] - s * cw.position[1], s * cw.position[0] + c * cw.position[1]])
        dia, thick = counterweight_disc(cw)
        patch = Circle(tuple(centre), dia / 2, fc="tab:orange", ec="saddlebrown", alpha=0.6, zorder=4)
        ax.add_patch(patch)
        discs.append((cw, origin, centre, dia, thick, patch))
    ax.set_aspect("equal", adjustable="datalim")
    ax.relim()
    ax.autoscale_view()
    # room round the linkage for the labels, then the limits fixed: every box below is measured against them
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    pad = 0.08 * max(x1 - x0, y1 - y0)
    ax.set_xlim(x0 - pad, x1 + pad)
    ax.set_ylim(y0 - pad, y1 + pad)
    mm_axes(ax)
    legend = ax.legend(fontsize=7, loc="upper right")
    freeze(ax)
    labels = Labels(ax)
    labels.take([legend, *(p for *_, p in discs)])
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    scale_bar(ax, labels, max(x1 - x0, y1 - y0))
    for cw, origin, centre, dia, thick, _ in discs:
        radius = math.hypot(*cw.position)
        theta = math.degrees(math.atan2(cw.position[1], cw.position[0]))
        _dimension(ax, labels, origin, centre, f"r = {num(radius * 1e3)} mm")
        labels.place(centre, f"counterweight on the {cw.link}: {num(cw.mass)} kg\nat {num(theta, 360.0)}° in the link frame\n"
                     f"steel disc Ø {num(dia * 1e3)} mm × {num(thick * 1e3)} mm", leader=True, fontsize=7,
                     bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "0.6", "lw": 0.5})
    ax.set_title(f"{_family(d)} at {num(math.degrees(phi))}° with its counterweights", fontsize=9)


def _gear_drawing(ax: Axes, d: MachineDesign) -> None:
    """Each sized gear pair, to scale: pitch circles (tip circles dashed), the centre distance and both
    diameters dimensioned, module and face width written."""
    sized = [g for g in (d.gears.stages if d.gears is not None else []) if g is not None]
    if not sized:
        ax.set_xticks([])
        ax.set_yticks([])
        ax.text(0.5, 0.5, "gears not sized for strength", ha="center", va="center", transform=ax.transAxes)
        ax.set_title("gear pairs", fontsize=9)
        return
    y = 0.0
    widest = max(g.centre_distance + (g.tip_diameters[0] + g.tip_diameters[1]) / 2 for g in sized)
    rows = []
    for g in sized:
        r1, r2 = g.diameters[0] / 2, g.diameters[1] / 2
        top = max(g.tip_diameters) / 2
        y -= top
        for x, r, tip in ((0.0, r1, g.tip_diameters[0] / 2), (g.centre_distance, r2, g.tip_diameters[1] / 2)):
            ax.add_patch(Circle((x, y), r, fill=False, lw=1.2, ec="tab:blue"))
            ax.add_patch(Circle((x, y), tip, fill=False, lw=0.6, ls="--", ec="tab:blue"))
            ax.plot(x, y, "k+", ms=5)
        rows.append((g, y, top, r1, r2))
        y -= top + 0.3 * widest
    ax.set_aspect("equal", adjustable="datalim")
    ax.relim()
    ax.autoscale_view()
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    ax.set_xlim(x0 - 0.6 * widest, x1 + 0.1 * widest)
    ax.set_ylim(y0 - 0.1 * widest, y1 + 0.1 * widest)
    mm_axes(ax)
    freeze(ax)
    labels = Labels(ax)
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    scale_bar(ax, labels, max(x1 - x0, y1 - y0))
    for g, y, top, r1, r2 in rows:
        _dimension(ax, labels, (0.0, y - top - 0.08 * widest), (g.centre_distance, y - top - 0.08 * widest),
                   f"a = {num(g.centre_distance * 1e3)} mm")
        _dimension(ax, labels, (0.0, y - r1), (0.0, y + r1), f"d1 = {num(g.diameters[0] * 1e3)} mm")
        _dimension(ax, labels, (g.centre_distance, y - r2), (g.centre_distance, y + r2),
                   f"d2 = {num(g.diameters[1] * 1e3)} mm")
        labels.place((-r1, y), f"{stage_name(g.stage)}\nz {g.pinion_teeth}:{g.gear_teeth}\n"
                     f"m {g.module * 1e3:g} mm\nb {num(g.face_width * 1e3)} mm",
                     ((-8.0, 0.0), (-20.0, 0.0), *OFFSETS), fontsize=7)
    ax.set_title("gear pairs (pitch circles; tip circles dashed)", fontsize=9)


def _flywheel_drawing(ax: Axes, d: MachineDesign) -> None:
    """The flywheel, to scale: front view and section, outer and inner diameters and width dimensioned."""
    b = d.placement
    if b is None:
        ax.set_xticks([])
        ax.set_yticks([])
        ax.text(0.5, 0.5, "no flywheel needed", ha="center", va="center", transform=ax.transAxes)
        ax.set_title("flywheel", fontsize=9)
        return
    R = b.outer_diameter / 2
    r = R - b.thickness if b.shape == "rim" and b.thickness is not None else 0.0
    ax.add_patch(Circle((0, 0), R, fc="#dfe7f3", ec="#2d3e5c", lw=1.2))
    if r > 0:
        ax.add_patch(Circle((0, 0), r, fc="white", ec="#2d3e5c", lw=1.0))
        for k in range(3):
            a = math.pi * k / 3
            ax.plot([-r * math.cos(a), r * math.cos(a)], [-r * math.sin(a), r * math.sin(a)], color="#2d3e5c", lw=2)
    ax.add_patch(Circle((0, 0), 0.08 * R, fc="white", ec="#2d3e5c"))
    x = 1.5 * R
    ax.add_patch(Rectangle((x, -R), b.width, 2 * R, fc="#dfe7f3", ec="#2d3e5c", lw=1.2))
    if r > 0:
        ax.add_patch(Rectangle((x + 0.35 * b.width, -r), 0.3 * b.width, 2 * r, fc="white", ec="#2d3e5c"))
    ax.set_xlim(-1.3 * R, x + b.width + 0.6 * R)
    ax.set_ylim(-1.6 * R, 1.45 * R)
    ax.set_aspect("equal", adjustable="datalim")
    mm_axes(ax)
    freeze(ax)
    labels = Labels(ax)
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    scale_bar(ax, labels, max(x1 - x0, y1 - y0))
    _dimension(ax, labels, (-R, -1.15 * R), (R, -1.15 * R), f"D = {num(b.outer_diameter * 1e3)} mm")
    if r > 0:
        _dimension(ax, labels, (-r, 0.0), (r, 0.0), f"d = {num(2 * r * 1e3)} mm")
    _dimension(ax, labels, (x, 1.12 * R), (x + b.width, 1.12 * R), f"b = {num(b.width * 1e3)} mm")
    ax.set_title(f"flywheel ({b.shape}) on the {b.shaft} shaft: {num(b.mass)} kg", fontsize=9)


# The drawing pages' layout, fixed (the text on them is placed by measure at this size).
_DRAWING_ADJUST = {"left": 0.08, "right": 0.98, "bottom": 0.15, "top": 0.88, "wspace": 0.3}


def dimensioned_figure(d: MachineDesign) -> Figure:
    """The linkage with its counterweights, the gear pairs and the flywheel, each to scale and dimensioned, on
    one A4 landscape page."""
    fig = plt.figure(figsize=(_PAGE[0] / 72, _PAGE[1] / 72))
    fig.subplots_adjust(**_DRAWING_ADJUST)
    grid = fig.add_gridspec(1, 3, width_ratios=(1.5, 1.0, 1.0))
    _linkage_drawing(fig.add_subplot(grid[0]), d)
    _gear_drawing(fig.add_subplot(grid[1]), d)
    _flywheel_drawing(fig.add_subplot(grid[2]), d)
    return fig


def design_summary_png(design: MachineDesign) -> bytes:
    """One page: the mechanism, driving torque, simulated speed, shaking force, motor torque, key figures [PNG]."""
    return figure_png(_summary_figure(design), dpi=90)


def _figure_footer(fig: Figure, record: DesignRecord, page: int) -> None:
    """The record's footer on a figure page, as the text pages have it."""
    tb = record.title_block
    ident = " ".join(x for x in (tb.number, f"rev. {tb.revision}" if tb.revision else "") if x)
    left = "  ·  ".join(x for x in (tb.title or record.name, ident, tb.state, record.created,
                                    f"mechsynth {record.version}",
                                    f"request SHA-256 {record.request_sha256[:16]}…") if x)
    fig.text(_MARGIN / _PAGE[0], 8 * mm / _PAGE[1], left, size=7, color="0.5", family="DejaVu Sans")
    fig.text(1 - _MARGIN / _PAGE[0], 8 * mm / _PAGE[1], f"page {page}", size=7, color="0.5", ha="right",
             family="DejaVu Sans")


def _figures(d: MachineDesign) -> list[tuple[str | None, Figure]]:
    """The drawing and diagram pages, each an A4 landscape figure with its title (None: a figure that has its
    own title and layout)."""
    out: list[tuple[str | None, Figure]] = [("Dimensioned drawings, to scale", dimensioned_figure(d)),
                                           (None, _summary_figure(d))]
    fig, axes = plt.subplots(1, 3, figsize=A4)
    _polar(axes[0], d)
    _moment(axes[1], d)
    _torque(axes[2], d)
    out.append(("Balancing", fig))
    fig, axes = plt.subplots(1, 3, figsize=A4)
    _energy_mass(axes[0], d)
    _speed(axes[1], d)
    _motor(axes[2], d)
    out.append(("Flywheel and motor", fig))
    if (running := running_figure(d)) is not None:
        out.append((None, running))
    if d.strength is not None:
        out.append(("Parts: each link along its length, its section to scale, where its checks are least",
                    strength_record_page(d.strength)))
    out += [(None, page) for page in foundation_record_pages(
        d.foundation, None if d.elastic is None else d.elastic.drive,
        None if d.regulation is None else d.regulation.regulation)]
    return out


def design_report_pdf(design: MachineDesign, alternatives: Sequence[Alternative] = (),
                      record: DesignRecord | None = None) -> bytes:
    """The design record [PDF, A4 landscape]: the title block (project, number, revision, title, designed,
    checked and approved with names and dates, state) and verdict, key figures, checks, warnings, every input
    with its unit, each stage with its check figure, counterweights, gear train, flywheel, motor and shafts, the
    alternatives; then the dimensioned drawings and the diagrams (summary, balancing, flywheel and motor,
    start-up and run-down).

    ``record`` names the design and holds the request; without one the report says so and lists no inputs.
    """
    d = design
    record = record or DesignRecord("machine design", "-", "-", {}, "not given")
    st = _styles()
    text = io.BytesIO()
    # invariant: no creation time or random document id, so one record written twice is the same bytes
    doc = BaseDocTemplate(text, pagesize=_PAGE, leftMargin=_MARGIN, rightMargin=_MARGIN, topMargin=_MARGIN,
                          bottomMargin=_MARGIN + 4 * mm, invariant=1)
    frame = Frame(doc.leftMargin, doc.bottomMargin, doc.width, doc.height, id="body", leftPadding=0,
                  rightPadding=0, topPadding=0, bottomPadding=0)
    doc.addPageTemplates([PageTemplate(id="page", frames=[frame], onPage=lambda c, _: _footer(c, record))])
    doc.build(_record_flowables(record, d, alternatives, st))
    # The figures stay vector: matplotlib writes them as PDF pages of the same size, numbered on from the text.
    out = PdfWriter(clone_from=PdfReader(io.BytesIO(text.getvalue())))
    pages = len(out.pages)
    drawn = io.BytesIO()
    with plt.rc_context(_STYLE), PdfPages(drawn, metadata={"CreationDate": None}) as pdf:
        for title, fig in _figures(d):
            if title is not None:
                fig.set_size_inches(_PAGE[0] / 72, _PAGE[1] / 72)
                fig.suptitle(title, x=_MARGIN / _PAGE[0], ha="left", fontsize=12, weight="bold")
                # fixed margins (tight_layout measures every text's extent: seconds on a busy machine)
                fig.subplots_adjust(**_DRAWING_ADJUST)
            pages += 1
            _figure_footer(fig, record, pages)
            pdf.savefig(literal_text(fig))
            plt.close(fig)
    out.append(PdfReader(io.BytesIO(drawn.getvalue())))
    out.add_metadata({"/Title": f"Machine design record: {record.name}",
                      "/Subject": f"request SHA-256 {record.request_sha256}",
                      "/Creator": f"mechsynth {record.version}", "/Author": record.title_block.designed_by,
                      TITLE_BLOCK_KEY: json.dumps(asdict(record.title_block), sort_keys=True),
                      SHEET_KEY: sheet_metadata(record)})
    buf = io.BytesIO()
    out.write(buf)
    return buf.getvalue()
