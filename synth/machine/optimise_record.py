"""The design record of an optimised machine: the chosen machine's record with a page for the certificate.

The chosen machine's record is :func:`design_report_pdf` of its design (title block, inputs of the optimisation,
every stage, the drawings and diagrams). A page follows it with what the optimisation claims and how it covered
the family: the gains over the chain's machine in every objective, the certificate's statement and counts, the
cells and the Pareto set.
"""

from __future__ import annotations

import io
import math
from xml.sax.saxutils import escape

from pypdf import PdfReader, PdfWriter
from reportlab.lib.pagesizes import A4, landscape
from reportlab.lib.styles import getSampleStyleSheet
from reportlab.lib.units import mm
from reportlab.platypus import Paragraph, SimpleDocTemplate, Spacer, Table, TableStyle

from .optimise import OBJECTIVES, OBJECTIVE_UNITS, MachineOptimum
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


def optimisation_record_pdf(opt: MachineOptimum, record: DesignRecord) -> bytes:
    """The chosen machine's design record with the certificate's page after it [PDF]."""
    out = PdfWriter(clone_from=PdfReader(io.BytesIO(design_report_pdf(opt.design, record=record))))
    out.append(PdfReader(io.BytesIO(certificate_page(opt, record))))
    buf = io.BytesIO()
    out.write(buf)
    return buf.getvalue()
