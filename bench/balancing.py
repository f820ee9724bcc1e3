"""Static and optimal four-bar balancing at 360 samples: cvxpy + Clarabel against scipy's SLSQP on the same
problems in the same run (same map, same constraints, same objective), plus in-process request times."""

from __future__ import annotations


import numpy as np
from scipy.optimize import minimize

import synth
from api.client import SynthClient
from api.schemas.balancing import BalanceIn, OptimalBalanceIn
from api.schemas.common import FOURBAR_EXAMPLE
from synth.balancing.fourbar import _rows, _static_system
from synth.balancing.program import counterweight_layout
from bench._timing import best_of

SAMPLES = 360
SPEED = 31.4
LINKS = ("crank", "rocker")
WEIGHTS = synth.Weights(shaking_force=1.0, shaking_moment=2.0, driving_torque=1.0, bearing_forces=0.1)
BUDGET = 4.0



def _setup() -> tuple[synth.Linkage, synth.LinearMap, list[int], np.ndarray]:
    linkage = BalanceIn.model_validate({"mechanism": FOURBAR_EXAMPLE}).to_linkage()
    an = synth.analyse(linkage, SPEED, samples=SAMPLES)
    lm = synth.linear_map(an.motion, linkage)
    cols = [c for link in LINKS for c in range(lm.columns(link).start, lm.columns(link).stop)]
    r_max = np.array([FOURBAR_EXAMPLE["crank_length_m"], FOURBAR_EXAMPLE["rocker_length_m"]])
    return linkage, lm, cols, r_max


def _cones(r_max: np.ndarray) -> list[dict[str, object]]:
    """|h| <= r_max m and |h|² <= m J per counterweight, as SLSQP inequality constraints (>= 0)."""
    def radius(x: np.ndarray) -> np.ndarray:
        v = x.reshape(-1, 4)
        return r_max * v[:, 0] - np.hypot(v[:, 1], v[:, 2])

    def inertia(x: np.ndarray) -> np.ndarray:
        v = x.reshape(-1, 4)
        return v[:, 0] * v[:, 3] - v[:, 1] ** 2 - v[:, 2] ** 2

    return [{"type": "ineq", "fun": radius}, {"type": "ineq", "fun": inertia},
            {"type": "ineq", "fun": lambda x: x.reshape(-1, 4)[:, [0, 3]].ravel()}]


def slsqp_static(linkage: synth.Linkage, lm: synth.LinearMap, r_max: np.ndarray) -> tuple[float, float]:
    cw = counterweight_layout(synth.CounterweightSpec(LINKS), linkage)
    ar, br = _static_system(linkage, lm, cw)
    x0 = np.tile([1.0, 0.0, 0.0, 0.1], len(LINKS))
    res = minimize(lambda x: x.reshape(-1, 4)[:, 0].sum(), x0, method="SLSQP",
                   constraints=[{"type": "eq", "fun": lambda x: ar @ x - br}, *_cones(r_max)],
                   options={"maxiter": 500, "ftol": 1e-12})
    return float(res.fun), float(np.abs(ar @ res.x - br).max())


def slsqp_optimal(linkage: synth.Linkage, lm: synth.LinearMap, cols: list[int],
                  r_max: np.ndarray) -> tuple[float, np.ndarray]:
    p0 = linkage.params()
    n = lm.y.shape[0]
    blocks = {
        "shaking_force": _rows(lm, [lm.force_rows.start, lm.force_rows.start + 1]),
        "shaking_moment": _rows(lm, [lm.moment_row]),
        "driving_torque": _rows(lm, [lm.torque_row]),
        "bearing_forces": _rows(lm, list(range(lm.torque_row))),
    }
    divisor = {"shaking_force": n, "shaking_moment": n, "driving_torque": n, "bearing_forces": n * len(lm.joints)}
    crank = FOURBAR_EXAMPLE["crank_length_m"]

    def objective(x: np.ndarray) -> float:
        p = p0.copy()
        p[cols] += x
        total = 0.0
        for key, (y, y0) in blocks.items():
            total += getattr(WEIGHTS, key) * np.linalg.norm(y @ p + y0) / np.sqrt(divisor[key])
        v = x.reshape(-1, 4)
        return float(total + WEIGHTS.added_mass * (v[:, 0].sum() + v[:, 3].sum() / crank**2))

    x0 = np.tile([0.5, 0.0, 0.0, 0.1], len(LINKS))
    budget = {"type": "ineq", "fun": lambda x: BUDGET - x.reshape(-1, 4)[:, 0].sum()}
    res = minimize(objective, x0, method="SLSQP", constraints=[budget, *_cones(r_max)],
                   options={"maxiter": 1000, "ftol": 1e-12})
    return float(res.fun), res.x


