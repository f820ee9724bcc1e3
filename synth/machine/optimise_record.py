"""The design record of an optimised machine: the chosen machine's record with a page for the certificate.

The chosen machine's record is :func:`design_report_pdf` of its design (title block, inputs of the optimisation,
every stage, the drawings and diagrams). A page follows it with what the optimisation claims and how it covered
the family: the gains over the chain's machine in every objective, the certificate's statement and counts, the
cells and the Pareto set; and a figure of the coverage: every member designed with its score along the family's
parameter, each cell as a band of its status at its bound.
"""

from __future__ import annotations

import io
import math
from xml.sax.saxutils import escape

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from pypdf import PdfReader, PdfWriter
from reportlab.lib.pagesizes import A4, landscape
from reportlab.lib.styles import getSampleStyleSheet
from reportlab.lib.units import mm
from reportlab.platypus import Paragraph, SimpleDocTemplate, Spacer, Table, TableStyle

from .optimise import BOUNDED, OBJECTIVES, OBJECTIVE_UNITS, MachineOptimum, _scores, score
from .record import DesignRecord
from .report import design_report_pdf


def _num(v: float | None, digits: int = 5) -> str:
    return "-" if v is None or not math.isfinite(v) else f"{v:.{digits}g}"


def certificate_page(opt: MachineOptimum, record: DesignRecord) -> bytes:
    """The certificate's page [PDF, A4 landscape]."""
    styles = getSampleStyleSheet()
    body, head = styles["BodyText"], styles["Heading2"]
    buf = io.BytesIO()
    doc = SimpleDocTemplate(buf, pagesize=landscape(A4), leftMargin=15 * mm, rightMargin=15 * mm,
                            topMargin=12 * mm, bottomMargin=12 * mm, title="Optimisation certificate")
    grid = TableStyle([("GRID", (0, 0), (-1, -1), 0.4, (0.6, 0.6, 0.6)), ("FONTSIZE", (0, 0), (-1, -1), 8),
                       ("BACKGROUND", (0, 0), (-1, 0), (0.9, 0.9, 0.9))])
    c = opt.certificate
    gains = [["objective", "unit", "chain's machine", "optimum", "gain", "relative"]]
    gains += [[g.objective, g.unit, _num(g.chain), _num(g.optimum), _num(g.gain), _num(g.relative, 3)]
              for g in opt.gains]
    counts = {k: sum(r.status == k for r in c.refinements) for k in ("searched", "pruned", "unsearched")}
    cover = [["kinematic members", "feasible", "runs", "members designed", "feasible designed", "cells",
              "searched", "pruned", "unsearched", "gap bound"],
             [str(c.scan.grid_points), str(c.scan.feasible_points), str(len(c.scan.runs)), str(c.members_designed),
              str(c.feasible_designed), str(len(c.refinements)), str(counts["searched"]), str(counts["pruned"]),
              str(counts["unsearched"]), "none claimed" if c.gap_bound is None else _num(c.gap_bound)]]
    a, b = (OBJECTIVES.index(n) for n in opt.pareto_objectives)
    pareto = [["parameter u", f"{opt.pareto_objectives[0]} [{OBJECTIVE_UNITS[a]}]",
               f"{opt.pareto_objectives[1]} [{OBJECTIVE_UNITS[b]}]", "stage"]]
    pareto += [[_num(m.parameter, 6), _num(m.values[a] if m.values else None),
                _num(m.values[b] if m.values else None), m.stage] for m in opt.pareto]
    weights = ", ".join(f"{k} {v:g}" for k, v in opt.spec.weights.items() if v > 0)
    story = [
        Paragraph(escape(f"Optimisation certificate: {record.name}"), head),
        Paragraph(escape(f"The machine of this record was chosen from its function by POST /v1/machines/optimise: "
                         f"family member u = {opt.parameter:.6g}, score {opt.score:.5g} (weights: {weights}); "
                         f"request SHA-256 {record.request_sha256}."), body),
        Spacer(1, 3 * mm), Table(gains, style=grid, hAlign="LEFT"), Spacer(1, 3 * mm),
        Paragraph(escape(c.statement), body), Spacer(1, 3 * mm),
        Table(cover, style=grid, hAlign="LEFT"), Spacer(1, 3 * mm),
        Paragraph(escape("Binding at the answer: " + (", ".join(c.binding) or "nothing within 2 % of its limit")),
                  body),
        Spacer(1, 3 * mm), Paragraph(escape("The Pareto set over every member designed:"), body),
        Table(pareto[:30], style=grid, hAlign="LEFT"),
    ]
    doc.build(story)
    return buf.getvalue()


