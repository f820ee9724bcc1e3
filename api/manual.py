"""The offline manual: Swagger UI at /docs and ReDoc at /redoc from packaged assets (the workbench at / links it).

A design office's network often has no way out, so the pages load nothing from outside: the scripts, styles
and icon come from the ``fastapi_offline`` package's data, served by the app itself; Swagger UI's online
validator badge and ReDoc's web fonts are switched off.
"""

from __future__ import annotations

from importlib.resources import files

from fastapi import FastAPI
from fastapi.openapi.docs import get_redoc_html, get_swagger_ui_html, get_swagger_ui_oauth2_redirect_html
from fastapi.responses import HTMLResponse
from fastapi.routing import APIRoute
from fastapi.staticfiles import StaticFiles

ASSETS_URL = "/manual-assets"
_ASSETS = files("fastapi_offline") / "static"


def operation_id(route: APIRoute) -> str:
    """OpenAPI operation id of a route: its handler's name (``balance_static``), the client method's name."""
    return route.name


def install(app: FastAPI) -> None:
    """Serve the manual on ``app``, which must be created with ``docs_url=None, redoc_url=None``."""
    app.mount(ASSETS_URL, StaticFiles(directory=str(_ASSETS)), name="manual-assets")
    openapi_url = app.openapi_url or "/openapi.json"
    favicon = f"{ASSETS_URL}/favicon.png"

    @app.get("/docs", include_in_schema=False)
    def swagger_ui() -> HTMLResponse:
        return get_swagger_ui_html(
            openapi_url=openapi_url,
            title=f"{app.title}: manual",
            swagger_js_url=f"{ASSETS_URL}/swagger-ui-bundle.js",
            swagger_css_url=f"{ASSETS_URL}/swagger-ui.css",
            swagger_favicon_url=favicon,
            oauth2_redirect_url="/docs/oauth2-redirect",
            # validatorUrl null: no badge fetched from the public validator.
            swagger_ui_parameters={"validatorUrl": None, "defaultModelsExpandDepth": 1},
        )

    @app.get("/docs/oauth2-redirect", include_in_schema=False)
    def swagger_ui_redirect() -> HTMLResponse:
        return get_swagger_ui_oauth2_redirect_html()

    @app.get("/redoc", include_in_schema=False)
    def redoc() -> HTMLResponse:
        return get_redoc_html(
            openapi_url=openapi_url,
            title=f"{app.title}: manual",
            redoc_js_url=f"{ASSETS_URL}/redoc.standalone.js",
            redoc_favicon_url=favicon,
            with_google_fonts=False,
        )
