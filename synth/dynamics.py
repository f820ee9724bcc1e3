"""Reduced (equivalent) model on the crank: inertia, its slope, the reduced torque of loads, kinetic energy."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .kinematics.motion import Motion, dot
from .kinetostatics import ExternalLoads, LinkArrays, external_loads, link_arrays, link_sum
from .model import FloatArray, Linkage


@dataclass(frozen=True, slots=True)
class ReducedModel:
    """The linkage reduced to its crank (seed 000:399-466, 003:254-310).

    ``inertia`` J_red(phi) [kg·m²], ``inertia_slope`` dJ_red/dphi [kg·m²/rad], ``load_torque`` M_red(phi) of
    process loads, link torques and gravity [N·m] (positive drives the crank), ``kinetic_energy`` at the
    motion's crank speed [J]; all (N,). ``friction_torque`` the pairs' friction losses reduced to the crank
    [N·m] (their power over the crank speed at the analysed speed; resists, >= 0 where friction only takes),
    None without friction.
    """

    phi: FloatArray
    inertia: FloatArray
    inertia_slope: FloatArray
    load_torque: FloatArray
    kinetic_energy: FloatArray
    friction_torque: FloatArray | None = None

    @property
    def resisting_torque(self) -> FloatArray:
        """The load torque with the friction losses taken off, M_red - M_friction [N·m] (positive drives)."""
        return self.load_torque if self.friction_torque is None else self.load_torque - self.friction_torque


def reduced_model(motion: Motion, linkage: Linkage, arrays: LinkArrays | None = None,
                  loads: ExternalLoads | None = None) -> ReducedModel:
    """J_red = sum(m·|v_S/w|² + J_S·(w_i/w)²), its derivative in phi, and M_red from the power of the loads.

    ``arrays`` are :func:`synth.kinetostatics.link_arrays` and ``loads`` :func:`synth.kinetostatics.external_loads`
    of this motion and linkage when the caller has them.
    """
    arrays = link_arrays(motion, linkage) if arrays is None else arrays
    w, eps = motion.omega_crank, motion.alpha_crank
    g = linkage.gravity.vector if linkage.gravity is not None else np.zeros(2)
    # All links at once (links on axis 0), from the velocities and accelerations themselves: with the analogues
    # d1 = v/w and d2 = (a - eps·d1)/w², sum(m·d1·d1 + J·t1²) = T2/w² and sum(m·d1·d2 + J·t1·t2) =
    # (P - eps/w·T2)/w³, where T2 = sum(m·v·v + J·omega²) and P = sum(m·v·a + J·omega·alpha).
    twice_kinetic = link_sum(arrays.mass, dot(arrays.com_vel, arrays.com_vel)) + link_sum(arrays.inertia,
                                                                                          arrays.omega * arrays.omega)
    rate = link_sum(arrays.mass, dot(arrays.com_vel, arrays.com_acc)) + link_sum(arrays.inertia,
                                                                                 arrays.omega * arrays.alpha)
    inertia = twice_kinetic / w**2
    slope = 2 * (rate - (eps / w) * twice_kinetic) / w**3 if eps else 2 * rate / w**3
    power = link_sum(arrays.mass, arrays.com_vel @ g)
    loads = external_loads(motion, linkage) if loads is None else loads
    if loads.has_force:
        power += dot(loads.force, loads.point_vel)
    for link, torque in loads.torques.items():
        power += torque * motion.link_omega[link]
    return ReducedModel(motion.phi, inertia, slope, power / w, 0.5 * inertia * w**2)
