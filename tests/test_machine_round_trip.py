"""Round trips: a full-balance answer sent back to /v1/analysis gives zero shaking force and moment."""

from __future__ import annotations

import numpy as np
import pytest

import synth
from api.translate.linkage import linkage_from
from mechsynth_client.client import InvalidInputError, SynthClient
from mechsynth_client.schemas.analysis import AnalysisIn
from mechsynth_client.schemas.balancing import FullBalanceIn
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE


@pytest.fixture(scope="module")
def full(client: SynthClient):  # type: ignore[no-untyped-def]
    return client.balance_full(FullBalanceIn(mechanism=FOURBAR_EXAMPLE, speed_rpm=300, samples=90))


def test_full_balance_answer_as_is_reanalyses_to_zero(  # type: ignore[no-untyped-def]
        client: SynthClient, full) -> None:
    out = client.analysis(AnalysisIn.model_validate(
        {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 90, "balancing": full.model_dump()}))
    before = full.summary_before
    # zero up to the solver's accuracy: the balance's own residual, relative to the unbalanced peaks
    assert out.summary.max_shaking_force_N <= 1e-6 * before.max_shaking_force_N
    assert out.summary.max_shaking_moment_Nm <= 1e-6 * before.max_shaking_moment_Nm
    # the rotors' torque is in the driving torque: the balancing answer's own figure, and virtual power agrees
    assert out.summary.rms_driving_torque_Nm == pytest.approx(full.summary_after.rms_driving_torque_Nm, rel=1e-9)
    assert out.checks.virtual_power_torque_max_diff_Nm < 1e-9 * (1 + out.summary.max_driving_torque_Nm)


def test_fields_one_by_one_equal_the_answer_as_is(client: SynthClient, full) -> None:  # type: ignore[no-untyped-def]
    parts = client.analysis(AnalysisIn.model_validate({
        "mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 90,
        "counterweights": [c.model_dump() for c in full.counterweights],
        "coupler_inertia_kgm2": full.coupler_inertia_kgm2,
        "counter_rotors": [r.model_dump() for r in full.counter_rotors or []]}))
    assert parts.summary.max_shaking_moment_Nm <= 1e-6 * full.summary_before.max_shaking_moment_Nm
    # without the rotors the moment comes back (the new user's 75.8 N·m surprise)
    no_rotors = client.analysis(AnalysisIn.model_validate({
        "mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 90,
        "counterweights": [c.model_dump() for c in full.counterweights],
        "coupler_inertia_kgm2": full.coupler_inertia_kgm2}))
    assert no_rotors.summary.max_shaking_moment_Nm > 0.1 * full.summary_before.max_shaking_moment_Nm


def test_rotor_reduced_inertia_reproduces_kinetic_energy() -> None:
    # identity: J_red·w²/2 of the linkage with rotors = the linkage's own + sum of 1/2·J·(k·w_i)² of the rotors
    linkage = linkage_from(AnalysisIn.model_validate({"mechanism": FOURBAR_EXAMPLE}))
    rotors = (synth.CounterRotor("crank", 0.01, 1.0), synth.CounterRotor("rocker", 0.02, 2.0))
    w = 10.0
    plain = synth.analyse(linkage, w, samples=60)
    with_rotors = synth.analyse(linkage, w, samples=60, counter_rotors=rotors)
    m = plain.motion
    rotor_energy = 0.5 * 0.01 * m.link_omega["crank"] ** 2 + 0.5 * 0.02 * (2 * m.link_omega["rocker"]) ** 2
    assert np.allclose(with_rotors.reduced.kinetic_energy, plain.reduced.kinetic_energy + rotor_energy, rtol=1e-12)


def test_bad_rotor_names_its_field(client: SynthClient) -> None:
    with pytest.raises(InvalidInputError) as err:
        client.analysis(AnalysisIn.model_validate({"mechanism": FOURBAR_EXAMPLE, "counter_rotors": [
            {"link": "ram", "inertia_kgm2": 0.1}]}))
    assert err.value.problem["field"] == "counter_rotors[0].link"
