"""Work bounded before it starts and shared fairly: studies queue beyond the running bound with their place,
owners take turns, a study's (and an owner's) estimated work is bounded, the tooth search refuses what it cannot
finish, answers are bounded in size and large ones streamed from a file, a 504 names the stage reached, and a
study's elapsed time leaves out the service's down time."""

from __future__ import annotations

import asyncio
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from fastapi.testclient import TestClient

import synth
from api.app import create_app
from api.settings import Settings
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE
from synth.execution import BATCH, INTERACTIVE, LocalPoolExecutor

STATIC = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 90,
          "max_radius_m": {"crank": 0.1, "rocker": 0.25}}


def _study(owner: str | None, variants: int = 400, **extra: Any) -> dict[str, Any]:
    spec: dict[str, Any] = {
        "endpoint": "/v1/balancing/static", "base": STATIC,
        "parameters": [{"path": "mechanism.crank_length_m", "range": [0.05, 0.12]}],
        "sampling": "lhs", "samples": variants, "metrics": ["total_added_mass_kg"], **extra}
    if owner is not None:
        spec["owner"] = owner
    return spec


@pytest.fixture()
def client(tmp_path: Path) -> Iterator[TestClient]:
    settings = Settings(workers=1, study_workers=1, max_running_studies=1, studies_db=str(tmp_path / "s.sqlite"),
                        max_study_work_s=100.0, max_owner_work_s=150.0)
    with TestClient(create_app(settings)) as c:
        yield c


def test_studies_beyond_the_running_bound_wait_with_their_place_and_owners_take_turns(client: TestClient) -> None:
    first = client.post("/v1/studies", json=_study("ann", 4000)).json()
    ann = [client.post("/v1/studies", json=_study("ann")).json() for _ in range(2)]
    bob = client.post("/v1/studies", json=_study("bob")).json()
    anonymous = client.post("/v1/studies", json=_study(None)).json()
    try:
        assert first["state"] == "running" and first["position"] is None and first["owner"] == "ann"
        places = {s["id"]: client.get(f"/v1/studies/{s['id']}").json() for s in [*ann, bob, anonymous]}
        assert all(p["state"] == "queued" and p["elapsed_s"] == 0 for p in places.values())
        # One place, held by ann: bob and anonymous (no study running) come before ann's second and third,
        # in the order they were submitted; then ann's own in hers.
        order = sorted(places, key=lambda i: places[i]["position"])
        assert order == [bob["id"], anonymous["id"], ann[0]["id"], ann[1]["id"]]
        assert [places[i]["position"] for i in order] == [1, 2, 3, 4]
        assert places[anonymous["id"]]["owner"] == "anonymous"
        ready = client.get("/ready").json()
        assert ready["studies_running"] == 1 and ready["studies_queued"] == 4
        # A cancelled queued study leaves the queue; the others move up.
        assert client.delete(f"/v1/studies/{bob['id']}").json()["state"] == "cancelled"
        assert client.get(f"/v1/studies/{anonymous['id']}").json()["position"] == 1
    finally:
        for s in [first, *ann, bob, anonymous]:
            client.delete(f"/v1/studies/{s['id']}")


def test_a_study_beyond_its_estimated_work_is_refused_naming_the_estimate(client: TestClient) -> None:
    # 100 000 variants of a 3-stage tooth search at 1 000 teeth: each streams about 6.5e10 products (about a
    # minute of a worker), so the study's estimate is days, beyond the 100 worker-seconds set here.
    teeth = {"endpoint": "/v1/gears/teeth", "base": {"total_ratio": 173.3, "stages": 3, "max_teeth": 1000},
             "parameters": [{"path": "total_ratio", "range": [100, 200]}], "sampling": "random",
             "samples": 100_000, "metrics": ["ratio_error"]}
    r = client.post("/v1/studies", json=teeth)
    assert r.status_code == 413 and r.json()["field"] == "parameters"
    assert "worker-days" in r.json()["detail"] and r.json()["got"] > r.json()["limit"] == 100


