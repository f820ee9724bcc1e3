"""The Dockerfile and CI run the README's own commands, so the server test covers them."""

from __future__ import annotations

import os
import re
import subprocess
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


def test_docker_image_installs_no_test_tools() -> None:
    # The image sets EXTRAS empty before the install target; make, given that environment, must install the
    # package without its test extra (dry run: the commands make would run, nothing installed).
    docker = (REPO / "Dockerfile").read_text()
    env_line = docker.index('ENV EXTRAS=""')
    assert env_line < docker.index("RUN make .venv/.installed")
    def dry_run(env: dict[str, str]) -> str:
        return subprocess.run(["make", "-n", "-B", ".venv/.installed"], cwd=REPO, capture_output=True, text=True,
                              check=True, env=env).stdout
    image = dry_run({**os.environ, "EXTRAS": ""})
    assert "pip install --quiet -e '.'" in image and "[test]" not in image
    # a developer's checkout still gets them
    plain = dry_run({k: v for k, v in os.environ.items() if k != "EXTRAS"})
    assert "pip install --quiet -e '.[test]'" in plain


def test_the_image_keeps_its_store_on_a_volume_the_service_user_owns() -> None:
    docker = (REPO / "Dockerfile").read_text()
    user = re.search(r"^USER (\w+)$", docker, flags=re.M)
    assert user is not None
    # /app and the store's directory belong to the user the service runs as, made before it takes over
    assert re.search(rf"chown {user[1]}:{user[1]} /app /data", docker)
    assert f"COPY --chown={user[1]}:{user[1]} . /app" in docker
    store = re.search(r"SYNTH_STUDIES_DB=(\S+)", docker)
    volume = re.search(r'^VOLUME \["(\S+)"\]$', docker, flags=re.M)
    assert store is not None and volume is not None and store[1].startswith(volume[1] + "/")
    # the run command the deployment page gives mounts a named volume there
    deployment = (REPO / "docs" / "deployment.md").read_text()
    assert f"-v mechsynth-data:{volume[1]} mechsynth" in deployment
