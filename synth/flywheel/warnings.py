"""Likely mistakes in a flywheel request or answer: loads that drive the machine, a delta outside every machine
type's range, a rim near its speed limit (see :mod:`synth.warnings` for the codes)."""

from __future__ import annotations

from ..analysis import Analysis
from ..warnings import DELTA_RANGE, RIM_SPEED_MARGIN, DesignWarning, check_analysis
from .geometry import GeometrySpec
from .problem import FlywheelResult


def check_flywheel(result: FlywheelResult, geometry: GeometrySpec | None = None,
                   analysis: Analysis | None = None) -> list[DesignWarning]:
    """Loads that drive the machine, a target delta outside every machine type's range, a rim near its speed limit;
    with the ``analysis`` of a linkage also :func:`check_linkage` and the transmission angle.

    The load sign is judged on the cycle's work as sized (``tables`` without an analysis, ``loads`` with one).
    """
    out: list[DesignWarning] = []
    load_field = "tables"
    if analysis is not None:
        out += [w for w in check_analysis(analysis) if w.code != "load_work_positive"]
        load_field = "loads" if analysis.linkage.loads else "torques"
    if result.driving_torque < 0:
        out.append(DesignWarning(
            "load_work_positive", load_field, result.cycle_work,
            f"the given torques do {result.cycle_work:.4g} J of positive work per cycle, so the constant driving "
            f"torque that balances them is negative ({result.driving_torque:.4g} N·m): resisting torques are "
            "negative, driving ones positive", "J"))
    lo, hi = DELTA_RANGE
    delta = result.target_delta
    if not lo <= delta <= hi:
        out.append(DesignWarning(
            "delta_out_of_range", "delta", delta,
            f"a target delta of {delta:.3g} lies outside the usual {lo:.3g}–{hi:.3g} of machines (the machine types' "
            "table lists them); the flywheel grows as 1/delta", "1"))
    if geometry is not None and geometry.max_rim_speed is not None and result.geometry is not None:
        best = result.geometry.best
        limit = geometry.max_rim_speed
        if best.rim_speed >= RIM_SPEED_MARGIN * limit:
            out.append(DesignWarning(
                "rim_speed_near_limit", "geometry.max_rim_speed_m_s", best.rim_speed,
                f"the flywheel's rim runs at {best.rim_speed:.3g} m/s, {best.rim_speed / limit:.0%} of the "
                f"{limit:g} m/s limit: no margin for overspeed; a larger width or another shaft gives one", "m/s"))
    return out
