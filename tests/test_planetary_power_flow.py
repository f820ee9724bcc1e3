"""Planetary efficiency by the direction of the power: the engine against two independent derivations.

1. The closed forms of Willis and Kudryavtsev for a simple stage with the ring held: sun driving
   eta = (1 + eta0·z_r/z_s)/(1 + z_r/z_s), carrier driving eta = (1 + z_r/z_s)/(1 + z_r/(z_s·eta0)).
2. The torques solved as a linear system for either assumption of which member drives the carrier-held train
   (equilibrium, unit input power, the relative train's output power eta0 times its input); an assumption is
   consistent when the member it takes as driving really puts power in, and of the consistent ones the
   physical answer creates no energy (efficiency at most 1) and loses the least. No sign rule is shared with
   the engine.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import synth
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.gearing import TeethIn
from mechsynth_client.schemas.train import TrainIn
from synth.gearing.train import planetary_efficiency

ETA0 = 0.97**2   # the default basic efficiency: two closed spur meshes
MEMBERS = ("sun", "ring", "carrier")


def _by_consistent_torques(stage: synth.PlanetaryStage, driving: str, driven: str) -> float:
    i0 = stage.basic_ratio()
    fixed = (set(MEMBERS) - {driving, driven}).pop()
    coef = {"sun": 1.0, "ring": -i0, "carrier": i0 - 1.0}   # Willis: sum coef·w = 0
    w = {fixed: 0.0, driving: 1.0, driven: -coef[driving] / coef[driven]}
    idx = {m: k for k, m in enumerate(MEMBERS)}
    ws, wr = w["sun"] - w["carrier"], w["ring"] - w["carrier"]
    answers = []
    for sun_drives in (True, False):
        a, b = np.zeros((3, 3)), np.array([0.0, 1.0, 0.0])
        a[0] = 1.0
        a[1, idx[driving]] = 1.0
        a[2, :2] = [ETA0 * ws, wr] if sun_drives else [ws, ETA0 * wr]
        t = np.linalg.solve(a, b)
        puts_in = (t[0] * ws if sun_drives else t[1] * wr) > 0
        eta = -t[idx[driven]] * w[driven]
        if puts_in and eta <= 1 + 1e-12:
            answers.append(float(eta))
    return max(answers)


def test_the_issues_stage_differs_by_direction_as_willis_and_kudryavtsev_say(client: SynthClient) -> None:
    zs, zp, zr = 20, 30, 80
    k = zr / zs
    sun_drives = (1 + ETA0 * k) / (1 + k)
    carrier_drives = (1 + k) / (1 + k / ETA0)
    forward = client.gears_train(TrainIn.model_validate(
        {"elements": [{"type": "planetary", "sun_teeth": zs, "planet_teeth": zp, "ring_teeth": zr}]}))
    back = client.gears_train(TrainIn.model_validate(
        {"elements": [{"type": "planetary", "sun_teeth": zs, "planet_teeth": zp, "ring_teeth": zr,
                       "input": "carrier", "output": "sun"}]}))
    assert forward.efficiency == pytest.approx(sun_drives, rel=1e-12)        # 0.95272
    assert back.efficiency == pytest.approx(carrier_drives, rel=1e-12)       # 0.95215, no longer 0.95272
    assert forward.back_efficiency == pytest.approx(carrier_drives, rel=1e-12)
    assert not forward.self_locking and not forward.locked and not forward.warnings


@pytest.mark.parametrize(("driving", "driven"), list(itertools.permutations(MEMBERS, 2)))
@pytest.mark.parametrize("stage", [
    synth.PlanetaryStage(20, 30, 80),
    synth.PlanetaryStage(17, 23, 70, planet_ring_teeth=18),                       # stepped planet, ring inside
    synth.PlanetaryStage(100, 101, 99, planet_ring_teeth=102, ring_internal=False),  # two suns: i0 = 0.98
    synth.PlanetaryStage(30, 20, 25, planet_ring_teeth=25, ring_internal=False),    # two suns: i0 = 0.556
], ids=["simple", "stepped", "two-suns-0.98", "two-suns-0.56"])
def test_every_role_matches_the_consistent_torques(stage: synth.PlanetaryStage, driving: str, driven: str) -> None:
    fixed = (set(MEMBERS) - {driving, driven}).pop()
    eta = planetary_efficiency(stage.basic_ratio(), ETA0, fixed, driving, driven)  # type: ignore[arg-type]
    assert eta == pytest.approx(_by_consistent_torques(stage, driving, driven), rel=1e-10, abs=1e-12)


def test_a_positive_ratio_stage_that_locks_one_way_says_so(client: SynthClient) -> None:
    # carrier in, sun out, ring (second sun) held, i0 = 100·99/(101·102): ratio 1/(1 - i0) = 50.7
    body = {"type": "planetary", "sun_teeth": 100, "planet_teeth": 101, "ring_teeth": 99, "planet_ring_teeth": 102,
            "ring_internal": False, "input": "carrier", "output": "sun"}
    answer = client.gears_train(TrainIn.model_validate({"elements": [body]}))
    i0 = (101 / 100) * (99 / 102)
    assert answer.ratio == pytest.approx(1 / (1 - i0), rel=1e-12)
    stage = synth.PlanetaryStage(100, 101, 99, "ring", "carrier", "sun", planet_ring_teeth=102, ring_internal=False)
    assert answer.efficiency == pytest.approx(_by_consistent_torques(stage, "carrier", "sun"), rel=1e-10)
    assert 0 < answer.efficiency < 0.3
    assert answer.back_efficiency == pytest.approx(_by_consistent_torques(stage, "sun", "carrier"), rel=1e-10)
    assert answer.back_efficiency <= 0 and answer.self_locking and not answer.locked
    (note,) = answer.warnings
    assert note.code == "self_locking_back" and note.field == "elements[0]"


def test_a_planetary_stage_of_the_tooth_search_carries_both_directions(client: SynthClient) -> None:
    answer = client.gears_teeth(TeethIn.model_validate({"total_ratio": 5.0, "stages": ["planetary"]}))
    (mesh,) = answer.stages
    assert mesh.sun_teeth and mesh.ring_teeth and mesh.planet_teeth
    k = mesh.ring_teeth / mesh.sun_teeth
    assert mesh.efficiency == pytest.approx((1 + ETA0 * k) / (1 + k), rel=1e-12)
    assert mesh.back_efficiency == pytest.approx((1 + k) / (1 + k / ETA0), rel=1e-12)
