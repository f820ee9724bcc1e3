"""The design library on both engines: saves as immutable revisions with the hash of their canonical request and
the answer the endpoint gives, history, search, diff with units, restore, 409 on a stale parent, sign-off rules
(author never signs; roles when signed in), frozen approved revisions, export and import with identical hashes,
404 and 503 problems."""

from __future__ import annotations

import copy
import hashlib
import io
import json
import time
from collections.abc import Iterator
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

import pytest
from fastapi import FastAPI, Request
from pypdf import PdfReader
from fastapi.testclient import TestClient

from api.app import create_app
from api.settings import Settings
from mechsynth_client.client import ProblemError, SynthClient
from mechsynth_client.schemas.library import SAVE_EXAMPLE, LibraryExport
from service import free_port
from store import Store, Users
from store.library import Library, title_block
from store_engines import pg_cluster, store_url  # noqa: F401  (fixtures)

DESIGN = "/v1/library/projects/press/designs/linkage"
REQUEST: dict[str, Any] = SAVE_EXAMPLE["request"]


def _app(url: str, **settings: Any) -> FastAPI:
    # a machine design takes seconds; on a machine shared with other work, more than the default deadline
    return create_app(Settings(executor="serial", database_url=url, request_deadline_s=300, **settings))


@pytest.fixture()
def client(store_url: str) -> Iterator[SynthClient]:
    with TestClient(_app(store_url)) as http:
        yield SynthClient(http=http)


def _changed(**fields: Any) -> dict[str, Any]:
    request = copy.deepcopy(REQUEST)
    request.update(fields)
    return request


def test_saves_keep_the_canonical_request_its_hash_and_its_answer(client: SynthClient) -> None:
    lib = client.library
    first = lib.save("press", "linkage", "/v1/balancing/static", REQUEST, message="first", author="ann")
    assert (first.number, first.parent, first.state, first.author) == (1, None, "draft", "ann")
    kept = lib.revision("press", "linkage", 1)
    # the request as the endpoint's schema reads it: the defaults filled in, and the hash is of its canonical JSON
    assert kept.request["speed_rpm"] == 300 and "gravity" in kept.request and "gravity" not in REQUEST
    text = json.dumps(kept.request, sort_keys=True, separators=(",", ":"), ensure_ascii=False)
    assert first.content_hash == hashlib.sha256(text.encode()).hexdigest()
    # the answer kept is the endpoint's own answer to that request
    direct = client.http.post("/v1/balancing/static", json=REQUEST).json()
    assert kept.answer is not None and kept.passed is True
    assert kept.answer["total_added_mass_kg"] == pytest.approx(direct["total_added_mass_kg"], rel=1e-12)

    second = lib.save("press", "linkage", "/v1/balancing/static", _changed(speed_rpm=360), message="faster",
                      parent=1, author="ann")
    assert (second.number, second.parent) == (2, 1)
    history = lib.history("press", "linkage")
    assert [r.number for r in history.revisions] == [1, 2] and history.endpoint == "/v1/balancing/static"
    assert [r.message for r in history.revisions] == ["first", "faster"]

    # the same request restored: a new revision, the same content hash
    restored = lib.restore("press", "linkage", 1, author="bob")
    assert (restored.number, restored.parent, restored.content_hash) == (3, 2, first.content_hash)
    assert restored.message == "restored revision 1"

    found = lib.search(project="press")
    assert [(r.design, r.number) for r in found] == [("linkage", 3)]
    assert {r.number for r in lib.search(author="ann", latest=False)} == {1, 2}
    assert lib.search(name="LINK", passed=False) == [] and len(lib.search(endpoint="/v1/balancing/static")) == 1
    assert [p.name for p in lib.projects()] == ["press"] and lib.projects()[0].revisions == 3


