"""The design record of a whole machine: a multi-page A4 PDF (matplotlib's PdfPages) and a one-page PNG summary.

The PDF opens with a title block (name, date, service version, the request's SHA-256) and the verdict, then
lists every input with its unit, each stage of the chain with its independent check figure, the counterweights
(mass, radius, angle and the steel disc that realises each), the gear train (a table per stage), the flywheel
where it sits, the motor and its operating point, every shaft, every check and every warning; the diagrams
follow (mechanism, driving torque, simulated speed, shaking force and moment, energy-mass diagram, motor
torque), and the alternatives when asked. Every page is A4 landscape; text is set in embedded TrueType fonts so
it can be extracted; a value smaller than 1e-9 of its column's (or quantity's) scale is printed as 0.
"""

from __future__ import annotations

import io
import math
import textwrap
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.backends.backend_pdf import PdfPages  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

from ..gearing import SizedStage  # noqa: E402
from ..model import Counterweight  # noqa: E402
from ..plots import draw_mechanism, figure_png, shaking_polar  # noqa: E402
from .chain import Alternative, MachineDesign  # noqa: E402
from .record import DesignRecord, input_rows  # noqa: E402
from .running_plots import running_figure  # noqa: E402

#: A4 landscape [in]: every page of the report.
A4 = (11.69, 8.27)
RPM = np.pi / 30
#: Relative size below which a value is printed as 0: solver noise, not a quantity.
ZERO = 1e-9
#: Steel of the counterweight discs [kg/m³].
STEEL = 7850.0
_MONO = "DejaVu Sans Mono"
_LINE = 0.0175          # text line height, fraction of the page height
_TOP, _BOTTOM, _LEFT = 0.93, 0.06, 0.045
_WIDTH = 150            # characters of a text line in the monospaced font
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
# Text pages: headings, tables and paragraphs flowed over A4 pages in a monospaced font.

@dataclass(frozen=True, slots=True)
class _Line:
    text: str
    weight: str = "normal"
    size: float = 8.0
    family: str = _MONO


class _Flow:
    """Lines of text flowed onto A4 pages, each page with the record's footer."""

    def __init__(self) -> None:
        self.lines: list[_Line] = []

    def heading(self, text: str) -> None:
        if self.lines:
            self.lines.append(_Line(""))
        for line in textwrap.wrap(text, 110):
            self.lines.append(_Line(line, "bold", 10.5, "DejaVu Sans"))

    def paragraph(self, text: str) -> None:
        for line in textwrap.wrap(text, _WIDTH) or [""]:
            self.lines.append(_Line(line))

    def table(self, header: Sequence[str], rows: Sequence[Sequence[str]], scale_columns: bool = False) -> None:
        """A table: columns as wide as their widest cell, numbers right-aligned, text left-aligned."""
        cells = [list(header)] + [list(r) for r in rows]
        widths = [max(len(r[c]) for r in cells) for c in range(len(header))]
        numeric = [all(_numeric(r[c]) for r in cells[1:]) and len(cells) > 1 for c in range(len(header))]

        def line(r: Sequence[str]) -> str:
            return "  ".join(v.rjust(w) if n else v.ljust(w) for v, w, n in zip(r, widths, numeric, strict=True))

        self.lines.append(_Line(line(header), "bold"))
        self.lines.append(_Line("  ".join("-" * w for w in widths)))
        for r in cells[1:]:
            text = line(r)
            while len(text) > _WIDTH:
                self.lines.append(_Line(text[:_WIDTH]))
                text = "    " + text[_WIDTH:]
            self.lines.append(_Line(text))

    def pages(self, first_top: float = _TOP) -> list[list[_Line]]:
        per_page = int((_TOP - _BOTTOM) / _LINE)
        first = int((first_top - _BOTTOM) / _LINE)
        out: list[list[_Line]] = []
        rest = self.lines
        take = first
        while rest:
            out.append(rest[:take])
            rest = rest[take:]
            take = per_page
        return out


def _numeric(text: str) -> bool:
    try:
        float(text.split(" ")[0])
    except ValueError:
        return text in ("-", "")
    return True


def _draw_lines(fig: Figure, lines: Iterable[_Line], top: float) -> None:
    y = top
    for ln in lines:
        fig.text(_LEFT, y, ln.text, family=ln.family, size=ln.size, weight=ln.weight, va="top", ha="left")
        y -= _LINE if ln.size <= 8.0 else _LINE * 1.35


