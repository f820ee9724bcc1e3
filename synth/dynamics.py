"""Reduced (equivalent) model on the crank: inertia, its slope, the reduced torque of loads, kinetic energy."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .kinematics.motion import Motion
from .kinetostatics import external_loads
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


def reduced_model(motion: Motion, linkage: Linkage) -> ReducedModel:
    """J_red = sum(m·|v_S/w|² + J_S·(w_i/w)²), its derivative in phi, and M_red from the power of the loads."""
    topo = linkage.mechanism.topology
    w, eps = motion.omega_crank, motion.alpha_crank
    n = motion.samples
    inertia, slope, power = np.zeros(n), np.zeros(n), np.zeros(n)
    g = linkage.gravity.vector if linkage.gravity is not None else np.zeros(2)
    for link in topo.links:
        props = linkage.mass_props(link)
        s = motion.point_on(link, props.com)
        d1 = s.vel / w
        d2 = (s.acc - eps * d1) / w**2
        t1 = motion.link_omega[link] / w
        t2 = (motion.link_alpha[link] - eps * t1) / w**2
        inertia += props.mass * np.einsum("ij,ij->i", d1, d1) + props.inertia * t1**2
        slope += 2 * props.mass * np.einsum("ij,ij->i", d1, d2) + 2 * props.inertia * t1 * t2
        power += props.mass * (s.vel @ g)
    loads = external_loads(motion, linkage)
    power += np.einsum("ij,ij->i", loads.force, loads.point_vel)
    for link, torque in loads.torques.items():
        power += torque * motion.link_omega[link]
    return ReducedModel(motion.phi, inertia, slope, power / w, 0.5 * inertia * w**2)
