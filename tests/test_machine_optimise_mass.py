"""The machine's whole mass and cost as objectives: the answer's machine mass is the sum of its parts, recomputed
here from the answer's own figures, and the optimum by machine mass is never worse than the densest scan."""

from __future__ import annotations

import copy
from typing import Any

import pytest

import synth
from api.translate.optimise import machine_optimise_from, mechanism_json
from mechsynth_client import SynthClient
from mechsynth_client.client import InvalidInputError
from mechsynth_client.schemas.optimise import (
    MAX_SCAN,
    SLIDER_CRANK_OPTIMISE_EXAMPLE,
    MachineOptimiseIn,
    MachineOptimiseOut,
)
from synth.machine import optimise as engine
from synth.machine.optimise_light import steady_member
from synth.synthesis import slider_crank
from tests.test_machine_optimise import _machine_request, machine_parts

#: The slider-crank press of the optimisation page, statically balanced (a crank counterweight), on a coarser
#: cycle, for the least added mass: its answer is designed whole, wheels sized, and reports every part.
PRESS: dict[str, Any] = {**copy.deepcopy(SLIDER_CRANK_OPTIMISE_EXAMPLE), "balancing": {"mode": "static"},
                         "weights": None, "objective": "added_mass", "samples": 48, "scan_members": 8}
#: The same press for the least machine mass over the densest scan. Sizing every member's wheels costs about
#: half a second a member, so here the drive sizes none (the machine is its counterweight, flywheel and motor);
#: the search's wheel sizing is checked on one member against the whole chain below.
BODY: dict[str, Any] = {**copy.deepcopy(PRESS), "objective": "machine_mass", "scan_members": MAX_SCAN,
                        "drive": {**PRESS["drive"], "size_gears": False}}


@pytest.fixture(scope="module")
def press(client: SynthClient) -> MachineOptimiseOut:
    return client.optimise_machine(MachineOptimiseIn.model_validate(PRESS))


@pytest.fixture(scope="module")
def answer(client: SynthClient) -> MachineOptimiseOut:
    return client.optimise_machine(MachineOptimiseIn.model_validate(BODY))


def test_machine_mass_is_the_sum_of_its_parts(press: MachineOptimiseOut) -> None:
    a = press
    d = a.design
    assert d.passed and a.parts is not None
    parts = machine_parts(d)
    # every part present: the crank counterweight, the flywheel body, two sized stages and the motor
    assert all(v > 0 for v in parts.values()), parts
    assert a.parts.counterweights_kg == pytest.approx(parts["counterweights"], rel=1e-9)
    assert a.parts.flywheel_kg == pytest.approx(parts["flywheel"], rel=1e-9)
    assert a.parts.gears_kg == pytest.approx(parts["gears"], rel=1e-9)
    assert a.parts.motor_kg == parts["motor"]
    total = sum(parts.values())
    assert a.parts.machine_mass_kg == pytest.approx(total, rel=1e-9)
    gains = {g.objective: g for g in a.gains}
    assert gains["machine_mass"].optimum == pytest.approx(total, rel=1e-9)
    # the default prices, as docs/optimise.md states them: 3, 2.5 and 12 per kg, the motor 6 per kg
    cost = 3.0 * parts["counterweights"] + 2.5 * parts["flywheel"] + 12.0 * parts["gears"] + 6.0 * parts["motor"]
    assert gains["cost"].optimum == pytest.approx(cost, rel=1e-9)
    assert a.parts.cost == pytest.approx(cost, rel=1e-9)
    # the chain's machine weighed too (its wheels sized in the scan)
    assert gains["machine_mass"].chain is not None and gains["machine_mass"].chain > parts["motor"]


def test_the_searchs_wheels_weigh_as_the_chain_sizes_them(client: SynthClient, press: MachineOptimiseOut) -> None:
    spec = machine_optimise_from(MachineOptimiseIn.model_validate(PRESS), 6)
    machine = spec.machine(slider_crank.member(spec.function, press.parameter))  # type: ignore[arg-type]
    steady = steady_member(machine, size_gears=True)
    assert press.parts is not None and steady.parts.gears is not None
    # the search bisects the face width 12 times (within ln 5 / 2^12, never below the least width): its
    # wheels weigh at least the chain's and within 1e-3 of them
    assert press.parts.gears_kg <= steady.parts.gears * (1 + 1e-12)
    assert steady.parts.gears == pytest.approx(press.parts.gears_kg, rel=1e-3)
    assert steady.parts.motor == press.parts.motor_kg and steady.parts.flywheel == pytest.approx(
        press.parts.flywheel_kg, rel=1e-9)


def test_machine_mass_never_worse_than_the_densest_scan(client: SynthClient, answer: MachineOptimiseOut) -> None:
    a = answer
    assert a.parts is not None
    densest = engine.scan_family(machine_optimise_from(MachineOptimiseIn.model_validate(BODY), 6)).candidates
    scanned = [m for m in a.members if m.stage == "scan"]
    assert {m.parameter for m in scanned} >= set(densest) and len(densest) == MAX_SCAN + 1
    feasible = [m for m in scanned if m.feasible]
    assert len(feasible) >= MAX_SCAN // 2
    mass = {m.name: m.mass for m in synth.motor_catalogue()}
    sized = []
    for m in feasible:
        assert m.added_mass_kg is not None and m.motor is not None and m.machine_mass_bound_kg is not None
        # the bound: the member's counterweights and flywheel body with its motor's catalogue mass, no wheels
        assert m.machine_mass_bound_kg == pytest.approx(m.added_mass_kg + mass[m.motor], rel=1e-12)
        if m.machine_mass_kg is not None:
            sized.append(m)
            assert m.machine_mass_kg >= m.machine_mass_bound_kg * (1 - 1e-12)
        # a member whose wheels were not sized weighs at least its bound
        weight = m.machine_mass_kg if m.machine_mass_kg is not None else m.machine_mass_bound_kg
        assert a.parts.machine_mass_kg <= weight * (1 + 1e-4), f"member u={m.parameter:.6g} beats the optimum"
    assert sized
    # the scan weighed its members on their steady machine, wheels sized as the chain sizes them: the whole
    # chain on the best sized of them, its parts recomputed here, weighs the same
    assert len(sized) == len(feasible)
    best = min(sized, key=lambda m: m.machine_mass_kg or 0.0)
    f = machine_optimise_from(MachineOptimiseIn.model_validate(BODY), 6).function
    member = slider_crank.member(f, best.parameter)  # type: ignore[arg-type]
    d = client.design_machine(_machine_request(BODY, mechanism_json(member)))
    parts = machine_parts(d)
    assert parts["gears"] == 0.0
    assert sum(parts.values()) == pytest.approx(best.machine_mass_kg, rel=1e-9)


def test_a_catalogue_without_masses_is_named(client: SynthClient) -> None:
    body = copy.deepcopy(BODY)
    body["drive"] = {**body["drive"], "motor_catalogue": [
        {"name": "own-1", "rated_power_W": 1500, "synchronous_rpm": 1500, "rated_rpm": 1420,
         "rotor_inertia_kgm2": 0.004}]}
    with pytest.raises(InvalidInputError) as err:
        client.optimise_machine(MachineOptimiseIn.model_validate(body))
    assert err.value.problem.get("field") == "drive.motor_catalogue.0.mass_kg"
