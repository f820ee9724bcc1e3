"""Friction in the pairs: the kinetostatics with Coulomb (and optional viscous) friction, losses and efficiency.

A revolute pair with journal radius r and coefficient f carries a friction moment f·r·|R| (the reaction is
tangent to the friction circle of radius f·r, seed 000:549-589, 003:902-953) against the relative rotation of
its links; a prismatic pair a friction force f·|N| along its slide against the relative sliding, N the force
normal to the slide. A slide run on rollers (a roller of radius rho on its guide, seed 000 §13.3) has rolling
friction instead: the moment k·|N| at the contact (k a length) resists the roller's turning, so the slide feels
(k/rho)·|N| along it and loses k·|N|·|v|/rho, the power of k·N at the roller's speed v/rho; the sliding
coefficient f is then the adhesion that keeps it rolling (pure rolling needs f > k/rho). Viscous terms add
c·w_rel or c·v_rel. The friction loads depend on the reactions they
change, so the equilibrium of every link, A(phi)·x + b(phi) + Phi(x) = 0, is solved by Newton's method at all
crank angles at once (one stacked linear solve per iteration) until the residual, relative to the largest
known load, is below ``tolerance``; the residual reached is reported. The direction of every friction load is
fixed by the kinematics (the sign of the relative velocity), and where the relative velocity is zero (a
reversal) the pair carries no friction.

Built on the frictionless kinetostatics' public functions: A from :func:`system_matrix`, and b = -A·x0 from
the frictionless solution x0, so zero coefficients return that solution itself. The shaking force and moment
do not change: friction is internal between the frame and the linkage, and the motor housing takes back what
the frame's pairs lose.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .errors import Infeasible, InvalidInput, angle_ranges_deg
from .kinematics.motion import Motion, cross, perp
from .kinematics import motion as linkage_motion
from .kinetostatics import Kinetostatics, solve_direct, system_matrix, unpack_unknowns
from .model import FloatArray, Linkage
from .topology import Joint, Topology

#: A coefficient of friction above this is refused: no dry or lubricated pair of machine materials comes near.
MAX_COEFFICIENT = 3.0
#: Newton's residual, relative to the largest known load of the cycle, at which the solve stops [-].
TOLERANCE = 1e-12
MAX_ITERATIONS = 60
#: Crank speed [rad/s] of the standstill limit: velocities fix the friction's directions, inertia is 1e-12 of it.
STANDSTILL_SPEED = 1e-6


@dataclass(frozen=True, slots=True)
class PairFriction:
    """Friction in one pair, named as the topology names its joint.

    ``coefficient`` f [-] (sliding); ``journal_radius`` r of a revolute pair's pin [m] (friction circle f·r);
    ``viscous`` c [N·m·s/rad for a revolute pair, N·s/m for a prismatic one]; ``static_coefficient`` f0 [-] for
    breaking away from rest (default f); ``rolling_resistance`` k [m] and ``roller_radius`` rho [m] of a slide
    run on rollers: its friction force is then (k/rho)·|N| and f only the adhesion that keeps them rolling.
    """

    joint: str
    coefficient: float
    journal_radius: float = 0.0
    viscous: float = 0.0
    static_coefficient: float | None = None
    rolling_resistance: float = 0.0
    roller_radius: float = 0.0

    @property
    def rolling(self) -> bool:
        """A slide run on rollers (a rolling resistance given)."""
        return self.rolling_resistance > 0

    @property
    def breakaway_coefficient(self) -> float:
        """f0, or f when no static coefficient is given [-]."""
        return self.coefficient if self.static_coefficient is None else self.static_coefficient


@dataclass(frozen=True, slots=True)
class FrictionAnalysis:
    """The kinetostatics with friction at every sample.

    ``unknowns``, ``reactions``, ``couples`` and ``driving_torque`` as :class:`synth.Kinetostatics` has them,
    with friction [N, N·m]; ``frictionless_torque`` the driving torque without it [N·m]; per pair by joint name
    ``friction`` the friction moment [N·m] (revolute) or force along the slide [N] (prismatic) on the joint's
    second body, counter-clockwise or along the slide axis positive, and ``power_loss`` [W] (>= 0); all (N,).
    ``loss_torque`` total power loss over crank speed [N·m]; ``efficiency`` instantaneous, 1 - loss/input
    where the drive puts power in, NaN elsewhere [-]; ``cycle_efficiency`` 1 - lost work/driving work over a
    uniform cycle (None when the drive does no net work or the samples are not one uniform cycle);
    ``residual`` Newton's relative residual reached and ``iterations``; ``power_check`` the largest
    |T - T0 - loss/w| [N·m] (virtual power with friction: what friction dissipates, the drive adds);
    ``pairs`` the friction it was solved with.
    """

    unknowns: FloatArray
    reactions: dict[str, FloatArray]
    couples: dict[str, FloatArray]
    driving_torque: FloatArray
    frictionless_torque: FloatArray
    friction: dict[str, FloatArray]
    power_loss: dict[str, FloatArray]
    loss_torque: FloatArray
    efficiency: FloatArray
    cycle_efficiency: float | None
    residual: float
    iterations: int
    power_check: float
    pairs: tuple[PairFriction, ...] = ()


def _body_velocity(motion: Motion, body: str | None, point: FloatArray) -> FloatArray:
    """Velocity of the point of ``body`` at ``point`` (frame: zero) [m/s], (N, 2)."""
    if body is None:
        return np.zeros_like(point)
    origin = motion.link_origin[body]
    r = point - motion.point_pos[origin]
    return np.asarray(motion.point_vel[origin] + motion.link_omega[body][:, None] * perp(r), dtype=float)


def _body_omega(motion: Motion, body: str | None) -> FloatArray:
    return np.zeros(motion.samples) if body is None else np.asarray(motion.link_omega[body], dtype=float)


def _slide_axis(motion: Motion, joint: Joint) -> FloatArray:
    angle = np.full(motion.samples, joint.axis_angle)
    if joint.axis_link is not None:
        angle = angle + motion.link_angle[joint.axis_link]
    return np.stack([np.cos(angle), np.sin(angle)], axis=-1)


def _link_lengths(motion: Motion, topo: Topology) -> dict[str, float]:
    """Length of every link between its farthest two pairs [m] (links that carry one pair only have none)."""
    out: dict[str, float] = {}
    for link in topo.links:
        points = sorted({j.point for j in topo.joints if link in j.bodies})
        pos = [motion.point_pos[p][0] for p in points]
        spans = [float(np.hypot(*(a - b))) for i, a in enumerate(pos) for b in pos[i + 1:]]
        if spans and max(spans) > 0:
            out[link] = max(spans)
    return out


def validate_pairs(motion: Motion, linkage: Linkage, pairs: Sequence[PairFriction], field: str = "friction") -> None:
    """InvalidInput naming the pair for an unknown joint, a negative or unreasonably large coefficient, a static
    coefficient below the sliding one, a journal radius on a slide or not smaller than a link it joins."""
    topo = linkage.mechanism.topology
    names = [j.name for j in topo.joints]
    lengths = _link_lengths(motion, topo)
    seen: set[str] = set()
    for p in pairs:
        where = f"{field}.{p.joint}"
        if p.joint not in names:
            raise InvalidInput(f"no pair {p.joint!r} in this mechanism; its pairs are {names}", field=where)
        if p.joint in seen:
            raise InvalidInput(f"friction of pair {p.joint!r} given twice", field=where)
        seen.add(p.joint)
        joint = topo.joints[names.index(p.joint)]
        for label, value in (("coefficient", p.coefficient), ("static_coefficient", p.breakaway_coefficient)):
            if not (math.isfinite(value) and 0 <= value <= MAX_COEFFICIENT):
                raise InvalidInput(f"pair {p.joint}: the {label.replace('_', ' ')} must lie in [0, {MAX_COEFFICIENT:g}]"
                                   f", got {value!r}", field=f"{where}.{label}")
        if p.static_coefficient is not None and p.static_coefficient < p.coefficient:
            raise InvalidInput(f"pair {p.joint}: the static coefficient must not be below the sliding one",
                               field=f"{where}.static_coefficient")
        if not (math.isfinite(p.viscous) and p.viscous >= 0):
            raise InvalidInput(f"pair {p.joint}: the viscous coefficient must be finite and not negative",
                               field=f"{where}.viscous")
        if not (math.isfinite(p.journal_radius) and p.journal_radius >= 0):
            raise InvalidInput(f"pair {p.joint}: the journal radius must be finite and not negative",
                               field=f"{where}.journal_radius_m")
        if joint.kind == "prismatic" and p.journal_radius > 0:
            raise InvalidInput(f"pair {p.joint} is a slide: it has no journal radius", field=f"{where}.journal_radius_m")
        _validate_rolling(p, joint, where)
        joined = [lengths[b] for b in joint.bodies if b is not None and b in lengths]
        if joined and p.journal_radius >= min(joined):
            raise InvalidInput(f"pair {p.joint}: the journal radius {p.journal_radius:g} m is not smaller than the "
                               f"link it joins ({min(joined):g} m)", field=f"{where}.journal_radius_m")


def _validate_rolling(p: PairFriction, joint: Joint, where: str) -> None:
    k, rho = p.rolling_resistance, p.roller_radius
    if not (math.isfinite(k) and k >= 0):
        raise InvalidInput(f"pair {p.joint}: the rolling resistance must be finite and not negative",
                           field=f"{where}.rolling_resistance_m")
    if not (math.isfinite(rho) and rho >= 0):
        raise InvalidInput(f"pair {p.joint}: the roller radius must be finite and not negative",
                           field=f"{where}.roller_radius_m")
    if k == 0:
        return
    if joint.kind != "prismatic":
        raise InvalidInput(f"pair {p.joint} turns on its journal: rolling resistance belongs to a slide run on "
                           "rollers", field=f"{where}.rolling_resistance_m")
    if rho <= k:
        raise InvalidInput(f"pair {p.joint}: a rolling resistance of {k:g} m needs a roller radius larger than it",
                           field=f"{where}.roller_radius_m")
    if p.coefficient <= k / rho:
        raise InvalidInput(f"pair {p.joint}: the roller slides: pure rolling needs the sliding coefficient "
                           f"{p.coefficient:g} above k/rho = {k / rho:.4g}", field=f"{where}.coefficient")


@dataclass(frozen=True, slots=True)
class _Pair:
    """One pair's friction data at every sample: the columns of its reaction, the direction sign of the
    relative motion, the relative velocity, and where the friction acts."""

    index: int
    joint: Joint
    radius: float  # friction circle f·r [m] (revolute) or f (prismatic) [-]
    viscous: float
    sign: FloatArray
    relative: FloatArray  # relative angular velocity [rad/s] or sliding speed along the axis [m/s]
    axis: FloatArray | None  # slide direction, (N, 2)
    point: FloatArray


def _pairs(motion: Motion, topo: Topology, pairs: Sequence[PairFriction], static: bool) -> list[_Pair]:
    names = [j.name for j in topo.joints]
    out = []
    for p in pairs:
        j = names.index(p.joint)
        joint = topo.joints[j]
        giver, receiver = joint.bodies
        point = np.asarray(motion.point_pos[joint.point], dtype=float)
        coefficient = p.breakaway_coefficient if static else p.coefficient
        if joint.kind == "revolute":
            rel = _body_omega(motion, receiver) - _body_omega(motion, giver)
            out.append(_Pair(j, joint, coefficient * p.journal_radius, p.viscous, np.sign(rel), rel, None, point))
        else:
            axis = _slide_axis(motion, joint)
            v = _body_velocity(motion, receiver, point) - _body_velocity(motion, giver, point)
            rel = np.einsum("ij,ij->i", v, axis)
            if p.rolling:
                # the rolling moment k·|N| over the roller's radius, starting as running (no breakaway of its own)
                coefficient = p.rolling_resistance / p.roller_radius
            out.append(_Pair(j, joint, coefficient, p.viscous, np.sign(rel), rel, axis, point))
    return out


def _friction_loads(motion: Motion, topo: Topology, pairs: list[_Pair], x: FloatArray,
                    viscous: bool) -> tuple[FloatArray, FloatArray, dict[str, FloatArray]]:
    """The friction loads Phi(x) on every link row (N, 3n), their Jacobian dPhi/dx (N, 3n, 3n), and each
    pair's friction (moment or force on its second body) (N,)."""
    n_links = len(topo.links)
    n = motion.samples
    phi = np.zeros((n, 3 * n_links))
    jac = np.zeros((n, 3 * n_links, 3 * n_links))
    values: dict[str, FloatArray] = {}
    for pr in pairs:
        c0, c1 = 2 * pr.index, 2 * pr.index + 1
        visc = pr.viscous * pr.relative if viscous else np.zeros(n)
        if pr.axis is None:
            rx, ry = x[:, c0], x[:, c1]
            mag = np.hypot(rx, ry)
            safe = np.where(mag > 0, mag, 1.0)
            value = -(pr.radius * mag * pr.sign + visc)  # moment on the second body
            d_value = -(pr.radius * pr.sign)[:, None] * np.stack([rx / safe, ry / safe], axis=-1)  # (N, 2)
            for body, s in ((pr.joint.bodies[1], 1.0), (pr.joint.bodies[0], -1.0)):
                if body is None:
                    continue
                row = 3 * topo.links.index(body) + 2
                phi[:, row] += s * value
                jac[:, row, c0] += s * d_value[:, 0]
                jac[:, row, c1] += s * d_value[:, 1]
        else:
            normal = x[:, c0]
            value = -(pr.radius * np.abs(normal) * pr.sign + visc)  # force along the slide on the second body
            d_value = -pr.radius * pr.sign * np.sign(normal)
            for body, s in ((pr.joint.bodies[1], 1.0), (pr.joint.bodies[0], -1.0)):
                if body is None:
                    continue
                i = 3 * topo.links.index(body)
                lever = cross(pr.point - motion.point_pos[motion.link_origin[body]], pr.axis)
                for row, coef in ((i, pr.axis[:, 0]), (i + 1, pr.axis[:, 1]), (i + 2, lever)):
                    phi[:, row] += s * coef * value
                    jac[:, row, c0] += s * coef * d_value
        values[pr.joint.name] = value
    return phi, jac, values


