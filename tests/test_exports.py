"""CSV of the curves and DXF/SVG drawings read back and compared with the JSON answer and with hand geometry."""

from __future__ import annotations

import csv
import io
import math
import xml.etree.ElementTree as ET

import ezdxf
import numpy as np
import pytest

from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE

CW = {"link": "crank", "mass_kg": 1.5, "position_m": [-0.08, 0.0]}
TRACE = {"name": "P", "link": "coupler", "position_m": [0.15, 0.08]}


def _rows(content: bytes) -> list[dict[str, str]]:
    return list(csv.DictReader(io.StringIO(content.decode("utf-8"))))


def test_analysis_csv_matches_the_json_answer(client: SynthClient) -> None:
    body = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 360, "trace_points": [TRACE]}
    js = client.http.post("/v1/analysis", json=body, params={"precision": "full"}).json()
    r = client.http.post("/v1/analysis", json=body, params={"format": "csv"})
    assert r.headers["content-type"].startswith("text/csv")
    assert 'filename="analysis.csv"' in r.headers["content-disposition"]
    rows = _rows(r.content)
    assert len(rows) == 360
    # One revolution in 360 samples: every crank angle reads as a whole degree, 120 rather than 119.99999999999999.
    assert [row["crank_angle_deg"] for row in rows[118:122]] == ["118", "119", "120", "121"]
    assert js["crank_angle_deg"][120] == 120.0
    for column, values in (("driving_torque_Nm", js["driving_torque_Nm"]),
                           ("transmission_angle_deg", js["transmission_angle_deg"]),
                           ("P_x_m", [p[0] for p in js["points"]["P"]["position_m"]]),
                           ("B_reaction_y_N", [f[1] for f in js["joint_reactions_N"]["B"]])):
        # 12 significant digits in the CSV against the JSON's full doubles.
        assert [float(row[column]) for row in rows] == pytest.approx(values, rel=1e-11, abs=1e-9)


def test_balance_csv_before_and_after(client: SynthClient) -> None:
    body = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 72}
    js = client.http.post("/v1/balancing/static", json=body).json()
    rows = _rows(client.http.post("/v1/balancing/static", json=body, params={"format": "csv"}).content)
    after = np.hypot([float(r["shaking_force_x_after_N"]) for r in rows], [float(r["shaking_force_y_after_N"]) for r in rows])
    before = np.hypot([float(r["shaking_force_x_before_N"]) for r in rows],
                      [float(r["shaking_force_y_before_N"]) for r in rows])
    # The JSON's re-analysed residual and peak before are the columns' maxima.
    assert after.max() == pytest.approx(js["checks"]["residual_shaking_force_N"], rel=1e-6, abs=1e-9)
    assert before.max() == pytest.approx(js["summary_before"]["max_shaking_force_N"], rel=1e-11)
    moment = np.array([float(r["shaking_moment_after_Nm"]) for r in rows])
    assert np.abs(moment).max() == pytest.approx(js["summary_after"]["max_shaking_moment_Nm"], rel=1e-11)


def test_flywheel_csv_speeds_stay_in_the_target_band(client: SynthClient) -> None:
    body = {"tables": {"crank_angle_deg": [0, 60, 120, 180, 240, 300, 360],
                       "resisting_torque_Nm": [-1.7, -1500.6, -1496.7, -385.74, -145.33, -250.0, -1.7],
                       "driving_torque_Nm": [0, 0, 0, 0, 0, 0, 0]},
            "mean_speed_rad_s": 9.8, "delta": 0.1}
    js = client.http.post("/v1/flywheel", json=body).json()
    rows = _rows(client.http.post("/v1/flywheel", json=body, params={"format": "csv"}).content)
    assert [float(r["excess_work_J"]) for r in rows] == pytest.approx(js["energy_mass"]["excess_work_J"], rel=1e-11,
                                                                        abs=1e-9)
    omega = np.array([float(r["omega_exact_rad_s"]) for r in rows])
    # The exact method's flywheel keeps w inside w_m(1 ± delta/2) (its samples, read off the dense profile).
    assert omega.min() >= js["omega_min_rad_s"] * (1 - 1e-6) and omega.max() <= js["omega_max_rad_s"] * (1 + 1e-6)


def test_dxf_drawing_puts_the_counterweight_where_the_geometry_says(client: SynthClient) -> None:
    body = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 72, "counterweights": [CW],
            "trace_points": [TRACE]}
    r = client.http.post("/v1/analysis/drawing", json=body, params={"format": "dxf", "angle_deg": 45})
    assert r.status_code == 200 and r.headers["content-type"] == "image/vnd.dxf"
    doc = ezdxf.read(io.StringIO(r.content.decode("utf-8")))
    assert doc.header["$INSUNITS"] == 4   # millimetres
    msp = doc.modelspace()
    layers = {e.dxf.layer for e in msp}
    assert layers >= {"FRAME", "LINKS", "JOINTS", "CRANK_CIRCLE", "COUNTERWEIGHTS", "TRACES", "TEXT"}
    # By hand: the crank at 45° turns the counterweight's (-80, 0) mm to (-80 cos 45°, -80 sin 45°).
    c = math.cos(math.radians(45))
    discs = [e for e in msp.query("CIRCLE") if e.dxf.layer == "COUNTERWEIGHTS"]
    assert len(discs) == 1
    assert (discs[0].dxf.center.x, discs[0].dxf.center.y) == pytest.approx((-80 * c, -80 * c), abs=1e-9)
    crank_circle = msp.query("CIRCLE").filter(lambda e: e.dxf.layer == "CRANK_CIRCLE")[0]
    assert crank_circle.dxf.radius == pytest.approx(100.0, rel=1e-12)
    labels = " ".join(t.dxf.text for t in msp.query("TEXT"))
    assert "1.5 kg at r 80 mm, 180 deg" in labels and "crank angle 45 deg" in labels
    # Balancing answers the same drawing for its balanced linkage.
    bal = client.http.post("/v1/balancing/static", json={"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 36},
                           params={"format": "dxf"})
    assert bal.status_code == 200
    bal_doc = ezdxf.read(io.StringIO(bal.content.decode("utf-8")))
    assert len([e for e in bal_doc.modelspace().query("CIRCLE") if e.dxf.layer == "COUNTERWEIGHTS"]) == 2


def test_svg_drawing_is_to_scale(client: SynthClient) -> None:
    body = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 36}
    r = client.http.post("/v1/analysis/drawing", json=body, params={"format": "svg"})
    assert r.headers["content-type"] == "image/svg+xml"
    root = ET.fromstring(r.content)
    width = float(root.attrib["width"].removesuffix("mm"))
    # The page holds the 300 mm frame plus pivots, labels and 10 mm margins: a 1:1 drawing.
    assert 320 < width < 600


def test_a_format_an_endpoint_does_not_offer_is_a_clear_422(client: SynthClient) -> None:
    body = {"tables": {"crank_angle_deg": [0, 90, 180, 270, 360], "reduced_torque_Nm": [0, -100, 0, 0, 0]},
            "mean_speed_rad_s": 10.0, "delta": 0.05}
    r = client.http.post("/v1/flywheel", json=body, params={"format": "dxf"})
    assert r.status_code == 422 and r.json()["field"] == "format"
