"""Typed engine errors; they carry data as attributes and know nothing of HTTP.

::

    SynthError
    ├── InvalidInput      (also a ValueError): a field that cannot be used as given
    ├── NotAssemblable    the loop does not close at some crank angles (phi, ranges)
    ├── Infeasible        a design target no admissible design can meet (reason, constraint)
    ├── SolverFailed      a solver stopped without an optimal answer (status)
    ├── SolverTimeout     a solve ran past its time budget (limit_s)
    ├── TooLarge          a request beyond a size limit (limit, got)
    └── WorkerLost        the worker process running a task died (exit_code)

``api/problems.py`` is the one place that maps these to HTTP problem responses.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Self

import numpy as np


class SynthError(Exception):
    """Base class of every error the engine raises on purpose."""

    slug = "synth-error"
    title = "Mechanism synthesis error"
    #: The stage of a chain of capabilities (a machine design's analysis, balancing, drive...) that raised it.
    stage: str | None = None

    def extras(self) -> dict[str, Any]:
        """Fields that help the caller act on the problem (angles, statuses, names)."""
        return {}

    def as_answer(self) -> Self:
        """This error kept as a value (a batch's answer for one variant), without its traceback: the traceback
        holds the frame that caught it, whose lists hold the error, a reference cycle that would keep the whole
        batch alive until the collector's next full pass."""
        return self.with_traceback(None)

    def __reduce__(self) -> tuple[Any, ...]:
        # Errors cross process boundaries (worker pools, Dask); rebuild them from their state, not their
        # constructor, whose signature differs per class.
        return (_rebuild, (type(self), self.args, self.__dict__))


def _rebuild(cls: type[SynthError], args: tuple[Any, ...], state: dict[str, Any]) -> SynthError:
    err = cls.__new__(cls)
    err.args = args
    err.__dict__.update(state)
    return err


class InvalidInput(SynthError, ValueError):
    """A field that cannot be used as given (negative mass, zero length, unknown link)."""

    slug = "invalid-input"
    title = "Invalid input"

    def __init__(self, message: str, field: str | None = None, code: str | None = None) -> None:
        super().__init__(message)
        self.field = field
        self.code = code

    def extras(self) -> dict[str, Any]:
        """The offending field's dotted name, when known, and the likely-mistake check's code that refused it."""
        out: dict[str, Any] = {"field": self.field} if self.field else {}
        if getattr(self, "code", None):
            out["code"] = self.code
        return out


def angle_ranges_deg(phi: Sequence[float] | np.ndarray, bad: np.ndarray) -> list[tuple[float, float]]:
    """Contiguous runs of ``bad`` samples as (start, end) crank angles in degrees, in sample order."""
    phi = np.asarray(phi, dtype=float)
    ranges: list[tuple[float, float]] = []
    start: int | None = None
    for i, flag in enumerate(np.asarray(bad, dtype=bool)):
        if flag and start is None:
            start = i
        if not flag and start is not None:
            ranges.append((float(np.degrees(phi[start])), float(np.degrees(phi[i - 1]))))
            start = None
    if start is not None:
        ranges.append((float(np.degrees(phi[start])), float(np.degrees(phi[-1]))))
    return ranges


class NotAssemblable(SynthError):
    """The linkage's loop does not close at some of the requested crank angles."""

    slug = "not-assemblable"
    title = "Linkage cannot be assembled"

    def __init__(
        self,
        message: str,
        phi: Sequence[float] | np.ndarray,
        ranges_deg: Sequence[tuple[float, float]] = (),
    ) -> None:
        super().__init__(message)
        self.phi = np.asarray(phi, dtype=float)
        self.ranges_deg = [(float(a), float(b)) for a, b in ranges_deg]

    def extras(self) -> dict[str, Any]:
        """Failing crank angle ranges in degrees, and how many samples failed."""
        return {
            "not_assemblable_ranges_deg": [list(r) for r in self.ranges_deg],
            "failing_samples": int(self.phi.size),
        }


class Infeasible(SynthError):
    """No admissible design meets the request; ``constraint`` names the binding limit."""

    slug = "infeasible"
    title = "Infeasible design target"

    def __init__(self, reason: str, constraint: str | None = None, **details: Any) -> None:
        super().__init__(reason)
        self.reason = reason
        self.constraint = constraint
        self.details = details

    def extras(self) -> dict[str, Any]:
        """The binding constraint and any numbers that explain it."""
        out: dict[str, Any] = {"constraint": self.constraint} if self.constraint else {}
        out.update(self.details)
        return out


class SolverFailed(SynthError):
    """A numerical solver stopped without an optimal answer."""

    slug = "solver-failed"
    title = "Solver failed"

    def __init__(self, status: str, message: str | None = None) -> None:
        super().__init__(message or f"solver stopped with status {status!r}")
        self.status = status

    def extras(self) -> dict[str, Any]:
        """The solver's own status string."""
        return {"solver_status": self.status}


class SolverTimeout(SynthError):
    """A solve ran past its time budget."""

    slug = "solver-timeout"
    title = "Solver time budget exceeded"

    def __init__(self, limit_s: float, message: str | None = None, **reached: Any) -> None:
        super().__init__(message or f"solver exceeded its time budget of {limit_s:g} s")
        self.limit_s = limit_s
        self.reached = reached

    def extras(self) -> dict[str, Any]:
        """The budget and whatever the solver reached before it stopped."""
        return {"limit_s": self.limit_s, **self.reached}


class TooLarge(SynthError):
    """A request beyond a configured size limit."""

    slug = "too-large"
    title = "Request too large"

    def __init__(self, what: str, limit: int, got: int, message: str | None = None,
                 field: str | None = None) -> None:
        super().__init__(message or f"{what}: {got} exceeds the limit of {limit}")
        self.what = what
        self.limit = limit
        self.got = got
        self.field = field

    def extras(self) -> dict[str, Any]:
        """The limit, the size asked for and, when one input sets the size, that field's dotted name."""
        out: dict[str, Any] = {"limit": self.limit, "got": self.got}
        if self.field:
            out["field"] = self.field
        return out


class WorkerLost(SynthError):
    """The worker process running a task died (out of memory, killed by the system, a crash inside a solver)."""

    slug = "worker-lost"
    title = "Worker process lost"

    def __init__(self, message: str, exit_code: int | None = None) -> None:
        super().__init__(message)
        self.exit_code = exit_code

    def extras(self) -> dict[str, Any]:
        """The worker's exit code (negative: the signal that ended it)."""
        return {"exit_code": self.exit_code}