def test_a_save_from_a_stale_parent_is_refused_unless_it_branches(client: SynthClient) -> None:
    lib = client.library
    lib.save("press", "linkage", "/v1/balancing/static", REQUEST, author="ann")
    lib.save("press", "linkage", "/v1/balancing/static", _changed(speed_rpm=320), parent=1, author="ann")
    # bob also started from revision 1
    with pytest.raises(ProblemError) as refused:
        lib.save("press", "linkage", "/v1/balancing/static", _changed(speed_rpm=280), parent=1, author="bob")
    assert refused.value.status == 409 and refused.value.problem["head_revision"] == 2
    assert "overwrite revision 2" in refused.value.problem["detail"]
    branched = lib.save("press", "linkage", "/v1/balancing/static", _changed(speed_rpm=280), parent=1,
                        branch=True, author="bob")
    assert (branched.number, branched.parent) == (3, 1)
    # a first save with a parent, and a design's endpoint changed, are refused too
    with pytest.raises(ProblemError) as missing:
        lib.save("press", "other", "/v1/balancing/static", REQUEST, parent=4, author="ann")
    assert missing.value.status == 404
    with pytest.raises(ProblemError) as other_kind:
        lib.save("press", "linkage", "/v1/analysis", {"mechanism": REQUEST["mechanism"], "speed_rpm": 300},
                 parent=3, author="ann")
    assert other_kind.value.status == 422 and other_kind.value.problem["field"] == "endpoint"


def test_an_invalid_design_is_refused_and_nothing_is_stored(client: SynthClient) -> None:
    bad = client.http.post(f"{DESIGN}/revisions", json={**SAVE_EXAMPLE, "request": _changed(speed_rpm=-5)})
    assert bad.status_code == 422 and bad.json()["field"] == "request.speed_rpm"
    nobody = client.http.post(f"{DESIGN}/revisions", json={**SAVE_EXAMPLE, "author": None})
    assert nobody.status_code == 422 and nobody.json()["field"] == "author"
    unknown = client.http.post(f"{DESIGN}/revisions", json={**SAVE_EXAMPLE, "endpoint": "/v1/nowhere"})
    assert unknown.status_code == 422 and unknown.json()["field"] == "endpoint"
    assert client.http.get(DESIGN).status_code == 404 and client.library.projects() == []
    missing = client.http.get(f"{DESIGN}/revisions/7")
    assert missing.status_code == 404 and missing.headers["content-type"] == "application/problem+json"


def test_a_diff_names_each_changed_input_with_its_unit_and_each_moved_figure(client: SynthClient) -> None:
    lib = client.library
    lib.save("press", "linkage", "/v1/balancing/static", REQUEST, author="ann")
    lib.save("press", "linkage", "/v1/balancing/static", _changed(speed_rpm=360, mass_budget_kg=8.0), parent=1,
             author="ann")
    diff = lib.diff("press", "linkage", 1, 2)
    assert {(c.path, c.unit, c.before, c.after) for c in diff.request} == {("speed_rpm", "rpm", 300, 360),
                                                                          ("mass_budget_kg", "kg", None, 8.0)}
    old, new = lib.revision("press", "linkage", 1).answer, lib.revision("press", "linkage", 2).answer
    assert old is not None and new is not None
    figures = {c.path: c for c in diff.answer}
    # the change reported is the difference of the two stored answers; and the unbalanced linkage's driving
    # torque, from inertia loads alone at a steady crank speed, grows with the speed squared: (360/300)^2 - 1
    torque = figures["summary_before.rms_driving_torque_Nm"]
    assert torque.unit == "N·m"
    assert torque.change == pytest.approx(new["summary_before"]["rms_driving_torque_Nm"]
                                          - old["summary_before"]["rms_driving_torque_Nm"], rel=1e-12)
    assert torque.change_rel == pytest.approx((360 / 300) ** 2 - 1, rel=1e-9)
    assert diff.unchanged_figures >= 1


def _signed_in(app: FastAPI, users: dict[str, Any]) -> None:
    """Stands for authentication: the user named by a test header is the signed-in user."""

    @app.middleware("http")
    async def who(request: Request, call_next: Any) -> Any:
        name = request.headers.get("x-test-user")
        if name:
            request.state.user = users[name]
        return await call_next(request)


