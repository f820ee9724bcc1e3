"""Counter-rotating inertias geared to a link: the moment they put on the frame and the torque they cost."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .errors import InvalidInput
from .kinematics.motion import Motion
from .model import FloatArray


@dataclass(frozen=True, slots=True)
class CounterRotor:
    """A counter-rotating inertia [kg·m²] geared to ``link`` turning at -``ratio`` times the link's speed."""

    link: str
    inertia: float
    ratio: float

    def validate(self, links: Sequence[str], where: str) -> None:
        """InvalidInput naming ``where`` for an unknown link, a negative inertia or a non-positive ratio."""
        if self.link not in links:
            raise InvalidInput(f"counter-rotor on unknown link {self.link!r}; links are {list(links)}",
                               field=f"{where}.link")
        if not (math.isfinite(self.inertia) and self.inertia >= 0):
            raise InvalidInput("a counter-rotor's inertia must not be negative", field=f"{where}.inertia_kgm2")
        if not (math.isfinite(self.ratio) and self.ratio > 0):
            raise InvalidInput("a counter-rotor's ratio must be positive", field=f"{where}.ratio")


def rotor_loads(motion: Motion, rotors: Sequence[CounterRotor]) -> tuple[FloatArray, FloatArray]:
    """Shaking moment on the frame [N·m] and extra driving torque [N·m] of geared counter-rotors, (N,) each.

    A rotor turning at -k·w_i has angular momentum -k·J·w_i: the frame feels -d/dt of it, k·J·alpha_i, and the
    crank supplies the rate of its kinetic energy k²·J·w_i·alpha_i over the crank speed.
    """
    moment = np.zeros(motion.samples)
    torque = np.zeros(motion.samples)
    for r in rotors:
        moment += r.ratio * r.inertia * motion.link_alpha[r.link]
        torque += r.ratio**2 * r.inertia * motion.link_omega[r.link] * motion.link_alpha[r.link] / motion.omega_crank
    return moment, torque


def rotor_inertia(motion: Motion, rotors: Sequence[CounterRotor]) -> tuple[FloatArray, FloatArray]:
    """The rotors' share of the reduced inertia, sum k²·J·(w_i/w)² [kg·m²], and its slope in phi [kg·m²/rad]."""
    w, eps = motion.omega_crank, motion.alpha_crank
    inertia = np.zeros(motion.samples)
    slope = np.zeros(motion.samples)
    for r in rotors:
        t1 = motion.link_omega[r.link] / w
        t2 = (motion.link_alpha[r.link] - eps * t1) / w**2
        inertia += r.ratio**2 * r.inertia * t1**2
        slope += 2 * r.ratio**2 * r.inertia * t1 * t2
    return inertia, slope
