"""The engine's public surface is documented and free of web code."""

from __future__ import annotations

import subprocess
import sys

import synth


def test_public_names_have_docstrings() -> None:
    assert all(getattr(synth, name).__doc__ for name in synth.__all__)


def test_engine_imports_no_web_code() -> None:
    probe = "import sys, synth; assert not {'fastapi', 'httpx', 'pydantic', 'starlette'} & set(sys.modules)"
    subprocess.run([sys.executable, "-c", probe], check=True)
