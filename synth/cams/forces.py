"""Kinetostatics of the cam-follower pair at a constant cam speed: contact force, spring, driving torque.

Along the follower's coordinate q (s [m] of a translating follower, gamma [rad] of an oscillating one) the cam
must supply the generalised force Q = m q_tt + k q + F0 + F_p: the follower's inertia (m a mass [kg] or a moment
of inertia about the pivot [kg·m²]; q_tt = omega² d2q/dtheta2), the spring of stiffness k and preload F0 at q = 0,
and the process load F_p acting against the lift. The contact force along the common normal is N = Q/lever, with
lever the normal's component along the contact point's motion per unit q (cos alpha, or a length). Contact holds
while N > 0.

The cam's driving torque is taken from the contact geometry, T = N (C x n) with C the contact point and n the
normal, and checked by virtual power: without friction the power into the cam equals the power the follower takes,
T omega = Q dq/dt, i.e. T = Q dq/dtheta.

A roller with rolling resistance k [m] (seed 000 §13.3) resists rolling on the cam with the couple k·N; the
roller turning freely on its pin, its moment balance asks a tangential force mu·N at the contact, mu = k/r, against
the roller centre's motion relative to the cam surface (t = n turned 90°, v_t = (dP/dtheta - omega x P/omega)·t).
So N = Q / (lever - mu s (w·t)) with s = sign v_t, and the cam's torque adds the tangential force's moment and the
couple: T = N (C x n - mu s C x t - s k). Virtual power then counts the loss: T = Q dq/dtheta + k N |v_t| / r,
the couple times the roller's rotation relative to the cam (it rolls on the contact point, so v_t = r times that).

The least spring is a linear program in (k, F0): the spring force must exceed, at every angle, 1 + margin times
the force that would lift the follower off the cam, -(m q_tt + F_p); minimise the largest spring force, reached at
full lift, with the initial compression F0/k at most a bound (default the total lift): without it the least
largest force is a preload without rate, a spring of infinite free length.
"""

from __future__ import annotations

from dataclasses import dataclass

import cvxpy as cp
import numpy as np

from ..errors import Infeasible, InvalidInput, SolverFailed
from ..model import FloatArray
from .profile import CamGeometry


@dataclass(frozen=True, slots=True)
class ProcessLoad:
    """A load against the lift [N or N·m] between two cam angles [rad] (a window may wrap past 2 pi)."""

    start: float
    end: float
    value: float

    def at(self, theta: FloatArray) -> FloatArray:
        """The load at each cam angle."""
        two_pi = 2.0 * np.pi
        span = (self.end - self.start) % two_pi or two_pi
        inside = (theta - self.start) % two_pi <= span
        return np.where(inside, self.value, 0.0)


@dataclass(frozen=True, slots=True)
class PairLoads:
    """What the follower asks of the cam: ``inertia`` (mass or moment of inertia), spring ``stiffness`` and
    ``preload`` (None: the least spring is found), process loads, the contact ``margin`` the spring must keep
    (spring force at least 1 + margin times the separating force), the cam ``speed`` [rad/s] and a roller's
    ``rolling_resistance`` k [m] on the cam (its couple k·N); a designed spring's largest initial compression
    F0/k [m] (None: the follower's total lift), and the ``wire`` and ``spring_index`` of its coil."""

    inertia: float
    speed: float
    stiffness: float | None = None
    preload: float | None = None
    process: tuple[ProcessLoad, ...] = ()
    margin: float = 0.2
    rolling_resistance: float = 0.0
    max_initial_compression: float | None = None
    wire: str = "music_wire"
    spring_index: float = 8.0


@dataclass(frozen=True, slots=True)
class PairForces:
    """Forces over the turn; ``torque_check`` is max |N (C x n) - Q dq/dtheta| over the largest |torque|."""

    stiffness: float
    preload: float
    spring_designed: bool
    generalised: FloatArray      # Q [N or N·m], (N,)
    spring: FloatArray           # k q + F0
    process: FloatArray          # F_p
    inertia: FloatArray          # m q_tt
    contact: FloatArray          # N [N], (N,)
    torque: FloatArray           # driving torque from the contact geometry [N·m]
    torque_virtual_power: FloatArray   # Q dq/dtheta [N·m]
    torque_check: float
    least_margin: float          # min over separating angles of spring / separating force, less 1 (inf if none)
    reduced_inertia: FloatArray  # the follower's inertia reduced to the camshaft, m (dq/dtheta)² [kg·m²]
    load_torque: FloatArray      # spring and process reduced to the camshaft, (k q + F0 + F_p) dq/dtheta [N·m]
    reduced_check: float         # max |T - loss - (load + omega²/2 dJ/dtheta)| over the peak |T|, dJ by differences
    rolling_loss: FloatArray     # the rolling resistance's share of the torque, k N |v_t| / r [N·m]; zeros without


