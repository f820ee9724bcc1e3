"""An estimate of a request's work before it runs [worker-seconds on one core], from the request alone.

A design study runs one request per variant, so its work is the count of variants times the work of one; the
service bounds that product (per study and per owner) before the study is stored. The estimates are coarse on
purpose: a per-request cost and a cost per crank angle (or per start, per member, per swept weight set) of
each endpoint, measured on one core of the development machine and rounded up; the tooth search's from the
products its meet in the middle streams per pass (about 1 ns each, see ``synth.gearing.teeth.MAX_STREAMED``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from pydantic import BaseModel

#: Per endpoint: fixed cost [s] and cost per crank angle [s].
_PER_SAMPLE: dict[str, tuple[float, float]] = {
    "/v1/analysis": (0.002, 4e-6),
    "/v1/balancing/static": (0.005, 1e-5),
    "/v1/balancing/full": (0.008, 1.5e-5),
    "/v1/balancing/optimal": (0.03, 3e-5),
    "/v1/balancing/slider-crank": (0.01, 1.5e-5),
    "/v1/flywheel": (0.01, 2e-5),
    "/v1/synthesis/crank-rocker": (0.2, 1e-3),
    "/v1/synthesis/slider-crank": (0.2, 1e-3),
    "/v1/machines/isolation": (0.02, 2e-4),
    "/v1/machines/isolation/design": (0.2, 2e-3),
    "/v1/machines/elastic-drive": (0.2, 3e-3),
    "/v1/machines/regulation": (0.1, 2e-3),
    "/v1/cams/analysis": (0.005, 2e-5),
    "/v1/cams/synthesis": (0.05, 1e-4),
}
#: Endpoints whose work is not driven by a count in the request: their cost [s].
_FIXED: dict[str, float] = {
    "/v1/balancing/rotor": 0.01,
    "/v1/gears/split": 0.02,
    "/v1/gears/drive": 0.1,
    "/v1/gears/rating": 0.02,
    "/v1/gears/train": 0.05,
    "/v1/structure": 0.005,
    "/v1/machines/design": 1.0,
}
# Path synthesis screens each start by one compiled loop of 40 Levenberg-Marquardt steps (about 0.3 ms a start
# for 10 points, more than linear in the points) and polishes up to four designs with IPOPT (a few ms each): at
# 1 ms a start the price stays above the work up to 40 points (256 starts through 40 points took 0.68 s).
_PATH_START_S = 0.001
_MEMBER_S = 0.05
_STREAMED_PRODUCT_S = 1e-9


def _tooth_pairs(max_teeth: int) -> float:
    """Candidate pairs of one spur stage after deduplication, about 0.26 max_teeth² (256 000 at 1000 teeth,
    23 000 at 200), never fewer than the ten thousand of the smallest searches."""
    return max(1e4, 0.26 * max_teeth**2)


def _teeth(b: Any) -> float:
    stages = b.stages if isinstance(b.stages, int) else len(b.stages)
    streamed = _tooth_pairs(int(b.max_teeth)) ** (stages - stages // 2)
    return 0.01 + streamed * _STREAMED_PRODUCT_S


def _path(b: Any) -> float:
    return 0.05 + int(b.starts) * _PATH_START_S * max(1.0, len(b.points_m) / 10)


#: A searched cell (its walk by bisection and its plateaus' searches) costs about this many members' chains.
_CELL_MEMBERS = 12


def optimise_s(b: Any, workers: int = 1) -> dict[str, float]:
    """POST /v1/machines/optimise's work on ``workers`` workers [s], by what drives it: the scan's members
    (shared by the workers), the cells searched (two at a time, their plateaus shared) and the optimum's design."""
    run = _MEMBER_S * int(b.samples) / 120
    cells = int(b.scan_members) - 1 if b.search_cells == "all" else min(int(b.search_cells), int(b.scan_members) - 1)
    return {"scan_members": math.ceil(int(b.scan_members) / workers) * run,
            "search_cells": _CELL_MEMBERS * cells * run / workers, "design": 1.0}


