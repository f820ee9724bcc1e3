"""Designing the isolators, and the frame's passage through resonance while the machine runs up.

The design chooses one isolator type for every position (vertical stiffness k_y, horizontal k_x = ratio·k_y,
damping ratio zeta) and optionally an inertia block under the frame's centre (mass m_b, radius of gyration
rho_b): the least frame amplitude with the peak force to the foundation under a limit, or the least peak force
with the amplitude under a limit, within the stiffness bounds and the static deflection limit. The problem is
nonconvex (resonances make both peaks multimodal in k) but has at most three variables, and one candidate costs
a few 3×3 complex solves per harmonic: so every candidate of a log-spaced grid is solved at once (global
coverage, no start to choose), and the best feasible one is refined by SLSQP on (log k_y, zeta, m_b) from there,
kept only if the plain harmonic solve confirms it. The chosen design is re-solved by
:func:`synth.machine.foundation.isolate`, with its time-integration check.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from scipy.optimize import minimize

from ..analysis import analyse
from ..counter_rotors import CounterRotor
from ..errors import Infeasible, InvalidInput
from ..model import FloatArray, Linkage
from .foundation import G, Forcing, Frame, Isolation, Isolator, forcing_of, frame_model, isolate, series

Objective = Literal["amplitude", "force"]
#: Grid of the search: stiffness points (log-spaced), damping points, block-mass points.
GRID = (48, 9, 6)
#: Candidates solved at once (memory: candidates × harmonics × samples complex numbers).
CHUNK = 128


@dataclass(frozen=True, slots=True)
class IsolationDesignSpec:
    """What to design: ``positions`` of the isolators [m]; ``stiffness_ratio`` k_x/k_y of the isolator type [-];
    ``objective`` ``amplitude`` (least frame amplitude, peak force <= ``max_force`` [N]) or ``force`` (least peak
    force, amplitude <= ``max_amplitude`` [m]); bounds on each isolator's k_y [N/m] and the damping ratio [-];
    ``max_static_deflection`` under the machine's weight [m] (None: free); ``max_block_mass`` of an inertia block
    under the frame's centre [kg] (0: none) with radius of gyration ``block_radius`` [m] (None: the frame's)."""

    positions: tuple[tuple[float, float], ...]
    objective: Objective
    max_force: float | None = None
    max_amplitude: float | None = None
    stiffness_ratio: float = 1.0
    min_stiffness: float = 1e3
    max_stiffness: float = 1e8
    min_damping_ratio: float = 0.02
    max_damping_ratio: float = 0.3
    max_static_deflection: float | None = None
    max_block_mass: float = 0.0
    block_radius: float | None = None

    def validate(self) -> None:
        """InvalidInput naming the field of an inconsistent spec."""
        if not self.positions:
            raise InvalidInput("the design needs the isolators' positions", field="positions_m")
        if self.objective == "amplitude" and self.max_force is None:
            raise InvalidInput("the least amplitude is sought under a force limit: give max_force_N",
                               field="max_force_N")
        if self.objective == "force" and self.max_amplitude is None:
            raise InvalidInput("the least force is sought under an amplitude limit: give max_amplitude_m",
                               field="max_amplitude_m")
        if not 0 < self.min_stiffness < self.max_stiffness:
            raise InvalidInput("the stiffness bounds must satisfy 0 < min < max", field="min_stiffness_N_m")
        if not 0 <= self.min_damping_ratio <= self.max_damping_ratio:
            raise InvalidInput("the damping bounds must satisfy 0 <= min <= max", field="min_damping_ratio")
        if self.stiffness_ratio <= 0:
            raise InvalidInput("the stiffness ratio must be positive", field="stiffness_ratio")


@dataclass(frozen=True, slots=True)
class IsolationDesign:
    """The chosen isolators: ``ky``, ``kx`` of each [N/m], ``damping_ratio`` [-], ``block_mass`` [kg];
    ``amplitude`` (largest movement of the centre or an isolator point) [m] and ``peak_force`` [N] of the plain
    solve; ``static_deflection`` [m]; ``isolation`` the full answer for it with its time-integration check;
    ``grid_best`` the objective at the best grid point and ``objective_value`` after refinement; ``candidates``
    solved; ``refined`` True when SLSQP improved on the grid; ``method`` in words."""

    ky: float
    kx: float
    damping_ratio: float
    block_mass: float
    amplitude: float
    peak_force: float
    static_deflection: float
    objective: Objective
    objective_value: float
    grid_best: float
    candidates: int
    refined: bool
    method: str
    isolation: Isolation


def _candidates_peaks(frame: Frame, spec: IsolationDesignSpec, forcing: Forcing, ky: FloatArray, zeta: FloatArray,
                      mb: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Peak amplitude [m] and peak force to the foundation [N] of each candidate (ky, zeta, m_b), all at once."""
    unit = [Isolator(p, spec.stiffness_ratio, 1.0) for p in spec.positions]
    s = series(frame, forcing)
    base = frame_model(frame, unit)
    n_iso = len(spec.positions)
    rho_b = spec.block_radius if spec.block_radius is not None else math.sqrt(frame.inertia / frame.mass)
    k_unit = base.stiffness
    c_unit = np.einsum("iaj,a,iak->jk", base.maps, np.sqrt([spec.stiffness_ratio, 1.0]), base.maps)
    n = forcing.phi.size
    t = np.arange(n) * forcing.period / n
    w = s.orders * s.speed
    phase = np.exp(1j * np.outer(w, t))  # (K, N)
    points = np.concatenate([[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], base.maps.reshape(-1, 3)])  # centre + isolators
    amp = np.empty(ky.size)
    force = np.empty(ky.size)
    for lo in range(0, ky.size, CHUNK):
        sl = slice(lo, lo + CHUNK)
        m_tot = frame.mass + mb[sl]
        mass = np.zeros((m_tot.size, 3, 3))
        mass[:, 0, 0] = mass[:, 1, 1] = m_tot
        mass[:, 2, 2] = frame.inertia + mb[sl] * rho_b**2
        kk = ky[sl, None, None] * k_unit
        cc = (2 * zeta[sl] * np.sqrt(ky[sl] * m_tot / n_iso))[:, None, None] * c_unit
        z = (kk[:, None] - (w**2)[None, :, None, None] * mass[:, None] + 1j * w[None, :, None, None] * cc[:, None])
        q = np.linalg.solve(z, np.broadcast_to(s.coefficients[None, :, :, None], z.shape[:2] + (3, 1)))[..., 0]
        passed = np.einsum("gjk,gnk->gnj", kk, q) + 1j * w[None, :, None] * np.einsum("gjk,gnk->gnj", cc, q)
        f_t = np.einsum("gkj,kn->gnj", passed[..., :2], phase).real
        x_t = np.einsum("gkj,kn->gnj", q, phase).real  # (G, N, 3)
        moved = np.einsum("pj,gnj->gnp", points, x_t).reshape(x_t.shape[0], n, -1, 2)
        force[sl] = np.max(np.linalg.norm(f_t, axis=2), axis=1)
        amp[sl] = np.max(np.linalg.norm(moved, axis=3), axis=(1, 2))
    return amp, force


