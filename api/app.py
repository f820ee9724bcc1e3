"""The FastAPI application: health and readiness, the /v1 routers, problem responses and limits."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from typing import Any, Literal

from fastapi import FastAPI, Request, Response
from pydantic import BaseModel, Field

from . import auth, manual, problems, workbench
from .routers import PREFIX, all_routers
from .settings import Settings
from .storage import migrate_at_start, open_store, store_status
from .execution.admission import Solvers
from .studies.router import router as studies_router
from .library.router import router as library_router
from .studies.runs import StudyRuns


class ReadyOut(BaseModel):
    """What the service's workers are doing: requests (bounded by admission) and design studies (beside it)."""

    status: Literal["ok", "busy", "warming", "degraded", "store-unavailable"] = Field(
        description="busy: every request slot is taken; new requests get 503. warming: a request worker runs "
                    "each capability once before it takes work (at the start, or after it was replaced; "
                    "requests wait for it or go to the others). degraded: a worker is being "
                    "replaced (requests wait for it or for the others), or the store takes no writes (`degraded` "
                    "says which). store-unavailable: the store cannot "
                    "be reached (store_problem says why); requests needing it get 503, and so does /ready.")
    executor: Literal["pool", "serial"] = Field(description="Where requests run: worker processes, or one thread.")
    started: bool = Field(description="The workers have been started.")
    workers: int = Field(description="Worker processes (1 for serial).")
    running: int = Field(description="Requests holding a worker slot. A study's tasks are not counted here: "
                                     "on the same workers, a request may first wait for one study task to end.")
    queued: int = Field(description="Requests waiting for a worker slot.")
    capacity: int = Field(description="Requests that may run or wait at once (workers + queue); beyond, 503.")
    completed: int = Field(description="Requests whose solver work ended, since the start.")
    timed_out: int = Field(description="Requests stopped at their deadline (504), since the start.")
    rejected: int = Field(description="Requests refused with 503 because every slot was taken, since the start.")
    studies_running: int = Field(description="Design studies this process runs now.")
    study_tasks_in_flight: int = Field(
        description="Design-study tasks (batches of variants) submitted and not finished, over all running studies: "
                    "at most workers + 1 per study. They bypass the request slots above, so while they run on "
                    "the same workers requests are slower, never refused.")
    workers_alive: int = Field(description="Request workers up now; fewer than `workers` while one is replaced.")
    workers_warm: int = Field(0, description="Request workers up and warm (each capability run once), ready to "
                                             "take work; fewer than `workers_alive` while one warms up.")
    worker_restarts: int = Field(description="Workers replaced since the start (died, timed out or cancelled).")
    batch_workers: int = Field(0, description="Workers of the study lane (0: studies share the request workers).")
    batch_workers_alive: int = Field(0, description="Study-lane workers up now.")
    tasks_queued: int = Field(0, description="Request tasks waiting for a worker.")
    batch_tasks_queued: int = Field(0, description="Study tasks waiting for a worker.")
    batch_tasks_running: int = Field(0, description="Study tasks on a worker now.")
    studies_queued: int = Field(0, description="Design studies waiting for a turn to run.")
    study_tasks_on: Literal["workers", "dask"] = Field(
        description="Where study tasks run: the service's own workers (shared with requests), or the Dask "
                    "cluster of SYNTH_DASK_SCHEDULER (requests unaffected).")
    store: str = Field(description="The store's engine: sqlite (embedded file) or postgresql.")
    store_ok: bool = Field(description="The store answered just now.")
    store_writable: bool = Field(True, description="The store takes writes now (false while it is locked by "
                                                   "another writer, read-only, or cannot be reached).")
    store_problem: str | None = Field(description="Why the store cannot be reached or cannot take writes, when so.")
    degraded: list[Literal["store", "workers"]] = Field(
        default_factory=list, description="What works in part now: store (it answers reads but takes no writes: "
                                          "saving, starting studies and signing in answer 503 with Retry-After), "
                                          "workers (a worker is being replaced).")