def _footer(fig: Figure, record: DesignRecord, page: int) -> None:
    fig.text(_LEFT, 0.025, f"{record.name}  ·  {record.created}  ·  mechsynth {record.version}  ·  request "
             f"SHA-256 {record.request_sha256[:16]}…", size=7, color="0.35", family="DejaVu Sans")
    fig.text(1 - _LEFT, 0.025, f"page {page}", size=7, color="0.35", ha="right", family="DejaVu Sans")


# ---------------------------------------------------------------------------------------------------------------
# The record's content.

def _verdict(d: MachineDesign) -> str:
    if d.passed:
        return "every check met"
    return "FAILS: " + ", ".join(c.name for c in d.checks if not c.passed)


def _title_block(fig: Figure, record: DesignRecord, d: MachineDesign) -> float:
    """Draw the title block; the height below which text may follow (fraction of the page)."""
    fig.text(_LEFT, 0.95, "Machine design record", size=17, weight="bold", va="top", family="DejaVu Sans")
    rows = [("name", record.name), ("date", record.created), ("service version", f"mechsynth {record.version}"),
            ("request SHA-256", record.request_sha256), ("result", _verdict(d))]
    y = 0.89
    for key, value in rows:
        fig.text(_LEFT, y, key, size=9, weight="bold", va="top", family="DejaVu Sans")
        fig.text(_LEFT + 0.16, y, value, size=9, va="top", family=_MONO)
        y -= 0.027
    fig.add_artist(Line2D([_LEFT, 1 - _LEFT], [y + 0.006, y + 0.006], color="0.3", lw=0.8,
                          transform=fig.transFigure))
    return y - 0.01


