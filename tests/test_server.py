"""The README's run command starts a real server, and every example of README.md and docs/ prints what it says
against it."""

from __future__ import annotations

import re
import subprocess
import sys
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


# The installed client alone: the engine, numpy and the service cannot be imported, whoever asks.
_WHEEL_ONLY = """
import importlib.abc, sys
class _Refuse(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in ("synth", "numpy", "api"):
            raise ImportError(f"the client imported {name}")
sys.meta_path.insert(0, _Refuse())
import mechsynth_client
assert mechsynth_client.__file__.startswith(sys.argv[1]), mechsynth_client.__file__
"""


def test_client_wheel_alone_runs_the_readme_example(server_url: str, tmp_path: Path) -> None:
    # The client's distribution built and installed as a user would, on its own: the README's first example runs
    # against the server and prints what the README says.
    pip = [sys.executable, "-m", "pip", "--quiet"]
    subprocess.run([*pip, "wheel", "--no-deps", "--no-build-isolation", "--wheel-dir", str(tmp_path / "dist"),
                    str(REPO / "client")], check=True)
    (wheel,) = (tmp_path / "dist").glob("mechsynth_client-*.whl")
    site = tmp_path / "site"
    subprocess.run([*pip, "install", "--no-deps", "--target", str(site), str(wheel)], check=True)
    block = next(b for b in doc_blocks.blocks() if b.path.name == "README.md" and b.language == "python")
    code = _WHEEL_ONLY + block.code.replace(doc_blocks.ADDRESS, server_url)
    run = subprocess.run([sys.executable, "-c", code, str(site)], cwd=tmp_path, capture_output=True, text=True,
                         env={"PYTHONPATH": str(site), "PATH": "/usr/bin:/bin"}, timeout=300)
    assert run.returncode == 0, run.stderr[-3000:]
    printed = [line.rstrip() for line in run.stdout.splitlines()]
    assert block.expected() and doc_blocks.mismatch(block.expected(), printed) is None, printed


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
