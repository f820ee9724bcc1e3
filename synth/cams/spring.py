"""The cam's return spring as a helical compression spring of round wire: what the rate and preload ask of it.

The least spring (:mod:`synth.cams.forces`) keeps the contact force above its margin at the least largest spring
force, with the initial compression bounded (default the follower's total lift), so that it is a spring and not a
constant force. Here it becomes a coil (Shigley's Mechanical Engineering Design, 10th ed., ch. 10): for the
spring index C = D/d, the Bergsträsser factor K_B = (4C + 2)/(4C - 3) and the largest force F_max, the wire
diameter d solves K_B·8·F_max·C/(π·d²) = s·S_ut(d), S_ut = A/d^m (table 10-4; s the allowable fraction of
table 10-6, set not removed), thickened when the fatigue factor (below) asks more; D = C·d; active coils n_a = G·d/(8·C³·k); squared and ground ends add two
coils to the solid length L_s = (n_a + 2)·d; free length L_0 = L_s + (1 + 0.15)·y_max with y_max the initial
compression plus the lift (15 % overrun to solid); installed length L_0 less the initial compression. The
surge frequency between two flat plates is f = (1/2)·sqrt(k/m_a), m_a = ρ·π²·d²·D·n_a/4, held at 13 times the
cam's frequency or more (the harmonics of a cam law carry energy up to about the 13th) and apart from every
harmonic of the follower's acceleration that carries 1 % of the largest. Fatigue by the Zimmerli data
(unpeened, S_sa = 241 MPa, S_sm = 379 MPa) on a Goodman line with S_su = 0.67·S_ut; buckling by the free
length over the coil diameter, at most 5.26 between flat parallel plates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InvalidInput
from ..model import FloatArray
from ..warnings import DesignWarning, ValidityCheck

#: Wire materials: S_ut = A/d^m with A [MPa·mm^m] and m (Shigley table 10-4), shear modulus G [Pa] (table 10-5),
#: the allowable static torsional stress as a fraction of S_ut (table 10-6, set not removed), density [kg/m³].
WIRES: dict[str, tuple[float, float, float, float, float]] = {
    "music_wire": (2211.0, 0.145, 81.7e9, 0.45, 7850.0),
    "oil_tempered": (1855.0, 0.187, 77.2e9, 0.50, 7850.0),
    "hard_drawn": (1783.0, 0.190, 80.0e9, 0.45, 7850.0),
    "chrome_vanadium": (2005.0, 0.168, 77.2e9, 0.50, 7850.0),
    "chrome_silicon": (1974.0, 0.108, 77.2e9, 0.50, 7850.0),
    "stainless_302": (1867.0, 0.146, 69.0e9, 0.35, 7920.0),
}
OVERRUN = 0.15
SURGE_ORDER = 13.0
ZIMMERLI_SA, ZIMMERLI_SM = 241e6, 379e6
MAX_SLENDERNESS = 5.26
#: A harmonic of the follower's acceleration within this fraction of the surge frequency excites it.
SURGE_BAND = 0.1
#: Harmonics below this fraction of the largest carry no energy worth a warning.
HARMONIC_SHARE = 0.01


@dataclass(frozen=True, slots=True)
class CoilSpring:
    """A helical compression spring: ``wire`` material, wire ``diameter`` d and mean coil diameter D [m], spring
    ``index`` C [-], ``active_coils`` n_a [-], ``free_length``, ``installed_length`` (at the follower's lowest
    position) and ``solid_length`` [m], ``initial_compression`` [m], ``max_force`` [N], ``max_stress`` [Pa],
    ``allowable_stress`` [Pa], ``fatigue_factor`` (Goodman, Zimmerli data) [-], ``surge_frequency`` [Hz],
    ``surge_order`` the surge frequency over the cam's [-], ``mass`` of the active coils [kg]."""

    wire: str
    diameter: float
    mean_diameter: float
    index: float
    active_coils: float
    free_length: float
    installed_length: float
    solid_length: float
    initial_compression: float
    max_force: float
    max_stress: float
    allowable_stress: float
    fatigue_factor: float
    surge_frequency: float
    surge_order: float
    mass: float


