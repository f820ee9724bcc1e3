"""The machine on its foundation, against baselines in the same run.

Run: ``.venv/bin/python -m bench.foundation``.

1. Isolation: the steady cycle solved per harmonic against the time integration with shooting that checks it
   (the same frame, the compressor's shaking force at 360 samples).
2. Isolator design: every grid candidate solved at once per harmonic against solving them one by one with the
   plain isolation solve (a slice of the grid, scaled to the whole).
3. Elastic drive: the steady cycle (a few plain revolutions, then Newton shooting) against letting the two-mass
   drive settle revolution after revolution from the same start until the state at the same crank angle repeats
   as closely; on a quick drive and on a heavy machine whose speed settles slowly. Both times include the rigid
   machine's steady state they start from; the engine's also its last, densely sampled revolution and the
   harmonics.
4. Regulation: the PI loop after a load step on a constant-inertia machine, simulated, against the closed-form
   inverse Laplace transform of the linear loop (the baseline of accuracy), and the time of each.
5. The blocks of the machine design: the README press designed with the foundation, elastic-drive and
   regulation blocks against the same design without them (the chain alone), and with each block alone.
"""

from __future__ import annotations

import math
import time

import numpy as np
from scipy.integrate import solve_ivp

import synth
from bench._timing import median_of
from api.translate.foundation import frame_and_isolators_from
from api.translate.linkage import linkage_from
from api.translate.machine import machine_from
from mechsynth_client.schemas.foundation import IsolationIn
from synth.machine import elastic_drive as ed
from synth.machine import foundation as fd
from synth.machine import foundation_design as fdd
from synth.machine.regulation import regulate, tune_pi
from synth.machine.simulate import MachineCycle


def _compressor() -> tuple[fd.Frame, tuple[fd.Isolator, ...], fd.Forcing, synth.Analysis]:
    body = IsolationIn.model_validate(IsolationIn.model_json_schema()["examples"][0])
    frame, isolators = frame_and_isolators_from(body)
    an = synth.analyse(linkage_from(body), body.omega_rad_s, samples=360)
    return frame, isolators, fd.forcing_of(an), an


def isolation() -> None:
    frame, isolators, forcing, _ = _compressor()
    model = fd.frame_model(frame, isolators)
    s = fd.series(frame, forcing)
    t = np.arange(forcing.phi.size) * forcing.period / forcing.phi.size
    harmonic = median_of(lambda: fd.isolate(frame, isolators, forcing, check=False), 5)
    integration = median_of(lambda: fd._periodic_by_integration(model, s, t), 3)
    r = fd.isolate(frame, isolators, forcing)
    print(f"isolation, {len(s.orders)} harmonics: harmonic solve {harmonic * 1e3:.2f} ms, time integration with "
          f"shooting {integration * 1e3:.1f} ms, ratio {integration / harmonic:.1f}x; they differ by "
          f"{r.check.relative_diff:.1e} of the peaks")


def design() -> None:
    frame, isolators, forcing, _ = _compressor()
    spec = fdd.IsolationDesignSpec(tuple(i.position for i in isolators), "amplitude", max_force=600.0,
                                   max_static_deflection=0.02, max_block_mass=400.0)
    n_k, n_z, n_m = fdd.GRID
    kg, zg, mg = (a.reshape(-1) for a in np.meshgrid(np.geomspace(1e5, 1e8, n_k), np.linspace(0.02, 0.3, n_z),
                                                     np.linspace(0, 400, n_m), indexing="ij"))
    t0 = time.perf_counter()
    amp, force = fdd._candidates_peaks(frame, spec, forcing, kg, zg, mg)
    batched = time.perf_counter() - t0
    sample = np.linspace(0, kg.size - 1, 60).astype(int)
    t0 = time.perf_counter()
    loop_force = []
    for i in sample:
        f = fdd._with_block(frame, float(mg[i]), None)
        res = fd.isolate(f, [fd.Isolator(p, float(kg[i]), float(kg[i]), damping_ratio=float(zg[i]))
                             for p in spec.positions], forcing, check=False)
        loop_force.append(res.peak_force)
    looped = (time.perf_counter() - t0) * kg.size / sample.size
    diff = float(np.max(np.abs(np.array(loop_force) - force[sample]) / force[sample]))
    t0 = time.perf_counter()
    d = fdd.design_isolation(frame, forcing, spec)
    whole = time.perf_counter() - t0
    print(f"isolator design, {kg.size} candidates: at once {batched:.2f} s, one by one {looped:.1f} s (from "
          f"{sample.size}), ratio {looped / batched:.1f}x, peak forces agree to {diff:.1e}; the whole design "
          f"with refinement and check {whole:.2f} s (refined: {d.refined})")