def test_sign_off_rules_and_frozen_approved_revisions(store_url: str) -> None:
    store = Store(store_url)
    store.migrate()
    people = Users(store)
    users = {name: people.create(name, roles) for name, roles in [
        ("ann", {"engineer"}), ("bob", {"engineer", "checker"}), ("cid", {"engineer", "approver", "checker"}),
        ("vic", {"viewer"})]}
    store.dispose()
    app = _app(store_url)
    _signed_in(app, users)
    with TestClient(app) as http:
        def as_(name: str, method: str, path: str, **kw: Any) -> Any:
            return http.request(method, f"{DESIGN}{path}", headers={"x-test-user": name}, **kw)

        body = {**SAVE_EXAMPLE, "author": "someone else"}     # a signed-in user's name wins over the field
        assert as_("vic", "POST", "/revisions", json=body).status_code == 403     # a viewer saves nothing
        saved = as_("ann", "POST", "/revisions", json=body).json()
        assert saved["author"] == "ann"
        assert as_("ann", "POST", "/revisions/1/check", json={}).status_code == 403      # no checker role
        assert as_("cid", "POST", "/revisions/1/approve", json={}).status_code == 409    # not checked yet
        checked = as_("bob", "POST", "/revisions/1/check", json={"name": "ann"}).json()
        assert (checked["state"], checked["checked_by"]) == ("checked", "bob")
        assert as_("bob", "POST", "/revisions/1/approve", json={}).status_code == 403    # no approver role
        approved = as_("cid", "POST", "/revisions/1/approve", json={}).json()
        assert (approved["state"], approved["approved_by"]) == ("approved", "cid")
        # frozen: signed again it answers 409 and says to save a new revision
        again = as_("bob", "POST", "/revisions/1/check", json={})
        assert again.status_code == 409 and "frozen" in again.json()["detail"]
        # a change is a new revision; approved in turn, it supersedes the first
        assert as_("ann", "POST", "/revisions", json={**body, "parent": 1,
                                                       "request": _changed(speed_rpm=330)}).status_code == 201
        as_("bob", "POST", "/revisions/2/check", json={})
        as_("cid", "POST", "/revisions/2/approve", json={})
        states = [(r["number"], r["state"], r["superseded_by"]) for r in as_("ann", "GET", "").json()["revisions"]]
        assert states == [(1, "superseded", 2), (2, "approved", None)]
        block = title_block(Library(app.state.store).info("press", "linkage", 2))
        today = datetime.now(timezone.utc).strftime("%Y-%m-%d")
        assert (block["record_number"], block["revision"], block["state"]) == ("press/linkage", 2, "approved")
        assert (block["designed_by"], block["checked_by"], block["approved_by"]) == ("ann", "bob", "cid")
        assert block["approved_on"] == today
        # a checker who wrote the revision may not sign it either
        assert as_("cid", "POST", "/revisions", json={**body, "parent": 2}).status_code == 201
        refused = as_("cid", "POST", "/revisions/3/check", json={})
        assert refused.status_code == 403 and refused.json()["type"] == "/problems/sign-off-refused"


def test_without_sign_in_names_come_from_the_request_and_the_author_never_signs(client: SynthClient) -> None:
    lib = client.library
    lib.save("press", "linkage", "/v1/balancing/static", REQUEST, author="ann")
    with pytest.raises(ProblemError) as own:
        lib.check("press", "linkage", 1, name="ann")
    assert own.value.status == 403
    by_header = client.http.post(f"{DESIGN}/revisions/1/check", json={}, headers={"X-Synth-User": "bob"})
    assert by_header.json()["checked_by"] == "bob"
    assert lib.approve("press", "linkage", 1, name="cid").state == "approved"


