"""The light client: it loads with httpx and pydantic alone, the async client answers like the sync one, every
export has a method that answers the format it names, and a busy service is asked again after the Retry-After it
names, within bounds."""

from __future__ import annotations

import asyncio
import csv
import importlib.metadata as md
import inspect
import io
import json
import re
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path
from typing import Any, get_args

import ezdxf
import httpx
import numpy as np
import pytest

import synth
from mechsynth_client.client import AsyncSynthClient, FigureFormat, NotAssemblableError, ServiceBusyError, SynthClient
from mechsynth_client.schemas.analysis import AnalysisIn
from mechsynth_client.schemas.balancing import BalanceIn, RotorIn
from mechsynth_client.schemas.flywheel import FlywheelIn, MachineType
from mechsynth_client.schemas.gearing import STAGE_TYPES
from mechsynth_client.schemas.synthesis import MAX_PATH_POINTS, MAX_PATH_STARTS

REPO = Path(__file__).resolve().parents[1]
CLIENT_PROJECT = tomllib.loads((REPO / "client" / "pyproject.toml").read_text())
EXAMPLE = AnalysisIn.model_validate(AnalysisIn.model_config["json_schema_extra"]["examples"][0])  # type: ignore[index]
# The manual's first examples of analysis, static balancing and a flywheel for a linkage, at few samples.
SAMPLES = 36
ANALYSIS = AnalysisIn.model_validate({**AnalysisIn.model_json_schema()["examples"][0], "samples": SAMPLES})
BALANCE = BalanceIn.model_validate({**BalanceIn.model_json_schema()["examples"][0], "samples": SAMPLES})
FLYWHEEL = FlywheelIn.model_validate({**FlywheelIn.model_json_schema()["examples"][1], "samples": SAMPLES})


def _requirement_closure(names: list[str]) -> set[str]:
    """Distributions the named ones may pull in, normalised, with their own extras, which they import when present
    (httpx loads pygments for its command line if it finds it)."""
    norm = lambda n: re.sub(r"[-_.]+", "-", n).lower()  # noqa: E731
    direct, todo, seen = {norm(n) for n in names}, [norm(n) for n in names], set()
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        try:
            requires = md.requires(name) or []
        except md.PackageNotFoundError:     # a requirement for other Pythons or platforms
            continue
        for req in requires:
            if name in direct or "extra ==" not in req:
                    todo.append(norm(re.match(r"[A-Za-z0-9_.-]+", req).group()))  # type: ignore[union-attr]
    return seen


def test_client_loads_with_httpx_and_pydantic_only() -> None:
    probe = ("import sys, json, mechsynth_client.client; "
             "print(json.dumps(sorted(m for m in sys.modules if m not in sys.stdlib_module_names)))")
    run = subprocess.run([sys.executable, "-c", probe], check=True, capture_output=True, text=True)
    loaded = json.loads(run.stdout)
    assert not {"fastapi", "starlette", "uvicorn", "cvxpy", "casadi", "matplotlib", "numpy", "scipy", "synth"} & {
        m.split(".")[0] for m in loaded}
    deps = CLIENT_PROJECT["project"]["dependencies"]
    assert sorted(re.match(r"[a-z]+", d).group() for d in deps) == ["httpx", "pydantic"]  # type: ignore[union-attr]
    allowed = _requirement_closure(["httpx", "pydantic"])
    owners = md.packages_distributions()
    # Modules no distribution owns are the interpreter's own (stdlib internals such as _sysconfigdata).
    ours = {"mechsynth_client", "api", "synth"}
    assert not {"api", "synth"} & {m.split(".")[0] for m in loaded}, "the client must not load the server"
    for top in {m.split(".")[0] for m in loaded} & set(owners) - ours - {"_distutils_hack"}:
        dists = {re.sub(r"[-_.]+", "-", d).lower() for d in owners[top]}
        assert dists & allowed, f"the client imports {top} ({dists}), not a dependency of httpx or pydantic"
    shipped = CLIENT_PROJECT["tool"]["hatch"]["build"]["targets"]["wheel"]["force-include"]
    assert shipped == {"../mechsynth_client": "mechsynth_client"}
    assert (REPO / "mechsynth_client" / "py.typed").exists()


