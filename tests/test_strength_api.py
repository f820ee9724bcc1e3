"""POST /v1/strength through the client: the four-bar and the six-bar press sized to the fixed point, the answer
checked against an engine run of its own, and bad input answered 422 naming the field, or the link, check and
crank angle."""

from __future__ import annotations

import copy
import math
from typing import Any

import pytest

from mechsynth_client.client import InfeasibleError, InvalidInputError, SynthClient
from mechsynth_client.schemas.strength import StrengthSizingIn

EXAMPLES: list[dict[str, Any]] = StrengthSizingIn.model_config["json_schema_extra"]["examples"]  # type: ignore


@pytest.mark.parametrize("example", EXAMPLES, ids=["fourbar", "press"])
def test_examples_are_sized_to_the_fixed_point(client: SynthClient, example: dict[str, Any]) -> None:
    out = client.strength(StrengthSizingIn.model_validate(example))
    assert out.passed
    assert out.mass_residual_kg == 0.0            # the final analysis used exactly the sections' masses
    assert out.closure_N < 1e-8                   # every bar in equilibrium under the kinetostatics' loads
    assert out.analyses == len(out.iterations) >= 2
    assert out.iterations[-1].sections == {s.link: s.section for s in out.links}
    for link in out.links:
        # rho A L, with the grade's density, from the answer's own numbers
        rho = 7850.0
        assert link.mass_kg == pytest.approx(rho * link.area_mm2 * 1e-6 * link.length_m, rel=1e-9)
        assert {c.name for c in link.checks} == {"static", "fatigue", "buckling_in_plane", "buckling_out_of_plane"}
        for c in link.checks:
            assert c.passed and (c.safety is None or c.safety >= c.required)
            assert 0.0 <= c.crank_angle_deg < 360.0
    assert out.mass_kg == pytest.approx(sum(link.mass_kg for link in out.links), rel=1e-12)


def test_press_names_its_bars_and_keeps_the_ram_a_block(client: SynthClient) -> None:
    out = client.strength(StrengthSizingIn.model_validate(EXAMPLES[1]))
    by = {link.link: link for link in out.links}
    assert set(by) == {"crank", "coupler", "rocker", "rod"}
    assert by["crank"].kind == "round" and by["rod"].kind == "tube" and by["rod"].material == "C45E+QT"
    # the rocker carries three joints on one line: Q at 0, B at 0.25 m, C at 0.4 m
    assert by["rocker"].points_m["Q"] == pytest.approx(0.0, abs=1e-12)
    assert by["rocker"].points_m["B"] == pytest.approx(0.25, rel=1e-9)
    assert by["rocker"].length_m == pytest.approx(0.4, rel=1e-9)


def test_a_material_without_its_limits_is_refused_at_the_edge(client: SynthClient) -> None:
    body = copy.deepcopy(EXAMPLES[0])
    body["material"] = {"name": "mine", "yield_strength_MPa": 300, "ultimate_strength_MPa": 500,
                        "elastic_modulus_GPa": 210, "density_kg_m3": 7850}
    with pytest.raises(Exception, match="fatigue_limit_MPa"):
        StrengthSizingIn.model_validate(body)
    body["material"]["fatigue_limit_MPa"] = 600
    with pytest.raises(InvalidInputError) as err:
        client.strength(StrengthSizingIn.model_validate(body))
    assert err.value.problem["field"] == "material.fatigue_limit_MPa"


def test_a_section_too_small_for_the_load_is_infeasible_naming_link_check_and_angle(client: SynthClient) -> None:
    body = copy.deepcopy(EXAMPLES[1])
    body["links"] = [{"link": "rod", "section": {"kind": "round", "max_size_mm": 4}}]
    with pytest.raises(InfeasibleError) as err:
        client.strength(StrengthSizingIn.model_validate(body))
    problem = err.value.problem
    assert problem["status"] == 422 and problem["link"] == "rod", problem
    assert problem["check"] in ("static", "fatigue", "buckling_in_plane", "buckling_out_of_plane")
    assert math.isfinite(problem["crank_angle_deg"])
    assert problem["constraint"] == f"links.rod.{problem['check']}"


def test_a_study_varies_the_strength_request_and_its_rows_are_the_answers() -> None:
    # The rod's load grows with the press force: its sized section's mass cannot shrink as the force grows, and
    # each row's metrics are what POST /v1/strength answers for that variant (a row is the endpoint's answer).
    import json

    import synth
    from api.execution.plans import PLANS, Limits
    from api.studies.paths import check_metrics
    from api.studies.tasks import variant_function
    from api.translate.strength import sizing_call
    from synth.execution import SerialExecutor

    assert PLANS["/v1/strength"][0] is StrengthSizingIn
    check_metrics("/v1/strength", ["mass_kg", "links.3.mass_kg", "links.0.checks.1.safety"])
    check_metrics("/v1/machines/design", ["strength.link_mass_kg", "strength.parts.crank_shaft.diameter_mm"])
    base = json.loads(json.dumps({**EXAMPLES[1], "samples": 72}))
    forces = [1000.0, 8000.0, 64000.0]
    spec = {"endpoint": "/v1/strength", "base": base, "metrics": ["mass_kg"],
            "parameters": [{"path": "loads.0.force_N", "values": forces}], "sampling": "grid"}
    rows: list[synth.VariantRow] = []
    executor = SerialExecutor()
    try:
        synth.run_study(synth.study_from_dict(spec), variant_function("/v1/strength", Limits(20_000, 6, 20.0)),
                        executor, rows.extend)
    finally:
        executor.shutdown()
    rows.sort(key=lambda r: r.index)
    assert all(r.ok for r in rows)
    masses = [r.metrics[0] for r in rows]  # type: ignore[index]
    assert masses[0] <= masses[1] <= masses[2] and masses[0] < masses[2]
    body = StrengthSizingIn.model_validate({**base, "loads": [{**base["loads"][0], "force_N": forces[1]}]})
    direct = synth.strength.size_links(*sizing_call(body), samples=72)
    assert masses[1] == pytest.approx(direct.mass, rel=1e-12)
