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
    """Two shafts turning at ±``order`` times crank speed, each with ``mass`` [kg] at ``radius`` [m].

    ``phase``: the shafts are set so that both masses point along +x (the slide direction) when
    ``order``·phi = ``phase`` [rad], in [0, 2·pi); ``amplitude``: the force amplitude it cancels [N].
    """

    order: int
    mass: float
    radius: float
    amplitude: float
    phase: float


@dataclass(frozen=True, slots=True)
class SliderCrankBalance:
    """Point-mass split, crank counterweight, Lanchester pairs, and the shaking force before and after.

    ``after_force`` is the plain engine's shaking force with the crank counterweight, plus the balancer shafts'
    inertia forces; ``residual`` its largest magnitude [N]; ``residual_by_order`` the largest magnitude [N] of
    each crank-order harmonic of it (index 0 is order 1).
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
    residual_by_order: tuple[float, ...]


#: Orders reported in the residual breakdown.
RESIDUAL_ORDERS = 6


def _harmonics(series: FloatArray, orders: int) -> tuple[FloatArray, FloatArray]:
    """Cosine and sine coefficients of crank orders 1..``orders`` of a series over one cycle at uniform angles.

    ``series`` (N,) or (N, d) sampled at phi_i = 2·pi·i/N: series ≈ sum_k c_k·cos(k·phi) + s_k·sin(k·phi);
    returns c, s of shape (orders,) or (orders, d). Computed by a real FFT (numpy.fft.rfft).
    """
    n = series.shape[0]
    if orders >= n // 2:
        raise InvalidInput(f"{orders} orders need more than {2 * orders} samples per cycle", field="samples")
    spec = np.fft.rfft(series, axis=0)[1:orders + 1] * (2.0 / n)
    return spec.real, -spec.imag


def _peak_by_order(force: FloatArray, orders: int) -> tuple[float, ...]:
    """Largest magnitude [N] over the cycle of each order's part of a planar force (N, 2): the major semi-axis
    of the ellipse c_k·cos(k·phi) + s_k·sin(k·phi) traces, the largest singular value of [c_k s_k]."""
    c, s = _harmonics(force, orders)
    return tuple(float(v) for v in np.linalg.svd(np.stack([c, s], axis=2), compute_uv=False)[:, 0])


def balance_slider_crank(linkage: Linkage, speed: float, *, counterweight_radius: float | None = None,
                         balancer_radii: tuple[float, float] = (0.05, 0.05), orders: int = 2,
                         samples: int = 360) -> SliderCrankBalance:
    """Statically split the rod into its crank pin and slider, cancel the rotating part with a crank
    counterweight and the reciprocating part's orders with Lanchester pairs.

    Each order is sized from the harmonic of the exact slider acceleration (an FFT of the engine's motion at
    constant crank speed ``speed`` [rad/s]), not from the series in lambda = r/l: with a_B's k-th harmonic of
    amplitude A_k·r·w² the pair needs m_k = m_B·r·A_k/(2·k²·rho_k) per shaft (A_1 = 1, A_2 ≈ r/l: the seed's
    6.32-6.33), and its phase follows the branch (the second order changes sign with the slider on the -x side).
    ``balancer_radii`` [m] are rho_1, rho_2. The check is independent: the plain kinetostatic model with the
    counterweight, plus the balancer shafts' inertia forces, broken down by order.
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
    before = analyse(linkage, speed, samples=samples)
    after = analyse(linkage.with_counterweights([cw]), speed, samples=samples)
    phi = after.motion.phi
    # The reciprocating part puts -m_B·a_B on the frame along x; each order k of it is F_k·cos(k·phi - theta_k).
    c, s = _harmonics(-m_b * before.motion.point_acc["B"][:, 0], max(orders, 2))
    amps = np.hypot(c, s)
    theta = np.arctan2(s, c)
    # A pair's two shafts turn at +k·w and -k·w with both masses along +x when k·phi = psi: together they put
    # 2·m·rho·(k·w)²·cos(k·phi - psi) on the frame along +x, so psi = theta_k + pi cancels order k.
    pairs = tuple(
        LanchesterPair(k, float(amps[k - 1]) / (2 * balancer_radii[k - 1] * (k * w) ** 2), balancer_radii[k - 1],
                       float(amps[k - 1]), float((theta[k - 1] + math.pi) % (2 * math.pi)))
        for k in range(1, orders + 1)
    )
    balancer = np.zeros((len(phi), 2))
    for p in pairs:
        balancer[:, 0] += 2 * p.mass * p.radius * (p.order * w) ** 2 * np.cos(p.order * phi - p.phase)
    force = after.kinetostatics.shaking_force + balancer
    residual = float(np.hypot(*force.T).max())
    f0 = before.summary().max_shaking_force
    by_order = _peak_by_order(force, min(RESIDUAL_ORDERS, samples // 2 - 1))
    return SliderCrankBalance(m_a, m_b, cw, pairs, before.summary(), force, residual,
                              residual / f0 if f0 > 0 else 0.0, float(amps[0]), float(amps[1]), by_order)
