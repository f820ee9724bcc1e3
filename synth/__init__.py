"""Mechanism synthesis engine: linkage analysis over a cycle, balancing, flywheels and drive design.

Everything is SI inside (m, kg, s, rad, N, N·m, kg·m²). The engine never imports the web layer.
"""

from .analysis import Analysis, Summary, analyse
from .dynamics import ReducedModel, reduced_model
from .errors import (
    Infeasible,
    InvalidInput,
    NotAssemblable,
    SolverFailed,
    SolverTimeout,
    SynthError,
    TooLarge,
)
from .kinematics import FourBar, Motion, SliderCrank, SlottedLever, cycle_angles, motion
from .kinetostatics import Kinetostatics, LinearMap, linear_map, solve_direct, virtual_power_torque
from .model import Counterweight, Gravity, Linkage, LinkTorque, MassProps, ProcessLoad
from .topology import Joint, Topology

__all__ = [
    "Analysis",
    "Counterweight",
    "FourBar",
    "Gravity",
    "Infeasible",
    "InvalidInput",
    "Joint",
    "Kinetostatics",
    "LinearMap",
    "LinkTorque",
    "Linkage",
    "MassProps",
    "Motion",
    "NotAssemblable",
    "ProcessLoad",
    "ReducedModel",
    "SliderCrank",
    "SlottedLever",
    "SolverFailed",
    "SolverTimeout",
    "Summary",
    "SynthError",
    "TooLarge",
    "Topology",
    "analyse",
    "cycle_angles",
    "linear_map",
    "motion",
    "reduced_model",
    "solve_direct",
    "virtual_power_torque",
]
