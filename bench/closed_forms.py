"""Vectorised numpy closed forms of whole analyses, written by hand per mechanism: the baselines of bench.analysis.

Each returns every array ``synth.analyse`` returns for that mechanism at constant crank speed (joint and centre of
mass kinematics, link angles and rates, all joint reactions and slide couples, driving torque, shaking force and
moment, the virtual-power torque, the reduced inertia, its slope, the reduced load torque and the kinetic energy),
keyed as :func:`engine_outputs` keys the engine's. The kinematics are the textbook ones (law of cosines or circle
intersection, the loop differentiated twice, Cramer's rule); the reactions come dyad by dyad from the moment
equations about the dyad's middle and outer joints, then the crank.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import synth

Outputs = dict[str, np.ndarray]


def _perp(v: np.ndarray) -> np.ndarray:
    return np.stack([-v[:, 1], v[:, 0]], axis=-1)


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.asarray(a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0])


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.asarray(a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1])


@dataclass
class _Body:
    """One link's centre of mass kinematics and its d'Alembert load: force ``f`` = m(g - a_S) [N] and moment
    ``m0`` about the frame origin [N·m] (inertia couple -J_S·alpha included)."""

    pos: np.ndarray
    vel: np.ndarray
    acc: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray
    mass: float
    inertia: float
    f: np.ndarray
    m0: np.ndarray


def _body(linkage: synth.Linkage, name: str, origin: tuple[np.ndarray, np.ndarray, np.ndarray],
          angle: np.ndarray, omega: np.ndarray, alpha: np.ndarray, g: np.ndarray) -> _Body:
    props = linkage.mass_props(name)
    c, s = np.cos(angle), np.sin(angle)
    r = np.stack([c * props.com[0] - s * props.com[1], s * props.com[0] + c * props.com[1]], axis=-1)
    kr = _perp(r)
    pos = origin[0] + r
    vel = origin[1] + omega[:, None] * kr
    acc = origin[2] + alpha[:, None] * kr - (omega * omega)[:, None] * r
    f = props.mass * (g - acc)
    return _Body(pos, vel, acc, omega, alpha, props.mass, props.inertia, f, _cross(pos, f) - props.inertia * alpha)


def _rrr(p_in: np.ndarray, p_mid: np.ndarray, p_out: np.ndarray, one: _Body, two: _Body,
         extra2: tuple[np.ndarray, np.ndarray] | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Reactions of an RRR dyad: link ``one`` from p_in to p_mid, link ``two`` from p_mid to p_out on the frame;
    ``extra2`` is a further (force, moment about the origin) on link two. Returns the force on ``one`` at p_in,
    the force of ``one`` on ``two`` at p_mid and the frame's force on ``two`` at p_out."""
    f2, m2 = (two.f, two.m0) if extra2 is None else (two.f + extra2[0], two.m0 + extra2[1])
    u, v = p_in - p_mid, p_mid - p_out
    c1 = -(one.m0 - _cross(p_mid, one.f))
    c2 = -(_cross(v, one.f) + m2 - _cross(p_out, f2))
    det = _cross(u, v)
    r_in = (c1[:, None] * v - c2[:, None] * u) / det[:, None]
    r_mid = r_in + one.f
    return r_in, r_mid, -r_mid - f2


def _rrp(p_in: np.ndarray, p_mid: np.ndarray, normal: np.ndarray, one: _Body,
         two: _Body) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Reactions of an RRP dyad: rod ``one`` from p_in to p_mid, slider ``two`` at p_mid on a fixed guide of unit
    normal ``normal``. Returns the force on the rod at p_in, the rod's force on the slider, the guide's normal
    force on the slider (its normal force acting at p_mid) and the guide's couple on the slider."""
    u = p_in - p_mid
    c1 = -(one.m0 - _cross(p_mid, one.f))
    total = one.f + two.f
    n_force = -(c1 + _cross(u, total)) / _cross(u, normal)
    r_in = -n_force[:, None] * normal - total
    couple = -(two.m0 - _cross(p_mid, two.f))
    return r_in, r_in + one.f, n_force[:, None] * normal, couple


def _crank(p_pin: np.ndarray, r_pin: np.ndarray, crank: _Body) -> tuple[np.ndarray, np.ndarray]:
    """Frame reaction at O (the origin) and the driving torque of a crank whose pin at p_pin pushes its dyad
    with the force r_pin."""
    return r_pin - crank.f, _cross(p_pin, r_pin) - crank.m0


