"""The workbench page at ``/``: static ES modules from this package's ``web`` folder, a client of the public API.

The page carries no engine logic: it reads field descriptions and units from ``/openapi.json`` and calls the
``/v1`` endpoints like any other client. Everything it loads comes from this app (no outside host), so it works
on a design office's closed network.
"""

from __future__ import annotations

from importlib.resources import files

from fastapi import FastAPI
from fastapi.responses import FileResponse
from fastapi.staticfiles import StaticFiles

ASSETS_URL = "/workbench"
_WEB = files("api") / "web"


def install(app: FastAPI) -> None:
    """Serve the workbench at ``/`` and its modules, style and icon under ``/workbench``."""
    app.mount(ASSETS_URL, StaticFiles(directory=str(_WEB)), name="workbench")

    @app.get("/", include_in_schema=False)
    def workbench() -> FileResponse:
        # no-cache: a browser revalidates the page, so a new release's modules are picked up at once.
        return FileResponse(str(_WEB / "index.html"), media_type="text/html", headers={"Cache-Control": "no-cache"})
