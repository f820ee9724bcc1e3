"""Full four-bar analysis at 3600 samples: the vectorised engine against a per-angle loop in the same run.

The baseline is the straightforward way: at each angle a numerical position solve (scipy's fsolve on the loop
closure, warm-started from the previous angle), 2x2 solves for velocities and accelerations, and one 9x9
linear solve for the reactions and the driving torque. It must agree with the engine before it is timed.
Also times a whole 360-sample POST /v1/analysis in-process.
"""

from __future__ import annotations


import numpy as np
from scipy.optimize import fsolve

import synth
from api.client import SynthClient
from api.schemas.analysis import AnalysisIn
from api.schemas.common import FOURBAR_EXAMPLE
from bench._timing import best_of

SAMPLES = 3600
OMEGA = 30.0


def _linkage() -> synth.Linkage:
    return AnalysisIn.model_validate({"mechanism": FOURBAR_EXAMPLE}).to_linkage()



def per_angle_torque(linkage: synth.Linkage, phi: np.ndarray, omega: float) -> np.ndarray:
    """Driving torque angle by angle, the way a first implementation would do it."""
    fb = linkage.mechanism
    assert isinstance(fb, synth.FourBar)
    a, b, c, d = fb.crank, fb.coupler, fb.rocker, fb.ground
    props = [linkage.mass_props(n) for n in ("crank", "coupler", "rocker")]
    guess = np.array([0.5, 1.5])
    out = np.empty(len(phi))

    def rot(t: float, v: tuple[float, float]) -> np.ndarray:
        return np.array([np.cos(t) * v[0] - np.sin(t) * v[1], np.sin(t) * v[0] + np.cos(t) * v[1]])

    def kperp(v: np.ndarray) -> np.ndarray:
        return np.array([-v[1], v[0]])

    for i, p in enumerate(phi):
        def loop(t: np.ndarray, p: float = p) -> list[float]:
            return [a * np.cos(p) + b * np.cos(t[0]) - d - c * np.cos(t[1]),
                    a * np.sin(p) + b * np.sin(t[0]) - c * np.sin(t[1])]

        guess = fsolve(loop, guess, xtol=1e-12)
        t2, t3 = guess
        e1, e2, e3 = (np.array([np.cos(t), np.sin(t)]) for t in (p, t2, t3))
        m2 = np.column_stack([b * kperp(e2), -c * kperp(e3)])
        w2, w3 = np.linalg.solve(m2, -a * omega * kperp(e1))
        rhs = a * omega**2 * e1 + b * w2**2 * e2 - c * w3**2 * e3
        al2, al3 = np.linalg.solve(m2, rhs)
        pos_a, pos_q = a * e1, np.array([d, 0.0])
        pos_b = pos_a + b * e2
        acc_a = -a * omega**2 * e1
        frames = [(np.zeros(2), p, omega, 0.0, np.zeros(2)),
                  (pos_a, t2, w2, al2, acc_a),
                  (pos_q, t3, w3, al3, np.zeros(2))]
        mat = np.zeros((9, 9))
        known = np.zeros(9)
        joints = [(None, 0, np.zeros(2)), (0, 1, pos_a), (1, 2, pos_b), (None, 2, pos_q)]
        for j, (giver, receiver, pt) in enumerate(joints):
            for body, sign in ((receiver, 1.0), (giver, -1.0)):
                if body is None:
                    continue
                lever = pt - frames[body][0]
                mat[3 * body, 2 * j] += sign
                mat[3 * body + 1, 2 * j + 1] += sign
                mat[3 * body + 2, 2 * j] -= sign * lever[1]
                mat[3 * body + 2, 2 * j + 1] += sign * lever[0]
        mat[2, 8] = 1.0
        for k, (_origin, th, w, al, acc_o) in enumerate(frames):
            r = rot(th, props[k].com)
            acc_s = acc_o + al * kperp(r) - w**2 * r
            force = -props[k].mass * acc_s
            known[3 * k : 3 * k + 2] = force
            known[3 * k + 2] = r[0] * force[1] - r[1] * force[0] - props[k].inertia * al
        out[i] = np.linalg.solve(mat, -known)[8]
    return out


def main() -> None:
    """Print engine vs per-angle timings and the in-process request time."""
    linkage = _linkage()
    phi = synth.cycle_angles(SAMPLES)
    engine = synth.analyse(linkage, OMEGA, samples=SAMPLES)
    baseline = per_angle_torque(linkage, phi, OMEGA)
    diff = float(np.abs(engine.kinetostatics.driving_torque - baseline).max())
    assert diff < 1e-6 * (1 + np.abs(baseline).max()), f"baseline disagrees with the engine by {diff}"

    t_engine = best_of(lambda: synth.analyse(linkage, OMEGA, samples=SAMPLES), 7)
    t_base = best_of(lambda: per_angle_torque(linkage, phi, OMEGA), 2)
    print(f"four-bar full analysis, {SAMPLES} samples (kinematics, reactions, torque, virtual power, reduced model)")
    print(f"  engine (vectorised):        {t_engine * 1e3:8.2f} ms")
    print(f"  per-angle loop (torque only): {t_base * 1e3:8.2f} ms")
    print(f"  speed-up:                   {t_base / t_engine:8.1f}x   (max torque difference {diff:.2e} N·m)")

    client = SynthClient.in_process()
    body = AnalysisIn.model_validate({"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 360})
    client.analysis(body)
    t_req = best_of(lambda: client.analysis(body), 20)
    t_health = best_of(client.health, 20)
    print(f"POST /v1/analysis, 360 samples, in-process through the client: {t_req * 1e3:.2f} ms (best of 20;")
    print(f"  of which {t_health * 1e3:.2f} ms is the in-process transport itself, as GET /health shows)")


if __name__ == "__main__":
    main()