async def _build_route_table(app: FastAPI) -> None:
    """Match one path no route has against the whole route table; its 404 goes nowhere.

    FastAPI builds a router's routes (their parameters' validators and dependencies) on the first request that
    reaches it: about 70 ms for the machines' routes, which the first optimisation after a start would pay. A
    path that matches nothing is tried against every route, so every router is built here, before the service
    says it is ready.
    """
    path = "/.route-table"
    scope: dict[str, Any] = {"type": "http", "asgi": {"version": "3.0"}, "http_version": "1.1", "method": "GET",
                             "scheme": "http", "path": path, "raw_path": path.encode(), "root_path": "",
                             "query_string": b"", "headers": [], "client": ("127.0.0.1", 0),
                             "server": ("127.0.0.1", 0)}

    async def receive() -> dict[str, Any]:
        return {"type": "http.request", "body": b"", "more_body": False}

    async def send(_: Any) -> None:
        return None

    await app.router(scope, receive, send)


def create_app(settings: Settings | None = None) -> FastAPI:
    """Build the service with ``settings`` (default: from the environment)."""
    settings = settings or Settings.from_env()
    solvers = Solvers(settings)
    store = open_store(settings)
    studies = StudyRuns(settings, solvers, store)

    @asynccontextmanager
    async def lifespan(_: FastAPI) -> AsyncIterator[None]:
        await asyncio.to_thread(migrate_at_start, store)
        await asyncio.to_thread(auth.start, app)
        await asyncio.to_thread(solvers.start)
        await asyncio.to_thread(studies.open)
        await _build_route_table(app)
        yield
        await asyncio.to_thread(auth.stop, app)
        studies.shutdown()
        solvers.shutdown()
        store.dispose()

    app = FastAPI(
        title="Mechanism synthesis service",
        version="0.1.0",
        description=(
            "Analyse planar linkages over a cycle, balance them with counterweights, size flywheels and design "
            "drives. SI units; field names carry their unit. Errors are RFC 9457 problem responses."
        ),
        lifespan=lifespan,
        docs_url=None,
        redoc_url=None,
        generate_unique_id_function=manual.operation_id,
    )
    app.state.settings = settings
    app.state.solvers = solvers
    app.state.studies = studies
    app.state.store = store
    problems.install(app, settings)
    manual.install(app)
    workbench.install(app)
    auth.install(app, settings)

    @app.get("/health", tags=["service"])
    async def health() -> dict[str, str]:
        """Liveness probe; answers from the web process without touching the workers."""
        return {"status": "ok"}

    @app.get("/ready", tags=["service"], response_model=ReadyOut,
             responses={503: {"model": ReadyOut, "description": "The store cannot be reached; store_problem "
                                                                  "says why."}})
    async def ready(request: Request, response: Response) -> ReadyOut:
        """Readiness: the executor, its workers, running and queued requests, the admission capacity, the
        design studies' work beside the requests, and whether the store answers (503 when it does not)."""
        status = request.app.state.solvers.status()
        stored = await asyncio.to_thread(store_status, request.app.state.store)
        state: Literal["ok", "busy", "warming", "degraded", "store-unavailable"] = (
            "ok" if status["queued"] < status["capacity"] else "busy")
        if status["started"] and status["workers_warm"] < status["workers_alive"]:
            state = "warming"
        degraded: list[Literal["store", "workers"]] = []
        if status["started"] and status["workers_alive"] < status["workers"]:
            state = "degraded"
            degraded.append("workers")
        if not stored["store_writable"]:
            state = "degraded"
            degraded.append("store")
        if not stored["store_ok"]:
            state = "store-unavailable"
            response.status_code = 503
        return ReadyOut(status=state, **status, **request.app.state.studies.status(), **stored, degraded=degraded)

    for router in (*all_routers(), studies_router, library_router, auth.router):
        app.include_router(router, prefix=PREFIX)
    problems.document(app)
    return app


app = create_app()
