"""The Dockerfile and CI run the README's own commands, so the server test covers them."""

from __future__ import annotations

import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def test_dockerfile_uses_the_readme_commands() -> None:
    docker = (REPO / "Dockerfile").read_text()
    readme = (REPO / "README.md").read_text()
    assert "make run" in readme and "make test" in readme
    # Install: the same Makefile target that `make run` depends on; start: `make run` itself.
    assert re.search(r"^RUN make \.venv/\.installed$", docker, flags=re.M)
    assert re.search(r'^CMD \["make", "run"', docker, flags=re.M)
    assert re.search(r"^USER (?!root)\w+", docker, flags=re.M)
    assert "EXPOSE 8000" in docker and "HEALTHCHECK" in docker and "/health" in docker
    makefile = (REPO / "Makefile").read_text()
    assert re.search(r"^run: \$\(STAMP\)$", makefile, flags=re.M) and "STAMP := $(VENV)/.installed" in makefile


def test_ci_runs_the_readme_test_command() -> None:
    assert "make test" in (REPO / ".ci" / "run").read_text()