def test_client_wheel_ships_its_own_package_only(tmp_path: Path) -> None:
    # Built as a user would install it: the wheel holds mechsynth_client and its metadata, no module named api.
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "--no-build-isolation",
                    "--wheel-dir", str(tmp_path), str(REPO / "client")], check=True)
    (wheel,) = tmp_path.glob("mechsynth_client-*.whl")
    tops = {name.split("/")[0] for name in zipfile.ZipFile(wheel).namelist()}
    assert {t for t in tops if not t.endswith(".dist-info")} == {"mechsynth_client"}
    assert "mechsynth_client/schemas/analysis.py" in zipfile.ZipFile(wheel).namelist()


def test_closed_choices_match_the_engine_tables() -> None:
    assert STAGE_TYPES == tuple(synth.stage_types())
    assert get_args(MachineType) == tuple(m.name for m in synth.machine_types())
    assert (MAX_PATH_POINTS, MAX_PATH_STARTS) == (synth.synthesis.MAX_POINTS, synth.synthesis.MAX_STARTS)


def _public(cls: type) -> set[str]:
    return {n for n, v in vars(cls).items() if not n.startswith("_") and callable(v) and n != "in_process"}


def test_async_client_has_every_method_as_a_coroutine() -> None:
    assert _public(SynthClient) - {"close"} == _public(AsyncSynthClient) - {"aclose"}
    assert all(inspect.iscoroutinefunction(getattr(AsyncSynthClient, n)) for n in _public(AsyncSynthClient))


def test_async_client_answers_like_the_sync_one(client: SynthClient) -> None:
    rotor = RotorIn.model_validate(RotorIn.model_config["json_schema_extra"]["examples"][0])  # type: ignore[index]
    broken = AnalysisIn.model_validate({"mechanism": {
        "type": "fourbar", "ground_length_m": 0.2, "crank_length_m": 0.15, "coupler_length_m": 0.1,
        "rocker_length_m": 0.12}})

    async def run() -> tuple[Any, ...]:
        async with AsyncSynthClient.in_process(precision="full") as aclient:   # as the shared client asks
            with pytest.raises(NotAssemblableError) as err:
                await aclient.analysis(broken)
            return (await aclient.analysis(EXAMPLE), await aclient.machine_types(),
                    await aclient.balance_rotor(rotor), err.value.problem)

    out, types, rotor_out, problem = asyncio.run(run())
    with pytest.raises(NotAssemblableError) as err:
        client.analysis(broken)
    assert out == client.analysis(EXAMPLE)
    assert types == client.machine_types() and rotor_out == client.balance_rotor(rotor)
    assert problem == err.value.problem


def _is_format(content: bytes, fmt: str) -> bool:
    """Whether ``content`` is a file of ``fmt`` by its signature: PNG's eight magic bytes, an XML document holding
    an <svg> element, a PDF's %PDF- header and %%EOF trailer."""
    if fmt == "png":
        return content.startswith(b"\x89PNG\r\n\x1a\n")
    if fmt == "svg":
        return content.startswith(b"<?xml") and b"<svg" in content
    return content.startswith(b"%PDF-") and content.rstrip().endswith(b"%%EOF")


def _columns(text: str) -> tuple[list[str], dict[str, list[float]], int]:
    """A CSV answer's header, its columns as numbers and its row count."""
    rows = list(csv.reader(io.StringIO(text)))
    header, data = rows[0], rows[1:]
    return header, {name: [float(row[i]) for row in data] for i, name in enumerate(header)}, len(data)


# 12 significant digits in the CSV against the JSON's full doubles.
CSV_REL, CSV_ABS = 1e-11, 1e-9


@pytest.mark.parametrize("fmt", get_args(FigureFormat))
def test_figure_methods_answer_the_format_asked(client: SynthClient, fmt: FigureFormat) -> None:
    figures = {"analysis": client.analysis_png(ANALYSIS, angle_deg=30, format=fmt),
               "balance": client.balance_png("static", BALANCE, format=fmt),
               "flywheel": client.flywheel_png(FLYWHEEL, format=fmt)}
    assert {name: _is_format(content, fmt) for name, content in figures.items()} == dict.fromkeys(figures, True)


