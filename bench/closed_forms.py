"""Vectorised numpy closed forms of whole analyses, written by hand per mechanism: the baselines of bench.analysis.

Each returns every array ``synth.analyse`` returns for that mechanism at constant crank speed (joint and centre of
mass kinematics, link angles and rates, all joint reactions and slide couples, driving torque, shaking force and
moment, the virtual-power torque, the reduced inertia, its slope, the reduced load torque and the kinetic energy),
keyed as :func:`engine_outputs` keys the engine's. The kinematics are the textbook ones (circle intersection, the
loop differentiated twice, Cramer's rule); the reactions come dyad by dyad from the moment equations about the
dyad's middle and outer joints, then the crank.

Plane vectors are complex numbers throughout, the fastest way numpy offers to write plane geometry: a vector
operation is one array operation over contiguous memory, a turn by 90 degrees a product by i, and an (N, 2) answer
a view of the complex array with no copy.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import synth

Outputs = dict[str, np.ndarray]


def xy(z: np.ndarray) -> np.ndarray:
    """Complex plane vectors (N,) as real ones (N, 2), a view."""
    return z.view(np.float64).reshape(-1, 2)


def cross(a: np.ndarray | complex, b: np.ndarray | complex) -> np.ndarray:
    return np.asarray((np.conj(a) * b).imag)


def dot(a: np.ndarray | complex, b: np.ndarray | complex) -> np.ndarray:
    return np.asarray((np.conj(a) * b).real)


@dataclass
class _Body:
    """One link's centre of mass kinematics (complex) and its d'Alembert load: force ``f`` = m(g - a_S) [N] and
    moment ``m0`` about the frame origin [N·m] (inertia couple -J_S·alpha included)."""

    pos: np.ndarray
    vel: np.ndarray
    acc: np.ndarray
    omega: np.ndarray | float
    alpha: np.ndarray | float
    mass: float
    inertia: float
    f: np.ndarray
    m0: np.ndarray


def _body(linkage: synth.Linkage, name: str, origin: tuple[np.ndarray | complex, ...], e: np.ndarray,
          omega: np.ndarray | float, alpha: np.ndarray | float, g: complex) -> _Body:
    """``e`` is the link's unit vector (complex) and ``origin`` its frame origin's position, velocity and
    acceleration."""
    props = linkage.mass_props(name)
    r = e * complex(props.com[0], props.com[1])
    pos = origin[0] + r
    vel = origin[1] + (1j * omega) * r
    acc = origin[2] + (1j * alpha - omega * omega) * r
    f = props.mass * (g - acc)
    return _Body(pos, vel, acc, omega, alpha, props.mass, props.inertia, f, cross(pos, f) - props.inertia * alpha)


def _rrr(p_in: np.ndarray, p_mid: np.ndarray, p_out: complex, one: _Body, two: _Body,
         extra2: tuple[np.ndarray, np.ndarray] | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Reactions of an RRR dyad: link ``one`` from p_in to p_mid, link ``two`` from p_mid to p_out on the frame;
    ``extra2`` is a further (force, moment about the origin) on link two. Returns the force on ``one`` at p_in,
    the force of ``one`` on ``two`` at p_mid and the frame's force on ``two`` at p_out."""
    f2, m2 = (two.f, two.m0) if extra2 is None else (two.f + extra2[0], two.m0 + extra2[1])
    u, v = p_in - p_mid, p_mid - p_out
    c1 = cross(p_mid, one.f) - one.m0
    c2 = cross(p_out, f2) - cross(v, one.f) - m2
    r_in = (c1 * v - c2 * u) / cross(u, v)
    r_mid = r_in + one.f
    return r_in, r_mid, -r_mid - f2


def _rrp(p_in: np.ndarray, p_mid: np.ndarray, normal: complex, one: _Body,
         two: _Body) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Reactions of an RRP dyad: rod ``one`` from p_in to p_mid, slider ``two`` at p_mid on a fixed guide of unit
    normal ``normal``. Returns the force on the rod at p_in, the rod's force on the slider, the guide's normal
    force on the slider (acting at p_mid) and the guide's couple on the slider."""
    u = p_in - p_mid
    c1 = cross(p_mid, one.f) - one.m0
    total = one.f + two.f
    n_force = -(c1 + cross(u, total)) / cross(u, normal)
    r_in = -n_force * normal - total
    couple = cross(p_mid, two.f) - two.m0
    return r_in, r_in + one.f, n_force * normal, couple


