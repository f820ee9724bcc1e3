"""Where a cam's model stops: each edge a named warning with a failed check, the answer still given.

``follower_jump``          the contact force falls to zero or below: the spring cannot hold the follower on the cam
                           at that speed, it leaves the profile and lands again (the torque of the answer assumes
                           the cam could pull it)
``pressure_angle_high``    the pressure angle passes its limit in a rise or a return (default 30° and 45°)
``profile_radius_small``   the convex profile's least radius of curvature below the limit (default 2 mm) or, with a
                           roller, below the roller's radius (the pitch curve's radius under twice the roller's,
                           the textbooks' least)
``jerk_infinite``          the acceleration steps where two segments meet (simple harmonic motion beside a dwell):
                           the jerk there is infinite, whatever the law's closed form prints inside the segment
``acceleration_infinite``  the velocity steps where two segments meet
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ..model import FloatArray
from ..warnings import DesignWarning, ValidityCheck, angle_ranges
from .forces import PairForces
from .laws import FollowerMotion, Segment
from .profile import CamGeometry

#: Default least radius of curvature of a profile [m]: sharper is not ground and hardened reliably.
MIN_PROFILE_RADIUS = 0.002
#: A step in acceleration or velocity at a joint below this fraction of the program's peak is rounding.
STEP_TOLERANCE = 1e-6


def _where(theta: FloatArray, mask: np.ndarray) -> str:
    return ", ".join(f"{math.degrees(a):.4g}–{math.degrees(b):.4g}°" for a, b in angle_ranges(theta, mask))


def contact_validity(theta: FloatArray, f: PairForces) -> tuple[list[DesignWarning], list[ValidityCheck]]:
    """``follower_jump`` where the contact force is zero or below."""
    least = float(f.contact.min())
    check = ValidityCheck("follower_contact", least, 0.0, least > 0.0,
                          "least contact force between cam and follower over the turn [N]", "N")
    if least > 0.0:
        return [], [check]
    lost = f.contact <= 0.0
    k = int(np.argmin(f.contact))
    return [DesignWarning(
        "follower_jump", "loads.spring_preload_N", least,
        f"the contact force falls to {least:.4g} N (least at cam angle {math.degrees(float(theta[k])):.4g}°; "
        f"zero or below at {_where(theta, lost)}): the follower leaves the cam there and the torque given assumes "
        "the cam could pull it; a stiffer or more preloaded spring, or a slower cam",
        "N", angle_ranges(theta, lost))], [check]


def geometry_validity(segments: Sequence[Segment], g: CamGeometry, max_pressure_rise: float,
                      max_pressure_return: float, min_radius: float) -> tuple[list[DesignWarning],
                                                                              list[ValidityCheck]]:
    """Pressure angle and profile radius against their limits [rad, m]."""
    m = g.motion
    kinds = np.array([s.kind for s in segments])[m.segment]
    alpha = np.abs(g.pressure_angle)
    notes: list[DesignWarning] = []
    checks: list[ValidityCheck] = []
    for kind, limit in (("rise", max_pressure_rise), ("return", max_pressure_return)):
        inside = kinds == kind
        if not inside.any():
            continue
        worst = float(alpha[inside].max())
        field = f"max_pressure_angle_{kind}_deg"
        checks.append(ValidityCheck(f"pressure_angle_{kind}", worst, limit, worst <= limit,
                                    f"largest pressure angle in the {kind}s against its limit [rad]", "rad"))
        if worst > limit:
            high = inside & (alpha > limit)
            notes.append(DesignWarning(
                "pressure_angle_high", field, worst,
                f"the pressure angle reaches {math.degrees(worst):.3g}° in a {kind} (limit "
                f"{math.degrees(limit):.3g}°) at cam angles {_where(m.theta, high)}: the follower is pushed "
                "sideways into its guide and may jam; a larger base circle or an offset", "rad",
                angle_ranges(m.theta, high)))
    roller = g.follower.roller
    need = max(min_radius, roller)
    convex = np.isfinite(g.rho) & (g.rho > 0)
    if convex.any() and need > 0:
        least = float(g.rho[convex].min())
        checks.append(ValidityCheck(
            "profile_radius", least, need, least >= need,
            "least radius of curvature of the convex profile against the limit"
            + (" (at least the roller's radius)" if roller > 0 else "") + " [m]", "m"))
        if least < need:
            sharp = convex & (g.rho < need)
            why = (f"the roller's radius {roller:.4g} m: the pitch curve's radius is under twice the roller's, "
                   "close to undercut and with a contact stress far above the rest of the profile"
                   if roller >= min_radius else f"the limit {min_radius:.4g} m")
            notes.append(DesignWarning(
                "profile_radius_small", "base_radius_m", least,
                f"the profile's radius of curvature falls to {least:.4g} m at cam angles {_where(m.theta, sharp)}, "
                f"below {why}; a larger base circle or a gentler law", "m", angle_ranges(m.theta, sharp)))
    return notes, checks


def joint_validity(segments: Sequence[Segment], m: FollowerMotion, speed: float,
                   unit: str) -> tuple[list[DesignWarning], list[ValidityCheck]]:
    """Steps in velocity or acceleration where consecutive segments meet (cyclically) [per rad, per rad²]."""
    ends = []
    for seg in segments:
        if seg.kind == "dwell":
            ends.append(((0.0, 0.0), (0.0, 0.0)))
            continue
        law = seg.normalised()
        sign = 1.0 if seg.kind == "rise" else -1.0
        _, f1, f2, _ = law(np.array([0.0, 1.0]))
        v = sign * seg.lift * f1 / seg.angle
        a = sign * seg.lift * f2 / seg.angle**2
        ends.append(((float(v[0]), float(a[0])), (float(v[1]), float(a[1]))))
    worst_v = 0.0
    peak_v = max(float(np.max(np.abs(m.v))), 1e-300)
    peak_a = max(float(np.max(np.abs(m.a))), 1e-300)
    notes: list[DesignWarning] = []
    worst = 0.0
    n = len(segments)
    for i in range(n):
        nxt = (i + 1) % n
        (v0, a0), (v1, a1) = ends[i][1], ends[nxt][0]
        at = math.degrees(float(m.bounds[i + 1])) % 360
        where = f"segments.{nxt}"
        if abs(v1 - v0) > STEP_TOLERANCE * peak_v:
            jump = abs(v1 - v0) * speed
            worst_v = max(worst_v, jump)
            notes.append(DesignWarning(
                "acceleration_infinite", where, jump,
                f"the velocity steps by {jump:.4g} {unit}/s where segment {i} meets segment {nxt} (cam angle "
                f"{at:.4g}°): the acceleration there is infinite; laws that end at rest", f"{unit}/s"))
        if abs(a1 - a0) > STEP_TOLERANCE * peak_a:
            jump = abs(a1 - a0) * speed**2
            worst = max(worst, jump)
            notes.append(DesignWarning(
                "jerk_infinite", where, jump,
                f"the acceleration steps by {jump:.4g} {unit}/s² where segment {i} ({_name(segments[i])}) meets "
                f"segment {nxt} ({_name(segments[nxt])}, cam angle {at:.4g}°): the jerk there is infinite, the follower is struck; "
                "a law with zero acceleration at its ends (cycloidal, 3-4-5-6-7, modified sine) beside a dwell",
                f"{unit}/s²"))
    checks = [ValidityCheck("acceleration_continuous", worst, 0.0, worst == 0.0,
                            f"largest step in the follower's acceleration where two segments meet [{unit}/s²]",
                            f"{unit}/s²")]
    if worst_v > 0:
        checks.append(ValidityCheck("velocity_continuous", worst_v, 0.0, False,
                                    f"largest step in the follower's velocity where two segments meet [{unit}/s]",
                                    f"{unit}/s"))
    return notes, checks


def _name(seg: Segment) -> str:
    return "dwell" if seg.kind == "dwell" else seg.law
