"""The client's handle on a design study: progress, waiting with a progress bar, results, front, cancel.

>>> handle = client.study(StudyIn(**spec))
>>> handle.wait(progress=True)              # 37/120 [#######.............] 2 failed, ETA 12 s
>>> print(handle.table())                   # the variants as a plain text table
>>> best = handle.pareto().front
"""

from __future__ import annotations

import asyncio
import sys
import time
from typing import Any, Protocol, TextIO

import httpx

from .schemas.studies import ParetoOut, ResultsOut, StudyOut, VariantOut


class Sender(Protocol):
    """What a study handle needs of a client: one request, retried while busy, a problem raised as an error."""

    def _send(self, method: str, path: str, **kwargs: Any) -> httpx.Response: ...


class AsyncSender(Protocol):
    """The same as :class:`Sender`, as a coroutine."""

    async def _send(self, method: str, path: str, **kwargs: Any) -> httpx.Response: ...

_FINAL = ("done", "cancelled", "interrupted", "failed")


class StudyHandle:
    """A study on the service, by id."""

    def __init__(self, client: Sender, study_id: str, last: StudyOut | None = None) -> None:
        self.client = client
        self.id = study_id
        self.last = last

    def _get(self, path: str, **params: Any) -> Any:
        return self.client._send("GET", f"/v1/studies/{self.id}{path}", params=params)

    def status(self) -> StudyOut:
        """State, done/total, failed variants, elapsed time and ETA."""
        self.last = StudyOut.model_validate_json(self._get("").content)
        return self.last

    def wait(self, progress: bool = False, timeout: float | None = None, poll_s: float = 0.5,
             out: TextIO | None = None) -> StudyOut:
        """Block until the study stops (done, cancelled, interrupted or failed); with ``progress`` a bar on the
        terminal (``out``, default stderr). Past ``timeout`` seconds, :class:`TimeoutError` (the study goes on)."""
        stream = out or sys.stderr
        deadline = None if timeout is None else time.monotonic() + timeout
        while True:
            status = self.status()
            if progress:
                stream.write("\r" + progress_line(status))
                stream.flush()
            if status.state in _FINAL:
                if progress:
                    stream.write("\n")
                return status
            if deadline is not None and time.monotonic() >= deadline:
                if progress:
                    stream.write("\n")
                raise TimeoutError(f"study {self.id} still {status.state} after {timeout:g} s "
                                   f"({status.done}/{status.total} variants)")
            time.sleep(poll_s)

    def page(self, offset: int = 0, limit: int = 1000) -> ResultsOut:
        """One page of variants in index order."""
        return ResultsOut.model_validate_json(self._get("/results", offset=offset, limit=limit).content)

    def results(self, page_size: int = 1000) -> list[dict[str, Any]]:
        """Every finished variant as a flat dict: ``index``, each parameter path, each metric, ``feasible``,
        ``problem_type`` and ``detail``."""
        rows: list[dict[str, Any]] = []
        offset = 0
        while True:
            page = self.page(offset, page_size)
            rows += [_flat(v, page.metrics) | {"detail": v.detail} for v in page.variants]
            if len(page.variants) < page_size:
                return rows
            offset += page_size

    def table(self, max_rows: int = 30) -> str:
        """The first ``max_rows`` variants as an aligned text table."""
        page = self.page(0, max_rows)
        return format_table([_flat(v, page.metrics) for v in page.variants])

    def csv(self) -> str:
        """Every finished variant as CSV text."""
        text: str = self._get("/results", format="csv").text
        return text

    def pareto(self) -> ParetoOut:
        """The feasible variants no other feasible variant beats in every objective."""
        return ParetoOut.model_validate_json(self._get("/pareto").content)

    def pareto_png(self, x: str | None = None, y: str | None = None) -> bytes:
        """Scatter of two metrics (default the first two objectives) with the front drawn."""
        params = {"format": "png", **{k: v for k, v in (("x", x), ("y", y)) if v is not None}}
        content: bytes = self._get("/pareto", **params).content
        return content

    def cancel(self) -> StudyOut:
        """Stop the study; finished variants stay."""
        response = self.client._send("DELETE", f"/v1/studies/{self.id}")
        self.last = StudyOut.model_validate_json(response.content)
        return self.last

    def resume(self) -> StudyOut:
        """Run the variants a cancelled or interrupted study has not finished."""
        response = self.client._send("POST", f"/v1/studies/{self.id}/resume")
        self.last = StudyOut.model_validate_json(response.content)
        return self.last


