"""The cam endpoints through the client: answers checked against formulas evaluated here on the answer's own
numbers, the exports read back (CSV, DXF with ezdxf, PNG), and bad input answered 422 naming the field or the
constraint."""

from __future__ import annotations

import copy
import csv
import io
import math
from typing import Any

import numpy as np
import pytest

from mechsynth_client.client import InfeasibleError, InvalidInputError, SynthClient
from mechsynth_client.schemas.cams import (
    CamAnalysisIn,
    CamSynthesisIn,
    OscillatingMotionOut,
    TranslatingMotionOut,
)

ANALYSIS: list[dict[str, Any]] = CamAnalysisIn.model_config["json_schema_extra"]["examples"]  # type: ignore
SYNTHESIS: list[dict[str, Any]] = CamSynthesisIn.model_config["json_schema_extra"]["examples"]  # type: ignore


def test_analysis_answers_with_its_checks_and_the_textbook_pressure_angle(client: SynthClient) -> None:
    body = CamAnalysisIn.model_validate(ANALYSIS[0])
    out = client.cam_analysis(body)
    m = out.motion
    assert isinstance(m, TranslatingMotionOut)
    # tan alpha = (ds/dtheta - e)/(sqrt(Rp² - e²) + s), evaluated here on the answer's own motion
    rp, e = out.profile.prime_radius_m, out.profile.offset_m
    expected = np.degrees(np.arctan2(np.array(m.v_m_per_rad) - e, math.sqrt(rp**2 - e**2) + np.array(m.s_m)))
    assert np.max(np.abs(np.array(out.profile.pressure_angle_deg) - expected)) < 1e-9
    c = out.checks
    assert c.table_pressure_angle_error_deg < 1e-4 and c.table_curvature_error < 1e-5 and c.derivative_error < 1e-6
    assert c.torque_virtual_power_error is not None and c.torque_virtual_power_error < 1e-9
    for law in c.laws:
        assert law.acceleration_coefficient == pytest.approx(law.textbook_acceleration_coefficient, abs=6e-4)
        assert 0.999 < law.sampled_peak_acceleration_ratio <= 1.0 + 1e-12
    f = out.forces
    assert f is not None and f.min_contact_force_N > 0 and f.least_contact_margin == pytest.approx(0.2, abs=1e-6)
    # v in SI is v per radian times the cam speed
    w = out.speed_rpm * math.pi / 30
    assert np.allclose(np.array(m.v_m_s), np.array(m.v_m_per_rad) * w, rtol=1e-12, atol=0)


def test_oscillating_follower_with_an_optimised_law(client: SynthClient) -> None:
    out = client.cam_analysis(CamAnalysisIn.model_validate(ANALYSIS[1]))
    assert isinstance(out.motion, OscillatingMotionOut)
    assert max(out.motion.psi_rad) == pytest.approx(math.radians(20.0), rel=1e-12)
    (law,) = out.optimised_laws
    assert law.objective == "peak_jerk" and law.solver_status == "optimal"
    assert 32.0 <= law.jerk_coefficient < 1.05 * 32.0      # bang-bang jerk's 32 is the least any rise can have
    assert out.checks.table_pressure_angle_error_deg < 1e-3


