"""Dimensional synthesis: linkages from what the machine must do, posed as optimisation problems."""

from .checks import LinkageCheck, check_fourbar, check_slider_crank
from .crank_rocker import CrankRockerResult, CrankRockerSpec, overlap_angle, synthesise_crank_rocker, time_ratio_of
from .family import Optimality
from .cognates import Cognate, cognates
from .path import (MAX_POINTS, MAX_STARTS, RANKINGS, PathFit, PathResult, PathSpec, coupler_curve,
                   default_path_limits, synthesise_path)
from .slider_crank import SliderCrankResult, SliderCrankSpec, synthesise_slider_crank

__all__ = [
    "Cognate",
    "CrankRockerResult",
    "CrankRockerSpec",
    "LinkageCheck",
    "MAX_POINTS",
    "MAX_STARTS",
    "Optimality",
    "PathFit",
    "PathResult",
    "PathSpec",
    "RANKINGS",
    "SliderCrankResult",
    "SliderCrankSpec",
    "check_fourbar",
    "check_slider_crank",
    "cognates",
    "coupler_curve",
    "default_path_limits",
    "overlap_angle",
    "synthesise_crank_rocker",
    "synthesise_path",
    "synthesise_slider_crank",
    "time_ratio_of",
]
