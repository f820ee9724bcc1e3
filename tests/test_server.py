"""The README's run command starts a real server, and every example of README.md and docs/ prints what it says
against it."""

from __future__ import annotations

import re
from collections.abc import Iterator
from pathlib import Path

import pytest

import doc_blocks
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.analysis import AnalysisIn
from service import running_service

REPO = Path(__file__).resolve().parents[1]
README = (REPO / "README.md").read_text()


def _run_command() -> list[str]:
    match = re.search(r"^(make run)\b", README, flags=re.M)
    assert match, "the README must show `make run`"
    return match.group(1).split()


@pytest.fixture(scope="module")
def server_url(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    with running_service(lambda port: [*_run_command(), f"PORT={port}"], tmp_path_factory.mktemp("studies")) as url:
        yield url


def test_client_against_real_server(server_url: str) -> None:
    with SynthClient(server_url) as client:
        assert client.health() == {"status": "ok"}
        example = AnalysisIn.model_config["json_schema_extra"]["examples"][0]  # type: ignore[index]
        out = client.analysis(AnalysisIn.model_validate(example))
        assert out.checks.virtual_power_torque_max_diff_Nm < 1e-9 * (1 + out.summary.max_driving_torque_Nm)
        assert client.analysis_png(AnalysisIn.model_validate(example))[:4] == b"\x89PNG"


@pytest.mark.parametrize("block", [b for b in doc_blocks.blocks() if b.runnable], ids=lambda b: b.name)
def test_documented_example_prints_what_it_says(server_url: str, block: doc_blocks.Block) -> None:
    # The stated output is the comment lines of the example itself (README.md and docs/*.md), compared with what
    # the running service answers now, numbers to the rounding a reader sees (doc_blocks.REL_TOL).
    printed = doc_blocks.run(block, server_url)
    why = doc_blocks.mismatch(block.expected(), printed) if block.expected() else None
    assert why is None, f"{block.name}: {why}"


def test_every_page_has_stated_output() -> None:
    # A page whose examples state nothing could drift unseen: each page states what at least one example prints.
    pages = {b.path for b in doc_blocks.blocks() if b.runnable}
    stated = {b.path for b in doc_blocks.blocks() if b.runnable and b.expected()}
    assert pages == stated, sorted(p.name for p in pages - stated)