def test_csv_and_dxf_read_back(client: SynthClient) -> None:
    body = CamAnalysisIn.model_validate({**ANALYSIS[0], "chord_tolerance_m": 2e-5})
    out = client.cam_analysis(body)
    rows = list(csv.DictReader(io.StringIO(client.cam_file(body, "csv").decode())))
    assert len(rows) == len(out.cam_angle_deg)
    assert float(rows[10]["profile_x_m"]) == pytest.approx(out.profile.profile_m[10][0], rel=1e-9)
    import ezdxf

    doc = ezdxf.read(io.StringIO(client.cam_file(body, "dxf").decode()))   # type: ignore[no-untyped-call]
    (poly,) = [e for e in doc.modelspace() if e.dxftype() == "LWPOLYLINE" and e.dxf.layer == "PROFILE"]
    assert poly.closed
    vertices = np.array([(x, y) for x, y, *_ in poly.get_points()]) / 1000.0
    # Every profile point of the JSON answer lies within the chord tolerance of the drawn polyline (distances to
    # each chord computed here), and the polyline is far coarser than the table.
    a, b = vertices, np.roll(vertices, -1, axis=0)
    p = np.array(out.profile.profile_m)
    d = b - a
    t = np.clip(np.einsum("pkj,kj->pk", p[:, None, :] - a[None], d) / np.einsum("kj,kj->k", d, d), 0.0, 1.0)
    dist = np.linalg.norm(p[:, None, :] - a[None] - t[..., None] * d[None], axis=2).min(axis=1)
    assert dist.max() <= 2e-5 * 1.01
    assert len(vertices) < len(p) / 2


def test_figure_is_a_png(client: SynthClient) -> None:
    png = client.cam_file(CamAnalysisIn.model_validate({**ANALYSIS[0], "drawing_angle_deg": 60}), "png")
    assert png[:8] == b"\x89PNG\r\n\x1a\n"


def test_least_cam_meets_its_limits_with_the_active_one_at_the_limit(client: SynthClient) -> None:
    out = client.cam_synthesis(CamSynthesisIn.model_validate(SYNTHESIS[0]))
    assert out.active_constraint == "max_pressure_angle_rise_deg"
    m = out.cam.motion
    assert isinstance(m, TranslatingMotionOut)
    rp = out.base_radius_m + 0.01
    alpha = np.degrees(np.arctan2(np.array(m.v_m_per_rad), rp + np.array(m.s_m)))
    rise = np.array(out.cam.cam_angle_deg) < 120
    # the textbook formula on the answer's own motion: the rise's largest pressure angle is the limit
    assert np.abs(alpha[rise]).max() == pytest.approx(30.0, abs=2e-3)   # 720 samples against the exact peak
    assert out.certificate.just_below_fails == "max_pressure_angle_rise_deg"
    assert out.cam.profile.base_radius_m == out.base_radius_m


def test_motion_laws_table(client: SynthClient) -> None:
    laws = {row.name: row for row in client.cam_laws()}
    assert laws["cycloidal"].acceleration_coefficient == pytest.approx(2 * math.pi, rel=1e-9)
    assert laws["modified_sine"].acceleration_coefficient == pytest.approx(5.528, abs=6e-4)   # Norton's table
    assert laws["modified_trapezoid"].acceleration_coefficient == pytest.approx(4.888, abs=6e-4)


def _bad(body: dict[str, Any], **change: Any) -> dict[str, Any]:
    out = copy.deepcopy(body)
    out.update(change)
    return out


def test_bad_input_is_named(client: SynthClient) -> None:
    short = _bad(ANALYSIS[0], segments=ANALYSIS[0]["segments"][:3])
    with pytest.raises(InvalidInputError) as err:
        client.cam_analysis(CamAnalysisIn.model_validate(short))
    assert err.value.status == 422 and err.value.problem["field"] == "segments"
    no_angle = _bad(ANALYSIS[0])
    no_angle["segments"][0]["angle_deg"] = 0
    with pytest.raises(InvalidInputError) as err:
        client.cam_analysis(CamAnalysisIn.model_validate(no_angle))
    assert err.value.problem["field"] == "segments.0.angle_deg"
    no_lift = _bad(ANALYSIS[0])
    del no_lift["segments"][0]["lift_m"]
    with pytest.raises(InvalidInputError) as err:
        client.cam_analysis(CamAnalysisIn.model_validate(no_lift))
    assert err.value.problem["field"] == "segments.0.lift_m"
    steep = _bad(SYNTHESIS[0], max_pressure_angle_rise_deg=5, base_radius_bounds_m=[0.005, 0.02])
    with pytest.raises(InfeasibleError) as ierr:
        client.cam_synthesis(CamSynthesisIn.model_validate(steep))
    assert ierr.value.problem["constraint"] == "max_pressure_angle_rise_deg"