def _totals(out: Outputs, bodies: dict[str, _Body], frame_forces: list[tuple[np.ndarray, np.ndarray]],
            frame_couples: list[np.ndarray], torque: np.ndarray, omega: float, g: np.ndarray) -> None:
    """Shaking force and moment, virtual-power torque and the reduced model from the bodies and the frame's
    reactions (pairs of point and force of the frame on the linkage)."""
    shaking = -sum((b.mass * b.acc for b in bodies.values()), np.zeros_like(torque[:, None] * g))
    moment = -torque - sum((_cross(p, r) for p, r in frame_forces), np.zeros_like(torque))
    moment = moment - sum(frame_couples, np.zeros_like(torque))
    moment = moment - sum((b.mass * _cross(b.pos, np.broadcast_to(g, b.pos.shape)) for b in bodies.values()),
                          np.zeros_like(torque))
    power = sum((_dot(b.f, b.vel) - b.inertia * b.alpha * b.omega for b in bodies.values()), np.zeros_like(torque))
    inertia = sum(((b.mass * _dot(b.vel, b.vel) + b.inertia * b.omega**2) / omega**2 for b in bodies.values()),
                  np.zeros_like(torque))
    slope = sum((2 * (b.mass * _dot(b.vel, b.acc) + b.inertia * b.omega * b.alpha) / omega**3
                 for b in bodies.values()), np.zeros_like(torque))
    load = sum((b.mass * _dot(b.vel, np.broadcast_to(g, b.vel.shape)) for b in bodies.values()),
               np.zeros_like(torque)) / omega
    out.update({"driving_torque": torque, "shaking_force": shaking, "shaking_moment": moment,
                "virtual_power_torque": -power / omega, "reduced_inertia": inertia, "inertia_slope": slope,
                "load_torque": load, "kinetic_energy": 0.5 * inertia * omega**2})
    for name, b in bodies.items():
        out[f"S_{name}.pos"], out[f"S_{name}.vel"], out[f"S_{name}.acc"] = b.pos, b.vel, b.acc


def _gravity(linkage: synth.Linkage) -> np.ndarray:
    return linkage.gravity.vector if linkage.gravity is not None else np.zeros(2)


def _crank_pin(a: float, phi: np.ndarray, omega: float) -> tuple[np.ndarray, tuple[np.ndarray, ...]]:
    e1 = np.stack([np.cos(phi), np.sin(phi)], axis=-1)
    return e1, (a * e1, a * omega * _perp(e1), -a * omega**2 * e1)