def _crank(p_pin: np.ndarray, r_pin: np.ndarray, crank: _Body) -> tuple[np.ndarray, np.ndarray]:
    """Frame reaction at O (the origin) and the driving torque of a crank whose pin at p_pin pushes its dyad
    with the force r_pin."""
    return r_pin - crank.f, cross(p_pin, r_pin) - crank.m0


def _totals(out: Outputs, bodies: dict[str, _Body], frame_moment: np.ndarray, torque: np.ndarray, omega: float,
            g: complex, n: int) -> None:
    """Shaking force and moment, virtual-power torque and the reduced model from the bodies; ``frame_moment`` is
    the moment about O of the frame's reactions on the linkage (forces and couples) other than at O."""
    shaking = np.zeros(n, dtype=complex)
    moment = -torque - frame_moment
    power = np.zeros(n)
    inertia = np.zeros(n)
    slope = np.zeros(n)
    load = np.zeros(n)
    for b in bodies.values():
        shaking -= b.mass * b.acc
        moment = moment - b.mass * cross(b.pos, g)
        power += dot(b.f, b.vel) - b.inertia * b.alpha * b.omega
        inertia += b.mass * dot(b.vel, b.vel) + b.inertia * b.omega * b.omega
        slope += b.mass * dot(b.vel, b.acc) + b.inertia * b.omega * b.alpha
        load += b.mass * dot(b.vel, g)
    inertia /= omega * omega
    out.update({"driving_torque": torque, "shaking_force": xy(shaking), "shaking_moment": moment,
                "virtual_power_torque": -power / omega, "reduced_inertia": inertia,
                "inertia_slope": 2 * slope / omega**3, "load_torque": load / omega,
                "kinetic_energy": 0.5 * inertia * omega**2})
    for name, b in bodies.items():
        for part, z in (("pos", b.pos), ("vel", b.vel), ("acc", b.acc)):
            out[f"S_{name}.{part}"] = xy(np.broadcast_to(z, (n,)).copy() if np.ndim(z) == 0 else z)


def _gravity(linkage: synth.Linkage) -> complex:
    g = linkage.gravity.vector if linkage.gravity is not None else np.zeros(2)
    return complex(g[0], g[1])


def _unit(phi: np.ndarray) -> np.ndarray:
    e = np.empty((len(phi), 2))
    np.cos(phi, out=e[:, 0])
    np.sin(phi, out=e[:, 1])
    return e.view(np.complex128)[:, 0]


def _point(out: Outputs, name: str, pos: np.ndarray, vel: np.ndarray, acc: np.ndarray) -> None:
    out[f"{name}.pos"], out[f"{name}.vel"], out[f"{name}.acc"] = xy(pos), xy(vel), xy(acc)


def _angle(out: Outputs, name: str, angle: np.ndarray, omega: np.ndarray, alpha: np.ndarray) -> None:
    out[f"{name}.angle"], out[f"{name}.omega"], out[f"{name}.alpha"] = angle, omega, alpha


