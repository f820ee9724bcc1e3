"""The FastAPI application: health and readiness, the /v1 routers, problem responses and limits."""

from __future__ import annotations

import asyncio
import importlib
import pkgutil
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from typing import Any

from fastapi import APIRouter, FastAPI, Request

from . import manual, problems, routers
from .settings import Settings
from .solvers import Solvers
from .study_runs import StudyRuns


# Every design endpoint lives under this prefix; the studies name endpoints by their full path.
PREFIX = "/v1"


def all_routers() -> list[APIRouter]:
    """Every ``router`` in ``api.routers``, in module-name order."""
    found = []
    for info in sorted(pkgutil.iter_modules(routers.__path__), key=lambda i: i.name):
        module = importlib.import_module(f"{routers.__name__}.{info.name}")
        if isinstance(getattr(module, "router", None), APIRouter):
            found.append(module.router)
    return found


def create_app(settings: Settings | None = None) -> FastAPI:
    """Build the service with ``settings`` (default: from the environment)."""
    settings = settings or Settings.from_env()
    solvers = Solvers(settings)
    studies = StudyRuns(settings, solvers)

    @asynccontextmanager
    async def lifespan(_: FastAPI) -> AsyncIterator[None]:
        await asyncio.to_thread(solvers.start)
        await asyncio.to_thread(studies.open)
        yield
        studies.shutdown()
        solvers.shutdown()

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
    problems.install(app, settings)
    manual.install(app)

    @app.get("/health", tags=["service"])
    async def health() -> dict[str, str]:
        """Liveness probe; answers from the web process without touching the workers."""
        return {"status": "ok"}

    @app.get("/ready", tags=["service"])
    async def ready(request: Request) -> dict[str, Any]:
        """Readiness: the executor, its workers, running and queued requests, and the admission capacity."""
        status = request.app.state.solvers.status()
        return {"status": "ok" if status["queued"] < status["capacity"] else "busy", **status}

    for router in all_routers():
        app.include_router(router, prefix=PREFIX)
    problems.document(app)
    return app


app = create_app()