def _optimise(b: Any) -> float:
    return sum(optimise_s(b).values())


def _flywheel(b: Any) -> float:
    """The sizing, and with an ``elastic_drive`` block the elastic drive's integrations too."""
    samples = int(getattr(b, "samples", None) or 360)
    fixed, per_sample = _PER_SAMPLE["/v1/flywheel"]
    if getattr(b, "elastic_drive", None) is not None:
        fixed, per_sample = fixed + _PER_SAMPLE["/v1/machines/elastic-drive"][0], (
            per_sample + _PER_SAMPLE["/v1/machines/elastic-drive"][1])
    return fixed + per_sample * samples


# A member of /v1/machines/optimise-linkage through the chain to its steady machine: about 0.08 s and 0.1 ms per
# crank angle on the six-bar press, about 0.4 s more with its gear wheels sized for strength (a machine-mass or
# cost objective with drive.size_gears); the optimum designed whole, start and run-down simulated, about 1 s.
_LINKAGE_MEMBER_S = 0.1
_LINKAGE_PER_SAMPLE_S = 1e-4
_LINKAGE_GEARS_S = 0.4
_LINKAGE_DESIGN_S = 1.0


def linkage_member_s(b: Any) -> float:
    """One member of a linkage optimisation through the chain [s]."""
    weighed = {b.objective} if b.objective is not None else {k for k, w in (b.weights or {}).items() if w > 0}
    gears = _LINKAGE_GEARS_S if b.machine.drive.size_gears and weighed & {"machine_mass", "cost"} else 0.0
    return _LINKAGE_MEMBER_S + _LINKAGE_PER_SAMPLE_S * int(b.machine.samples) + gears


def optimise_linkage_s(b: Any, workers: int = 1) -> dict[str, float]:
    """The work of a linkage optimisation on ``workers`` workers [s] by the request field that drives it: the
    sample (every member designed, the request's own numbers among them, shared by the workers), the refinement
    (every start spending all its chain runs, one start per worker at a time) and the optimum's design."""
    member = linkage_member_s(b)
    rounds = math.ceil(int(b.refined) / workers)
    return {"samples": math.ceil((int(b.samples) + 1) / workers) * member,
            "refine_runs": rounds * int(b.refine_runs) * member, "design": _LINKAGE_DESIGN_S}


_SPECIAL: dict[str, Callable[[Any], float]] = {
    "/v1/gears/teeth": _teeth,
    "/v1/synthesis/path": _path,
    "/v1/machines/optimise": _optimise,
    "/v1/flywheel": _flywheel,
}

_SPECIAL["/v1/machines/optimise-linkage"] = lambda b: sum(optimise_linkage_s(b).values())


def estimate_s(endpoint: str, body: BaseModel) -> float:
    """Estimated work of one request of ``endpoint`` [worker-seconds]."""
    if endpoint in _SPECIAL:
        return _SPECIAL[endpoint](body)
    if endpoint in _PER_SAMPLE:
        fixed, per_sample = _PER_SAMPLE[endpoint]
        samples = getattr(body, "samples", None) or 360
        sweep = len(getattr(body, "sweep", None) or ()) + 1
        return (fixed + per_sample * int(samples)) * sweep
    return _FIXED.get(endpoint, 0.05)


def describe_s(seconds: float) -> str:
    """A work estimate for people: seconds, hours or days of one worker."""
    if seconds < 3600:
        return f"{seconds:.3g} worker-seconds"
    if seconds < 86400 * 3:
        return f"{seconds / 3600:.3g} worker-hours"
    return f"{seconds / 86400:.3g} worker-days"


def finite(seconds: float) -> float:
    """An estimate as a finite number (an overflowing power is simply huge)."""
    return seconds if math.isfinite(seconds) else 1e300
