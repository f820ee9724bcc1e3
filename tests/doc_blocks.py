"""The runnable examples of README.md and docs/*.md, and what each says it prints.

A ```python block runs as a script; a ```sh block runs with bash when it calls the service with curl. The literal
address ``http://127.0.0.1:8000`` is replaced by the service under test. What a block prints is written in the
block itself, in order, as comment lines starting with ``#> `` (other comments explain and are not compared).
Numbers are compared with a relative tolerance (:data:`REL_TOL`), everything else exactly.

``python tests/doc_blocks.py --update http://127.0.0.1:8000 [README]`` rewrites those comments from a running
service (in the files whose name contains the last argument).
"""

from __future__ import annotations

import math
import os
import re
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
ADDRESS = "http://127.0.0.1:8000"
# Printed figures are rounded for the reader (3 to 5 significant digits); solver noise is far below this.
REL_TOL = 1e-3
ABS_TOL = 1e-6
NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")
FENCE = re.compile(r"^```(python|sh)\n(.*?)^```$", flags=re.M | re.S)


@dataclass(frozen=True)
class Block:
    """One fenced example: where it is, its language and code, and the output it claims."""

    path: Path
    line: int
    language: str
    code: str

    @property
    def name(self) -> str:
        return f"{self.path.relative_to(REPO)}:{self.line}"

    @property
    def runnable(self) -> bool:
        if self.language == "python":
            return True
        return "curl " in self.code and ADDRESS in self.code

    def expected(self) -> list[str]:
        return [text for _, text in _output_comments(self.language, self.code.splitlines())]


def blocks() -> list[Block]:
    """Every fenced python and sh block of README.md and docs/*.md, in file order."""
    found = []
    for path in [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]:
        text = path.read_text()
        for m in FENCE.finditer(text):
            found.append(Block(path, text.count("\n", 0, m.start()) + 1, m.group(1), m.group(2)))
    return found


def _output_comments(language: str, lines: list[str]) -> list[tuple[int, str]]:
    """(line index, text) of each comment line that states output: those starting with ``#> ``."""
    return [(k, line.lstrip()[3:]) for k, line in enumerate(lines)
            if line.lstrip().startswith("#> ") or line.strip() == "#>"]


def run(block: Block, base_url: str, timeout_s: float = 300) -> list[str]:
    """The block's printed lines when run against ``base_url``, in a scratch directory."""
    code = block.code.replace(ADDRESS, base_url)
    with tempfile.TemporaryDirectory() as scratch:
        if block.language == "python":
            cmd = [sys.executable, "-c", code]
        else:
            cmd = ["bash", "-euo", "pipefail", "-c", code]
        env = {**os.environ, "PYTHONPATH": str(REPO)}
        proc = subprocess.run(cmd, cwd=scratch, capture_output=True, text=True, timeout=timeout_s, env=env)
    if proc.returncode:
        raise AssertionError(f"{block.name} failed:\n{proc.stderr[-3000:]}")
    return [line.rstrip() for line in proc.stdout.splitlines()]


def mismatch(expected: list[str], got: list[str]) -> str | None:
    """Why the printed lines differ from the stated ones, or None when they agree."""
    if len(expected) != len(got):
        return f"{len(got)} lines printed, {len(expected)} stated:\n" + "\n".join(got)
    for want, have in zip(expected, got):
        want_nums, have_nums = NUMBER.findall(want), NUMBER.findall(have)
        if NUMBER.sub("#", want) != NUMBER.sub("#", have) or len(want_nums) != len(have_nums):
            return f"stated {want!r}, printed {have!r}"
        for a, b in zip(want_nums, have_nums):
            if not math.isclose(float(a), float(b), rel_tol=REL_TOL, abs_tol=ABS_TOL):
                return f"stated {want!r}, printed {have!r} ({a} vs {b})"
    return None


def update(base_url: str, only: str = "") -> None:
    """Rewrite the output comments of every block (of the files whose name contains ``only``) with what it
    prints now.

    Each group of ``#> `` lines is replaced by a marker printed where it stands, so the lines printed between two
    markers are the group's, however many a loop prints."""
    for path in [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]:
        if only not in path.name:
            continue
        text = path.read_text()
        for m in reversed(list(FENCE.finditer(text))):
            block = Block(path, text.count("\n", 0, m.start()) + 1, m.group(1), m.group(2))
            lines = block.code.splitlines()
            groups = _groups(lines)
            if not block.runnable or not groups:
                continue
            marked = list(lines)
            for group in reversed(groups):
                indent = _indent(lines[group[0]])
                say = f'print("{_MARK}")' if block.language == "python" else f'echo "{_MARK}"'
                marked[group[0]:group[-1] + 1] = [indent + say]
            printed = run(Block(path, block.line, block.language, "\n".join(marked) + "\n"), base_url)
            chunks: list[list[str]] = [[]]
            for line in printed:
                if line == _MARK:
                    chunks.append([])
                else:
                    chunks[-1].append(line)
            new = list(lines)
            for group, chunk in reversed(list(zip(groups, chunks[:-1]))):
                new[group[0]:group[-1] + 1] = [f"{_indent(lines[group[0]])}#> {c}" for c in chunk]
            text = text[:m.start(2)] + "\n".join(new) + "\n" + text[m.end(2):]
        path.write_text(text)


_MARK = "<<stated output>>"


def _indent(line: str) -> str:
    return line[: len(line) - len(line.lstrip())]


def _groups(lines: list[str]) -> list[list[int]]:
    """Runs of consecutive ``#> `` lines, as line indexes."""
    groups: list[list[int]] = []
    for k, _ in _output_comments("python", lines):
        if groups and groups[-1][-1] == k - 1:
            groups[-1].append(k)
        else:
            groups.append([k])
    return groups


if __name__ == "__main__":
    if len(sys.argv) in (3, 4) and sys.argv[1] == "--update":
        update(*sys.argv[2:])
    else:
        raise SystemExit(__doc__)