def test_export_and_import_keep_every_hash_and_sign_nothing(store_url: str, tmp_path: Path) -> None:
    from mechsynth_client.schemas.machine import PRESS_EXAMPLE

    with TestClient(_app(store_url)) as http:
        lib = SynthClient(http=http).library
        machine = lib.save("press", "machine", "/v1/machines/design", PRESS_EXAMPLE, author="ann")
        lib.save("press", "linkage", "/v1/balancing/static", REQUEST, author="ann")
        lib.save("press", "linkage", "/v1/balancing/static", _changed(speed_rpm=360), parent=1, author="bob")
        lib.check("press", "linkage", 2, name="ann")
        record = lib.record_pdf("press", "machine", 1)
        document = lib.export("press")
    assert machine.links.record is not None and record[:5] == b"%PDF-"
    assert lib_text_holds(record, machine.content_hash)       # the record is of exactly this revision
    # the other service: a SQLite file of its own, and request bodies bounded far below the export's size, which
    # the import has a bound of its own for
    size = len(document.model_dump_json())
    with TestClient(_app(f"sqlite:///{tmp_path / 'other.sqlite'}", max_body_bytes=size // 4)) as http:
        other = SynthClient(http=http).library
        padded = {**SAVE_EXAMPLE, "message": "", "request": {**REQUEST, "pad": "x" * (size // 2)}}
        assert http.post(f"{DESIGN}/revisions", json=padded).status_code == 413
        tampered = document.model_copy(deep=True)
        tampered.designs[0].revisions[0].request["speed_rpm"] = 301
        with pytest.raises(ProblemError) as changed:
            other.import_project(tampered)
        assert changed.value.status == 422 and changed.value.problem["field"].endswith("content_hash")
        imported = other.import_project(document)
        assert (imported.name, imported.designs, imported.revisions) == ("press", 2, 3)
        with pytest.raises(ProblemError) as twice:
            other.import_project(document)
        assert twice.value.status == 409
        # the history is kept (numbers, hashes, authors, messages); a file signs nothing here: every revision is
        # imported, unsigned, its claims kept as a note, its answer marked as computed elsewhere, no record
        copied = other.history("press", "linkage").revisions
        assert [(r.number, r.content_hash, r.author) for r in copied] == \
            [(r.number, r.content_hash, r.author) for d in document.designs if d.name == "linkage"
             for r in d.revisions]
        assert {(r.state, r.checked_by, r.approved_by, r.passed, r.answer_origin) for r in copied} == \
            {("imported", None, None, None, "imported")}
        assert copied[1].imported_note is not None and "checked by ann" in copied[1].imported_note
        assert "not verified" in copied[1].imported_note
        with pytest.raises(ProblemError) as no_record:
            other.record_pdf("press", "machine", 1)
        assert no_record.value.status == 404
        again = LibraryExport.model_validate(other.export("press").model_dump())
        assert [[(r.number, r.content_hash, r.request) for r in d.revisions] for d in again.designs] == \
            [[(r.number, r.content_hash, r.request) for r in d.revisions] for d in document.designs]


def test_an_import_whose_times_are_no_dates_is_refused_naming_the_time(client: SynthClient) -> None:
    # 1e15 s after 1970 is in the year 31 690 377, past 9999-12-31, the last day a date can name: such an export
    # once stored its project and then failed to answer it
    client.library.save("press", "linkage", "/v1/balancing/static", REQUEST, author="ann")
    document = client.library.export("press").model_dump()
    for where, edit in (("created_at", lambda d: d.update(created_at=1e15)),
                        ("designs.0.revisions.0.created_at",
                         lambda d: d["designs"][0]["revisions"][0].update(created_at=1e15))):
        bad = copy.deepcopy(document)
        edit(bad)
        answer = client.http.post("/v1/library/import", json=bad)
        assert answer.status_code == 422, answer.text
        assert answer.json()["field"].endswith(where), answer.json()


def lib_text_holds(pdf: bytes, text: str) -> bool:
    """The PDF's text (pypdf) holds ``text`` (line breaks and spaces ignored)."""
    import io

    from pypdf import PdfReader

    pages = "".join(p.extract_text() for p in PdfReader(io.BytesIO(pdf)).pages)
    return text in "".join(pages.split())


def test_an_unreachable_store_answers_503_and_ready_says_why() -> None:
    app = _app(f"postgresql://synth@127.0.0.1:{free_port()}/none")
    with TestClient(app) as http:
        ready = http.get("/ready")
        assert ready.status_code == 503 and ready.json()["status"] == "store-unavailable"
        assert ready.json()["store_problem"]
        saved = http.post(f"{DESIGN}/revisions", json=SAVE_EXAMPLE)
        assert saved.status_code == 503 and saved.json()["type"] == "/problems/store-unavailable"
        assert http.get("/v1/studies").status_code == 503
        assert http.get("/health").status_code == 200


def test_two_services_on_one_store_cancel_each_other_s_study(tmp_path: Path) -> None:
    # two apps in this process on one SQLite file stand for two service processes; short leases so that the
    # running one's heartbeat (a third of the lease) notices the cancel quickly
    from mechsynth_client.schemas.common import FOURBAR_EXAMPLE

    url = f"sqlite:///{tmp_path / 'shared.sqlite'}"
    settings = Settings(executor="serial", database_url=url, study_lease_s=0.6)
    spec = {"endpoint": "/v1/balancing/static",
            "base": {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 360,
                     "max_radius_m": {"crank": 0.1, "rocker": 0.25}},
            "parameters": [{"path": "mass_budget_kg", "range": [2.0, 8.0], "count": 2000}],
            "metrics": ["total_added_mass_kg"]}
    with TestClient(create_app(settings)) as runner, TestClient(create_app(settings)) as other:
        study = f"/v1/studies/{runner.post('/v1/studies', json=spec).json()['id']}"
        while runner.get(study).json()["done"] < 5:
            time.sleep(0.05)
        assert other.delete(study).json()["state"] == "cancelled"
        deadline = time.monotonic() + 10
        while runner.get("/ready").json()["studies_running"] and time.monotonic() < deadline:
            time.sleep(0.1)
        assert runner.get("/ready").json()["studies_running"] == 0
        stopped = runner.get(study).json()
        assert stopped["state"] == "cancelled" and 5 <= stopped["done"] < 2000
        time.sleep(1.0)
        assert runner.get(study).json()["done"] == stopped["done"]     # nothing written after the cancel


def test_the_async_client_has_every_library_method(store_url: str) -> None:
    import asyncio
    import inspect

    import httpx

    from mechsynth_client.client import AsyncSynthClient
    from mechsynth_client.library import AsyncLibraryClient, LibraryClient

    def public(cls: type) -> set[str]:
        return {n for n, v in vars(cls).items() if not n.startswith("_") and callable(v)}

    assert public(LibraryClient) == public(AsyncLibraryClient)
    assert all(inspect.iscoroutinefunction(getattr(AsyncLibraryClient, n)) for n in public(AsyncLibraryClient))
    with TestClient(_app(store_url)) as http:       # started (workers, store); spoken to over ASGI below
        async def run() -> tuple[Any, ...]:
            transport = httpx.ASGITransport(app=http.app)
            async with AsyncSynthClient(http=httpx.AsyncClient(transport=transport, base_url="http://localhost")) as client:
                saved = await client.library.save("press", "linkage", "/v1/balancing/static", REQUEST, author="ann")
                return saved, await client.library.history("press", "linkage")

        saved, history = asyncio.run(run())
        assert [r.content_hash for r in history.revisions] == [saved.content_hash]
        assert SynthClient(http=http).library.revision("press", "linkage", 1).content_hash == saved.content_hash


def test_a_machine_record_downloaded_after_sign_off_carries_the_signed_title_block(tmp_path: Path) -> None:
    from mechsynth_client.schemas.machine import PRESS_EXAMPLE

    # one engine: two machine designs take long, and the record's update is the same statement on both
    with TestClient(_app(f"sqlite:///{tmp_path / 'store.sqlite'}")) as http:
        lib = SynthClient(http=http).library
        saved = lib.save("press", "machine", "/v1/machines/design", PRESS_EXAMPLE, author="ann")
        kept = lib.revision("press", "machine", 1)
        # the content hash is the record's own "request SHA-256": the title block is no part of the design
        assert kept.answer is not None and kept.answer["request_sha256"] == saved.content_hash
        draft = lib.record_pdf("press", "machine", 1)
        assert lib_text_holds(draft, "ann") and lib_text_holds(draft, "press/machine")
        assert lib_text_holds(draft, "draft") and lib_text_holds(draft, saved.content_hash)
        lib.check("press", "machine", 1, name="bob")
        lib.approve("press", "machine", 1, name="cid")
        signed = lib.record_pdf("press", "machine", 1)
        # written once: the signed record is kept and given again as it is
        assert lib.record_pdf("press", "machine", 1) == signed
    today = datetime.now(timezone.utc).strftime("%Y-%m-%d")
    first_page = "".join(PdfReader(io.BytesIO(signed)).pages[0].extract_text().split())
    for text in ("press/machine", "approved", "bob" + today, "cid" + today, saved.content_hash):
        assert text in first_page, text
    assert "draft" not in first_page