def test_analysis_csv_is_the_json_answer_one_row_per_sample(client: SynthClient) -> None:
    header, col, rows = _columns(client.analysis_csv(ANALYSIS))
    out = client.analysis(ANALYSIS)
    assert header[:4] == ["crank_angle_deg", "driving_torque_Nm", "virtual_power_torque_Nm", "shaking_force_x_N"]
    assert rows == SAMPLES
    assert col["crank_angle_deg"] == pytest.approx(out.crank_angle_deg, rel=CSV_REL, abs=CSV_ABS)
    assert col["driving_torque_Nm"] == pytest.approx(out.driving_torque_Nm, rel=CSV_REL, abs=CSV_ABS)
    assert col["shaking_force_y_N"] == pytest.approx([f[1] for f in out.shaking_force_N], rel=CSV_REL, abs=CSV_ABS)
    assert col["rocker_angle_deg"] == pytest.approx(out.links["rocker"].angle_deg, rel=CSV_REL, abs=CSV_ABS)


def test_balance_csv_is_before_and_after_of_the_json_answer(client: SynthClient) -> None:
    header, col, rows = _columns(client.balance_csv("static", BALANCE))
    out = client.balance_static(BALANCE)
    unbalanced = client.analysis(AnalysisIn.model_validate(
        BALANCE.model_dump(mode="json", include={"mechanism", "speed_rpm", "samples"})))
    # The columns synth.exports.balance_table writes.
    assert header == ["crank_angle_deg", "shaking_force_x_before_N", "shaking_force_y_before_N",
                      "shaking_force_x_after_N", "shaking_force_y_after_N", "shaking_moment_before_Nm",
                      "shaking_moment_after_Nm", "driving_torque_before_Nm", "driving_torque_after_Nm"]
    assert rows == SAMPLES
    # Before: the plain analysis of the same linkage; after: what the answer's summary reduces to.
    assert col["driving_torque_before_Nm"] == pytest.approx(unbalanced.driving_torque_Nm, rel=CSV_REL, abs=CSV_ABS)
    force_after = np.hypot(col["shaking_force_x_after_N"], col["shaking_force_y_after_N"])
    assert np.sqrt(np.mean(force_after**2)) == pytest.approx(out.summary_after.rms_shaking_force_N, abs=1e-8)
    assert np.abs(col["driving_torque_after_Nm"]).max() == pytest.approx(out.summary_after.max_driving_torque_Nm,
                                                                        rel=CSV_REL)


def test_balance_dxf_draws_the_answers_counterweights(client: SynthClient) -> None:
    doc = ezdxf.read(io.StringIO(client.balance_dxf("static", BALANCE).decode("utf-8")))
    out = client.balance_static(BALANCE)
    assert doc.header["$INSUNITS"] == 4   # millimetres
    # One disc per counterweight of the JSON answer, on the drawing's COUNTERWEIGHTS layer.
    discs = doc.modelspace().query('CIRCLE[layer=="COUNTERWEIGHTS"]')
    assert len(out.counterweights) >= 1 and len(discs) == len(out.counterweights)


def test_flywheel_csv_is_the_json_cycle_one_row_per_sample(client: SynthClient) -> None:
    header, col, rows = _columns(client.flywheel_csv(FLYWHEEL))
    out = client.flywheel(FLYWHEEL)
    assert header == ["crank_angle_deg", "reduced_inertia_kgm2", "reduced_torque_Nm", "excess_work_J",
                      *(f"omega_{m.method}_rad_s" for m in out.methods)]
    assert rows == SAMPLES
    diagram = out.energy_mass
    assert col["crank_angle_deg"] == pytest.approx(diagram.crank_angle_deg, rel=CSV_REL, abs=CSV_ABS)
    assert col["reduced_inertia_kgm2"] == pytest.approx(diagram.reduced_inertia_kgm2, rel=CSV_REL, abs=CSV_ABS)
    assert col["excess_work_J"] == pytest.approx(diagram.excess_work_J, rel=CSV_REL, abs=CSV_ABS)
    # Each method's speeds are its dense simulated profile read at the samples: within that profile's extremes.
    for method in out.methods:
        omega = col[f"omega_{method.method}_rad_s"]
        lo, hi = method.omega_min_rad_s * (1 - CSV_REL), method.omega_max_rad_s * (1 + CSV_REL)
        assert lo <= min(omega) <= max(omega) <= hi, method.method


