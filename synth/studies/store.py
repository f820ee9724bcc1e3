"""What the study runner and the service need from a store of studies, without the store itself: the stored
study's record and the interface (:class:`StudyStore`) that a data layer outside the engine implements.

The runner only ever calls a sink with each finished batch's rows (``store.write_rows`` bound to a study); the
rest of the interface is what a service does with stored studies: create, claim to run, stop, page through rows.
A claim is a lease: the process running a study holds it until an expiry it renews, so that another process
sharing the store never takes a study that is still running and takes a lapsed one exactly once.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from ..model import FloatArray
from .runner import VariantRow

STATES = ("queued", "running", "done", "cancelled", "interrupted", "failed")
ACTIVE = ("queued", "running")


@dataclass(frozen=True, slots=True)
class StudyRecord:
    """A stored study and its progress.

    Parameters
    ----------
    id
        The study's id [-].
    spec
        The study as submitted (plain JSON-like data) [-].
    total
        Variants in the study [-].
    state
        ``queued``, ``running``, ``done``, ``cancelled``, ``interrupted`` or ``failed`` [-].
    done
        Variants with a row (failed ones included) [-].
    failed
        Variants whose row is a problem [-].
    created_at
        Creation time, seconds since the epoch [s].
    elapsed_s
        Running time over all runs so far [s].
    eta_s
        Estimated time to finish the current run, None when not running or not yet measurable [s].
    message
        Why a study failed or stopped, when it did [-].
    """

    id: str
    spec: Mapping[str, Any]
    total: int
    state: str
    done: int
    failed: int
    created_at: float
    elapsed_s: float
    eta_s: float | None
    message: str | None


class StudyStore(Protocol):
    """Studies and their rows, shared by every process of a service; one instance per process (its lease owner)."""

    def create(self, spec: Mapping[str, Any], total: int) -> str:
        """Store a new study, queued and held by this process; its id."""

    def get(self, study_id: str) -> StudyRecord | None:
        """The study with its progress, or None when there is no such study."""

    def recent(self, limit: int = 100, offset: int = 0) -> list[StudyRecord]:
        """The latest studies first, with their progress."""

    def claim(self, study_id: str) -> bool:
        """Mark a study running from now under this process's lease; False when another process's lease on it is
        live or the study is done (then nothing changes)."""

    def renew(self) -> set[str]:
        """Extend this process's leases on its queued and running studies; the ids still held."""

    def stopped(self, study_id: str, state: str, message: str | None = None) -> None:
        """End this process's run of a study in ``state``, adding its running time, releasing the lease."""

    def cancel(self, study_id: str) -> bool:
        """Cancel a queued or running study whichever process runs it; False when it was neither."""

    def sweep(self) -> int:
        """Studies queued or running whose lease lapsed (their process stopped) become ``interrupted``; how many."""

    def write_rows(self, study_id: str, rows: Sequence[VariantRow]) -> None:
        """Store a batch of rows in one transaction (the runner's sink)."""

    def missing(self, study_id: str, total: int) -> list[int]:
        """Indices of the variants that have no row yet, ascending."""

    def rows(self, study_id: str, offset: int = 0, limit: int | None = None) -> list[VariantRow]:
        """Rows in index order, from ``offset``, at most ``limit``."""

    def iter_rows(self, study_id: str, chunk: int = 2_000) -> Iterator[VariantRow]:
        """Every row in index order, read ``chunk`` at a time (for exports that must not hold them all)."""

    def metric_table(self, study_id: str, width: int) -> tuple[NDArray[np.int64], FloatArray, NDArray[np.bool_]]:
        """Index, metrics (NaN where missing; ``width`` columns) and feasibility of every variant that gave its
        metrics, in index order."""

    def rows_at(self, study_id: str, indices: Sequence[int]) -> list[VariantRow]:
        """The rows of the given variant indices, in index order."""