def realisable(x: np.ndarray, r_max: np.ndarray) -> tuple[list[synth.Counterweight], float]:
    """SLSQP's answer as real counterweights (radius clipped to its limit, own inertia at least zero), and the
    largest constraint violation it had."""
    v = x.reshape(-1, 4)
    h = np.hypot(v[:, 1], v[:, 2])
    violation = float(max((h - r_max * v[:, 0]).max(), (h**2 - v[:, 0] * v[:, 3]).max(), 0.0))
    cws = []
    for i, link in enumerate(LINKS):
        m = max(float(v[i, 0]), h[i] / r_max[i])
        pos = (v[i, 1] / m, v[i, 2] / m)
        cws.append(synth.Counterweight(link, m, pos, max(0.0, float(v[i, 3]) - m * (pos[0] ** 2 + pos[1] ** 2))))
    return cws, violation


def main() -> None:
    """Print objectives and timings of both solvers, and in-process request times."""
    linkage, lm, cols, r_max = _setup()
    spec = synth.CounterweightSpec(LINKS)
    ours = synth.balance_static(linkage, SPEED, spec, samples=SAMPLES)
    theirs, eq_err = slsqp_static(linkage, lm, r_max)
    t_ours = best_of(lambda: synth.balance_static(linkage, SPEED, spec, samples=SAMPLES), 5)
    t_map = best_of(lambda: synth.linear_map(synth.analyse(linkage, SPEED, samples=SAMPLES).motion, linkage), 5)
    t_theirs = best_of(lambda: slsqp_static(linkage, lm, r_max), 3) + t_map
    print(f"static balancing, {SAMPLES} samples (objective: added mass [kg]; both include building the map)")
    print(f"  cvxpy + Clarabel: {ours.total_added_mass:.9f} kg in {t_ours * 1e3:7.1f} ms "
          f"(end to end, with the plain re-analysis; residual force {ours.residual_force:.1e} N)")
    print(f"  scipy SLSQP:      {theirs:.9f} kg in {t_theirs * 1e3:7.1f} ms (equality error {eq_err:.1e})")
    print(f"  objective ratio (ours/SLSQP) {ours.total_added_mass / theirs:.9f}, speed-up {t_theirs / t_ours:.1f}x")

    opt = synth.balance_optimal(linkage, SPEED, spec, weights=WEIGHTS, mass_budget=BUDGET, samples=SAMPLES,
                                weight_scale="absolute")
    theirs_map, x = slsqp_optimal(linkage, lm, cols, r_max)
    cws, violation = realisable(x, r_max)
    theirs_opt = synth.objective_value(synth.analyse(linkage.with_counterweights(cws), SPEED, samples=SAMPLES),
                                       WEIGHTS, cws)
    t_ours = best_of(lambda: synth.balance_optimal(linkage, SPEED, spec, weights=WEIGHTS, mass_budget=BUDGET,
                                                    samples=SAMPLES, weight_scale="absolute"), 5)
    t_theirs = best_of(lambda: slsqp_optimal(linkage, lm, cols, r_max), 2) + t_map
    print(f"optimal balancing, {SAMPLES} samples (weighted RMS objective)")
    print(f"  cvxpy + Clarabel: {opt.objective:.6f} in {t_ours * 1e3:7.1f} ms (objective from the plain re-analysis)")
    print(f"  scipy SLSQP:      {theirs_opt:.6f} in {t_theirs * 1e3:7.1f} ms (re-analysed after making it realisable;"
          f" on the map {theirs_map:.6f} with constraints violated by up to {violation:.1e})")
    print(f"  objective ratio (ours/SLSQP) {opt.objective / theirs_opt:.6f}, speed-up {t_theirs / t_ours:.1f}x")

    client = SynthClient.in_process()
    static_body = BalanceIn.model_validate({"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300})
    optimal_body = OptimalBalanceIn.model_validate({"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300,
                                                    "mass_budget_kg": BUDGET, "weights": {
                                                        "shaking_force": 1, "shaking_moment": 2,
                                                        "driving_torque": 1, "bearing_forces": 0.1}})
    client.balance_static(static_body)
    print(f"POST /v1/balancing/static in-process:  {best_of(lambda: client.balance_static(static_body), 10) * 1e3:.1f} ms")
    print(f"POST /v1/balancing/optimal in-process: {best_of(lambda: client.balance_optimal(optimal_body), 10) * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
