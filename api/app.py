"""The FastAPI application: health, the /v1 routers, problem responses and limits."""

from __future__ import annotations

import importlib
import pkgutil

from fastapi import APIRouter, FastAPI

from . import manual, problems, routers
from .settings import Settings
from .solvers import SolverGate


def _routers() -> list[APIRouter]:
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
    app = FastAPI(
        title="Mechanism synthesis service",
        version="0.1.0",
        description=(
            "Analyse planar linkages over a cycle, balance them with counterweights, size flywheels and design "
            "drives. SI units; field names carry their unit. Errors are RFC 9457 problem responses."
        ),
        docs_url=None,
        redoc_url=None,
        generate_unique_id_function=manual.operation_id,
    )
    app.state.settings = settings
    app.state.solver_gate = SolverGate(settings.solver_wait_s)
    problems.install(app, settings.max_body_bytes)
    manual.install(app)

    @app.get("/health", tags=["service"])
    def health() -> dict[str, str]:
        """Liveness probe."""
        return {"status": "ok"}

    for router in _routers():
        app.include_router(router, prefix="/v1")
    return app


app = create_app()
