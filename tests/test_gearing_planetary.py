"""Planetary stages in POST /v1/gears/teeth: their real constraints, against a plain search written here."""

from __future__ import annotations

import math

import pytest

from mechsynth_client.client import InfeasibleError, SynthClient
from mechsynth_client.schemas.gearing import TeethIn


def _plain_best(target: float, planets: int, max_teeth: int, lowest: int) -> tuple[float, int]:
    # Independent: loops over sun and planet with the conditions stated directly; closest ratio, then fewest teeth.
    # Coaxial z_r = z_s + 2 z_p; equal spacing (z_s + z_r) % planets == 0; tips of neighbouring planets clear:
    # centre distance 2·a·sin(pi/n) with a = (z_s + z_p)·m/2 above the planet's tip diameter (z_p + 2)·m; the
    # table's range 3..9 for a planetary stage; no interference between sun and planet at 20° (both >= 18 here).
    best = (math.inf, 0)
    for zs in range(lowest, max_teeth + 1):
        for zp in range(lowest, max_teeth + 1):
            zr = zs + 2 * zp
            if zr > max_teeth or (zs + zr) % planets or (zs + zp) * math.sin(math.pi / planets) <= zp + 2:
                continue
            ratio = 1 + zr / zs
            if not 3 <= ratio <= 9:
                continue
            err = abs(ratio / target - 1)
            if err < best[0] - 1e-12 or (abs(err - best[0]) <= 1e-12 and zs + zp + zr < best[1]):
                best = (err, zs + zp + zr)
    return best


@pytest.mark.parametrize(("target", "planets"), [(5.3, 3), (7.7, 4)])
def test_planetary_stage_meets_its_constraints(client: SynthClient, target: float, planets: int) -> None:
    body = TeethIn.model_validate({"total_ratio": target, "stages": ["planetary"], "planets": planets,
                                   "max_teeth": 90})
    out = client.gears_teeth(body)
    (stage,) = out.stages
    zs, zp, zr = stage.sun_teeth, stage.planet_teeth, stage.ring_teeth
    assert zs is not None and zp is not None and zr is not None
    assert zr == zs + 2 * zp and (zs + zr) % planets == 0 and stage.planets == planets
    assert (zs + zp) * math.sin(math.pi / planets) > zp + 2
    assert stage.ratio == pytest.approx(1 + zr / zs, rel=1e-15)
    # The lowest wheel at 20° full depth is 18 (undercut limit 17.1), as the search uses.
    err, teeth = _plain_best(target, planets, 90, 18)
    assert out.ratio_error == pytest.approx(err, abs=1e-12) and out.total_teeth == teeth
    assert out.checks.agrees is True


def test_spur_and_planetary_train(client: SynthClient) -> None:
    # A spur pair before a planetary stage: the product of the stage ratios is the train's, each within its range.
    out = client.gears_teeth(TeethIn.model_validate({"total_ratio": 17.3, "stages": ["spur", "planetary"],
                                                      "max_teeth": 80}))
    spur, planet = out.stages
    assert spur.sun_teeth is None and planet.sun_teeth is not None
    assert out.total_ratio == pytest.approx(spur.gear_teeth / spur.pinion_teeth * (1 + planet.ring_teeth / planet.sun_teeth),
                                            rel=1e-12)
    assert out.checks.agrees is True


def test_no_planetary_fits_is_named(client: SynthClient) -> None:
    # Ring at most 40 teeth: z_s, z_p >= 18 make z_r >= 54, so no stage exists.
    with pytest.raises(InfeasibleError) as err:
        client.gears_teeth(TeethIn.model_validate({"total_ratio": 5, "stages": ["planetary"], "max_teeth": 40}))
    assert err.value.problem["constraint"] == "stages[0]"
