"""The crank shaft's loads from the linkage's analysis: the crank's reaction, the driving torque and the drive.

Input: an :class:`synth.analysis.Analysis` and a :class:`CrankShaftLayout` (where the crank, the drive and an
optional flywheel sit along the shaft between its bearings, and whether the drive is a coupling or a gear with its
pitch radius, mesh direction, pressure and helix angles). Output: :func:`crank_shaft_loads` gives the
:class:`synth.strength.shafts.ShaftLoad` items over the cycle for :func:`synth.strength.shafts.size_shaft`, and
:func:`hub_torques` the torque each hub's key carries.

The crank pivot's reaction is the force the frame, here the shaft, exerts on the crank; the crank presses on the
shaft with its opposite. The shaft hands the driving torque T(phi) to the crank and takes it from the drive, so the
crank puts -T and the drive +T on it; a gear drive also pushes the shaft with its mesh forces. A flywheel adds its
weight; at the analysis' steady crank speed its inertia torque is nil, and its key carries the torque the flywheel
lends and takes back, T - mean(T), when the motor gives the mean.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from ..analysis import Analysis
from ..errors import InvalidInput
from ..model import FloatArray
from .shafts import ShaftLoad, gear_mesh_forces


@dataclass(frozen=True, slots=True)
class CrankShaftLayout:
    """Positions along the crank shaft from bearing A [m] (B at ``span``): ``crank_position``,
    ``drive_position``, ``flywheel_position`` (None: no flywheel on this shaft) with ``flywheel_mass`` [kg];
    ``drive`` ``coupling`` or ``gear``: its ``pitch_radius`` [m], ``mesh_angle`` to the mating gear [rad],
    ``pressure_angle`` and ``helix_angle`` [rad]; ``gravity`` [m/s²] along -y for the flywheel's weight."""

    span: float
    crank_position: float
    drive_position: float
    drive: Literal["coupling", "gear"] = "coupling"
    pitch_radius: float = 0.0
    mesh_angle: float = 0.0
    pressure_angle: float = math.radians(20.0)
    helix_angle: float = 0.0
    flywheel_position: float | None = None
    flywheel_mass: float = 0.0
    gravity: float = 9.81


def crank_pivot(analysis: Analysis) -> str:
    """The name of the revolute joint between the frame and the crank."""
    topo = analysis.linkage.mechanism.topology
    for j in topo.joints:
        if j.kind == "revolute" and j.bodies == (None, topo.crank):
            return j.name
    raise InvalidInput("the linkage's crank has no revolute pivot on the frame", field="mechanism")


def crank_shaft_loads(analysis: Analysis, layout: CrankShaftLayout) -> list[ShaftLoad]:
    """The crank shaft's loads over the cycle, for :func:`synth.strength.shafts.size_shaft`."""
    reaction = np.asarray(analysis.kinetostatics.reactions[crank_pivot(analysis)], dtype=float)
    torque = np.asarray(analysis.kinetostatics.driving_torque, dtype=float)
    n = torque.size
    loads = [ShaftLoad("crank", layout.crank_position, -reaction, torque=-torque)]
    if layout.drive == "gear":
        force, moment, axial = gear_mesh_forces(torque, layout.pitch_radius, layout.mesh_angle,
                                                pressure_angle=layout.pressure_angle,
                                                helix_angle=layout.helix_angle)
        loads.append(ShaftLoad("drive gear", layout.drive_position, force, moment=moment, axial=axial,
                               torque=torque))
    elif layout.drive == "coupling":
        loads.append(ShaftLoad("coupling", layout.drive_position, np.zeros((n, 2)), torque=torque))
    else:
        raise InvalidInput(f"the crank shaft's drive is a coupling or a gear, got {layout.drive!r}", field="drive")
    if layout.flywheel_position is not None:
        if not (math.isfinite(layout.flywheel_mass) and layout.flywheel_mass >= 0.0):
            raise InvalidInput("the flywheel's mass must be positive", field="flywheel_mass")
        weight = np.tile([0.0, -layout.flywheel_mass * layout.gravity], (n, 1))
        loads.append(ShaftLoad("flywheel", layout.flywheel_position, weight))
    return loads


def hub_torques(analysis: Analysis) -> dict[str, FloatArray]:
    """The torque each hub of the crank shaft passes over the cycle (N,) [N·m]: the crank's and the drive's the
    driving torque, the flywheel's its swing about the mean, a counterweight's none (it is part of the crank)."""
    torque = np.asarray(analysis.kinetostatics.driving_torque, dtype=float)
    return {"crank": torque, "drive": torque, "coupling": torque, "flywheel": torque - float(torque.mean()),
            "counterweight": np.zeros_like(torque)}
