"""Static and optimal four-bar balancing at 360 samples: the engine's programs (assembled for Clarabel) against
scipy's SLSQP on the same problems in the same run (same map, same constraints, same objective, solve only on
both sides), plus in-process request medians, a sweep of ten weight sets among them."""

from __future__ import annotations


import numpy as np
from scipy.optimize import minimize

import synth
from api.translate.linkage import linkage_from
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.balancing import BalanceIn, OptimalBalanceIn
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE
from synth.balancing.fourbar import _force_rows, _optimal_program, _program, _rows, _static_system
from synth.balancing.program import counterweight_layout, solve
from bench._timing import asgi_medians, median_of

SAMPLES = 360
SPEED = 31.4
LINKS = ("crank", "rocker")
WEIGHTS = synth.Weights(shaking_force=1.0, shaking_moment=2.0, driving_torque=1.0, bearing_forces=0.1)
BUDGET = 4.0



def _setup() -> tuple[synth.Linkage, synth.LinearMap, list[int], np.ndarray]:
    linkage = linkage_from(BalanceIn.model_validate({"mechanism": FOURBAR_EXAMPLE}))
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
    ar, br = _static_system(linkage, _force_rows(lm), cw)
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


def ours_static(linkage: synth.Linkage, lm: synth.LinearMap) -> float:
    """The engine's static program on the same map (assembled for Clarabel and solved): added mass [kg]."""
    cw = counterweight_layout(synth.CounterweightSpec(LINKS), linkage)
    ar, br = _static_system(linkage, _force_rows(lm), cw)
    program = _program(cw)
    program.equal(ar, br)
    program.q = cw.mass_columns() + 1e-9 * cw.inertia_columns()
    x = solve(program, 20.0, "static balancing")
    return float(cw.mass_columns() @ x)


def ours_optimal(linkage: synth.Linkage, lm: synth.LinearMap) -> np.ndarray:
    """The engine's optimal program on the same map: the counterweight variables."""
    cw = counterweight_layout(synth.CounterweightSpec(LINKS), linkage)
    terms = tuple(k for k in ("shaking_force", "shaking_moment", "driving_torque", "bearing_forces")
                  if getattr(WEIGHTS, k) > 0)
    built = _optimal_program(lm, linkage, cw, terms, BUDGET)
    built.program.q = built.costs(WEIGHTS)
    return solve(built.program, 20.0, "optimal balancing")[: cw.size]


def main() -> None:
    """Solves against SLSQP on the same programs, then in-process request medians."""
    linkage, lm, cols, r_max = _setup()
    print(f"four-bar balancing, {SAMPLES} samples; medians. Solve only: both sides start from the same linear "
          "map and neither re-analyses.")
    mass = ours_static(linkage, lm)
    theirs, eq_err = slsqp_static(linkage, lm, r_max)
    t_ours = median_of(lambda: ours_static(linkage, lm), 21)
    t_theirs = median_of(lambda: slsqp_static(linkage, lm, r_max), 9)
    print("static (least added mass [kg], shaking force identically zero)")
    print(f"  Clarabel, program assembled directly: {mass:.9f} kg in {t_ours * 1e3:7.2f} ms")
    print(f"  scipy SLSQP:                          {theirs:.9f} kg in {t_theirs * 1e3:7.2f} ms "
          f"(equality error {eq_err:.1e})")
    print(f"  objective ratio (ours/SLSQP) {mass / theirs:.9f}, speed-up {t_theirs / t_ours:.1f}x")

    x = ours_optimal(linkage, lm)
    ours_cws, ours_violation = realisable(x, r_max)
    ours_obj = synth.objective_value(synth.analyse(linkage.with_counterweights(ours_cws), SPEED, samples=SAMPLES),
                                     WEIGHTS, ours_cws)
    theirs_map, xs = slsqp_optimal(linkage, lm, cols, r_max)
    cws, violation = realisable(xs, r_max)
    theirs_opt = synth.objective_value(synth.analyse(linkage.with_counterweights(cws), SPEED, samples=SAMPLES),
                                       WEIGHTS, cws)
    t_ours = median_of(lambda: ours_optimal(linkage, lm), 21)
    t_theirs = median_of(lambda: slsqp_optimal(linkage, lm, cols, r_max), 5)
    print("optimal (weighted RMS objective, evaluated afterwards on a plain re-analysis of each answer)")
    print(f"  Clarabel, program assembled directly: {ours_obj:.6f} in {t_ours * 1e3:7.2f} ms "
          f"(constraints violated by up to {ours_violation:.1e})")
    print(f"  scipy SLSQP:                          {theirs_opt:.6f} in {t_theirs * 1e3:7.2f} ms "
          f"(on the map {theirs_map:.6f}, constraints violated by up to {violation:.1e})")
    print(f"  objective ratio (ours/SLSQP) {ours_obj / theirs_opt:.6f}, speed-up {t_theirs / t_ours:.1f}x")

    client = SynthClient.in_process()
    static_body = BalanceIn.model_validate({"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300})
    weights = {"shaking_force": 1, "shaking_moment": 2, "driving_torque": 1, "bearing_forces": 0.1}
    optimal_body = OptimalBalanceIn.model_validate({"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300,
                                                    "mass_budget_kg": BUDGET, "weights": weights})
    sweep = [{**weights, "driving_torque": 0.5 * k} for k in range(1, 10)]
    sweep_body = OptimalBalanceIn.model_validate({**optimal_body.model_dump(), "sweep": sweep})
    singles = [OptimalBalanceIn.model_validate({**optimal_body.model_dump(), "weights": w}) for w in sweep]
    t_static = median_of(lambda: client.balance_static(static_body), 21)
    t_optimal = median_of(lambda: client.balance_optimal(optimal_body), 21)
    t_sweep = median_of(lambda: client.balance_optimal(sweep_body), 9)
    t_singles = median_of(lambda: [client.balance_optimal(optimal_body)] + [client.balance_optimal(b) for b in singles], 5)
    as_json = {"static": static_body, "optimal": optimal_body, "sweep": sweep_body}
    asgi = asgi_medians({name: ("POST", "/v1/balancing/" + ("static" if name == "static" else "optimal"),
                                body.model_dump(mode="json", exclude_none=True))
                         for name, body in as_json.items()}, 21)
    print(f"in-process requests, {SAMPLES} samples, medians: over ASGI from an event loop (the service's work) | "
          "through the synchronous client (its thread hand-offs included)")
    print(f"  POST /v1/balancing/static:            {asgi['static'] * 1e3:7.2f} | {t_static * 1e3:7.2f} ms")
    print(f"  POST /v1/balancing/optimal:           {asgi['optimal'] * 1e3:7.2f} | {t_optimal * 1e3:7.2f} ms")
    print(f"  POST /v1/balancing/optimal, sweep 10: {asgi['sweep'] * 1e3:7.2f} | {t_sweep * 1e3:7.2f} ms (one program, "
          f"one solver re-solved; the same 10 points as 10 requests: {t_singles * 1e3:.1f} ms, "
          f"{t_singles / t_sweep:.1f}x)")


if __name__ == "__main__":
    main()
