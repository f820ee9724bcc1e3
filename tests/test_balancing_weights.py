"""Optimal balancing weights are dimensionless by default: each term over its value before balancing."""

from __future__ import annotations

import dataclasses

import pytest

import synth
from api.translate.linkage import linkage_from
from mechsynth_client.schemas.balancing import OptimalBalanceIn
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE


@pytest.fixture(scope="module")
def fourbar() -> tuple[synth.Linkage, float]:
    body = OptimalBalanceIn.model_validate({"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300})
    return linkage_from(body), body.omega_rad_s


def test_relative_weights_improve_what_they_weight(fourbar: tuple[synth.Linkage, float]) -> None:
    # the README's example: force 1, moment 2, within 4 kg; both weighted terms fall below their values before
    linkage, w = fourbar
    weights = synth.Weights(shaking_force=1.0, shaking_moment=2.0)
    r = synth.balance_optimal(linkage, w, weights=weights, mass_budget=4.0, samples=90)
    assert r.after.rms_shaking_force < r.before.rms_shaking_force
    assert r.after.rms_shaking_moment < r.before.rms_shaking_moment
    assert r.weights == weights and r.weight_scale == "relative"


def test_relative_scale_is_the_absolute_program_with_weights_over_the_terms(fourbar: tuple[synth.Linkage, float]) -> None:
    # identity: relative weights w equal absolute weights w / (term before), term values from a plain analysis
    linkage, w = fourbar
    weights = synth.Weights(shaking_force=1.0, shaking_moment=2.0)
    before = synth.analyse(linkage, w, samples=90).summary()
    scaled = dataclasses.replace(weights, shaking_force=1.0 / before.rms_shaking_force,
                                 shaking_moment=2.0 / before.rms_shaking_moment)
    rel = synth.balance_optimal(linkage, w, weights=weights, mass_budget=4.0, samples=90)
    absolute = synth.balance_optimal(linkage, w, weights=scaled, mass_budget=4.0, samples=90, weight_scale="absolute")
    assert rel.after.rms_shaking_force == pytest.approx(absolute.after.rms_shaking_force, rel=1e-4, abs=1e-6)
    assert rel.after.rms_shaking_moment == pytest.approx(absolute.after.rms_shaking_moment, rel=1e-4)


def test_sweep_points_echo_their_weights_over_http(client) -> None:  # type: ignore[no-untyped-def]
    body = OptimalBalanceIn.model_validate({
        "mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "mass_budget_kg": 4.0, "samples": 90,
        "weights": {"shaking_force": 1.0, "shaking_moment": 2.0},
        "sweep": [{"shaking_force": 1.0}, {"shaking_force": 0.0, "shaking_moment": 1.0}]})
    out = client.balance_optimal(body)
    points = [out, *out.tradeoff]
    assert [(p.weights.shaking_force, p.weights.shaking_moment) for p in points] == [(1, 2), (1, 0), (0, 1)]
    # the sweep spans the trade-off: force-only leaves the least force, moment-only the least moment
    forces = [p.summary_after.rms_shaking_force_N for p in points]
    moments = [p.summary_after.rms_shaking_moment_Nm for p in points]
    assert forces.index(min(forces)) == 1 and moments.index(min(moments)) == 2
