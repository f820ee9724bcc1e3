"""The design record of an optimised machine: the chosen machine's record with a page for the certificate."""

from __future__ import annotations

import io
import math

import pytest
from pypdf import PdfReader

import synth
from synth.machine.optimise import score
from synth.machine.optimise_record import coverage_figure

from api.translate.optimise import machine_optimise_from
from mechsynth_client import SynthClient
from mechsynth_client.schemas.optimise import (
    CRANK_ROCKER_OPTIMISE_EXAMPLE,
    QUICK_SCAN,
    MachineOptimiseIn,
)
from tests.test_machine_optimise import _machine_request


def test_the_record_has_a_page_for_the_certificate(client: SynthClient) -> None:
    body = MachineOptimiseIn.model_validate({**CRANK_ROCKER_OPTIMISE_EXAMPLE, **QUICK_SCAN})
    pdf = PdfReader(io.BytesIO(client.optimisation_record_pdf(body)))
    answer = client.optimise_machine(body)
    # the chosen machine's own record, as /v1/machines/design writes it, comes first
    alone = PdfReader(io.BytesIO(client.design_report_pdf(_machine_request(
        {**CRANK_ROCKER_OPTIMISE_EXAMPLE, **QUICK_SCAN}, answer.mechanism))))
    assert len(pdf.pages) == len(alone.pages) + 2
    last = " ".join((pdf.pages[-2].extract_text() or "").split())
    assert "Optimisation certificate" in last
    assert f"u = {answer.parameter:.6g}" in last
    # the certificate's own statement and the gains are on the page
    assert " ".join(answer.certificate.statement.split())[:60] in last
    for g in answer.gains:
        assert g.objective in last


def test_the_coverage_figure_draws_the_answers_members_and_cells() -> None:
    # the figure's data are the optimisation's own: every feasible member at its parameter and score, the
    # optimum's star, one bound line per cell with a finite bound
    spec = machine_optimise_from(MachineOptimiseIn.model_validate({**CRANK_ROCKER_OPTIMISE_EXAMPLE, **QUICK_SCAN}), 6)
    opt = synth.optimise_machine(spec)
    ax = coverage_figure(opt).axes[0]
    lines = {str(line.get_label()): line for line in ax.get_lines()}
    s = [score(spec, m.values, opt.normalisers) for m in opt.members
         if m.feasible and m.values is not None and m.stage == "scan"]
    scanned = lines["scanned member"]
    assert sorted(scanned.get_ydata()) == pytest.approx(sorted(s), rel=1e-12)
    star = lines["optimum"]
    assert (star.get_xdata()[0], star.get_ydata()[0]) == (opt.parameter, opt.score)
    bounds = [line for line in ax.get_lines() if str(line.get_label()).startswith("_") and len(line.get_xdata()) == 2]
    assert len(bounds) == sum(math.isfinite(r.bound) for r in opt.certificate.refinements)
