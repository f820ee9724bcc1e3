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

    The load sign is judged on the cycle's work as sized (``tables`` without an analysis, ``loads`` with one),
    against the role of the constant balancing torque: with the tables as loads it must drive (positive), with
    them as the drive (an engine's gas torque) it must resist (negative). Separate driving and resisting tables
    are each judged on their own work first.
    """
    out: list[DesignWarning] = []
    load_field = "tables"
    if analysis is not None:
        out += [w for w in check_analysis(analysis) if w.code != "load_work_positive"]
        load_field = "loads" if analysis.linkage.loads else "torques"
    out += _sign_mistakes(result, load_field)
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


def _sign_mistakes(result: FlywheelResult, load_field: str) -> list[DesignWarning]:
    cycle, work, torque = result.cycle, result.cycle_work, result.driving_torque
    out: list[DesignWarning] = []
    if cycle.driving_work is not None and cycle.driving_work < 0:
        out.append(DesignWarning(
            "drive_work_negative", "tables.driving_torque_Nm", cycle.driving_work,
            f"the driving torques do {cycle.driving_work:.4g} J of negative work per cycle: driving torques are "
            "positive where they drive the crank, resisting ones negative", "J"))
    if cycle.resisting_work is not None and cycle.resisting_work > 0:
        out.append(DesignWarning(
            "load_work_positive", "tables.resisting_torque_Nm", cycle.resisting_work,
            f"the resisting torques do {cycle.resisting_work:.4g} J of positive work per cycle: resisting torques "
            "are negative, driving ones positive", "J"))
    if out:
        return out
    if cycle.balance == "driving" and torque < 0:
        out.append(DesignWarning(
            "load_work_positive", load_field, work,
            f"the given torques do {work:.4g} J of positive work per cycle, so the constant driving "
            f"torque that balances them is negative ({torque:.4g} N·m): resisting torques are "
            "negative, driving ones positive (an engine's torque table drives: give it as driving_torque_Nm, or "
            "set constant_torque_role to resisting)", "J"))
    if cycle.balance == "resisting" and torque > 0:
        out.append(DesignWarning(
            "drive_work_negative", load_field, work,
            f"the given driving torques do {work:.4g} J of negative work per cycle, so the constant resisting "
            f"torque that balances them would drive ({torque:.4g} N·m): driving torques are positive, resisting "
            "ones negative", "J"))
    return out