def _crank_states(a: float, phi: np.ndarray, omega: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    e1 = _unit(phi)
    pin = a * e1
    return e1, pin, (1j * omega) * pin, (-omega * omega) * pin


def _rrr_kinematics(pin: tuple[np.ndarray, np.ndarray, np.ndarray], q: complex, b: float, c: float,
                    branch: int) -> tuple[np.ndarray, ...]:
    """The RRR dyad A-B-Q with A moving and Q fixed, by circle intersection and Cramer's rule on the loop
    A + b·e2 = Q + c·e3 differentiated in time: B's states, both unit vectors, rates and accelerations."""
    p, v, a = pin
    to_q = q - p
    dist = np.abs(to_q)
    x = (b * b - c * c + dist * dist) / (2 * dist)
    bpos = p + (to_q / dist) * (x + (1j * branch) * np.sqrt(b * b - x * x))
    e2, e3 = (bpos - p) / b, (bpos - q) / c
    s32 = cross(e2, e3)
    # i·b·w2·e2 - i·c·w3·e3 = -v_A, and the same with the accelerations' right-hand side; a scalar product with
    # e3 (or e2) keeps one unknown, as e3·(i·e2) = cross(e2, e3).
    w2 = -dot(v, e3) / (b * s32)
    w3 = -dot(v, e2) / (c * s32)
    rhs = b * (w2 * w2) * e2 - c * (w3 * w3) * e3 - a
    al2 = dot(rhs, e3) / (b * s32)
    al3 = dot(rhs, e2) / (c * s32)
    k3 = 1j * e3
    return bpos, (c * w3) * k3, c * (al3 * k3 - (w3 * w3) * e3), e2, e3, w2, w3, al2, al3


def fourbar(linkage: synth.Linkage, phi: np.ndarray, omega: float) -> Outputs:
    """Four-bar O-A-B-Q: the coupler-rocker dyad's kinematics and reactions, then the crank; the transmission
    angle too."""
    fb = linkage.mechanism
    assert isinstance(fb, synth.FourBar)
    n, g, d = len(phi), _gravity(linkage), fb.ground
    e1, pa, va, aa = _crank_states(fb.crank, phi, omega)
    pb, vb, ab, e2, e3, w2, w3, al2, al3 = _rrr_kinematics((pa, va, aa), d, fb.coupler, fb.rocker, fb.branch)
    bodies = {
        "crank": _body(linkage, "crank", (0.0, 0.0, 0.0), e1, omega, 0.0, g),
        "coupler": _body(linkage, "coupler", (pa, va, aa), e2, w2, al2, g),
        "rocker": _body(linkage, "rocker", (d, 0.0, 0.0), e3, w3, al3, g),
    }
    r_a, r_b, r_q = _rrr(pa, pb, d, bodies["coupler"], bodies["rocker"])
    r_o, torque = _crank(pa, r_a, bodies["crank"])
    out: Outputs = {"O": xy(r_o), "A": xy(r_a), "B": xy(r_b), "Q": xy(r_q)}
    _point(out, "A", pa, va, aa)
    _point(out, "B", pb, vb, ab)
    _angle(out, "crank", phi, np.full(n, omega), np.zeros(n))
    t2, t3 = np.angle(e2), np.angle(e3)
    _angle(out, "coupler", t2, w2, al2)
    _angle(out, "rocker", t3, w3, al3)
    diff = np.mod(t3 - t2, 2 * np.pi)
    out["transmission_angle"] = np.where(diff > np.pi, 2 * np.pi - diff, diff)
    _totals(out, bodies, d * r_q.imag, torque, omega, g, n)
    return out


def slider_crank(linkage: synth.Linkage, phi: np.ndarray, omega: float) -> Outputs:
    """Slider-crank O-A-B on the line y = offset: the rod angle from its sine, the rod-slider dyad (RRP), then
    the crank."""
    sc = linkage.mechanism
    assert isinstance(sc, synth.SliderCrank)
    a, l_, e = sc.crank, sc.rod, sc.offset
    n, g = len(phi), _gravity(linkage)
    e1, pa, va, aa = _crank_states(a, phi, omega)
    sin2 = (e - pa.imag) / l_
    cos2 = sc.branch * np.sqrt(1.0 - sin2 * sin2)
    e2 = cos2 + 1j * sin2
    w2 = -omega * pa.real / (l_ * cos2)                       # a cos(phi) w + l cos(t2) w2 = 0
    al2 = (omega * omega * pa.imag + l_ * sin2 * w2 * w2) / (l_ * cos2)
    k2 = 1j * e2
    pb = pa + l_ * e2
    vb = va + (l_ * w2) * k2
    ab = aa + l_ * (al2 * k2 - (w2 * w2) * e2)
    bodies = {
        "crank": _body(linkage, "crank", (0.0, 0.0, 0.0), e1, omega, 0.0, g),
        "rod": _body(linkage, "rod", (pa, va, aa), e2, w2, al2, g),
        "slider": _body(linkage, "slider", (pb, vb, ab), np.ones(n, dtype=complex), 0.0, 0.0, g),
    }
    r_a, r_b, r_guide, couple = _rrp(pa, pb, 1j, bodies["rod"], bodies["slider"])
    r_o, torque = _crank(pa, r_a, bodies["crank"])
    out: Outputs = {"O": xy(r_o), "A": xy(r_a), "B": xy(r_b), "guide": xy(r_guide), "guide.couple": couple}
    _point(out, "A", pa, va, aa)
    _point(out, "B", pb, vb, ab)
    _angle(out, "crank", phi, np.full(n, omega), np.zeros(n))
    _angle(out, "rod", np.angle(e2), w2, al2)
    _totals(out, bodies, cross(pb, r_guide) + couple, torque, omega, g, n)
    return out


SIX_BAR_Q = 0.3 + 0j


def six_bar_kinematics(phi: np.ndarray, omega: float) -> dict[str, tuple[np.ndarray, ...]]:
    """The six-bar press of ``SIX_BAR_PRESS_EXAMPLE`` (crank 0.1, coupler 0.35, rocker 0.25 on Q = (0.3, 0), C on
    the rocker at 0.4, rod 0.5 to the ram D on the vertical guide x = 0.45): the four-bar's dyad, C on the rocker,
    D by the rod's circle. Points as (position, velocity, acceleration), links as (unit vector, rate,
    acceleration), complex; at omega = 1 the rates are the analogues d/dphi and d²/dphi²."""
    arm, rod, xg = 0.4, 0.5, 0.45
    q = SIX_BAR_Q
    e1, pa, va, aa = _crank_states(0.1, phi, omega)
    pb, vb, ab, e2, e3, w2, w3, al2, al3 = _rrr_kinematics((pa, va, aa), q, 0.35, 0.25, 1)
    k3 = 1j * e3
    pc, vc = q + arm * e3, (arm * w3) * k3
    ac = arm * (al3 * k3 - (w3 * w3) * e3)
    dx = xg - pc.real
    s = np.sqrt(rod * rod - dx * dx)                            # D = (xg, y_C + s)
    s1 = dx * vc.real / s
    s2 = ((dx * ac.real - vc.real * vc.real) - s1 * s1) / s
    pd = xg + 1j * (pc.imag + s)
    vd = 1j * (vc.imag + s1)
    ad = 1j * (ac.imag + s2)
    r = pd - pc
    w4 = cross(r, vd - vc) / (rod * rod)                        # |r| is constant: r·r' = 0
    al4 = cross(r, ad - ac) / (rod * rod)
    return {"A": (pa, va, aa), "B": (pb, vb, ab), "C": (pc, vc, ac), "D": (pd, vd, ad),
            "crank": (e1, np.full(len(phi), omega), np.zeros(len(phi))), "coupler": (e2, w2, al2),
            "rocker": (e3, w3, al3), "rod": (r / rod, w4, al4)}


def six_bar_press(linkage: synth.Linkage, phi: np.ndarray, omega: float) -> Outputs:
    """The six-bar press of ``SIX_BAR_PRESS_EXAMPLE``: :func:`six_bar_kinematics`, then the reactions of the
    rod-ram dyad (RRP) first, its reaction at C loading the rocker, then the coupler-rocker dyad and the crank."""
    q = SIX_BAR_Q
    n, g = len(phi), _gravity(linkage)
    kin = six_bar_kinematics(phi, omega)
    (pa, va, aa), (pb, vb, ab), (pc, vc, ac), (pd, vd, ad) = (kin[p] for p in "ABCD")
    (e1, _, _), (e2, w2, al2), (e3, w3, al3), (e4, w4, al4) = (kin[k] for k in ("crank", "coupler", "rocker", "rod"))
    bodies = {
        "crank": _body(linkage, "crank", (0.0, 0.0, 0.0), e1, omega, 0.0, g),
        "coupler": _body(linkage, "coupler", (pa, va, aa), e2, w2, al2, g),
        "rocker": _body(linkage, "rocker", (q, 0.0, 0.0), e3, w3, al3, g),
        "rod": _body(linkage, "rod", (pc, vc, ac), e4, w4, al4, g),
        "ram": _body(linkage, "ram", (pd, vd, ad), np.ones(n, dtype=complex), 0.0, 0.0, g),
    }
    r_c, r_d, r_guide, couple = _rrp(pc, pd, -1.0 + 0j, bodies["rod"], bodies["ram"])   # the guide's axis at 90°
    # The rod pulls on the rocker at C with -r_c.
    r_a, r_b, r_q = _rrr(pa, pb, q, bodies["coupler"], bodies["rocker"], (-r_c, cross(pc, -r_c)))
    r_o, torque = _crank(pa, r_a, bodies["crank"])
    out: Outputs = {"O": xy(r_o), "A": xy(r_a), "B": xy(r_b), "Q": xy(r_q), "C": xy(r_c), "D": xy(r_d),
                    "guide": xy(r_guide), "guide.couple": couple}
    for name, states in (("A", (pa, va, aa)), ("B", (pb, vb, ab)), ("C", (pc, vc, ac)), ("D", (pd, vd, ad))):
        _point(out, name, *states)
    _angle(out, "crank", phi, np.full(n, omega), np.zeros(n))
    for link, (e, w, al) in (("coupler", (e2, w2, al2)), ("rocker", (e3, w3, al3)), ("rod", (e4, w4, al4))):
        _angle(out, link, np.angle(e), w, al)
    _totals(out, bodies, cross(q, r_q) + cross(pd, r_guide) + couple, torque, omega, g, n)
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


def fourbar_careful(linkage: synth.Linkage, phi: np.ndarray, omega: float) -> Outputs:
    """The same outputs as :func:`fourbar`, written for speed: every constant folded in before the arrays are
    touched, the crank's cosine and sine computed once, each quantity formed in as few passes over memory as numpy
    allows (products with a constant complex number in one pass, cross and scalar products from the real and
    imaginary views, no per-link objects, no loop over bodies). The floor an analysis of the same outputs can be
    measured against."""
    fb = linkage.mechanism
    assert isinstance(fb, synth.FourBar)
    a, b, c, d, branch = fb.crank, fb.coupler, fb.rocker, fb.ground, fb.branch
    g = _gravity(linkage)
    (m1, s1, j1), (m2, s2, j2), (m3, s3, j3) = (
        (p.mass, complex(p.com[0], p.com[1]), p.inertia) for p in map(linkage.mass_props, ("crank", "coupler", "rocker")))
    n, w, w2c = len(phi), omega, omega * omega
    e1 = _unit(phi)
    pa = a * e1
    va = (1j * w) * pa
    aa = -w2c * pa
    # B by circle intersection: the foot of B on A-Q at x from A, B at height h from it
    to_q = d - pa
    dist2 = to_q.real * to_q.real + to_q.imag * to_q.imag
    dist = np.sqrt(dist2)
    x = (b * b - c * c + dist2) / (2 * dist)
    h = np.sqrt(b * b - x * x)
    pb = pa + to_q * ((x + (1j * branch) * h) / dist)
    e2 = (pb - pa) * (1 / b)
    e3 = (pb - d) * (1 / c)
    s32 = e2.real * e3.imag - e2.imag * e3.real
    inv2, inv3 = 1 / (b * s32), 1 / (c * s32)
    w2 = -(va.real * e3.real + va.imag * e3.imag) * inv2
    w3 = -(va.real * e2.real + va.imag * e2.imag) * inv3
    rhs = (b * w2 * w2) * e2 - (c * w3 * w3) * e3 - aa
    al2 = (rhs.real * e3.real + rhs.imag * e3.imag) * inv2
    al3 = (rhs.real * e2.real + rhs.imag * e2.imag) * inv3
    k3 = 1j * e3
    vb = (c * w3) * k3
    ab = c * (al3 * k3 - (w3 * w3) * e3)
    # centres of mass and d'Alembert forces f = m(g - a_S)
    r1, r2, r3 = e1 * s1, e2 * s2, e3 * s3
    p1, v1, a1 = r1, (1j * w) * r1, -w2c * r1
    p2, v2, a2 = pa + r2, va + (1j * w2) * r2, aa + (1j * al2 - w2 * w2) * r2
    p3, v3, a3 = d + r3, (1j * w3) * r3, (1j * al3 - w3 * w3) * r3
    f1, f2, f3 = m1 * (g - a1), m2 * (g - a2), m3 * (g - a3)
    c1_ = p1.real * f1.imag - p1.imag * f1.real
    mo2 = p2.real * f2.imag - p2.imag * f2.real - j2 * al2
    mo3 = p3.real * f3.imag - p3.imag * f3.real - j3 * al3
    # the coupler-rocker dyad from its moment equations about B and Q, then the crank
    u, v = pa - pb, pb - d
    k1 = pb.real * f2.imag - pb.imag * f2.real - mo2
    k2 = d * f3.imag - (v.real * f2.imag - v.imag * f2.real) - mo3
    r_a = (k1 * v - k2 * u) / (u.real * v.imag - u.imag * v.real)
    r_b = r_a + f2
    r_q = -r_b - f3
    r_o = r_a - f1
    torque = pa.real * r_a.imag - pa.imag * r_a.real - c1_
    out: Outputs = {"O": xy(r_o), "A": xy(r_a), "B": xy(r_b), "Q": xy(r_q),
                    "A.pos": xy(pa), "A.vel": xy(va), "A.acc": xy(aa), "B.pos": xy(pb), "B.vel": xy(vb),
                    "B.acc": xy(ab), "crank.angle": phi, "crank.omega": np.full(n, w), "crank.alpha": np.zeros(n)}
    t2, t3 = np.arctan2(e2.imag, e2.real), np.arctan2(e3.imag, e3.real)
    out["coupler.angle"], out["coupler.omega"], out["coupler.alpha"] = t2, w2, al2
    out["rocker.angle"], out["rocker.omega"], out["rocker.alpha"] = t3, w3, al3
    diff = np.abs(np.mod(t3 - t2, 2 * np.pi) - np.pi)
    out["transmission_angle"] = np.pi - diff
    gx, gy = g.real, g.imag
    mass = m1 + m2 + m3
    moved = m1 * p1 + m2 * p2 + m3 * p3
    out["shaking_force"] = xy(f1 + f2 + f3 - mass * g)
    out["shaking_moment"] = -torque - d * r_q.imag - (moved.real * gy - moved.imag * gx)
    energy = (m1 * (v1.real * v1.real + v1.imag * v1.imag) + m2 * (v2.real * v2.real + v2.imag * v2.imag)
              + m3 * (v3.real * v3.real + v3.imag * v3.imag) + j1 * w2c + j2 * w2 * w2 + j3 * w3 * w3)
    power = (f1.real * v1.real + f1.imag * v1.imag + f2.real * v2.real + f2.imag * v2.imag
             + f3.real * v3.real + f3.imag * v3.imag - j2 * al2 * w2 - j3 * al3 * w3)
    slope = (m1 * (v1.real * a1.real + v1.imag * a1.imag) + m2 * (v2.real * a2.real + v2.imag * a2.imag)
             + m3 * (v3.real * a3.real + v3.imag * a3.imag) + j2 * w2 * al2 + j3 * w3 * al3)
    momentum = m1 * v1 + m2 * v2 + m3 * v3
    out["driving_torque"] = torque
    out["virtual_power_torque"] = power * (-1 / w)
    out["reduced_inertia"] = energy * (1 / w2c)
    out["inertia_slope"] = slope * (2 / w**3)
    out["load_torque"] = (momentum.real * gx + momentum.imag * gy) * (1 / w)
    out["kinetic_energy"] = 0.5 * energy
    for name, (pos, vel, acc) in (("crank", (p1, v1, a1)), ("coupler", (p2, v2, a2)), ("rocker", (p3, v3, a3))):
        out[f"S_{name}.pos"], out[f"S_{name}.vel"], out[f"S_{name}.acc"] = xy(pos), xy(vel), xy(acc)
    return out