def _least_spring(q: FloatArray, need: FloatArray, margin: float, stiffness: float | None,
                  preload: float | None, max_compression: float) -> tuple[float, float]:
    k = cp.Variable(nonneg=True)
    f0 = cp.Variable(nonneg=True)
    fixed = [k == stiffness] if stiffness is not None else []
    fixed += [f0 == preload] if preload is not None else []
    if stiffness is None and preload is None:
        # a preload without rate is a constant force, a spring of infinite free length: the initial compression
        # F0/k is bounded, so the least largest force comes with a rate
        fixed.append(f0 <= max_compression * k)
    problem = cp.Problem(cp.Minimize(k * float(q.max()) + f0), [k * q + f0 >= (1.0 + margin) * need, *fixed])
    try:
        problem.solve(solver=cp.CLARABEL)  # type: ignore[no-untyped-call]
    except cp.SolverError as exc:
        raise SolverFailed("solver_error", f"the spring program failed: {exc}") from exc
    if problem.status in (cp.INFEASIBLE, cp.INFEASIBLE_INACCURATE):
        raise Infeasible("no spring with the given stiffness or preload keeps the follower on the cam",
                         constraint="contact_margin")
    if problem.status != cp.OPTIMAL or k.value is None or f0.value is None:
        raise SolverFailed(str(problem.status))
    return max(float(k.value), 0.0), max(float(f0.value), 0.0)


def pair_forces(g: CamGeometry, loads: PairLoads) -> PairForces:
    """Contact force, spring and driving torque over the turn at ``loads.speed``."""
    m, w = g.motion, loads.speed
    inertia = loads.inertia * w * w * m.a
    process = np.zeros_like(m.s)
    for p in loads.process:
        process = process + p.at(m.theta)
    need = np.maximum(-(inertia + process), 0.0)
    designed = loads.stiffness is None or loads.preload is None
    if designed:
        compression = loads.max_initial_compression
        if compression is None:
            compression = float(np.ptp(m.s))
        if not compression > 0:
            raise InvalidInput("the spring's initial compression must be positive",
                               field="loads.max_initial_compression_m")
        k, f0 = _least_spring(m.s, need, loads.margin, loads.stiffness, loads.preload, compression)
    else:
        assert loads.stiffness is not None and loads.preload is not None
        k, f0 = loads.stiffness, loads.preload
    spring = k * m.s + f0
    Q = inertia + spring + process
    lever, arm, loss_per_newton = _rolling(g, loads.rolling_resistance)
    if np.any(np.abs(lever) < 1e-12):
        raise InvalidInput("the contact normal is square to the follower's motion at some cam angle: the "
                           "follower locks", field="follower")
    N = Q / lever
    torque = N * arm
    loss = N * loss_per_newton
    vp = Q * m.v + loss
    scale = max(float(np.max(np.abs(torque))), 1e-300)
    separating = need > 0.0
    least = float(np.min(spring[separating] / need[separating]) - 1.0) if separating.any() else float("inf")
    # The camshaft as the crank of a machine: the follower's kinetic energy m (q')² omega²/2 makes a reduced
    # inertia J = m (dq/dtheta)², and at constant speed T = load + (omega²/2) dJ/dtheta; the derivative is taken
    # here by fourth-order periodic differences of the J table, a path apart from the law's acceleration.
    reduced_inertia = loads.inertia * m.v**2
    load_torque = (spring + process) * m.v
    n = len(m.theta)
    h = 2.0 * np.pi / n
    r = [np.roll(reduced_inertia, -shift) for shift in (-2, -1, 1, 2)]
    dJ = (r[0] - 8.0 * r[1] + 8.0 * r[2] - r[3]) / (12.0 * h)
    idx = np.arange(n)
    smooth = np.ones(n, dtype=bool)
    for shift in (-2, -1, 1, 2):
        smooth &= m.segment[(idx + shift) % n] == m.segment
    reduced = float(np.max(np.abs(torque - loss - load_torque - 0.5 * w * w * dJ)[smooth], initial=0.0)) / scale
    return PairForces(k, f0, designed, Q, spring, process, inertia, N, torque, vp,
                      float(np.max(np.abs(torque - vp))) / scale, least, reduced_inertia, load_torque, reduced, loss)


def _rolling(g: CamGeometry, k: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The lever and arm of the contact force with a roller's rolling resistance ``k`` [m], and the rolling loss
    per newton of contact force [m] (see the module's notes); the plain lever and arm, and zeros, without."""
    if k == 0.0:
        return g.lever, g.arm, np.zeros_like(g.lever)
    r = g.follower.roller
    if g.follower.contact != "roller" or not 0.0 < k < r:
        raise InvalidInput(f"a rolling resistance of {k:g} m needs a roller follower of a larger radius",
                           field="loads.rolling_resistance_m")
    n, c = g.normal, g.contact
    t = np.stack([-n[:, 1], n[:, 0]], axis=-1)
    centre = c + r * n
    rel = g.drive * g.motion.v[:, None] - np.stack([-centre[:, 1], centre[:, 0]], axis=-1)
    vt = rel[:, 0] * t[:, 0] + rel[:, 1] * t[:, 1]
    s = np.sign(vt)
    mu = k / r
    lever = g.lever - mu * s * (g.drive[:, 0] * t[:, 0] + g.drive[:, 1] * t[:, 1])
    arm = g.arm - mu * s * (c[:, 0] * t[:, 1] - c[:, 1] * t[:, 0]) - s * k
    return lever, arm, k * np.abs(vt) / r