def coil_spring(stiffness: float, preload: float, lift: float, speed: float, acceleration: FloatArray,
                wire: str = "music_wire", index: float = 8.0) -> tuple[CoilSpring, list[DesignWarning],
                                                                       list[ValidityCheck]]:
    """The coil for rate ``stiffness`` [N/m] and ``preload`` [N] over the follower's ``lift`` [m] at cam
    ``speed`` [rad/s]; ``acceleration`` the follower's d²s/dθ² at uniform cam angles over the turn (its
    harmonics against the surge frequency)."""
    if wire not in WIRES:
        raise InvalidInput(f"unknown spring wire {wire!r}; one of {sorted(WIRES)}", field="loads.spring_wire")
    if not 4.0 <= index <= 12.0:
        raise InvalidInput("the spring index D/d must lie in [4, 12]", field="loads.spring_index")
    if not (stiffness > 0 and preload >= 0 and lift > 0):
        raise InvalidInput("a coil needs a positive rate and lift", field="loads.spring_stiffness_N_m")
    a_coef, m_exp, shear, share, density = WIRES[wire]
    f_max = stiffness * lift + preload
    f_min = preload
    kb = (4 * index + 2) / (4 * index - 3)
    d = 1e-3
    for _ in range(60):
        sut = float(a_coef / (d * 1e3) ** m_exp * 1e6)
        new = math.sqrt(kb * 8 * f_max * index / (math.pi * share * sut))
        if abs(new - d) <= 1e-12 * new:
            break
        d = new
    d = new

    def fatigue_at(d: float) -> float:
        sut = float(a_coef / (d * 1e3) ** m_exp * 1e6)
        ssu = 0.67 * sut
        sse = ZIMMERLI_SA / (1 - ZIMMERLI_SM / ssu)
        per_newton = kb * 8 * index / (math.pi * d**2)
        return float(1.0 / (0.5 * (f_max - f_min) * per_newton / sse + 0.5 * (f_max + f_min) * per_newton / ssu))

    # the wire thickened until the Goodman line holds too (the stresses fall as 1/d², the strengths slowly)
    for _ in range(60):
        fatigue = fatigue_at(d)
        if fatigue >= 1.0:
            break
        d *= math.sqrt(1.0 / fatigue) * (1 + 1e-9)
    fatigue = fatigue_at(d)
    sut = a_coef / (d * 1e3) ** m_exp * 1e6
    mean = index * d
    active = shear * d / (8 * index**3 * stiffness)
    solid = (active + 2) * d
    delta0 = preload / stiffness
    free = solid + (1 + OVERRUN) * (delta0 + lift)
    installed = free - delta0
    tau_max = kb * 8 * f_max * mean / (math.pi * d**3)
    mass = density * math.pi**2 * d**2 * mean * active / 4
    surge = 0.5 * math.sqrt(stiffness / mass)
    cam_hz = speed / (2 * math.pi)
    order = surge / cam_hz
    coil = CoilSpring(wire, d, mean, index, active, free, installed, solid, delta0, f_max, tau_max, share * sut,
                      fatigue, surge, order, mass)
    notes: list[DesignWarning] = []
    checks = [ValidityCheck("spring_surge", order, SURGE_ORDER, order >= SURGE_ORDER,
                            "the spring's surge frequency over the cam's frequency, against the 13th harmonic"),
              ValidityCheck("spring_fatigue", fatigue, 1.0, fatigue >= 1.0,
                            "the coil's fatigue factor (Goodman line, Zimmerli's unpeened data)"),
              ValidityCheck("spring_buckling", free / mean, MAX_SLENDERNESS, free / mean <= MAX_SLENDERNESS,
                            "free length over mean coil diameter against 5.26 (flat parallel plates)")]
    spectrum = np.abs(np.fft.rfft(acceleration))[1:]
    if spectrum.size and spectrum.max() > 0:
        orders = np.arange(1, spectrum.size + 1)
        strong = spectrum >= HARMONIC_SHARE * spectrum.max()
        near = strong & (np.abs(orders - order) <= SURGE_BAND * order)
        if near.any():
            n = int(orders[near][np.argmax(spectrum[near])])
            checks.append(ValidityCheck("spring_surge_harmonic", float(n), order, False,
                                        "a harmonic of the follower's acceleration within 10 % of the surge "
                                        "frequency (its order, against the surge's)"))
            notes.append(DesignWarning(
                "spring_surge", "loads.spring_index", surge,
                f"harmonic {n} of the follower's acceleration ({n * cam_hz:.4g} Hz, "
                f"{spectrum[n - 1] / spectrum.max():.2%} of the largest) lies within 10 % of the spring's surge "
                f"frequency {surge:.4g} Hz: the coils resonate and the force the spring holds is lost", "Hz"))
    if order < SURGE_ORDER:
        notes.append(DesignWarning(
            "spring_surge", "loads.spring_index", surge,
            f"the spring surges at {surge:.4g} Hz, only {order:.3g} times the cam's {cam_hz:.4g} Hz (at least 13): "
            "the law's harmonics excite its coils; a smaller index or a stiffer wire", "Hz"))
    if fatigue < 1.0:
        notes.append(DesignWarning(
            "spring_fatigue", "loads.spring_wire", fatigue,
            f"the coil's fatigue factor is {fatigue:.3g} (below 1 on the Goodman line, unpeened): it breaks in "
            "service; a shot-peened or stronger wire, or a longer initial compression", "1"))
    if free / mean > MAX_SLENDERNESS:
        notes.append(DesignWarning(
            "spring_buckling", "loads.spring_index", free / mean,
            f"the free length is {free / mean:.3g} times the coil diameter (beyond 5.26): the spring buckles "
            "unless guided on a rod or in a bore", "1"))
    return coil, notes, checks
