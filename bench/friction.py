"""Friction and start-up benchmarks against baselines in the same run.

Run: ``.venv/bin/python -m bench.friction``.

1. Kinetostatics with friction in every pair of the shaper (3600 samples): the stacked Newton over all crank
   angles at once against the same Newton run angle by angle (one small linear solve per angle and iteration).
2. The run-up of a press from rest to its steady state: the compiled Runge-Kutta steps against scipy's
   solve_ivp (RK45, a Python right-hand side on the same tables, rtol 1e-9) over the same time span.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

import synth
from bench._timing import median_of
from synth.friction import PairFriction, _friction_loads, _pairs
from synth.kinematics import Motion
from synth.kinetostatics import system_matrix
from synth.machine import MachineCycle, simulate_startup

SAMPLES = 3600


def _shaper() -> tuple[synth.Analysis, list[PairFriction]]:
    mech = synth.SlottedLever(crank=0.1, ground=0.3, rocker=0.6, ram_height=0.7)
    links = {"crank": synth.MassProps(5.0), "rocker": synth.MassProps(10.0, (0.25, 0.0), 0.3),
             "ram": synth.MassProps(12.0)}
    load = synth.ProcessLoad(kind="window", magnitude=1200.0, start=-math.pi / 3, end=math.pi / 3)
    an = synth.analyse(synth.Linkage(mech, links, gravity=synth.Gravity(), loads=(load,)), 4.0, samples=SAMPLES)
    pairs = [PairFriction(j.name, 0.12, 0.0 if j.kind == "prismatic" else 0.02) for j in mech.topology.joints]
    return an, pairs


def _at(motion: Motion, k: int) -> Motion:
    """The motion at sample ``k`` alone."""
    cut = slice(k, k + 1)
    return Motion(motion.phi[cut], motion.omega_crank, motion.alpha_crank,
                  {n: v[cut] for n, v in motion.point_pos.items()}, {n: v[cut] for n, v in motion.point_vel.items()},
                  {n: v[cut] for n, v in motion.point_acc.items()}, {n: v[cut] for n, v in motion.link_angle.items()},
                  {n: v[cut] for n, v in motion.link_omega.items()}, {n: v[cut] for n, v in motion.link_alpha.items()},
                  motion.link_origin)


def _per_angle(an: synth.Analysis, pairs: list[PairFriction]) -> np.ndarray:
    """The same Newton, one crank angle at a time (the friction loads and one small solve per angle and
    iteration)."""
    topo = an.linkage.mechanism.topology
    a = system_matrix(an.motion, topo)
    x0 = an.kinetostatics.unknowns
    known = -np.einsum("nij,nj->ni", a, x0)
    scale = np.max(np.abs(known))
    torque = np.empty(an.motion.samples)
    for k in range(an.motion.samples):
        here = _at(an.motion, k)
        data = _pairs(here, topo, pairs, False)
        x = x0[k : k + 1].copy()
        for _ in range(60):
            phi, jac, _ = _friction_loads(here, topo, data, x, True)
            r = a[k] @ x[0] + known[k] + phi[0]
            if np.max(np.abs(r)) <= 1e-12 * scale:
                break
            x[0] = x[0] - np.linalg.solve(a[k] + jac[0], r)
        torque[k] = x[0, -1]
    return torque


def _friction_bench() -> None:
    an, pairs = _shaper()
    stacked = median_of(lambda: synth.friction_kinetostatics(an.motion, an.linkage, an.kinetostatics, pairs), 5)
    loop = median_of(lambda: _per_angle(an, pairs), 1)
    fr = synth.friction_kinetostatics(an.motion, an.linkage, an.kinetostatics, pairs)
    diff = float(np.max(np.abs(_per_angle(an, pairs) - fr.driving_torque)))
    print(f"friction, shaper {SAMPLES} samples: stacked Newton {stacked * 1e3:.1f} ms ({fr.iterations} iterations), "
          f"angle by angle {loop * 1e3:.0f} ms: {loop / stacked:.0f}x; same torque to {diff:.1e} N·m")


def _startup_bench() -> None:
    mech = synth.SliderCrank(crank=0.1, rod=0.4)
    links = {"crank": synth.MassProps(4.0, (0.03, 0.0), 0.01), "rod": synth.MassProps(6.0, (0.2, 0.0), 0.08),
             "slider": synth.MassProps(10.0)}
    table = np.linspace(0, 2 * math.pi, 13)
    load = synth.ProcessLoad(kind="crank_table", table_x=tuple(table), values=tuple(800 + 600 * np.sin(table) ** 2))
    red = synth.analyse(synth.Linkage(mech, links, gravity=synth.Gravity(), loads=(load,)), 10.0, samples=360).reduced
    cycle = MachineCycle(red.phi, red.inertia, red.inertia_slope, red.load_torque)
    motor = synth.Motor.from_catalogue(synth.find_motor("4A80B4"), 14.2, 0.92)
    inertia = 3.0
    ours = median_of(lambda: simulate_startup(cycle, inertia, motor), 3)
    up = simulate_startup(cycle, inertia, motor)
    assert up.run is not None
    span = float(up.run.time[-1])
    phi0 = float(up.run.phi[0])
    closed = [np.append(v, v[0]) for v in (red.inertia, red.inertia_slope, red.load_torque)]
    nodes = np.append(red.phi, 2 * math.pi)

    def rhs(_: float, y: np.ndarray) -> list[float]:
        p = y[0] % (2 * math.pi)
        j, dj, m = (float(np.interp(p, nodes, v)) for v in closed)
        speed = motor.gear_ratio * y[1]
        drive = motor.gear_ratio * motor.efficiency * float(motor.start_torque_at(speed))
        return [y[1], (drive + m - 0.5 * dj * y[1] ** 2) / (j + inertia)]

    base = median_of(lambda: solve_ivp(rhs, (0.0, span), [phi0, 0.0], rtol=1e-9, atol=1e-9), 1)
    ref = solve_ivp(rhs, (0.0, span), [phi0, 0.0], rtol=1e-9, atol=1e-9)
    print(f"start-up, press over {span:.2f} s ({up.run.time.size} steps): compiled RK4 {ours * 1e3:.0f} ms, "
          f"solve_ivp {base * 1e3:.0f} ms: {base / ours:.1f}x; end speeds {up.run.omega[-1]:.4f} and "
          f"{ref.y[1, -1]:.4f} rad/s")


def main() -> None:
    """Print both benchmarks."""
    _friction_bench()
    _startup_bench()


if __name__ == "__main__":
    main()