def _uniform_cycle(phi: FloatArray) -> bool:
    n = phi.size
    return n > 1 and bool(np.allclose(np.diff(phi), 2 * math.pi / n, rtol=1e-9, atol=1e-12))


def friction_kinetostatics(motion: Motion, linkage: Linkage, frictionless: Kinetostatics,
                           pairs: Sequence[PairFriction], *, static: bool = False,
                           tolerance: float = TOLERANCE) -> FrictionAnalysis:
    """Kinetostatics with friction in ``pairs`` at every sample of ``motion``.

    Parameters
    ----------
    motion
        The linkage's motion (the frictionless analysis' own).
    linkage
        The linkage with its masses and loads.
    frictionless
        Its frictionless kinetostatics (:func:`synth.solve_direct`, or an analysis' with counter-rotors, whose
        share of the driving torque is kept).
    pairs
        Friction per pair; pairs not listed are frictionless.
    static
        Use each pair's static coefficient and no viscous terms (breaking away from rest).
    tolerance
        Newton's relative residual to reach [-].

    Raises InvalidInput for bad coefficients and Infeasible (constraint ``friction``) with the crank angles
    where the linkage self-locks: no driving torque overcomes the friction there.
    """
    validate_pairs(motion, linkage, pairs)
    topo = linkage.mechanism.topology
    if topo.indeterminate:
        # Friction forces follow the normal forces, which redundant pairs leave undetermined.
        raise InvalidInput("friction in the pairs of a linkage with redundant constraints (a passive link) is not "
                           "determined by equilibrium: analyse it without friction, or take the passive link out",
                           field="friction")
    a = system_matrix(motion, topo)
    x0 = frictionless.unknowns
    known = -np.einsum("nij,nj->ni", a, x0)  # b of A·x + b = 0, from the frictionless solution
    scale = max(float(np.max(np.abs(known))), float(np.max(np.abs(x0))), 1e-300)
    data = _pairs(motion, topo, pairs, static)
    x = x0.copy()
    iterations = 0
    while True:
        phi, jac, values = _friction_loads(motion, topo, data, x, not static)
        r = np.einsum("nij,nj->ni", a, x) + known + phi
        residual = float(np.max(np.abs(r))) / scale
        if residual <= tolerance:
            break
        if iterations == MAX_ITERATIONS or not math.isfinite(residual):
            bad = ~(np.max(np.abs(r), axis=1) / scale <= max(tolerance, 1e-6))
            raise Infeasible(
                f"the linkage self-locks under friction at {int(bad.sum())} of {motion.samples} crank angles: no "
                "driving torque overcomes the friction there (lower the coefficients or change the geometry)",
                constraint="friction", phi_deg=angle_ranges_deg(motion.phi, bad))
        with np.errstate(all="ignore"):
            step = np.linalg.solve(a + jac, r[..., None])[..., 0]
        x = x - np.where(np.isfinite(step), step, 0.0)
        iterations += 1
    extra = frictionless.driving_torque - x0[:, -1]  # counter-rotors' share, friction-free
    torque = x[:, -1] + extra
    w = motion.omega_crank
    losses = {}
    for pr in data:
        # friction opposes the relative motion, so minus its value times the relative velocity is what it takes
        losses[pr.joint.name] = np.asarray(-values[pr.joint.name] * pr.relative, dtype=float)
    total = sum(losses.values(), np.zeros(motion.samples))
    loss_torque = total / w
    power_in = torque * w
    with np.errstate(divide="ignore", invalid="ignore"):
        efficiency = np.where(power_in > 1e-12 * scale * abs(w), 1.0 - total / power_in, np.nan)
    cycle = None
    if _uniform_cycle(motion.phi):
        driving_work = float(np.mean(torque))
        if driving_work > 0:
            cycle = 1.0 - float(np.mean(loss_torque)) / driving_work
    reactions, couples = unpack_unknowns(motion, topo, x)
    check = float(np.max(np.abs(torque - frictionless.driving_torque - loss_torque)))
    return FrictionAnalysis(x, reactions, couples, torque, frictionless.driving_torque, values, losses, loss_torque,
                            efficiency, cycle, residual, iterations, check, tuple(pairs))


def breakaway_torque(linkage: Linkage, pairs: Sequence[PairFriction], phi: FloatArray) -> FloatArray:
    """Friction torque at the crank that breaking away from rest must overcome, at crank angles ``phi`` [rad]
    -> [N·m], (N,).

    The static coefficients on the reactions of the linkage at rest (loads and gravity, no inertia: the limit of
    a vanishing crank speed, whose velocities still give each friction its direction when turning forward).
    """
    mot = linkage_motion(linkage.mechanism, np.asarray(phi, dtype=float), STANDSTILL_SPEED, 0.0)
    rest = friction_kinetostatics(mot, linkage, solve_direct(mot, linkage), pairs, static=True)
    return rest.loss_torque
