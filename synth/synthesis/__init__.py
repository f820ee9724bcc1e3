"""Dimensional synthesis: linkages from what the machine must do, posed as optimisation problems."""

from .checks import LinkageCheck, check_fourbar, check_slider_crank
from .crank_rocker import CrankRockerResult, CrankRockerSpec, overlap_angle, synthesise_crank_rocker, time_ratio_of
from .family import Optimality

__all__ = [
    "CrankRockerResult",
    "CrankRockerSpec",
    "LinkageCheck",
    "Optimality",
    "check_fourbar",
    "check_slider_crank",
    "overlap_angle",
    "synthesise_crank_rocker",
    "time_ratio_of",
]
