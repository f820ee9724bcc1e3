"""Loops numpy cannot run at their speed, compiled to machine code by numba: steps that each depend on the one
before (a Runge-Kutta march, a start's Levenberg-Marquardt iterations) and per-value work with branches (a
number's text).

A Runge-Kutta march over a cycle is a few thousand dependent steps of a dozen flops each: as Python it is
interpreter overhead, as an expression graph (CasADi's virtual machine) about a microsecond a step; compiled it is
tens of nanoseconds. Functions are compiled on first use and cached on disk beside their module (numba's cache),
so a new process loads them instead of compiling; a worker's warm-up makes that first use.

The arithmetic is IEEE (no fast-math reordering) and a division by zero gives an infinity or NaN as numpy's does
(the callers check the result is finite), never an exception from inside the loop.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar, cast

import numba

F = TypeVar("F", bound=Callable[..., object])


def compiled(fn: F) -> F:
    """``fn`` compiled by numba in nopython mode, cached on disk, with numpy's division semantics."""
    return cast(F, numba.njit(cache=True, error_model="numpy")(fn))
