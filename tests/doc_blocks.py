"""The runnable examples of README.md and docs/*.md, and what each says it prints.

A ```python block runs as a script; a ```sh block runs with bash when it calls the service with curl. The literal
address ``http://127.0.0.1:8000`` is replaced by the service under test. What a block prints is written in the
block itself as comment lines starting with ``# ``: in a Python block, the comment lines right below a line that
prints (a ``print(`` line, or a line of a loop that prints); in a shell block, the comment lines at its end. Numbers
are compared with a relative tolerance (:data:`REL_TOL`), everything else exactly.

``python tests/doc_blocks.py --update http://127.0.0.1:8000`` rewrites those comments from a running service.
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
    """(line index, text) of each comment line that states output."""
    out: list[tuple[int, str]] = []
    if language == "sh":
        i = len(lines)
        while i > 0 and lines[i - 1].lstrip().startswith("# "):
            i -= 1
        return [(k, lines[k].lstrip()[2:]) for k in range(i, len(lines))]
    prints = False
    for k, line in enumerate(lines):
        stripped = line.lstrip()
        if stripped.startswith("# ") and prints:
            out.append((k, stripped[2:]))
            continue
        if not stripped.startswith("#"):
            indent = len(line) - len(stripped)
            if indent == 0 or not prints:
                prints = "print(" in line or _loop_prints(lines, k)
    return out


def _loop_prints(lines: list[str], k: int) -> bool:
    """A ``for``/``with`` header whose indented body prints."""
    if not re.match(r"\s*(for|with|async with|if)\b.*:\s*$", lines[k]):
        return False
    indent = len(lines[k]) - len(lines[k].lstrip())
    for line in lines[k + 1:]:
        if line.strip() and len(line) - len(line.lstrip()) <= indent:
            break
        if "print(" in line:
            return True
    return False


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
    return proc.stdout.splitlines()


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


def update(base_url: str) -> None:
    """Rewrite every block's output comments with what it prints now."""
    for path in [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]:
        text = path.read_text()
        for m in reversed(list(FENCE.finditer(text))):
            block = Block(path, text.count("\n", 0, m.start()) + 1, m.group(1), m.group(2))
            if not block.runnable:
                continue
            lines = block.code.splitlines()
            new = _rewrite(block.language, lines, _output_comments(block.language, lines), run(block, base_url))
            text = text[:m.start(2)] + "\n".join(new) + "\n" + text[m.end(2):]
        path.write_text(text)


def _rewrite(language: str, lines: list[str], stated: list[tuple[int, str]], got: list[str]) -> list[str]:
    if language == "sh":
        keep = lines[:stated[0][0]] if stated else lines
        return keep + [f"# {g}" for g in got]
    groups: list[list[int]] = []
    for k, _ in stated:
        if groups and groups[-1][-1] == k - 1:
            groups[-1].append(k)
        else:
            groups.append([k])
    sizes = [len(g) for g in groups]
    if sum(sizes) != len(got):
        raise SystemExit(f"cannot place {len(got)} printed lines into {sizes} stated groups: fix by hand")
    out, it = list(lines), iter(got)
    for group in groups:
        indent = lines[group[0]][: len(lines[group[0]]) - len(lines[group[0]].lstrip())]
        for k in group:
            out[k] = f"{indent}# {next(it)}"
    return out


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--update":
        update(sys.argv[2])
    else:
        raise SystemExit(__doc__)
