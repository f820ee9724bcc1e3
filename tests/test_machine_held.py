"""The machine's record written from the design the service already made: ?format=pdf (and png) of a request the
service has just designed reuses that design instead of running the chain again, and its numbers are the held
answer's; the results held are few, the least recently used dropped first, each user's apart."""

from __future__ import annotations

import io
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient
from pypdf import PdfReader

from api.app import create_app
from api.execution import plans
from api.execution.held import HELD_RESULTS, HeldResults
from api.settings import Settings
from test_machine_record import FOURBAR_MACHINE


@pytest.fixture
def counted(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[tuple[TestClient, list[int]]]:
    """An app in this process (solver work on its one thread) whose machine designs are counted."""
    calls: list[int] = []
    real = plans.design_machine

    def design_machine(*args: Any, **kwargs: Any) -> Any:
        calls.append(1)
        return real(*args, **kwargs)

    monkeypatch.setattr(plans, "design_machine", design_machine)
    settings = Settings(executor="serial", studies_db=str(tmp_path / "s.sqlite"))
    with TestClient(create_app(settings), base_url="http://localhost") as c:
        yield c, calls


def _number(text: str, label: str) -> float:
    found = re.search(rf"{re.escape(label)}\s+(-?[\d.]+(?:e[-+]?\d+)?)", text)
    assert found, label
    return float(found.group(1))


def test_the_record_of_the_design_just_made_is_written_from_it(counted: tuple[TestClient, list[int]]) -> None:
    c, calls = counted
    answer = c.post("/v1/machines/design", json=FOURBAR_MACHINE)
    assert answer.status_code == 200, answer.text
    assert len(calls) == 1
    design = answer.json()
    # the same request as a record, its title block added (not part of the design's identity): no second design
    titled = {**FOURBAR_MACHINE, "title_block": {"project": "Press line 4", "number": "MD-0042"}}
    pdf = c.post("/v1/machines/design?format=pdf", json=titled)
    assert pdf.status_code == 200 and pdf.headers["content-type"] == "application/pdf"
    assert len(calls) == 1
    text = "\n".join(p.extract_text() for p in PdfReader(io.BytesIO(pdf.content)).pages)
    assert "Press line 4" in text and design["request_sha256"] in text
    # the record's figures are the held answer's (the record prints four significant digits)
    checks = {ch["name"]: ch for ch in design["checks"]}
    assert _number(text, "motor torque, RMS (heating)") == pytest.approx(checks["motor_rms_torque"]["value"], rel=5e-4)
    assert _number(text, "motor torque, peak") == pytest.approx(checks["motor_peak_torque"]["value"], rel=5e-4)
    assert design["motor"]["motor"]["name"] in text
    # the summary figure too; another request is designed anew
    assert c.post("/v1/machines/design?format=png", json=FOURBAR_MACHINE).headers["content-type"] == "image/png"
    assert len(calls) == 1
    other = c.post("/v1/machines/design?format=pdf", json={**FOURBAR_MACHINE, "speed_rpm": 290})
    assert other.status_code == 200 and len(calls) == 2
    # a JSON answer is always designed anew (its time is the design's), and the same numbers come back
    again = c.post("/v1/machines/design", json=FOURBAR_MACHINE)
    assert again.status_code == 200 and len(calls) == 3
    assert again.json()["checks"] == design["checks"]


def test_few_results_are_held_and_the_least_recently_used_goes_first() -> None:
    held = HeldResults()
    for n in range(HELD_RESULTS):
        held.put(("", f"request {n}"), n)
    assert held.get(("", "request 0")) == 0            # now the most recently used
    held.put(("", "one more"), -1)
    assert len(held) == HELD_RESULTS
    assert held.get(("", "request 1")) is None         # the least recently used went
    assert held.get(("", "request 0")) == 0 and held.get(("", "one more")) == -1
    # a user's design is never another user's: the key holds who asked
    assert held.get(("7", "request 0")) is None