def test_one_owners_queued_and_running_studies_share_one_bound(client: TestClient) -> None:
    # Each study of 40 000 static-balancing variants at 90 angles is estimated at 40 000 x (5 ms + 90 x 10 us)
    # = 236 s > 100: refused alone; 10 000 variants (59 s) pass, two of them (118 s) pass the owner's 150,
    # a third does not; another owner is not held back.
    assert client.post("/v1/studies", json=_study("ann", 40_000)).status_code == 413
    ids = []
    try:
        for _ in range(2):
            r = client.post("/v1/studies", json=_study("ann", 10_000))
            assert r.status_code == 202
            ids.append(r.json()["id"])
        third = client.post("/v1/studies", json=_study("ann", 10_000))
        assert third.status_code == 413 and third.json()["field"] == "owner"
        other = client.post("/v1/studies", json=_study("bob", 10_000))
        assert other.status_code == 202
        ids.append(other.json()["id"])
    finally:
        for i in ids:
            client.delete(f"/v1/studies/{i}")


def test_the_three_stage_thousand_teeth_search_is_refused_within_two_seconds(client: TestClient) -> None:
    start = time.monotonic()
    r = client.post("/v1/gears/teeth", json={"total_ratio": 173.3, "stages": 3, "max_teeth": 1000})
    seconds = time.monotonic() - start
    assert r.status_code == 413 and r.json()["field"] == "max_teeth" and seconds < 2.0
    assert "products per pass" in r.json()["detail"] or "stream" in r.json()["detail"]
    # The same search at 100 teeth answers (its ratio within the 171.5 those bounds reach: 150).
    ok = client.post("/v1/gears/teeth", json={"total_ratio": 150, "stages": 3, "max_teeth": 100})
    assert ok.status_code == 200


def test_answers_are_bounded_in_size_and_large_ones_streamed(tmp_path: Path) -> None:
    body = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 20_000}
    whole = Settings(workers=1, studies_db=str(tmp_path / "a.sqlite"), spool_above_bytes=1_000_000_000)
    with TestClient(create_app(whole)) as c:
        # in full precision: the bound's estimate (20 bytes a number) is for the engine's every digit
        reference = c.post("/v1/analysis", params={"precision": "full"}, json=body)
    assert reference.status_code == 200 and "content-length" in reference.headers
    size = len(reference.content)
    # The estimate (20 bytes a number) is within a fifth of the JSON the engine's numbers make.
    numbers = size / 20
    spooled = Settings(workers=1, studies_db=str(tmp_path / "b.sqlite"), spool_above_bytes=100_000,
                       max_answer_bytes=int(numbers * 20 * 1.25))
    with TestClient(create_app(spooled)) as c:
        streamed = c.post("/v1/analysis", params={"precision": "full"}, json=body)
        assert streamed.status_code == 200 and streamed.content == reference.content
        assert int(streamed.headers["content-length"]) == size
    bounded = Settings(workers=1, studies_db=str(tmp_path / "c.sqlite"), max_answer_bytes=int(size * 0.8))
    with TestClient(create_app(bounded)) as c:
        refused = c.post("/v1/analysis", params={"precision": "full"}, json=body)
        assert refused.status_code == 413 and refused.json()["field"] == "samples"
        assert "format=npz" in refused.json()["detail"]
        # As npz (8 bytes a number) the same answer is within the bound.
        assert c.post("/v1/analysis", params={"format": "npz"}, json=body).status_code == 200
    assert not list(Path(tempfile_dir()).glob("synth-answer-*.part"))


def tempfile_dir() -> str:
    import tempfile

    return tempfile.gettempdir()


def test_a_504_names_the_stage_reached(tmp_path: Path) -> None:
    from api.execution.admission import Solvers

    solvers = Solvers(Settings(workers=1, queue_size=4, request_deadline_s=0.5, studies_db=str(tmp_path / "s.db")))
    solvers.start()

    async def both() -> list[BaseException | None]:
        now = time.monotonic()
        # One worker: a task running past its deadline, and one queued behind it whose deadline comes first.
        running = asyncio.ensure_future(solvers.run(now + 1.0, time.sleep, 5.0))
        await asyncio.sleep(0.1)
        queued = asyncio.ensure_future(solvers.run(time.monotonic() + 0.5, abs, -1.0))
        out = await asyncio.gather(running, queued, return_exceptions=True)
        return [o if isinstance(o, BaseException) else None for o in out]

    try:
        running, queued = asyncio.run(both())
    finally:
        solvers.shutdown()
    assert isinstance(running, synth.SolverTimeout) and running.reached["stage"] == "running"
    assert isinstance(queued, synth.SolverTimeout) and queued.reached["stage"] == "queued"
    assert "never reached a worker" in str(queued)
    assert queued.reached["elapsed_s"] == pytest.approx(0.5, abs=0.2)