def test_a_roller_too_large_for_the_profile_is_422(client: SynthClient) -> None:
    # A fast rise on a small cam: the knife-edge cam of the same prime radius (the roller's pitch curve) has its
    # least convex radius of curvature, taken from that answer; a roller 5 % larger undercuts.
    segs = [{"kind": "rise", "angle_deg": 60, "lift_m": 0.03}, {"kind": "dwell", "angle_deg": 120},
            {"kind": "return", "angle_deg": 60, "lift_m": 0.03}, {"kind": "dwell", "angle_deg": 120}]
    knife = client.cam_analysis(CamAnalysisIn.model_validate(
        {"segments": segs, "follower": {"contact": "knife_edge"}, "base_radius_m": 0.025, "speed_rpm": 100}))
    limit = knife.profile.min_curvature_radius_m
    body = {"segments": segs, "follower": {"contact": "roller", "roller_radius_m": 1.05 * limit},
            "base_radius_m": 0.025 - 1.05 * limit, "speed_rpm": 100}
    with pytest.raises(InvalidInputError) as err:
        client.cam_analysis(CamAnalysisIn.model_validate(body))
    assert err.value.problem["field"] == "follower.roller_radius_m"


def test_pdf_is_a_design_record_identified_by_the_request_hash(client: SynthClient) -> None:
    import hashlib
    import json

    from pypdf import PdfReader

    body = CamSynthesisIn.model_validate(SYNTHESIS[0])
    pdf = PdfReader(io.BytesIO(client.cam_file(body, "pdf")))
    assert len(pdf.pages) == 2
    text = pdf.pages[0].extract_text()
    # the hash of the request's canonical JSON (as validated, defaults in, nulls out), computed here
    canonical = json.dumps(body.model_dump(mode="json", exclude_none=True), sort_keys=True, separators=(",", ":"))
    assert hashlib.sha256(canonical.encode()).hexdigest() in text.replace("\n", "")
    assert "max_pressure_angle_rise_deg" in text and "The least cam" in text


def test_the_camshaft_as_a_crank_feeds_the_flywheel(client: SynthClient) -> None:
    from mechsynth_client.schemas.flywheel import FlywheelIn

    body = CamAnalysisIn.model_validate({**ANALYSIS[0], "samples": 360})
    out = client.cam_analysis(body)
    f = out.forces
    assert f is not None and out.checks.reduced_model_error is not None
    assert out.checks.reduced_model_error < 1e-5     # T = load + (omega²/2) dJ/dtheta, dJ by differences
    # Energy over the turn: the mean driving torque is the load's mean (the follower's kinetic energy returns)
    assert np.mean(f.driving_torque_Nm) == pytest.approx(np.mean(f.load_torque_Nm), rel=1e-9)
    # the process work: 50 N over the 20 mm rise, per turn, is the mean torque times 2 pi
    assert np.mean(f.load_torque_Nm) * 2 * math.pi == pytest.approx(50.0 * 0.02, rel=1e-3)
    angles = [*out.cam_angle_deg, 360.0]
    load = [*f.load_torque_Nm, f.load_torque_Nm[0]]
    inertia = [*f.reduced_inertia_kgm2, f.reduced_inertia_kgm2[0]]
    mean = float(np.mean(f.load_torque_Nm))
    fly = client.flywheel(FlywheelIn.model_validate({
        "tables": {"crank_angle_deg": angles, "reduced_inertia_kgm2": inertia, "driving_torque_Nm": [mean] * len(load),
                   "resisting_torque_Nm": [-t for t in load]},
        "mean_speed_rpm": 300, "delta": 0.02}))
    # the flywheel's own check: its inertia, simulated by integrating the equation of motion, gives the target
    assert fly.achieved_delta == pytest.approx(0.02, rel=0.02)
    assert fly.cycle_work_J == pytest.approx(0.0, abs=1e-6 * 50.0 * 0.02)   # the driving torque balances the load
