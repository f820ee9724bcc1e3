"""Slider-crank balancing: crank counterweight for the rotating part, Lanchester balancer for the reciprocating
part's first and second orders (seed 003:673-733)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..analysis import Summary, analyse
from ..errors import InvalidInput
from ..kinematics import SliderCrank
from ..model import Counterweight, FloatArray, Linkage


@dataclass(frozen=True, slots=True)
class LanchesterPair:
    """Two shafts turning at ±``order`` times crank speed, each with ``mass`` [kg] at ``radius`` [m]."""

    order: int
    mass: float
    radius: float
    amplitude: float  # force amplitude it cancels [N]


@dataclass(frozen=True, slots=True)
class SliderCrankBalance:
    """Point-mass split, crank counterweight, Lanchester pairs, and the shaking force before and after.

    ``after_force`` is the plain engine's shaking force with the crank counterweight, plus the balancer shafts'
    inertia forces; ``residual`` its largest magnitude [N] (higher orders remain).
    """

    rotating_mass: float
    reciprocating_mass: float
    crank_counterweight: Counterweight
    pairs: tuple[LanchesterPair, ...]
    before: Summary
    after_force: FloatArray
    residual: float
    residual_rel: float
    first_order_amplitude: float
    second_order_amplitude: float


def balance_slider_crank(linkage: Linkage, speed: float, *, counterweight_radius: float | None = None,
                         balancer_radii: tuple[float, float] = (0.05, 0.05), orders: int = 2,
                         samples: int = 360) -> SliderCrankBalance:
    """Statically split the rod into its crank pin and slider, cancel the rotating part with a crank
    counterweight and the reciprocating part's orders with Lanchester pairs: m_k = m_B·r·A_k/(2·k²·rho_k)
    with A_1 = 1 and A_2 = r/l (so m_I = m_B·r/(2·rho_I), seed 6.32-6.33). The check is independent: the plain
    kinetostatic model with the counterweight, plus the balancer shafts' inertia forces.
    """
    mech = linkage.mechanism
    if not isinstance(mech, SliderCrank):
        raise InvalidInput("slider-crank balancing needs a slider_crank mechanism", field="mechanism.type")
    if mech.offset != 0:
        raise InvalidInput("the Lanchester split assumes an in-line slider-crank (offset 0)", field="mechanism.offset_m")
    if orders not in (1, 2):
        raise InvalidInput("orders must be 1 or 2", field="orders")
    r, l_ = mech.crank, mech.rod
    rc = counterweight_radius if counterweight_radius is not None else r
    for name, v in (("counterweight_radius_m", rc), ("balancer_radii_m", min(balancer_radii))):
        if not (math.isfinite(v) and v > 0):
            raise InvalidInput(f"{name} must be positive", field=name)
    rod, crank, slider = (linkage.params_of(n) for n in ("rod", "crank", "slider"))
    rod_b = rod[1] / l_  # static split of the rod: m_B·l = m_rod·x_rod
    m_a = rod[0] - rod_b
    m_b = slider[0] + rod_b
    crank_first = complex(crank[1], crank[2]) + m_a * r
    cw = Counterweight("crank", abs(crank_first) / rc,
                       (-crank_first.real / abs(crank_first) * rc, -crank_first.imag / abs(crank_first) * rc)
                       if abs(crank_first) > 0 else (0.0, 0.0))
    w = speed
    amps = [m_b * r * w**2, m_b * r * w**2 * r / l_]
    order_factor = [1.0, r / l_]
    pairs = tuple(
        LanchesterPair(k, m_b * r * order_factor[k - 1] / (2 * k**2 * balancer_radii[k - 1]), balancer_radii[k - 1],
                       amps[k - 1])
        for k in range(1, orders + 1)
    )
    before = analyse(linkage, speed, samples=samples)
    after = analyse(linkage.with_counterweights([cw]), speed, samples=samples)
    phi = after.motion.phi
    # Each pair's two shafts turn at +k·w and -k·w, phased so their masses meet on the slide axis, behind the
    # slider at phi = 0: together they put 2·m·rho·(k·w)²·cos(k·phi) on the frame along -x.
    balancer = np.zeros((len(phi), 2))
    for p in pairs:
        balancer[:, 0] -= 2 * p.mass * p.radius * (p.order * w) ** 2 * np.cos(p.order * phi)
    force = after.kinetostatics.shaking_force + balancer
    residual = float(np.hypot(*force.T).max())
    f0 = before.summary().max_shaking_force
    return SliderCrankBalance(m_a, m_b, cw, pairs, before.summary(), force, residual,
                              residual / f0 if f0 > 0 else 0.0, amps[0], amps[1])