def _settling(cycle: MachineCycle, motor: synth.Motor, c: float, machine: float,
              d: ed.ElasticDrive) -> tuple[float, int]:
    """Revolution after revolution from the engine's start until the state repeats: time [s] and revolutions."""
    j1 = motor.gear_ratio**2 * motor.rotor_inertia
    j2 = float(np.mean(cycle.inertia)) + machine
    b = 2 * 0.05 * math.sqrt(c * j1 * j2 / (j1 + j2))
    model = ed._Model(cycle, machine, motor, j1, c, b)
    t0 = time.perf_counter()
    rigid = synth.simulate_machine(cycle, j1 + machine, motor)  # its start, as the engine's: timed alike
    phi0 = float(cycle.phi[0])
    w = float(np.interp(phi0, rigid.phi, rigid.omega, period=2 * math.pi))
    m = float(model.drive(w)) - j1 * float(np.interp(phi0, rigid.phi, rigid.alpha, period=2 * math.pi))
    y = np.array([m / c, w, phi0, w, 0, 0, 0])
    scale = np.array([abs(m / c) + float(np.max(np.abs(cycle.load_torque))) / c, rigid.mean_speed,
                      rigid.mean_speed])
    revs, target = 0, phi0

    def around(t: float, s: np.ndarray) -> float:
        return float(s[2] - target - 2 * math.pi)

    around.terminal = True  # type: ignore[attr-defined]
    around.direction = 1  # type: ignore[attr-defined]
    while revs < 2000:
        y[2] = target
        sol = solve_ivp(model.rhs, (0, 100), y, method=ed.METHOD, rtol=1e-8, events=around,
                        max_step=min(2 * math.pi / (2 * math.pi * d.natural_frequency) / 8,
                                     2 * math.pi / rigid.mean_speed / 64))
        end = sol.y_events[0][0]
        revs += 1
        z0, z1 = np.array([y[0], y[1], y[3]]), np.array([end[0], end[1], end[3]])
        y = end.copy()
        y[4:] = 0
        if np.all(np.abs(z1 - z0) <= ed.PERIODIC_TOLERANCE * scale):
            break
    return time.perf_counter() - t0, revs


def elastic() -> None:
    _, _, _, an = _compressor()
    red = an.reduced
    motor = synth.Motor(1500 * math.pi / 30, 1440 * math.pi / 30, 30.0, gear_ratio=3.0, efficiency=0.95,
                        rotor_inertia=0.02, breakdown_torque=70.0)
    n = 60
    phi = np.arange(n) * 2 * math.pi / n
    heavy_motor = synth.Motor(1500 * math.pi / 30, 1440 * math.pi / 30, 100.0, rotor_inertia=1.0)
    cases = {
        "the compressor": (MachineCycle(red.phi, red.inertia, red.inertia_slope, red.load_torque - 30.0), motor,
                           2e4, 0.3),
        "a heavy machine": (MachineCycle(phi, np.full(n, 50.0), np.zeros(n), -50.0 + 20 * np.cos(3 * phi)),
                            heavy_motor, 2e4, 0.0),
    }
    for name, (cycle, m, c, machine) in cases.items():
        t0 = time.perf_counter()
        d = ed.elastic_drive(cycle, m, c, machine_inertia=machine, start=False)
        ours = time.perf_counter() - t0
        settling, revs = _settling(cycle, m, c, machine, d)
        print(f"elastic drive, {name} at {d.natural_frequency:.1f} Hz: the engine {ours:.2f} s ({d.revolutions} "
              f"revolutions), settling revolution by revolution {settling:.2f} s ({revs} revolutions), ratio "
              f"{settling / ours:.1f}x; dynamic factor {d.dynamic_factor:.4f}, energy residual "
              f"{d.steady.energy_residual:.1e}")


def regulation() -> None:
    n = 60
    phi = np.arange(n) * 2 * math.pi / n
    j = 4.0
    motor = synth.Motor(1500 * math.pi / 30, 1440 * math.pi / 30, 30.0, gear_ratio=3.0, efficiency=0.95)
    cycle = MachineCycle(phi, np.full(n, j), np.zeros(n), np.full(n, -60.0))
    s = motor.reduced().slope
    c = tune_pi(j, s, 0.4, 0.1)
    t0 = time.perf_counter()
    r = regulate(cycle, 0.0, motor, 25.0, delta=0.005, controller=c)
    simulated = time.perf_counter() - t0
    late = r.time >= r.step_time
    t = r.time[late] - r.step_time
    t0 = time.perf_counter()
    poles = np.roots([j, s * (1 + c.kp), s * c.ki])
    sigma, wd = poles[0].real, abs(poles[0].imag)
    dw = -25.0 * np.exp(sigma * t) * np.sin(wd * t) / (j * wd)
    closed = time.perf_counter() - t0
    err = float(np.max(np.abs(r.omega[late] - r.speed_before - dw)) / np.max(np.abs(dw)))
    print(f"regulation, PI after a load step: simulated {simulated * 1e3:.0f} ms, closed form {closed * 1e3:.2f} ms "
          f"(ratio {simulated / max(closed, 1e-9):.0f}x, what the simulation buys: any J(phi), load and filter); "
          f"they differ by {err:.1e} of the dip; settled after {r.settling_time:.3f} s, overshoot {r.overshoot:.3f}")


def blocks() -> None:
    from mechsynth_client.schemas.foundation import FRAME_EXAMPLE, ISOLATORS_EXAMPLE
    from mechsynth_client.schemas.machine import PRESS_EXAMPLE, MachineIn

    around = {"foundation": {"frame": FRAME_EXAMPLE, "isolators": ISOLATORS_EXAMPLE, "max_force_N": 600},
              "elastic_drive": {"stiffness_Nm_rad": 1e4, "damping_ratio": 0.1, "start": False},
              "regulation": {"load_step_Nm": 40}}

    def spec(**blocks: object) -> synth.MachineSpec:
        return machine_from(MachineIn.model_validate({**PRESS_EXAMPLE, "samples": 180, **blocks}), 6)

    chain = median_of(lambda: synth.design_machine(spec()), 5)
    parts = {}
    for name, block in around.items():
        one = spec(**{name: block})
        parts[name] = median_of(lambda: synth.design_machine(one), 5)
    whole = median_of(lambda: synth.design_machine(spec(**around)), 5)
    print(f"machine design blocks (press, 180 samples): the chain alone {chain:.2f} s, with all three blocks "
          f"{whole:.2f} s (ratio {whole / chain:.2f}); with one block "
          + ", ".join(f"{n} {t:.2f} s ({t / chain:.2f})" for n, t in parts.items()))


def main() -> None:
    isolation()
    design()
    elastic()
    regulation()
    blocks()


if __name__ == "__main__":
    main()
