"""Figures read back: PNG size and every panel drawn on, the after-curve visible, SVG and PDF well formed."""

from __future__ import annotations

import io
import xml.etree.ElementTree as ET

import matplotlib.image as mpimg
import numpy as np
import pytest

from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE

SLIDER_CRANK = {"type": "slider_crank", "crank_length_m": 0.05, "rod_length_m": 0.2,
                "links": {"crank": {"mass_kg": 1.0, "com_m": [0.02, 0]}, "rod": {"mass_kg": 0.8, "com_m": [0.06, 0]},
                          "slider": {"mass_kg": 1.2}}}
SHAPER = {"type": "slotted_lever", "crank_length_m": 0.1, "ground_length_m": 0.3, "rocker_length_m": 0.6,
          "ram_height_m": 0.7, "links": {"crank": {"mass_kg": 5.0}, "ram": {"mass_kg": 12.0},
                                         "rocker": {"mass_kg": 10.0, "com_m": [0.25, 0.0], "inertia_kgm2": 0.3}}}
TABLES = {"crank_angle_deg": [0, 90, 180, 270, 360], "reduced_torque_Nm": [0, -100, 0, 0, 0]}


def _image(content: bytes) -> np.ndarray:
    assert content[:8] == b"\x89PNG\r\n\x1a\n"
    return np.asarray(mpimg.imread(io.BytesIO(content), format="png"))[:, :, :3]


def _ink(cell: np.ndarray) -> float:
    """Share of pixels that are not white."""
    return float(np.mean(cell.min(axis=2) < 0.9))


def _cells(img: np.ndarray, rows: int, cols: int) -> list[np.ndarray]:
    h, w, _ = img.shape
    return [img[r * h // rows:(r + 1) * h // rows, c * w // cols:(c + 1) * w // cols]
            for r in range(rows) for c in range(cols)]


def _red(cell: np.ndarray) -> int:
    """Pixels of the "after" colour (tab:red, #d62728)."""
    target = np.array([0xD6, 0x27, 0x28]) / 255
    return int(np.sum(np.abs(cell - target).max(axis=2) < 0.08))


def _post(client: SynthClient, path: str, body: dict, **params: str) -> bytes:
    r = client.http.post(path, json=body, params=params)
    assert r.status_code == 200, r.text
    return r.content


@pytest.mark.parametrize("mechanism", [FOURBAR_EXAMPLE, SLIDER_CRANK, SHAPER], ids=["fourbar", "slider", "shaper"])
def test_analysis_figure_has_four_drawn_panels(client: SynthClient, mechanism: dict) -> None:
    body = {"mechanism": mechanism, "speed_rpm": 300, "samples": 72,
            "trace_points": [] if mechanism is not FOURBAR_EXAMPLE else
            [{"name": "P", "link": "coupler", "position_m": [0.15, 0.08]}]}
    img = _image(_post(client, "/v1/analysis", body, format="png", angle_deg="45"))
    h, w, _ = img.shape
    assert w > 1200 and h > 900   # 13 x 10 in at 110 dpi, trimmed to the drawn area
    for cell in _cells(img, 2, 2):
        assert _ink(cell) > 0.02


def test_balancing_figure_shows_the_after_curve_and_the_sweep(client: SynthClient) -> None:
    body = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 72, "mass_budget_kg": 4.0,
            "weights": {"shaking_force": 1.0, "shaking_moment": 2.0, "driving_torque": 1.0},
            "sweep": [{"shaking_force": 1.0}, {"shaking_force": 1.0, "driving_torque": 5.0}]}
    img = _image(_post(client, "/v1/balancing/optimal", body, format="png"))
    cells = _cells(img, 2, 3)
    assert all(_ink(c) > 0.02 for c in cells)
    polar, moment, torque = cells[:3]
    # The after-curve is drawn in its own colour on the polar diagram and on both curves before/after.
    assert min(_red(polar), _red(moment), _red(torque)) > 200


def test_static_balance_figure_keeps_a_zero_after_force_visible(client: SynthClient) -> None:
    body = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 72}
    img = _image(_post(client, "/v1/balancing/static", body, format="png"))
    assert _red(_cells(img, 2, 3)[0]) > 50   # the marker at the origin, not hidden under it


def test_flywheel_figure_for_constant_and_variable_inertia(client: SynthClient) -> None:
    constant = _image(_post(client, "/v1/flywheel", {"tables": TABLES, "mean_speed_rad_s": 10.0, "delta": 0.05},
                            format="png"))
    variable = _image(_post(client, "/v1/flywheel", {"mechanism": SLIDER_CRANK, "mean_speed_rpm": 480, "samples": 90,
                                                     "delta": 0.02, "loads": [{"type": "window", "force_N": 2500,
                                                                               "start_deg": 0, "end_deg": 180}]},
                            format="png"))
    # A constant J_red gives two panels (excess work, speed); a variable one adds the energy-mass diagram.
    assert constant.shape[1] / constant.shape[0] == pytest.approx(2 * 6.5 / 5.0, rel=0.2)
    assert variable.shape[1] / variable.shape[0] == pytest.approx(3 * 6.5 / 5.0, rel=0.2)
    for img, panels in ((constant, 2), (variable, 3)):
        assert all(_ink(c) > 0.02 for c in _cells(img, 1, panels))


def test_svg_and_pdf_by_query_and_accept_header(client: SynthClient) -> None:
    body = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 36}
    r = client.http.post("/v1/analysis", json=body, headers={"accept": "image/svg+xml"})
    assert r.headers["content-type"] == "image/svg+xml"
    root = ET.fromstring(r.content)
    assert root.tag.endswith("svg") and len(root.findall(".//{http://www.w3.org/2000/svg}path")) > 50
    pdf = client.http.post("/v1/analysis", json=body, params={"format": "pdf"})
    assert pdf.headers["content-type"] == "application/pdf"
    assert pdf.content.startswith(b"%PDF-") and pdf.content.rstrip().endswith(b"%%EOF")
    assert client.http.post("/v1/analysis", json=body).headers["content-type"] == "application/json"
