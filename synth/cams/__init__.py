"""Disc cams: follower motion laws (standard and optimised), the cam's profile with its pressure angle and
curvature, the least cam for pressure-angle and curvature limits, and the cam-follower pair's forces.

Everything is SI inside: m, rad, kg, N, N·m; the cam turns counter-clockwise at ``speed`` [rad/s].
"""

from ..errors import InvalidInput
from .design import (
    TEXTBOOK_PEAK_ACCELERATION,
    CamAnalysis,
    CamSpec,
    CamSynthesis,
    LawCheck,
    LawOptions,
    analyse_cam,
    synthesise_cam,
)
from .exports import RecordTitle, cam_csv, cam_dxf, cam_export, cam_figure, cam_record_pdf, cam_table, profile_polyline
from .forces import PairForces, PairLoads, ProcessLoad, pair_forces
from .laws import (
    LAWS,
    STANDARD_LAWS,
    FollowerMotion,
    LawCoefficients,
    Segment,
    check_segments,
    follower_motion,
    law_coefficients,
)
from .optimal_law import OptimisedLaw, SplineLaw, optimise_law
from .profile import CamGeometry, Follower, TableCheck, cam_geometry, table_check
from .synthesis import CamLimits, LeastCam, least_cam

__all__ = [
    "LAWS", "STANDARD_LAWS", "TEXTBOOK_PEAK_ACCELERATION", "CamAnalysis", "CamGeometry", "CamLimits", "CamSpec",
    "CamSynthesis", "Follower", "FollowerMotion", "InvalidInput", "LawCheck", "LawCoefficients", "LawOptions",
    "LeastCam", "OptimisedLaw", "PairForces", "PairLoads", "ProcessLoad", "Segment", "SplineLaw", "TableCheck",
    "analyse_cam", "cam_csv", "cam_dxf", "cam_export", "cam_figure", "cam_geometry", "cam_table",
    "check_segments", "follower_motion", "law_coefficients", "least_cam", "optimise_law", "pair_forces",
    "profile_polyline", "synthesise_cam", "table_check",
]


def standard_laws() -> list[LawCoefficients]:
    """The peak coefficients of every standard law, in the order of :data:`STANDARD_LAWS`."""
    return [law_coefficients(name) for name in STANDARD_LAWS]


__all__ += ["standard_laws", "RecordTitle", "cam_record_pdf"]