def test_async_exports_answer_like_the_sync_ones(client: SynthClient) -> None:
    async def run() -> tuple[str, bytes]:
        async with AsyncSynthClient.in_process() as aclient:
            return await aclient.analysis_csv(ANALYSIS), await aclient.balance_png("static", BALANCE, format="pdf")

    text, pdf = asyncio.run(run())
    assert text == client.analysis_csv(ANALYSIS)
    assert _is_format(pdf, "pdf")


def _busy_then_ok(retry_after: list[str | None]) -> tuple[httpx.MockTransport, list[int]]:
    calls: list[int] = []

    def handler(request: httpx.Request) -> httpx.Response:
        calls.append(1)
        if len(calls) <= len(retry_after):
            wait = retry_after[len(calls) - 1]
            busy = {"type": "/problems/busy", "title": "Busy", "status": 503, "detail": "queue full"}
            return httpx.Response(503, headers={} if wait is None else {"retry-after": wait}, json=busy)
        return httpx.Response(200, json={"status": "ok"})

    return httpx.MockTransport(handler), calls


def test_busy_service_is_asked_again_after_retry_after(monkeypatch: pytest.MonkeyPatch) -> None:
    waits: list[float] = []
    monkeypatch.setattr("mechsynth_client.client.time.sleep", waits.append)
    transport, calls = _busy_then_ok(["2", None, "Wed, 21 Oct 2015 07:28:00 GMT"])
    c = SynthClient(http=httpx.Client(transport=transport, base_url="http://test"), retries=3, max_retry_wait_s=5)
    assert c.health() == {"status": "ok"} and len(calls) == 4
    # 2 s as asked; no header: the first back-off step after one retry (1 s); a date in the past: at once.
    assert waits == [2.0, 1.0, 0.0]


def test_retries_are_bounded_in_count_and_wait(monkeypatch: pytest.MonkeyPatch) -> None:
    waits: list[float] = []
    monkeypatch.setattr("mechsynth_client.client.time.sleep", waits.append)
    transport, calls = _busy_then_ok(["600"] * 10)
    c = SynthClient(http=httpx.Client(transport=transport, base_url="http://test"), retries=2, max_retry_wait_s=1.5)
    with pytest.raises(ServiceBusyError) as err:
        c.health()
    assert len(calls) == 3 and waits == [1.5, 1.5]
    assert err.value.status == 503 and err.value.retry_after_s == 600 and err.value.detail == "queue full"


def test_async_client_retries_alike(monkeypatch: pytest.MonkeyPatch) -> None:
    waits: list[float] = []

    async def record(seconds: float) -> None:
        waits.append(seconds)

    monkeypatch.setattr("mechsynth_client.client.asyncio.sleep", record)
    transport, calls = _busy_then_ok(["0.25"])

    async def run() -> dict[str, Any]:
        async with AsyncSynthClient(http=httpx.AsyncClient(transport=transport, base_url="http://test")) as c:
            return await c.health()

    assert asyncio.run(run()) == {"status": "ok"} and waits == [0.25] and len(calls) == 2


def test_a_service_that_is_not_there_is_named_with_its_url() -> None:
    import socket

    from mechsynth_client import ServiceUnreachableError

    with socket.socket() as probe:   # a loopback port nothing listens on once the probe closes
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    url = f"http://127.0.0.1:{port}"
    with SynthClient(url, timeout_s=5) as down, pytest.raises(ServiceUnreachableError) as err:
        down.health()
    assert err.value.url == url and url in str(err.value) and "is it running" in str(err.value)

    async def run() -> None:
        async with AsyncSynthClient(url, timeout_s=5) as adown:
            await adown.health()

    with pytest.raises(ServiceUnreachableError):
        asyncio.run(run())