def _still(n: int, xy: tuple[float, float]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return np.broadcast_to(np.asarray(xy, dtype=float), (n, 2)), np.zeros((n, 2)), np.zeros((n, 2))


def _angle(out: Outputs, name: str, angle: np.ndarray, omega: np.ndarray, alpha: np.ndarray) -> None:
    out[f"{name}.angle"], out[f"{name}.omega"], out[f"{name}.alpha"] = angle, omega, alpha


def _point(out: Outputs, name: str, state: tuple[np.ndarray, ...]) -> None:
    out[f"{name}.pos"], out[f"{name}.vel"], out[f"{name}.acc"] = state


def fourbar(linkage: synth.Linkage, phi: np.ndarray, omega: float) -> Outputs:
    """Four-bar O-A-B-Q: B by the law of cosines, rates by Cramer's rule on the differentiated loop, the
    coupler-rocker dyad, then the crank; the transmission angle too."""
    fb = linkage.mechanism
    assert isinstance(fb, synth.FourBar)
    a, b, c, d = fb.crank, fb.coupler, fb.rocker, fb.ground
    n, g, zero = len(phi), _gravity(linkage), np.zeros_like(phi)
    e1, pin = _crank_pin(a, phi, omega)
    q = np.array([d, 0.0])
    aq = q - pin[0]
    dist = np.hypot(aq[:, 0], aq[:, 1])
    t2 = np.arctan2(aq[:, 1], aq[:, 0]) + fb.branch * np.arccos((b * b + dist * dist - c * c) / (2 * b * dist))
    e2 = np.stack([np.cos(t2), np.sin(t2)], axis=-1)
    pb = pin[0] + b * e2
    e3 = (pb - q) / c
    t3 = np.arctan2(e3[:, 1], e3[:, 0])
    s32 = _cross(e2, e3)
    w2 = -a * omega * _cross(e1, e3) / (b * s32)
    w3 = -a * omega * _cross(e1, e2) / (c * s32)
    rhs = a * omega**2 * e1 + b * (w2**2)[:, None] * e2 - c * (w3**2)[:, None] * e3
    al2 = _dot(rhs, e3) / (b * s32)
    al3 = _dot(rhs, e2) / (c * s32)
    k3 = _perp(e3)
    b_state = (pb, c * w3[:, None] * k3, c * (al3[:, None] * k3 - (w3**2)[:, None] * e3))
    bodies = {
        "crank": _body(linkage, "crank", _still(n, (0.0, 0.0)), phi, np.full(n, omega), zero, g),
        "coupler": _body(linkage, "coupler", pin, t2, w2, al2, g),
        "rocker": _body(linkage, "rocker", _still(n, (d, 0.0)), t3, w3, al3, g),
    }
    r_a, r_b, r_q = _rrr(pin[0], pb, np.broadcast_to(q, pb.shape), bodies["coupler"], bodies["rocker"])
    r_o, torque = _crank(pin[0], r_a, bodies["crank"])
    out: Outputs = {"O": r_o, "A": r_a, "B": r_b, "Q": r_q}
    _point(out, "A", pin)
    _point(out, "B", b_state)
    _angle(out, "crank", phi, np.full(n, omega), zero)
    _angle(out, "coupler", np.arctan2(e2[:, 1], e2[:, 0]), w2, al2)
    _angle(out, "rocker", t3, w3, al3)
    diff = np.mod(t3 - t2, 2 * np.pi)
    out["transmission_angle"] = np.where(diff > np.pi, 2 * np.pi - diff, diff)
    _totals(out, bodies, [(np.broadcast_to(q, pb.shape), r_q)], [], torque, omega, g)
    return out


def slider_crank(linkage: synth.Linkage, phi: np.ndarray, omega: float) -> Outputs:
    """Slider-crank O-A-B on the line y = offset: the rod angle from its sine, the rod-slider dyad (RRP), then
    the crank."""
    sc = linkage.mechanism
    assert isinstance(sc, synth.SliderCrank)
    a, l_, e = sc.crank, sc.rod, sc.offset
    n, g, zero = len(phi), _gravity(linkage), np.zeros_like(phi)
    e1, pin = _crank_pin(a, phi, omega)
    sin2 = (e - pin[0][:, 1]) / l_
    cos2 = sc.branch * np.sqrt(1.0 - sin2 * sin2)
    e2 = np.stack([cos2, sin2], axis=-1)
    w2 = -omega * pin[0][:, 0] / (l_ * cos2)                       # a cos(phi) w + l cos(t2) w2 = 0
    al2 = (omega**2 * pin[0][:, 1] + l_ * sin2 * w2**2) / (l_ * cos2)
    k2 = _perp(e2)
    pb = pin[0] + l_ * e2
    b_state = (pb, pin[1] + l_ * w2[:, None] * k2, pin[2] + l_ * (al2[:, None] * k2 - (w2**2)[:, None] * e2))
    bodies = {
        "crank": _body(linkage, "crank", _still(n, (0.0, 0.0)), phi, np.full(n, omega), zero, g),
        "rod": _body(linkage, "rod", pin, np.arctan2(sin2, cos2), w2, al2, g),
        "slider": _body(linkage, "slider", b_state, zero, zero, zero, g),
    }
    normal = np.broadcast_to([0.0, 1.0], pb.shape)
    r_a, r_b, r_guide, couple = _rrp(pin[0], pb, normal, bodies["rod"], bodies["slider"])
    r_o, torque = _crank(pin[0], r_a, bodies["crank"])
    out: Outputs = {"O": r_o, "A": r_a, "B": r_b, "guide": r_guide, "guide.couple": couple}
    _point(out, "A", pin)
    _point(out, "B", b_state)
    _angle(out, "crank", phi, np.full(n, omega), zero)
    _angle(out, "rod", np.arctan2(sin2, cos2), w2, al2)
    _totals(out, bodies, [(pb, r_guide)], [couple], torque, omega, g)
    return out


def six_bar_press(linkage: synth.Linkage, phi: np.ndarray, omega: float) -> Outputs:
    """The six-bar press of ``SIX_BAR_PRESS_EXAMPLE``: kinematics from bench.linkage's hand-written solution, the
    rod-ram dyad (RRP on the vertical guide) first, its reaction at C loading the rocker, then the coupler-rocker
    dyad and the crank."""
    from bench.linkage import by_hand

    n, g = len(phi), _gravity(linkage)
    hand = by_hand(phi)

    def state(name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        pos, d1, d2 = hand[name]
        return pos, omega * d1, omega**2 * d2

    def turning(name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        angle, d1, d2 = hand[name]
        return angle, omega * d1, omega**2 * d2

    pa, pb, pc, pd = (state(p) for p in "ABCD")
    pq = _still(n, (0.3, 0.0))
    zero = np.zeros(n)
    bodies = {
        "crank": _body(linkage, "crank", _still(n, (0.0, 0.0)), phi, np.full(n, omega), zero, g),
        "coupler": _body(linkage, "coupler", pa, *turning("coupler"), g),
        "rocker": _body(linkage, "rocker", pq, *turning("rocker"), g),
        "rod": _body(linkage, "rod", pc, *turning("rod"), g),
        "ram": _body(linkage, "ram", pd, zero, zero, zero, g),
    }
    normal = np.broadcast_to([-1.0, 0.0], (n, 2))          # the guide's axis at 90 degrees
    r_c, r_d, r_guide, couple = _rrp(pc[0], pd[0], normal, bodies["rod"], bodies["ram"])
    # The rod pulls on the rocker at C with -r_c.
    r_a, r_b, r_q = _rrr(pa[0], pb[0], pq[0], bodies["coupler"], bodies["rocker"], (-r_c, _cross(pc[0], -r_c)))
    r_o, torque = _crank(pa[0], r_a, bodies["crank"])
    out: Outputs = {"O": r_o, "A": r_a, "B": r_b, "Q": r_q, "C": r_c, "D": r_d, "guide": r_guide,
                    "guide.couple": couple}
    for p, s in zip("ABCD", (pa, pb, pc, pd), strict=True):
        _point(out, p, s)
    _angle(out, "crank", phi, np.full(n, omega), zero)
    for link in ("coupler", "rocker", "rod"):
        _angle(out, link, *turning(link))
    _totals(out, bodies, [(pq[0], r_q), (pd[0], r_guide)], [couple], torque, omega, g)
    return out


def engine_outputs(an: synth.Analysis, keys: list[str]) -> Outputs:
    """The engine's arrays under the closed forms' keys."""
    m, k, r = an.motion, an.kinetostatics, an.reduced
    table: Outputs = {
        "driving_torque": k.driving_torque, "shaking_force": k.shaking_force, "shaking_moment": k.shaking_moment,
        "virtual_power_torque": an.virtual_power_torque, "reduced_inertia": r.inertia,
        "inertia_slope": r.inertia_slope, "load_torque": r.load_torque, "kinetic_energy": r.kinetic_energy,
    }
    if (tau := an.transmission_angle) is not None:
        table["transmission_angle"] = tau
    out: Outputs = {}
    for key in keys:
        name, _, part = key.partition(".")
        if key in table:
            out[key] = table[key]
        elif not part:
            out[key] = k.reactions[name]
        elif part == "couple":
            out[key] = k.couples[name]
        elif name in m.link_angle and part in ("angle", "omega", "alpha"):
            out[key] = {"angle": m.link_angle, "omega": m.link_omega, "alpha": m.link_alpha}[part][name]
        else:
            out[key] = {"pos": m.point_pos, "vel": m.point_vel, "acc": m.point_acc}[part][name]
    return out


def worst_relative_difference(engine: Outputs, closed: Outputs) -> tuple[float, str]:
    """Largest |engine - closed form| over each array's scale (its largest magnitude, at least 1), and where.
    Angles are compared on the circle."""
    worst, where = 0.0, ""
    for key, ref in closed.items():
        diff = np.asarray(engine[key]) - ref
        if key.endswith(".angle"):
            diff = np.angle(np.exp(1j * diff))
        rel = float(np.abs(diff).max()) / max(1.0, float(np.abs(ref).max()))
        if rel > worst:
            worst, where = rel, key
    return worst, where
