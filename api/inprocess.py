"""The service in the caller's own process, for the client's in-process mode (tests, notebooks, scripts).

The client package knows nothing of the service: it finds this module through the entry point
``mechsynth_client.inprocess`` that the service's distribution declares (``pyproject.toml``), and asks it for an
app or an HTTP client bound to one. Installing the service is what makes ``SynthClient.in_process()`` work.
"""

from __future__ import annotations

import warnings
from typing import Any, Literal

import httpx

from .app import create_app
from .settings import Settings

Executor = Literal["serial", "pool"]


def app(executor: Executor = "serial") -> Any:
    """A fresh ASGI app of the service whose solver work runs on ``executor``."""
    return create_app(Settings(executor=executor))


def http_client(executor: Executor = "serial", base_url: str = "http://localhost") -> httpx.Client:
    """A synchronous HTTP client that speaks to a fresh app in this process, without a network."""
    with warnings.catch_warnings():
        # starlette announces a future move of its test client to another HTTP library; ours speaks httpx.
        warnings.filterwarnings("ignore", message="Using `httpx` with `starlette.testclient`")
        from fastapi.testclient import TestClient

    return TestClient(app(executor), base_url=base_url)
