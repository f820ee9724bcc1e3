"""The design record of an optimised machine: the chosen machine's record with a page for the certificate."""

from __future__ import annotations

import io

from pypdf import PdfReader

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
    assert len(pdf.pages) == len(alone.pages) + 1
    last = " ".join((pdf.pages[-1].extract_text() or "").split())
    assert "Optimisation certificate" in last
    assert f"u = {answer.parameter:.6g}" in last
    # the certificate's own statement and the gains are on the page
    assert " ".join(answer.certificate.statement.split())[:60] in last
    for g in answer.gains:
        assert g.objective in last