def design_isolation(frame: Frame, forcing: Forcing, spec: IsolationDesignSpec) -> IsolationDesign:
    """The isolators (and inertia block) that best meet ``spec`` for the frame under ``forcing``; Infeasible naming
    the constraint no isolator within the bounds can meet."""
    spec.validate()
    n_iso = len(spec.positions)
    limit = spec.max_force if spec.objective == "amplitude" else spec.max_amplitude
    assert limit is not None
    constraint_name = "max_force_N" if spec.objective == "amplitude" else "max_amplitude_m"
    n_k, n_z, n_m = GRID
    masses = np.linspace(0.0, spec.max_block_mass, n_m) if spec.max_block_mass > 0 else np.zeros(1)
    k_floor = spec.min_stiffness
    if spec.max_static_deflection is not None:
        k_floor = max(k_floor, frame.mass * G / (n_iso * spec.max_static_deflection))
        if k_floor > spec.max_stiffness:
            raise Infeasible("no isolator within the stiffness bounds holds the machine's weight within the static "
                             "deflection limit", constraint="max_static_deflection_m",
                             least_deflection_m=frame.mass * G / (n_iso * spec.max_stiffness))
    ks = np.geomspace(k_floor, spec.max_stiffness, n_k)
    zs = (np.linspace(spec.min_damping_ratio, spec.max_damping_ratio, n_z)
          if spec.max_damping_ratio > spec.min_damping_ratio else np.array([spec.min_damping_ratio]))
    kg, zg, mg = (a.reshape(-1) for a in np.meshgrid(ks, zs, masses, indexing="ij"))
    amp, force = _candidates_peaks(frame, spec, forcing, kg, zg, mg)
    deflection = (frame.mass + mg) * G / (n_iso * kg)
    ok_static = np.ones(kg.size, bool) if spec.max_static_deflection is None else (
        deflection <= spec.max_static_deflection * (1 + 1e-12))
    goal, bound = (amp, force) if spec.objective == "amplitude" else (force, amp)
    feasible = ok_static & (bound <= limit)
    if not feasible.any():
        best = float(np.min(np.where(ok_static, bound, np.inf)))
        raise Infeasible(
            f"no isolators within the bounds keep the {'peak force' if spec.objective == 'amplitude' else 'amplitude'}"
            f" under the limit: the least reachable is {best:.4g}", constraint=constraint_name, least_reachable=best)
    i0 = int(np.argmin(np.where(feasible, goal, np.inf)))
    grid_best = float(goal[i0])

    # refinement in scaled variables: log10 k, zeta, block mass over its bound
    m_scale = max(spec.max_block_mass, 1.0)

    def unpack(u: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        return (np.array([10 ** u[0]]), np.array([u[1]]), np.array([u[2] * m_scale]))

    def peaks(u: FloatArray) -> tuple[float, float]:
        a, f = _candidates_peaks(frame, spec, forcing, *unpack(u))
        return (float(a[0]), float(f[0])) if spec.objective == "amplitude" else (float(f[0]), float(a[0]))

    x0 = np.array([math.log10(kg[i0]), zg[i0], mg[i0] / m_scale])
    bounds = [(math.log10(k_floor), math.log10(spec.max_stiffness)), (zs[0], zs[-1]),
              (0.0, spec.max_block_mass / m_scale)]
    cons = [{"type": "ineq", "fun": lambda u: (limit - peaks(u)[1]) / limit}]
    if spec.max_static_deflection is not None:
        dmax = spec.max_static_deflection
        cons.append({"type": "ineq", "fun": lambda u: (dmax - (frame.mass + u[2] * m_scale) * G
                                                         / (n_iso * 10 ** u[0])) / dmax})
    scale = max(grid_best, 1e-300)
    opt = minimize(lambda u: peaks(u)[0] / scale, x0, method="SLSQP", bounds=bounds, constraints=cons,
                   options={"maxiter": 60, "ftol": 1e-9})
    chosen, refined = x0, False
    if np.all(np.isfinite(opt.x)):
        u = np.clip(opt.x, [b[0] for b in bounds], [b[1] for b in bounds])
        g_val, b_val = peaks(u)
        d_val = (frame.mass + u[2] * m_scale) * G / (n_iso * 10 ** u[0])
        ok = b_val <= limit * (1 + 1e-9) and (spec.max_static_deflection is None
                                             or d_val <= spec.max_static_deflection * (1 + 1e-9))
        if ok and g_val < grid_best * (1 - 1e-9):
            chosen, refined = u, True
    k_val, z_val, m_val = (float(v[0]) for v in unpack(chosen))
    block_frame = _with_block(frame, m_val, spec.block_radius)
    isolators = tuple(Isolator(p, spec.stiffness_ratio * k_val, k_val, damping_ratio=z_val) for p in spec.positions)
    result = isolate(block_frame, isolators, forcing)
    amp_val = max(result.peak_displacement, result.peak_isolator_displacement)
    value = amp_val if spec.objective == "amplitude" else result.peak_force
    return IsolationDesign(
        k_val, spec.stiffness_ratio * k_val, z_val, m_val, amp_val, result.peak_force,
        block_frame.mass * G / (n_iso * k_val), spec.objective, value, grid_best, int(kg.size) + int(opt.nfev),
        refined,
        f"grid of {kg.size} candidates (log-spaced k_y × damping × block mass) solved at once per harmonic, "
        f"SLSQP refinement from the best feasible one ({'kept' if refined else 'no gain, grid point kept'})",
        result)


def _with_block(frame: Frame, block_mass: float, block_radius: float | None) -> Frame:
    rho = block_radius if block_radius is not None else math.sqrt(frame.inertia / frame.mass)
    return Frame(frame.mass + block_mass, frame.inertia + block_mass * rho**2, frame.centre)


def design_linkage_isolation(linkage: Linkage, speed: float, frame: Frame, spec: IsolationDesignSpec, *,
                             samples: int = 360, max_samples: int = 100_000,
                             counter_rotors: tuple[CounterRotor, ...] = ()) -> IsolationDesign:
    """Analyse ``linkage`` at constant crank ``speed`` [rad/s] and design its isolators (see
    :func:`design_isolation`)."""
    an = analyse(linkage, speed, samples=samples, max_samples=max_samples, counter_rotors=counter_rotors)
    return design_isolation(frame, forcing_of(an), spec)