#: Colours of the cells by status.
CELL_COLOURS = {"searched": "#2e7d32", "pruned": "#9e9e9e", "unsearched": "#ef6c00"}


def coverage_figure(opt: MachineOptimum) -> Figure:
    """The family as the optimisation covered it: each member designed at its parameter u with its score (scanned,
    searched, refused or failing a check), the cells between scanned members as bands coloured by status with their
    bound drawn across them, the chain's member and the optimum."""
    fig = Figure(figsize=(11.69, 8.27))
    ax = fig.add_axes((0.08, 0.12, 0.88, 0.76))
    c = opt.certificate
    members = list(opt.members)
    s = _scores(opt.spec, members, opt.normalisers)
    ok = np.isfinite(s)
    u = np.array([m.parameter for m in members])
    scanned = np.array([m.stage == "scan" for m in members])
    bounded = np.array([m.stage == BOUNDED for m in members])
    # a bounded member is drawn at its bound: its score is at least that
    floors = np.array([score(opt.spec, m.floor_values, opt.normalisers) if m.floor_values is not None else np.nan
                       for m in members])
    shown = ([float(v) for v in s[ok]] + [r.bound for r in c.refinements if math.isfinite(r.bound)]
             + [float(v) for v in floors[bounded] if np.isfinite(v)])
    lo, hi = (min(shown), max(shown)) if shown else (0.0, 1.0)
    pad = 0.05 * (hi - lo or abs(hi) or 1.0)
    top = hi + 3 * pad
    for r in c.refinements:
        colour = CELL_COLOURS.get(r.status, "#9e9e9e")
        ax.axvspan(r.lo, r.hi, color=colour, alpha=0.12 if r.status == "pruned" else 0.25, lw=0)
        if math.isfinite(r.bound):
            ax.plot([r.lo, r.hi], [r.bound, r.bound], color=colour, lw=1.5)
    ax.plot(u[ok & scanned], s[ok & scanned], "o", ms=4, color="#1565c0", label="scanned member")
    ax.plot(u[ok & ~scanned], s[ok & ~scanned], "x", ms=4, color="#6a1b9a", label="member of a searched cell")
    if bounded.any():
        ax.plot(u[bounded], floors[bounded], "^", ms=4, mfc="none", color="#757575",
                label="bounded, not designed further (drawn at its bound)")
    if (~ok & ~bounded).any():
        ax.plot(u[~ok & ~bounded], np.full(int((~ok & ~bounded).sum()), top), "v", ms=5, color="#c62828",
                label="refused or failing a check (drawn at the top)")
    if opt.chain_score is not None:
        ax.plot([opt.chain.parameter], [opt.chain_score], "D", ms=8, mfc="none", mec="black", label="chain's member")
    ax.plot([opt.parameter], [opt.score], "*", ms=16, color="#f9a825", mec="black", label="optimum")
    for status, colour in CELL_COLOURS.items():
        n = sum(r.status == status for r in c.refinements)
        ax.plot([], [], color=colour, lw=6, alpha=0.5, label=f"{status} cells ({n}), bound as a line")
    ax.set_ylim(lo - pad, top + pad)
    ax.set_xlabel("family parameter u [-]")
    ax.set_ylabel("score (weighted objectives over the chain's) [-]")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left", fontsize=8, ncols=2)
    fig.suptitle(f"How the family was covered: {c.members_designed} members designed, {len(c.refinements)} cells; "
                 f"optimum u = {opt.parameter:.6g}, score {opt.score:.5g}", fontsize=11)
    return fig


def optimisation_record_pdf(opt: MachineOptimum, record: DesignRecord) -> bytes:
    """The chosen machine's design record with the certificate's page and the coverage figure after it [PDF]."""
    out = PdfWriter(clone_from=PdfReader(io.BytesIO(design_report_pdf(opt.design, record=record))))
    out.append(PdfReader(io.BytesIO(certificate_page(opt, record))))
    figure = io.BytesIO()
    coverage_figure(opt).savefig(figure, format="pdf")
    out.append(PdfReader(figure))
    buf = io.BytesIO()
    out.write(buf)
    return buf.getvalue()