def test_elapsed_time_leaves_out_the_time_the_service_was_down(tmp_path: Path) -> None:
    from store import SqlStudyStore, Store, database_url

    store = Store(database_url(None, str(tmp_path / "s.sqlite")))
    store.migrate()
    lease_s = 1.0
    first = SqlStudyStore(store, lease_s=lease_s)
    study_id = first.create(_study("ann"), 10)
    assert first.claim(study_id)
    time.sleep(0.3)
    first.write_rows(study_id, [])   # a batch written 0.3 s into the run renews the lease
    time.sleep(1.5)                  # ... then the process is killed: its lease lapses, the service is down
    assert SqlStudyStore(store, lease_s=lease_s).sweep() == 1   # the restarted service
    record = first.get(study_id)
    assert record is not None and record.state == "interrupted"
    # 0.3 s ran (timer resolution and a loaded machine: +0.15 s); the 1.5 s after the last batch are not counted.
    assert 0.3 <= record.elapsed_s < 0.45


def test_study_tasks_wait_for_interactive_ones_on_shared_workers() -> None:
    # One shared worker: it takes an interactive task before any waiting batch task, whatever the order queued.
    pool = LocalPoolExecutor(1, batch_workers=0)
    try:
        blocker = pool.submit(time.sleep, 0.5)
        time.sleep(0.1)
        batch = [pool.lane(BATCH, "ann").submit(time.monotonic) for _ in range(3)]
        interactive = pool.submit(time.monotonic)
        blocker.result(timeout=30)
        done = {"batch": min(f.result(timeout=30) for f in batch), INTERACTIVE: interactive.result(timeout=30)}
        order = sorted(done, key=lambda k: done[k])
        assert order == [INTERACTIVE, "batch"]
    finally:
        pool.shutdown()


def test_study_lane_runs_niced_and_owners_alternate() -> None:
    import os

    pool = LocalPoolExecutor(1, batch_workers=1, batch_nice=19)
    try:
        assert pool.lane(BATCH, "ann").submit(os.nice, 0).result(timeout=30) == 19   # os.nice(0): its niceness
        assert pool.submit(os.nice, 0).result(timeout=30) == 0
        blocker = pool.lane(BATCH, "ann").submit(time.sleep, 0.5)
        time.sleep(0.1)
        ann = [pool.lane(BATCH, "ann").submit(time.monotonic) for _ in range(3)]
        bob = pool.lane(BATCH, "bob").submit(time.monotonic)
        blocker.result(timeout=30)
        started = sorted([("ann", f.result(timeout=30)) for f in ann] + [("bob", bob.result(timeout=30))],
                         key=lambda item: item[1])
        # Queued ann, ann, ann, bob: served ann, bob, ann, ann (round robin between the owners).
        assert [name for name, _ in started] == ["ann", "bob", "ann", "ann"]
    finally:
        pool.shutdown()


def test_a_path_synthesis_beyond_its_estimated_time_is_refused_before_it_starts(tmp_path: Path) -> None:
    # 40 points of a four-bar's coupler curve, 256 starts: 0.05 + 256 x 0.001 x 40/10 = 1.07 s of work on one worker
    # by the service's price of a path synthesis (api/execution/work.py), beyond the 1 s set here; 64 starts
    # (0.31 s) are within it.
    from tests.test_service_limits import FOURBAR

    settings = Settings(workers=1, max_request_work_s=1.0, studies_db=str(tmp_path / "s.sqlite"))
    with TestClient(create_app(settings)) as c:
        curve = c.post("/v1/analysis", json={"mechanism": FOURBAR, "crank_angle_deg": [9.0 * k for k in range(40)],
                                             "trace_points": [{"name": "P", "link": "coupler",
                                                               "position_m": [0.15, 0.08]}]})
        long_path = {"points_m": curve.json()["points"]["P"]["position_m"], "starts": 256, "seed": 1}
        start = time.monotonic()
        r = c.post("/v1/synthesis/path", json=long_path)
        assert r.status_code == 413 and r.json()["field"] == "starts" and time.monotonic() - start < 2.0
        assert r.json()["got"] == 1 and r.json()["limit"] == 1
        assert c.post("/v1/synthesis/path", json={**long_path, "starts": 64}).status_code == 200
