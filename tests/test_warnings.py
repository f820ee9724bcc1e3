"""Warnings: each check fires on the mistake it names (code, field, number) and stays quiet on the README's examples."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

import synth
from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE

REPO = Path(__file__).resolve().parents[1]
DOCUMENTATION = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]
SLIDER_CRANK = {"type": "slider_crank", "crank_length_m": 0.05, "rod_length_m": 0.2,
                "links": {"crank": {"mass_kg": 1.0, "com_m": [0.02, 0]}, "rod": {"mass_kg": 0.8, "com_m": [0.06, 0]},
                          "slider": {"mass_kg": 1.2}}}


def _codes(out: dict) -> dict[str, dict]:
    return {w["code"]: w for w in out["warnings"]}


def _analysis(client: SynthClient, mechanism: dict, **extra: object) -> dict:
    r = client.http.post("/v1/analysis", json={"mechanism": mechanism, "speed_rpm": 300, "samples": 36, **extra})
    assert r.status_code == 200, r.text
    return r.json()


def test_lengths_typed_in_millimetres(client: SynthClient) -> None:
    # The four-bar typed in millimetres: 300 "m" of ground.
    mm = {**FOURBAR_EXAMPLE, "ground_length_m": 300.0, "crank_length_m": 100.0, "coupler_length_m": 250.0,
          "rocker_length_m": 250.0}
    found = {w["field"]: w for w in _analysis(client, mm)["warnings"] if w["code"] == "length_likely_mm"}
    assert set(found) == {f"mechanism.{n}_length_m" for n in ("ground", "crank", "coupler", "rocker")}
    assert found["mechanism.ground_length_m"]["value"] == 300.0 and found["mechanism.ground_length_m"]["unit"] == "m"


def test_mass_typed_in_grams(client: SynthClient) -> None:
    # 1200 "kg" on a 0.2 m slider-crank: a steel cube of 0.2 m weighs 7850·0.2³ = 62.8 kg.
    grams = {**SLIDER_CRANK, "links": {**SLIDER_CRANK["links"], "slider": {"mass_kg": 1200.0}}}
    w = _codes(_analysis(client, grams))["mass_likely_grams"]
    assert w["field"] == "mechanism.links.slider.mass_kg" and w["value"] == 1200.0
    cw = [{"link": "crank", "mass_kg": 500.0, "position_m": [-0.03, 0.0]}]
    w = _codes(_analysis(client, SLIDER_CRANK, counterweights=cw))["mass_likely_grams"]
    assert w["field"] == "counterweights[0].mass_kg" and w["value"] == 500.0


def test_inertia_without_mass(client: SynthClient) -> None:
    links = {**FOURBAR_EXAMPLE["links"], "rocker": {"inertia_kgm2": 0.008}}
    w = _codes(_analysis(client, {**FOURBAR_EXAMPLE, "links": links}))["inertia_without_mass"]
    assert w["field"] == "mechanism.links.rocker.inertia_kgm2" and w["value"] == 0.008


def test_links_left_out(client: SynthClient) -> None:
    bare = {k: v for k, v in FOURBAR_EXAMPLE.items() if k != "links"}
    assert _codes(_analysis(client, bare))["links_missing"]["field"] == "mechanism.links"
    no_coupler = {"crank": FOURBAR_EXAMPLE["links"]["crank"], "rocker": FOURBAR_EXAMPLE["links"]["rocker"]}
    w = _codes(_analysis(client, {**FOURBAR_EXAMPLE, "links": no_coupler}))
    assert w["link_left_out"]["field"] == "mechanism.links.coupler" and "links_missing" not in w


def test_counterweight_beyond_its_link(client: SynthClient) -> None:
    # The crank is 0.1 m long; a counterweight 0.15 m behind its pivot needs an arm of its own.
    out = _analysis(client, FOURBAR_EXAMPLE, counterweights=[{"link": "crank", "mass_kg": 0.5, "position_m": [-0.15, 0]}])
    w = _codes(out)["counterweight_beyond_link"]
    assert w["field"] == "counterweights[0].position_m" and w["value"] == pytest.approx(0.15, rel=1e-12)


def test_counterweight_beyond_its_link_after_balancing(client: SynthClient) -> None:
    # A radius limit of 0.2 m on the 0.1 m crank lets the least-mass program use all of it.
    body = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 36, "max_radius_m": {"crank": 0.2}}
    out = client.http.post("/v1/balancing/static", json=body).json()
    w = _codes(out)["counterweight_beyond_link"]
    crank = next(p for p in out["placements"] if p["link"] == "crank")
    assert w["field"] == "max_radius_m.crank" and w["value"] == pytest.approx(crank["radius_m"], rel=1e-12)
    assert crank["radius_m"] > FOURBAR_EXAMPLE["crank_length_m"]


def test_transmission_angle_under_40_degrees(client: SynthClient) -> None:
    # The four-bar 0.30/0.10/0.35/0.25: the law of cosines at the shortest diagonal B-D = 0.2 m (crank
    # angle 0) gives the least transmission angle, computed here independently of the engine.
    mech = {**FOURBAR_EXAMPLE, "coupler_length_m": 0.35}
    c, r, d = 0.35, 0.25, 0.3 - 0.1
    expected = math.degrees(math.acos((c * c + r * r - d * d) / (2 * c * r)))
    w = _codes(_analysis(client, mech, samples=360))["transmission_angle_low"]
    assert w["field"] == "mechanism" and w["unit"] == "deg"
    assert w["value"] == pytest.approx(expected, abs=1e-6)   # degrees rounded to 1e-6 at the edge
    (start, end), = w["crank_angle_ranges_deg"]
    assert start > 180 and end < 180   # one range wrapping through crank angle 0, where the minimum lies


def test_loads_that_drive_the_machine(client: SynthClient) -> None:
    # A negative window force "against the velocity" pushes with it: the load's work per revolution is positive.
    load = {"type": "window", "force_N": -500.0, "start_deg": 0, "end_deg": 180}
    w = _codes(_analysis(client, SLIDER_CRANK, loads=[load], samples=360))["load_work_positive"]
    assert w["field"] == "loads" and w["value"] > 0
    # Independent figure: a force F against the slider's velocity over the outstroke does -F·stroke of work.
    assert w["value"] == pytest.approx(500.0 * 2 * 0.05, rel=2e-2)


def _flywheel(client: SynthClient, **body: object) -> dict:
    r = client.http.post("/v1/flywheel", json=body)
    assert r.status_code == 200, r.text
    return r.json()


TABLE = {"crank_angle_deg": [0, 90, 180, 270, 360], "reduced_torque_Nm": [0, -100, 0, 0, 0]}


def test_flywheel_resisting_torques_typed_positive(client: SynthClient) -> None:
    positive = {**TABLE, "reduced_torque_Nm": [-v for v in TABLE["reduced_torque_Nm"]]}
    out = _flywheel(client, tables=positive, mean_speed_rad_s=10.0, delta=0.05)
    w = _codes(out)["load_work_positive"]
    assert w["field"] == "tables" and w["value"] == pytest.approx(out["cycle_work_J"], rel=1e-12)
    assert out["constant_driving_torque_Nm"] < 0


def test_flywheel_delta_outside_every_machine_type(client: SynthClient) -> None:
    out = _flywheel(client, tables=TABLE, mean_speed_rad_s=10.0, delta=1e-6)
    w = _codes(out)["delta_out_of_range"]
    assert w["field"] == "delta" and w["value"] == 1e-6
    assert min(t.delta_min for t in synth.machine_types()) > w["value"]


def test_flywheel_rim_speed_near_its_limit(client: SynthClient) -> None:
    # The lightest rim for this cycle runs at about 4.46 m/s whatever the limit above it; 4.6 m/s leaves 3 %.
    out = _flywheel(client, tables=TABLE, mean_speed_rad_s=10.0, delta=0.05,
                    geometry={"max_rim_speed_m_s": 4.6})
    w = _codes(out)["rim_speed_near_limit"]
    assert w["field"] == "geometry.max_rim_speed_m_s"
    assert w["value"] == pytest.approx(out["geometry"]["best"]["rim_speed_m_s"], rel=1e-12)
    assert w["value"] >= 0.95 * 4.6
    roomy = _flywheel(client, tables=TABLE, mean_speed_rad_s=10.0, delta=0.05, geometry={"max_rim_speed_m_s": 30.0})
    assert roomy["warnings"] == []


def test_rotor_correction_at_a_small_radius(client: SynthClient) -> None:
    # 1 kg at 0.1 m balanced at 0.01 m needs 10 kg (m·r is conserved).
    body = {"masses": [{"mass_kg": 1.0, "radius_m": 0.1, "angle_deg": 0}], "mode": "static", "correction_radius_m": 0.01}
    r = client.http.post("/v1/balancing/rotor", json=body)
    w = _codes(r.json())["correction_radius_small"]
    assert w["field"] == "corrections[0].radius_m" and r.json()["corrections"][0]["mass_kg"] == pytest.approx(10.0)


def test_gearing_warnings_share_the_shape(client: SynthClient) -> None:
    r = client.http.post("/v1/gears/teeth", json={"total_ratio": 17.3, "stages": 2, "min_teeth": 12})
    w = r.json()["warnings"][0]
    assert w["code"] == "below_undercut_limit" and w["field"] == "min_teeth" and w["value"] == 12


def _readme_requests() -> list[tuple[str, dict]]:
    """(path, body) of every curl example in the README and docs/ that posts JSON."""
    found = []
    for chunk in "".join(page.read_text() for page in DOCUMENTATION).split("curl -s ")[1:]:
        path = re.match(r"'?http://127\.0\.0\.1:8000(/v1/[\w/-]+)", chunk)
        body = re.search(r"-d '(\{.*?\})'", chunk, re.S)
        if path and body and not path.group(1).startswith("/v1/studies"):
            # A study answers 202 and its rows are the design endpoints' answers. A drawing answers DXF or SVG only: its body's warnings are those of the analysis it draws.
            found.append((path.group(1).removesuffix("/drawing"), json.loads(body.group(1))))
    return found


# The README's drive example shows the shipped catalogue's notes: representative data (without a rotor inertia for
# that motor) and torques at the rated power, as the textbook example computes them. Its press machine gathers
# every stage's notes: the catalogue's (drive) and, its lightest flywheel being the one at the rim speed limit,
# no margin for overspeed (flywheel).
DOCUMENTED = {"/v1/gears/drive": {"representative_catalogue", "rotor_inertia_missing", "rated_power_exceeds"},
              "/v1/machines/design": {"representative_catalogue", "rim_speed_near_limit"},
              # docs/synthesis.md's slider-crank for a time ratio of 1.3: its best transmission angle is 39.0°, just under
              # the analysis' 40° (asin((a + e)/b) of the answer), and the answer says so
              "/v1/synthesis/slider-crank": {"transmission_angle_low"}}


# Answers that are exact bookkeeping of what was given (a structure's counts) carry no warnings field, nor does a
# cam's analysis, whose limits (pressure angle, curvature, contact) are refusals or checks of its answer.
NO_WARNINGS_FIELD = {"/v1/structure"}


def test_readme_examples_have_no_warnings(client: SynthClient) -> None:
    requests = _readme_requests()
    assert {p for p, _ in requests} >= {"/v1/analysis", "/v1/balancing/static", "/v1/flywheel", "/v1/gears/split"}
    for path, body in requests:
        r = client.http.post(path, json=body)
        assert r.status_code == 200, (path, r.text)
        if path in NO_WARNINGS_FIELD:
            assert "warnings" not in r.json()
            continue
        codes = {w["code"] for w in r.json()["warnings"]}
        assert codes == DOCUMENTED.get(path, set()), (path, r.json()["warnings"])


def test_warnings_are_plain_data() -> None:
    an = synth.analyse(synth.Linkage(synth.FourBar(0.3, 0.1, 0.35, 0.25)), 10.0, samples=12)
    warnings = synth.check_analysis(an)
    assert {w.code for w in warnings} == {"links_missing", "transmission_angle_low"}
    assert all(np.isfinite(w.value) for w in warnings if w.value is not None)
