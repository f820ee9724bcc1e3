"""Four-bar analysis at 3600 samples: the generic engine against hand-written closed forms in the same run.

Two baselines, both written for the four-bar alone and checked against the engine before they are timed:
a vectorised closed form (law of cosines for the positions, Cramer's rule for velocities, accelerations and the
reactions of the coupler-rocker dyad, then the crank), and the per-angle loop a user would write (the same
closed form angle by angle, with a 9x9 numpy solve for the reactions). Then POST /v1/analysis at 3600 samples
in-process, and the response's JSON written by orjson against pydantic's model_dump_json of the same answer.
"""

from __future__ import annotations


import json
import math

import numpy as np

import synth
from mechsynth_client.client import SynthClient
from api.media import json_bytes
from mechsynth_client.schemas.analysis import AnalysisIn, AnalysisOut
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE
from bench._timing import asgi_medians, median_of
from synth.execution import keep_freed_memory

SAMPLES = 3600
OMEGA = 30.0


def _linkage() -> synth.Linkage:
    return AnalysisIn.model_validate({"mechanism": FOURBAR_EXAMPLE}).to_linkage()



def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def closed_form(linkage: synth.Linkage, phi: np.ndarray, omega: float) -> tuple[np.ndarray, np.ndarray]:
    """Driving torque and the crank-coupler reaction of a four-bar at constant crank speed, vectorised."""
    fb = linkage.mechanism
    assert isinstance(fb, synth.FourBar)
    a, b, c, d = fb.crank, fb.coupler, fb.rocker, fb.ground
    pa = a * np.stack([np.cos(phi), np.sin(phi)], axis=-1)
    aq = np.array([d, 0.0]) - pa
    dist = np.hypot(aq[:, 0], aq[:, 1])
    gamma = np.arccos((b * b + dist * dist - c * c) / (2 * b * dist))
    t2 = np.arctan2(aq[:, 1], aq[:, 0]) + fb.branch * gamma
    pb = pa + b * np.stack([np.cos(t2), np.sin(t2)], axis=-1)
    t3 = np.arctan2(pb[:, 1], pb[:, 0] - d)
    s32 = np.sin(t3 - t2)
    w2 = a * omega * np.sin(phi - t3) / (b * s32)
    w3 = a * omega * np.sin(phi - t2) / (c * s32)
    # accelerations: b al2 k x e2 - c al3 k x e3 = a w² e1 + b w2² e2 - c w3² e3 (components along e3, e2)
    e1, e2, e3 = (np.stack([np.cos(t), np.sin(t)], axis=-1) for t in (phi, t2, t3))
    rhs = a * omega**2 * e1 + b * (w2**2)[:, None] * e2 - c * (w3**2)[:, None] * e3
    al2 = np.einsum("ij,ij->i", rhs, e3) / (b * s32)
    al3 = np.einsum("ij,ij->i", rhs, e2) / (c * s32)
    props = [linkage.mass_props(n) for n in ("crank", "coupler", "rocker")]
    frames = [(np.zeros_like(pa), phi, np.full_like(phi, omega), np.zeros_like(phi), np.zeros_like(pa)),
              (pa, t2, w2, al2, -a * omega**2 * e1),
              (np.broadcast_to([d, 0.0], pa.shape), t3, w3, al3, np.zeros_like(pa))]
    force, moment, com = [], [], []
    for p, (origin, th, w, al, acc_o) in zip(props, frames, strict=True):
        ct, st = np.cos(th), np.sin(th)
        r = np.stack([ct * p.com[0] - st * p.com[1], st * p.com[0] + ct * p.com[1]], axis=-1)
        kr = np.stack([-r[:, 1], r[:, 0]], axis=-1)
        acc = acc_o + al[:, None] * kr - (w * w)[:, None] * r
        force.append(-p.mass * acc)
        moment.append(-p.inertia * al)   # inertia couple (the inertia is about the centre of mass)
        com.append(origin + r)
    # Dyad: coupler moments about B and rocker moments about Q give the crank's force on the coupler, R_A.
    u, v = pa - pb, pb - np.array([d, 0.0])
    c1 = -(_cross(com[1] - pb, force[1]) + moment[1])
    c2 = -(_cross(v, force[1]) + _cross(com[2] - np.array([d, 0.0]), force[2]) + moment[2])
    det = _cross(u, v)
    r_a = np.stack([(c1 * v[:, 0] - u[:, 0] * c2) / det, (c1 * v[:, 1] - u[:, 1] * c2) / det], axis=-1)
    torque = _cross(pa, r_a) - _cross(com[0], force[0]) - moment[0]
    return torque, r_a


