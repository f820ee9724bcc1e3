"""Synthesis answers carry the analysis' own warnings: an unusable linkage is said to be one.

Independent derivation: the transmission angle of the returned four-bar by the law of cosines over the crank
angle, cos mu = (b² + c² - |AQ|²)/(2·b·c) with |AQ|² = a² + d² - 2·a·d·cos phi, written here apart from the
engine's kinematics; link ratios straight from the returned lengths.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.analysis import AnalysisIn
from mechsynth_client.schemas.synthesis import CrankRockerIn, SliderCrankSynthesisIn
from synth.warnings import MAX_LINK_RATIO, MIN_TRANSMISSION_ANGLE

MASSLESS = {"links_missing", "link_left_out"}   # a synthesis answer without densities has no masses: by design


def _least_deviation(m: dict[str, float]) -> float:
    a, b, c, d = (m[k] for k in ("crank_length_m", "coupler_length_m", "rocker_length_m", "ground_length_m"))
    phi = np.linspace(0, 2 * math.pi, 200_001)
    aq2 = a * a + d * d - 2 * a * d * np.cos(phi)
    mu = np.arccos(np.clip((b * b + c * c - aq2) / (2 * b * c), -1, 1))
    return float(np.min(np.minimum(mu, math.pi - mu)))


def test_a_nearly_flat_crank_rocker_says_its_transmission_angle_is_unusable(client: SynthClient) -> None:
    answer = client.synthesise_crank_rocker(CrankRockerIn.model_validate(
        {"swing_deg": 179, "time_ratio": 3, "scale_link": "rocker", "scale_length_m": 0.2}))
    worst = _least_deviation(answer.mechanism.model_dump())
    assert worst < MIN_TRANSMISSION_ANGLE
    (note,) = [w for w in answer.warnings if w.code == "transmission_angle_low"]
    # the engine samples 720 crank angles: its least angle lies within a grid step's change of the fine scan
    assert note.value == pytest.approx(math.degrees(worst), abs=0.5)
    assert note.unit == "deg" and note.crank_angle_ranges_deg
    # the same warnings as /v1/analysis finds for the returned mechanism
    again = client.analysis(AnalysisIn(mechanism=answer.mechanism, speed_rpm=60, samples=720))
    assert {w.code for w in answer.warnings} == {w.code for w in again.warnings} - MASSLESS


def test_a_good_crank_rocker_has_no_warning(client: SynthClient) -> None:
    answer = client.synthesise_crank_rocker(CrankRockerIn.model_validate(
        {"swing_deg": 40, "time_ratio": 1.1, "scale_link": "rocker", "scale_length_m": 0.15}))
    assert _least_deviation(answer.mechanism.model_dump()) > MIN_TRANSMISSION_ANGLE
    assert answer.warnings == []


def test_a_tiny_crank_says_its_link_ratio_is_beyond_a_drawing_office(client: SynthClient) -> None:
    answer = client.synthesise_crank_rocker(CrankRockerIn.model_validate(
        {"swing_deg": 4, "time_ratio": 1.0, "scale_link": "rocker", "scale_length_m": 0.2}))
    m = answer.mechanism.model_dump()
    lengths = {k: v for k, v in m.items() if k.endswith("_length_m")}
    ratio = max(lengths.values()) / min(lengths.values())
    assert ratio > MAX_LINK_RATIO
    (note,) = [w for w in answer.warnings if w.code == "link_ratio_large"]
    assert note.value == pytest.approx(ratio, rel=1e-12)
    assert note.field == "mechanism." + min(lengths, key=lambda k: lengths[k])
    again = client.analysis(AnalysisIn(mechanism=answer.mechanism, speed_rpm=60, samples=72))
    assert "link_ratio_large" in {w.code for w in again.warnings}


def test_a_steep_slider_crank_says_so(client: SynthClient) -> None:
    answer = client.synthesise_slider_crank(SliderCrankSynthesisIn.model_validate(
        {"stroke_m": 0.1, "time_ratio": 2.5}))
    m = answer.mechanism
    # 90° less the rod's steepest inclination asin((a + |e|)/b), the crank across the guide
    worst = 0.5 * math.pi - math.asin((m.crank_length_m + abs(m.offset_m)) / m.rod_length_m)
    codes = {w.code: w for w in answer.warnings}
    assert (worst < MIN_TRANSMISSION_ANGLE) == ("transmission_angle_low" in codes)
    if worst < MIN_TRANSMISSION_ANGLE:
        assert codes["transmission_angle_low"].value == pytest.approx(math.degrees(worst), abs=0.5)
