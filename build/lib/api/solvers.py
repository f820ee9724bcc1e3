"""Where solver work runs inside the service.

cvxpy problems are not thread-safe and IPOPT (through CasADi) can crash when two solves run at once in threads
of one process. FastAPI runs our synchronous handlers in a thread pool, so solves are serialised explicitly:
one solve at a time per process, behind a lock. A request that cannot get the slot within the wait budget
answers 504 (SolverTimeout) instead of queueing without bound; the solver's own time limit bounds each solve.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import ParamSpec, TypeVar

from synth.errors import SolverTimeout

P = ParamSpec("P")
R = TypeVar("R")


class SolverGate:
    """Runs one solver call at a time; waits at most ``wait_s`` seconds for its turn."""

    def __init__(self, wait_s: float) -> None:
        self.wait_s = wait_s
        self._lock = threading.Lock()

    def run(self, fn: Callable[P, R], *args: P.args, **kwargs: P.kwargs) -> R:
        """Call ``fn`` while holding the solver slot."""
        if not self._lock.acquire(timeout=self.wait_s):
            raise SolverTimeout(self.wait_s, f"no solver slot became free within {self.wait_s:g} s")
        try:
            return fn(*args, **kwargs)
        finally:
            self._lock.release()