def per_angle_torque(linkage: synth.Linkage, phi: np.ndarray, omega: float) -> np.ndarray:
    """Driving torque angle by angle, the way a user would write it: closed-form kinematics, then one 9x9
    reaction solve per angle."""
    fb = linkage.mechanism
    assert isinstance(fb, synth.FourBar)
    a, b, c, d = fb.crank, fb.coupler, fb.rocker, fb.ground
    props = [linkage.mass_props(n) for n in ("crank", "coupler", "rocker")]
    out = np.empty(len(phi))

    def rot(t: float, v: tuple[float, float]) -> np.ndarray:
        return np.array([math.cos(t) * v[0] - math.sin(t) * v[1], math.sin(t) * v[0] + math.cos(t) * v[1]])

    def kperp(v: np.ndarray) -> np.ndarray:
        return np.array([-v[1], v[0]])

    for i, p in enumerate(phi):
        ax, ay = a * math.cos(p), a * math.sin(p)
        qx, qy = d - ax, -ay
        dist = math.hypot(qx, qy)
        t2 = math.atan2(qy, qx) + fb.branch * math.acos((b * b + dist * dist - c * c) / (2 * b * dist))
        bx, by = ax + b * math.cos(t2), ay + b * math.sin(t2)
        t3 = math.atan2(by, bx - d)
        e1, e2, e3 = (np.array([math.cos(t), math.sin(t)]) for t in (p, t2, t3))
        m2 = np.column_stack([b * kperp(e2), -c * kperp(e3)])
        w2, w3 = np.linalg.solve(m2, -a * omega * kperp(e1))
        rhs = a * omega**2 * e1 + b * w2**2 * e2 - c * w3**2 * e3
        al2, al3 = np.linalg.solve(m2, rhs)
        pos_a, pos_q = np.array([ax, ay]), np.array([d, 0.0])
        pos_b = np.array([bx, by])
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
    """Engine against both closed forms, then the request and its serialisation."""
    linkage = _linkage()
    phi = synth.cycle_angles(SAMPLES)
    engine = synth.analyse(linkage, OMEGA, samples=SAMPLES)
    torque = engine.kinetostatics.driving_torque
    vec_torque, r_a = closed_form(linkage, phi, OMEGA)
    loop_torque = per_angle_torque(linkage, phi, OMEGA)
    scale = 1 + float(np.abs(torque).max())
    for name, other in (("vectorised closed form", vec_torque), ("per-angle loop", loop_torque)):
        diff = float(np.abs(torque - other).max())
        assert diff < 1e-9 * scale, f"{name} disagrees with the engine by {diff}"
    diff_ra = float(np.abs(engine.kinetostatics.reactions["A"] - r_a).max())
    assert diff_ra < 1e-9 * scale, f"the closed form's reaction at A disagrees by {diff_ra}"

    # First with the allocator as a plain Python process has it, then as the service's workers set it (freed
    # cycle-sized arrays kept for reuse); both sides of each ratio are timed under the same setting.
    t_engine_plain = median_of(lambda: synth.analyse(linkage, OMEGA, samples=SAMPLES), 31)
    t_vec_plain = median_of(lambda: closed_form(linkage, phi, OMEGA), 31)
    tuned = keep_freed_memory()
    t_engine = median_of(lambda: synth.analyse(linkage, OMEGA, samples=SAMPLES), 31)
    t_vec = median_of(lambda: closed_form(linkage, phi, OMEGA), 31)
    t_loop = median_of(lambda: per_angle_torque(linkage, phi, OMEGA), 3)
    print(f"four-bar analysis, {SAMPLES} samples, medians (the closed forms agree with the engine to "
          f"{float(np.abs(torque - vec_torque).max()):.1e} N·m)")
    print("  engine synth.analyse (generic: kinematics, all reactions, torque, shaking force and moment, virtual"
          " power, reduced model) against the vectorised closed form (kinematics, reaction at A, torque):")
    print(f"    plain allocator:           engine {t_engine_plain * 1e3:6.2f} ms, closed form {t_vec_plain * 1e3:5.2f} ms"
          f"   engine / closed form = {t_engine_plain / t_vec_plain:.1f}")
    print(f"    as in a worker{'' if tuned else ' (not glibc: unchanged)'}:  engine {t_engine * 1e3:6.2f} ms, "
          f"closed form {t_vec * 1e3:5.2f} ms   engine / closed form = {t_engine / t_vec:.1f}")
    print(f"  per-angle closed-form loop (torque):                        {t_loop * 1e3:7.2f} ms   "
          f"speed-up {t_loop / t_engine:.0f}x")

    client = SynthClient.in_process()
    body = AnalysisIn.model_validate({"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": SAMPLES})
    payload = body.model_dump(mode="json", exclude_none=True)
    # The raw POST: the server's whole work and the transport, not the client's own parsing of the answer.
    t_req = median_of(lambda: client.http.post("/v1/analysis", json=payload).raise_for_status(), 15)
    t_health = median_of(client.health, 15)
    out = AnalysisOut.from_engine(engine)
    t_orjson = median_of(lambda: json_bytes(AnalysisOut.from_engine(engine)), 15)
    t_pydantic = median_of(lambda: AnalysisOut.from_engine(engine).to_lists().model_dump_json(), 5)
    assert json.loads(json_bytes(out)) == json.loads(out.to_lists().model_dump_json())
    asgi = asgi_medians({"analysis": ("POST", "/v1/analysis", payload), "health": ("GET", "/health", None)}, 15)
    print(f"POST /v1/analysis, {SAMPLES} samples, in-process (raw POST, the client does not parse the answer):")
    print(f"  over ASGI from an event loop (the service's work): {asgi['analysis'] * 1e3:.2f} ms "
          f"(GET /health {asgi['health'] * 1e3:.2f} ms)")
    print(f"  through the synchronous client (its thread hand-offs included): {t_req * 1e3:.2f} ms "
          f"(GET /health {t_health * 1e3:.2f} ms)")
    print(f"  response JSON from the engine's arrays: orjson {t_orjson * 1e3:.2f} ms, pydantic model_dump_json "
          f"{t_pydantic * 1e3:.2f} ms ({t_pydantic / t_orjson:.0f}x), same parsed content")


if __name__ == "__main__":
    main()
