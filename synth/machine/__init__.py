"""One machine description and the design chain over every capability, checked by simulating the machine."""

from .chain import Alternative, Balancing, MachineCheck, MachineDesign, MachineShaft, alternatives, design_machine
from .optimise import MachineOptimum, OptimiseSpec, optimise_machine
from .simulate import MachineCycle, MachineMotion, simulate_machine
from .startup import RunDown, StartCheck, StartUp, Transient, simulate_rundown, simulate_startup, start_check
from .spec import BALANCING_MODES, BalancingChoice, DriveSpec, FlywheelChoice, MachineSpec

__all__ = [
    "Alternative", "BALANCING_MODES", "Balancing", "BalancingChoice", "DriveSpec", "FlywheelChoice",
    "MachineCheck", "MachineCycle", "MachineDesign", "MachineMotion", "MachineOptimum", "MachineShaft", "MachineSpec",
    "OptimiseSpec", "alternatives", "design_machine", "optimise_machine", "simulate_machine",
    "RunDown", "StartCheck", "StartUp", "Transient", "simulate_rundown", "simulate_startup", "start_check",
]
