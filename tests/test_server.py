"""The README's run command starts a real server, and the README's Python example works against it."""

from __future__ import annotations

import os
import re
import signal
import socket
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

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
    proc = subprocess.Popen(
        [*_run_command(), f"PORT={port}"], cwd=REPO, start_new_session=True,
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


def test_client_against_real_server(server_url: str) -> None:
    with SynthClient(server_url) as client:
        assert client.health() == {"status": "ok"}
        example = AnalysisIn.model_config["json_schema_extra"]["examples"][0]  # type: ignore[index]
        out = client.analysis(AnalysisIn.model_validate(example))
        assert out.checks.virtual_power_torque_max_diff_Nm < 1e-9 * (1 + out.summary.max_driving_torque_Nm)
        assert client.analysis_png(AnalysisIn.model_validate(example))[:4] == b"\x89PNG"


def test_readme_python_example_runs(server_url: str) -> None:
    blocks = re.findall(r"```python\n(.*?)```", README, flags=re.S)
    assert blocks, "the README has a Python example"
    for code in blocks:
        code = code.replace("http://127.0.0.1:8000", server_url)
        namespace: dict[str, object] = {}
        exec(compile(code, "README.md", "exec"), namespace)  # noqa: S102