class AsyncStudyHandle:
    """A study on the service, by id, for asyncio: status, wait, pages of results, the front, cancel, resume."""

    def __init__(self, client: AsyncSender, study_id: str, last: StudyOut | None = None) -> None:
        self.client = client
        self.id = study_id
        self.last = last

    async def status(self) -> StudyOut:
        """State, done/total, failed variants, elapsed time and ETA."""
        response = await self.client._send("GET", f"/v1/studies/{self.id}")
        self.last = StudyOut.model_validate_json(response.content)
        return self.last

    async def wait(self, timeout: float | None = None, poll_s: float = 0.5) -> StudyOut:
        """Until the study stops (done, cancelled, interrupted or failed); past ``timeout`` s, TimeoutError."""
        deadline = None if timeout is None else time.monotonic() + timeout
        while (status := await self.status()).state not in _FINAL:
            if deadline is not None and time.monotonic() >= deadline:
                raise TimeoutError(f"study {self.id} still {status.state} after {timeout:g} s")
            await asyncio.sleep(poll_s)
        return status

    async def page(self, offset: int = 0, limit: int = 1000) -> ResultsOut:
        """One page of variants in index order."""
        response = await self.client._send("GET", f"/v1/studies/{self.id}/results",
                                           params={"offset": offset, "limit": limit})
        return ResultsOut.model_validate_json(response.content)

    async def pareto(self) -> ParetoOut:
        """The feasible variants no other feasible variant beats in every objective."""
        return ParetoOut.model_validate_json((await self.client._send("GET", f"/v1/studies/{self.id}/pareto")).content)

    async def cancel(self) -> StudyOut:
        """Stop the study; finished variants stay."""
        self.last = StudyOut.model_validate_json((await self.client._send("DELETE", f"/v1/studies/{self.id}")).content)
        return self.last

    async def resume(self) -> StudyOut:
        """Run the variants a cancelled or interrupted study has not finished."""
        response = await self.client._send("POST", f"/v1/studies/{self.id}/resume")
        self.last = StudyOut.model_validate_json(response.content)
        return self.last


def progress_line(s: StudyOut, width: int = 30) -> str:
    """``done/total [####....] state, failed, ETA`` on one line."""
    filled = int(width * s.done / s.total) if s.total else width
    eta = f", ETA {s.eta_s:.0f} s" if s.eta_s is not None else ""
    failed = f", {s.failed} failed" if s.failed else ""
    return f"{s.done}/{s.total} [{'#' * filled}{'.' * (width - filled)}] {s.state}{failed}{eta}   "


def format_table(rows: list[dict[str, Any]]) -> str:
    """Rows of flat dicts as an aligned text table (floats to 6 significant digits)."""
    if not rows:
        return "(no variants yet)"
    columns = list(rows[0])
    cells = [[_cell(r.get(c)) for c in columns] for r in rows]
    widths = [max(len(c), *(len(row[i]) for row in cells)) for i, c in enumerate(columns)]
    lines = ["  ".join(c.ljust(w) for c, w in zip(columns, widths))]
    lines += ["  ".join(v.ljust(w) for v, w in zip(row, widths)) for row in cells]
    return "\n".join(lines)


def _flat(v: VariantOut, metrics: list[str]) -> dict[str, Any]:
    values = v.metrics or {}
    return {"index": v.index, **v.parameters, **{m: values.get(m) for m in metrics}, "feasible": v.feasible,
            "problem_type": v.problem_type}


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)
