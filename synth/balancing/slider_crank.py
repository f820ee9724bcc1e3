"""Slider-crank balancing: crank counterweight for the rotating part, Lanchester balancer for the reciprocating
part's first and second orders (seed 003:673-733), in-line or offset (desaxé)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..analysis import Analysis, Summary, analyse
from ..errors import InvalidInput
from ..kinematics import SliderCrank
from ..model import Counterweight, FloatArray, Linkage


@dataclass(frozen=True, slots=True)
class LanchesterPair:
    """Two shafts turning at ±``order`` times crank speed, each with ``mass`` [kg] at ``radius`` [m].

    ``phase`` [rad], in [0, 2·pi): at crank angle 0 the mass on the shaft turning at -``order``·w (clockwise)
    points at ``phase`` counter-clockwise from +x (the slide direction), the one on the shaft at +``order``·w at
    -``phase``, its mirror image in the slide axis; both point along +x when ``order``·phi = ``phase``.
    ``amplitude``: the force amplitude it cancels [N]. The shafts sit in mirror image about the slide axis, the
    line y = offset, so the pair's force lies on that line wherever along it they are.
    """

    order: int
    mass: float
    radius: float
    amplitude: float
    phase: float


@dataclass(frozen=True, slots=True)
class SliderCrankBalance:
    """Point-mass split, crank counterweight, Lanchester pairs, and the shaking force and moment before and after.

    ``after_force`` is the plain engine's shaking force with the crank counterweight, plus the balancer masses'
    inertia forces; ``residual`` its largest magnitude [N]; ``residual_by_order`` the largest magnitude [N] of
    each crank-order harmonic of it (index 0 is order 1). ``after_moment`` is the plain engine's shaking moment
    about O with the counterweight plus the balancer masses' moment [N·m]; ``residual_moment`` its largest
    magnitude, ``balancer_moment`` the largest moment about O of the balancers alone, which act on the line
    y = ``balancer_line_y`` [m] (the slide axis). ``analysis_after`` is the plain engine's analysis with the
    counterweight, without the balancers.
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
    balancer_line_y: float
    after_moment: FloatArray
    residual_moment: float
    residual_moment_rel: float
    balancer_moment: float
    analysis_before: Analysis
    analysis_after: Analysis


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


def balancer_loads(pairs: tuple[LanchesterPair, ...], phi: FloatArray, speed: float,
                   line_y: float) -> tuple[FloatArray, FloatArray]:
    """Force (N, 2) [N] and moment about O (N,) [N·m] the balancer masses put on the frame at constant crank
    speed ``speed`` [rad/s], each mass followed on its own shaft as ``LanchesterPair`` places it.

    A pair's shafts are put at (0, ``line_y`` ± radius): any mirror-image placement about the line y =
    ``line_y`` [m] gives the same force and moment, the shafts' opposite y-forces making no couple.
    """
    force = np.zeros((len(phi), 2))
    moment = np.zeros(len(phi))
    for p in pairs:
        for turn, side in ((1.0, -1.0), (-1.0, 1.0)):
            angle = turn * (p.order * phi - p.phase)
            out = np.stack([np.cos(angle), np.sin(angle)], axis=-1)
            pull = p.mass * p.radius * (p.order * speed) ** 2 * out  # -m·a of a mass turning at a constant rate
            at = np.array([0.0, line_y + side * p.radius]) + p.radius * out
            force += pull
            moment += at[:, 0] * pull[:, 1] - at[:, 1] * pull[:, 0]
    return force, moment


