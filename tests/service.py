"""A real service on a free loopback port for the tests that need one (the README's command, the workbench)."""

from __future__ import annotations

import collections
import os
import signal
import socket
import subprocess
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

import httpx
import pytest

REPO = Path(__file__).resolve().parents[1]


def free_port() -> int:
    """A loopback port nothing listens on now."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@contextmanager
def running_service(command: Callable[[int], list[str]], studies_dir: Path,
                    start_timeout_s: float = 120) -> Iterator[str]:
    """Start ``command(port)`` in the repository with its study store in ``studies_dir``; yield its base URL once
    ``/health`` answers, and stop the whole process group afterwards."""
    with running_process(command, studies_dir, start_timeout_s) as (url, _):
        yield url


@contextmanager
def running_process(command: Callable[[int], list[str]], studies_dir: Path, start_timeout_s: float = 120,
                    env: dict[str, str] | None = None) -> Iterator[tuple[str, subprocess.Popen[bytes]]]:
    """:func:`running_service` that also yields the process (to kill it) and takes more environment."""
    port = free_port()
    env = {**os.environ, "SYNTH_STUDIES_DB": str(studies_dir / "studies.sqlite"), **(env or {})}
    proc = subprocess.Popen(command(port), cwd=REPO, env=env, start_new_session=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    # the server's log is read as it comes (a full pipe would stop a server that logs much, as one whose store
    # fails does), its last 64 kB kept to show when it does not start
    tail: collections.deque[bytes] = collections.deque(maxlen=256)
    reader = threading.Thread(target=lambda: tail.extend(iter(lambda: proc.stderr.read(256) if proc.stderr
                                                               else b"", b"")), daemon=True)
    reader.start()
    url = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + start_timeout_s
        while True:
            try:
                if httpx.get(f"{url}/health", timeout=1).status_code == 200:
                    break
            except httpx.TransportError:
                pass
            if proc.poll() is not None or time.monotonic() > deadline:
                reader.join(timeout=5)
                err = b"".join(tail).decode(errors="replace")
                pytest.fail(f"the service did not start with {' '.join(command(port))}: {err[-2000:]}")
            time.sleep(0.2)
        yield url, proc
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGTERM)
        proc.wait(timeout=30)
        reader.join(timeout=5)
        if proc.stderr:
            proc.stderr.close()
