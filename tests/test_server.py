"""The README's run command starts a real server, and every example of README.md and docs/ prints what it says
against it."""

from __future__ import annotations

import os
import re
import signal
import socket
import shutil
import subprocess
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

import doc_blocks
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.analysis import AnalysisIn

REPO = Path(__file__).resolve().parents[1]
README = (REPO / "README.md").read_text()


def _run_command() -> list[str]:
    match = re.search(r"^(make run)\b", README, flags=re.M)
    assert match, "the README must show `make run`"
    return match.group(1).split()


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.fixture(scope="module")
def server_url() -> Iterator[str]:
    port = _free_port()
    scratch = tempfile.mkdtemp(prefix="synth-server-")
    env = {**os.environ, "SYNTH_STUDIES_DB": os.path.join(scratch, "studies.sqlite")}
    proc = subprocess.Popen(
        [*_run_command(), f"PORT={port}"], cwd=REPO, start_new_session=True, env=env,
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
    )
    url = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + 120
        while True:
            try:
                if httpx.get(f"{url}/health", timeout=1).status_code == 200:
                    break
            except httpx.TransportError:
                pass
            if proc.poll() is not None or time.monotonic() > deadline:
                err = proc.stderr.read().decode() if proc.stderr else ""
                pytest.fail(f"server did not start with {' '.join(_run_command())}: {err[-2000:]}")
            time.sleep(0.3)
        yield url
    finally:
        os.killpg(proc.pid, signal.SIGTERM)
        proc.wait(timeout=30)
        if proc.stderr:
            proc.stderr.close()
        shutil.rmtree(scratch, ignore_errors=True)


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