def _key_figures(d: MachineDesign) -> list[list[str]]:
    motor, body = d.drive.motor, d.placement
    return [
        ["mechanism", type(d.spec.linkage.mechanism).__name__],
        ["working speed", f"{num(d.spec.speed / RPM)} rpm"],
        ["mean crank power", f"{num(d.output_power)} W"],
        ["motor", f"{motor.name}: {num(motor.rated_power)} W, {num(motor.rated_speed / RPM)} rpm rated, runs at "
                  f"{num(d.drive.shafts[0].speed / RPM)} rpm under the mean load"],
        ["train ratio (teeth)", f"{num(d.train_ratio, digits=5)} = "
                                + " × ".join(num(u, digits=5) for u in d.stage_ratios)],
        ["balancing", d.balancing.mode],
        ["flywheel", "none needed" if body is None else
         f"{num(body.inertia)} kg·m² on the {body.shaft} shaft ({num(d.flywheel_inertia)} kg·m² "
         f"crank-equivalent), {body.shape}, outer diameter {num(body.outer_diameter)} m, {num(body.mass)} kg"],
        ["simulated delta", f"{num(d.motion.delta)} (target {num(d.spec.delta)})"],
        ["simulated mean crank speed", f"{num(d.motion.mean_speed / RPM)} rpm"],
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


def _inputs(flow: _Flow, record: DesignRecord) -> None:
    flow.heading("Inputs: the request as received, defaults included")
    flow.table(["field", "value", "unit"], [list(r) for r in input_rows(record.request)])


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


def _record_pages(save: Callable[[Figure], None], record: DesignRecord, d: MachineDesign,
                  alternatives: Sequence[Alternative]) -> int:
    """The text pages; returns the number of pages written."""
    flow = _Flow()
    flow.heading("Design")
    flow.table(["quantity", "value"], _key_figures(d))
    flow.heading("Checks against the simulated machine")
    flow.table(["check", "value", "limit", "met", "what it compares"],
               [[c.name, num(c.value, c.limit), num(c.limit), "yes" if c.passed else "NO", c.detail]
                for c in d.checks])
    flow.heading(f"Warnings ({len(d.warnings)})")
    if d.warnings:
        for w in d.warnings:
            flow.paragraph(f"[{w.stage or '-'}] {w.code}" + (f" ({w.field})" if w.field else "") + f": {w.message}")
    else:
        flow.paragraph("none")
    _inputs(flow, record)
    flow.heading("Stages and their check figures")
    flow.table(["stage", "result", "check", "check figure"], _stage_rows(d))
    flow.heading("Counterweights")
    flow.paragraph("Radius and angle in the link frame (origin at the link's first joint, x toward its second); "
                   "each realised as a steel disc of its own inertia, or as thick as its radius when that inertia "
                   "is smaller.")
    cw = _counterweight_rows(d)
    if cw:
        flow.table(["link", "mass [kg]", "radius [m]", "angle [deg]", "own inertia [kg·m²]",
                    "steel disc diameter [m]", "disc thickness [m]"], cw)
    else:
        flow.paragraph("none")
    flow.heading("Gear train, motor side first")
    flow.table([h for h, _ in GEAR_COLUMNS],
               [[cell(d, k) for _, cell in GEAR_COLUMNS] for k in range(len(d.spec.drive.stages))])
    flow.heading("Gears sized for strength")
    flow.paragraph(_sizing_paragraph(d))
    if d.gears is not None:
        flow.table([h for h, _ in STRENGTH_COLUMNS],
                   [[cell(d, k) for _, cell in STRENGTH_COLUMNS] for k in range(len(d.spec.drive.stages))])
    flow.heading("Flywheel")
    flow.table(["quantity", "value"], _flywheel_rows(d))
    flow.heading("Motor")
    flow.table(["quantity", "value"], _motor_rows(d))
    flow.heading("Shafts in the simulated steady motion (the torque each passes on)")
    peak = max((s.peak_torque for s in d.shafts), default=0.0)
    flow.table(["shaft", "speed [rpm]", "power [W]", "mean T [N·m]", "peak T [N·m]", "RMS T [N·m]",
                "inertia [kg·m²]", "flywheel"],
               [[s.name, num(s.mean_speed / RPM), num(s.mean_power, d.output_power), num(s.mean_torque, peak),
                 num(s.peak_torque, peak), num(s.rms_torque, peak), num(s.inertia), "yes" if s.carries_flywheel
                 else ""] for s in d.shafts])
    if alternatives:
        flow.heading("What each balancing choice costs")
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
        flow.table(["mode", "RMS force [N]", "RMS moment [N·m]", "flywheel, crank-eq. [kg·m²]",
                    "flywheel mass [kg]", "motor", "passed"], rows)
        for a in alternatives:
            if a.design is None:
                flow.paragraph(f"{a.mode}: {a.reason}")
    pages = 0
    for i, lines in enumerate(flow.pages(first_top=0.72)):
        fig = plt.figure(figsize=A4)
        top = _TOP
        if i == 0:
            top = _title_block(fig, record, d)
        _draw_lines(fig, lines, top)
        pages += 1
        _footer(fig, record, pages)
        save(fig)
        plt.close(fig)
    return pages


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
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    return fig


def design_summary_png(design: MachineDesign) -> bytes:
    """One page: the mechanism, driving torque, simulated speed, shaking force, motor torque, key figures [PNG]."""
    return figure_png(_summary_figure(design), dpi=90)


def design_report_pdf(design: MachineDesign, alternatives: Sequence[Alternative] = (),
                      record: DesignRecord | None = None) -> bytes:
    """The design record [PDF, A4 landscape]: title block and verdict, key figures, checks, warnings, every
    input with its unit, each stage with its check figure, counterweights, gear train, flywheel, motor and
    shafts, the alternatives; then the diagrams (summary, balancing, flywheel and motor, start-up and run-down).

    ``record`` names the design and holds the request; without one the report says so and lists no inputs.
    """
    d = design
    record = record or DesignRecord("machine design", "-", "-", {}, "not given")
    buf = io.BytesIO()
    with plt.rc_context(_STYLE), PdfPages(buf, metadata={"Title": f"Machine design record: {record.name}",
                                                         "Subject": f"request SHA-256 {record.request_sha256}",
                                                         "Creator": f"mechsynth {record.version}"}) as pdf:
        page = _record_pages(pdf.savefig, record, d, alternatives)
        figures = [_summary_figure(d)]
        fig, axes = plt.subplots(1, 3, figsize=A4)
        _polar(axes[0], d)
        _moment(axes[1], d)
        _torque(axes[2], d)
        fig.suptitle("balancing")
        fig.tight_layout(rect=(0, 0.03, 1, 1))
        figures.append(fig)
        fig, axes = plt.subplots(1, 3, figsize=A4)
        _energy_mass(axes[0], d)
        _speed(axes[1], d)
        _motor(axes[2], d)
        fig.suptitle("flywheel and motor")
        fig.tight_layout(rect=(0, 0.03, 1, 1))
        figures.append(fig)
        if (running := running_figure(d)) is not None:
            figures.append(running)
        for fig in figures:
            page += 1
            _footer(fig, record, page)
            pdf.savefig(fig)
            plt.close(fig)
    return buf.getvalue()
