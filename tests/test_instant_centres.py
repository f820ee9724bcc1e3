"""Instant centres, centrodes and path curvature on request in POST /v1/analysis, against independent geometry."""

from __future__ import annotations

from typing import Any

import numpy as np

from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.analysis import AnalysisIn
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE


def _fourbar(client: SynthClient, **flags: bool) -> Any:
    return client.analysis(AnalysisIn.model_validate(
        {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 60, "samples": 720, **flags}))


def _line_intersection(p1: np.ndarray, p2: np.ndarray, q1: np.ndarray, q2: np.ndarray) -> np.ndarray:
    """Where line p1p2 meets line q1q2, per sample, as homogeneous unit vectors (cross product of the lines)."""
    def line(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return np.cross(np.column_stack([a, np.ones(len(a))]), np.column_stack([b, np.ones(len(b))]))
    h = np.cross(line(p1, p2), line(q1, q2))
    return h / np.linalg.norm(h, axis=1, keepdims=True)


def test_coupler_centre_is_where_crank_and_rocker_lines_meet(client: SynthClient) -> None:
    out = _fourbar(client, instant_centres=True, relative_centres=True)
    assert out.centres is not None and out.curvature is None
    pts = {k: np.array(v.position_m) for k, v in out.points.items()}
    # independent: the coupler's centre relative to the frame lies on the crank's line OA and the rocker's QB
    expected = _line_intersection(pts["O"], pts["A"], pts["Q"], pts["B"])
    got = np.array(out.centres.absolute["coupler"])
    # same projective point: the two unit vectors are parallel (their cross product vanishes)
    assert np.max(np.linalg.norm(np.cross(got, expected), axis=1)) <= 1e-9
    # the crank's and rocker's centres are their fixed pivots
    crank = np.array(out.centres.absolute["crank"])
    assert np.allclose(crank[:, :2] / crank[:, 2:], pts["O"], atol=1e-12)
    assert out.centres.kennedy_check <= 1e-12
    assert set(out.centres.relative) >= {"frame/crank", "crank/coupler", "coupler/rocker"}
    # the crank/coupler centre is the pin A they share
    ca = np.array(out.centres.relative["crank/coupler"])
    assert np.allclose(ca[:, :2] / ca[:, 2:], pts["A"], atol=1e-9)
    # the moving centrode is the fixed one in the coupler's frame: turned back it is the fixed one again
    theta = np.radians(np.array(out.links["coupler"].angle_deg))
    mov = np.array(out.centres.moving_centrode)
    fixed = np.array(out.centres.fixed_centrode)
    x = pts["A"][:, 0] + np.cos(theta) * mov[:, 0] / mov[:, 2] - np.sin(theta) * mov[:, 1] / mov[:, 2]
    finite = np.abs(fixed[:, 2]) > 1e-3
    assert np.allclose(x[finite], (fixed[:, 0] / fixed[:, 2])[finite], atol=1e-9)


def test_path_curvature_against_the_crank_and_a_circle_through_three_points(client: SynthClient) -> None:
    out = _fourbar(client, path_curvature=True)
    assert out.curvature is not None and out.centres is None
    # closed form: the crank pin's path is the crank circle, curvature 1/r
    assert np.allclose(np.abs(out.curvature["A"].curvature_1_m), 1 / FOURBAR_EXAMPLE["crank_length_m"], rtol=1e-12)
    assert len(out.curvature["O"].stopped_deg) == 720
    # independent: the circle through three neighbouring samples of the coupler's centre of mass (0.5° apart)
    p = np.array(out.points["S_coupler"].position_m)
    a, b, c = np.roll(p, 1, axis=0), p, np.roll(p, -1, axis=0)
    ab, bc, ca = (np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1), np.linalg.norm(a - c, axis=1))
    area2 = (b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]
    circle = 2 * area2 / (ab * bc * ca)  # signed 1/R of the circumscribed circle
    k = np.array(out.curvature["S_coupler"].curvature_1_m)
    assert np.max(np.abs(k - circle)) <= 1e-3 * np.max(np.abs(k))


def test_without_the_flags_no_geometry_is_computed(client: SynthClient) -> None:
    out = client.analysis(AnalysisIn.model_validate({"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 60, "samples": 36}))
    assert out.centres is None and out.curvature is None