def balance_slider_crank(linkage: Linkage, speed: float, *, counterweight_radius: float | None = None,
                         balancer_radii: tuple[float, float] = (0.05, 0.05), orders: int = 2,
                         samples: int = 360) -> SliderCrankBalance:
    """Statically split the rod into its crank pin and slider, cancel the rotating part with a crank
    counterweight and the reciprocating part's orders with Lanchester pairs.

    Each order is sized from the harmonic of the exact slider acceleration (an FFT of the engine's motion at
    constant crank speed ``speed`` [rad/s]), not from the series in lambda = r/l: with a_B's k-th harmonic of
    amplitude A_k·r·w² the pair needs m_k = m_B·r·A_k/(2·k²·rho_k) per shaft (A_1 = 1, A_2 ≈ r/l: the seed's
    6.32-6.33), and its phase is that harmonic's: the second order changes sign with the slider on the -x side,
    and an offset e gives the first order a sine part (about m_B·w²·r·e/l). The rest of x_B is a function of
    sin(phi), unchanged by phi -> pi - phi, so even orders stay cosines and the odd ones an offset adds are sines.
    The shafts sit in mirror image about the slide axis y = e, so the pairs' force is in line with the slider's
    and adds e times itself to the moment about O.
    ``balancer_radii`` [m] are rho_1, rho_2. The check is independent: the plain kinetostatic model with the
    counterweight, plus the balancer masses followed on their shafts, broken down by order.
    """
    mech = linkage.mechanism
    if not isinstance(mech, SliderCrank):
        raise InvalidInput("slider-crank balancing needs a slider_crank mechanism", field="mechanism.type")
    if orders not in (1, 2):
        raise InvalidInput("orders must be 1 or 2", field="orders")
    r, l_ = mech.crank, mech.rod
    rc = counterweight_radius if counterweight_radius is not None else r
    for name, v in (("counterweight_radius_m", rc), ("balancer_radii_m", min(balancer_radii))):
        if not (math.isfinite(v) and v > 0):
            raise InvalidInput(f"{name} must be positive", field=name)
    rod, crank, slider = (linkage.params_of(n) for n in ("rod", "crank", "slider"))
    # The static split is exact for the shaking force with or without an offset: a centre of mass on AB is the
    # fixed combination (1 - x/l)·A + (x/l)·B of the joints, so its acceleration is that of a_A and a_B. A centre
    # of mass off AB (the rod's m·y) is not split: the residual shows what it leaves.
    rod_b = rod[1] / l_  # m_B·l = m_rod·x_rod
    m_a = rod[0] - rod_b
    m_b = slider[0] + rod_b
    crank_first = complex(crank[1], crank[2]) + m_a * r
    cw = Counterweight("crank", abs(crank_first) / rc,
                       (-crank_first.real / abs(crank_first) * rc, -crank_first.imag / abs(crank_first) * rc)
                       if abs(crank_first) > 0 else (0.0, 0.0))
    w = speed
    before = analyse(linkage, speed, samples=samples)
    after = analyse(linkage.with_counterweights([cw]), speed, samples=samples, base_motion=before.mechanism_motion)
    phi = after.motion.phi
    # The reciprocating part puts -m_B·a_B on the frame along x; each order k of it is F_k·cos(k·phi - theta_k),
    # theta_k = 0 or pi in-line; an offset moves theta_1 off them.
    c, s = _harmonics(-m_b * before.motion.point_acc["B"][:, 0], max(orders, 2))
    amps = np.hypot(c, s)
    theta = np.arctan2(s, c)
    # A pair puts 2·m·rho·(k·w)²·cos(k·phi - psi) on the frame along +x, so psi = theta_k + pi cancels order k.
    pairs = tuple(
        LanchesterPair(k, float(amps[k - 1]) / (2 * balancer_radii[k - 1] * (k * w) ** 2), balancer_radii[k - 1],
                       float(amps[k - 1]), float((theta[k - 1] + math.pi) % (2 * math.pi)))
        for k in range(1, orders + 1)
    )
    line_y = mech.offset
    bal_force, bal_moment = balancer_loads(pairs, phi, w, line_y)
    force = after.kinetostatics.shaking_force + bal_force
    moment = after.kinetostatics.shaking_moment + bal_moment
    residual = float(np.hypot(*force.T).max())
    residual_moment = float(np.abs(moment).max())
    summary = before.summary()
    f0, m0 = summary.max_shaking_force, summary.max_shaking_moment
    by_order = _peak_by_order(force, min(RESIDUAL_ORDERS, samples // 2 - 1))
    return SliderCrankBalance(m_a, m_b, cw, pairs, summary, force, residual, residual / f0 if f0 > 0 else 0.0,
                              float(amps[0]), float(amps[1]), by_order, line_y, moment, residual_moment,
                              residual_moment / m0 if m0 > 0 else 0.0, float(np.abs(bal_moment).max()),
                              before, after)
