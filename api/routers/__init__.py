"""One router per resource; every module here exposing ``router`` is mounted under :data:`PREFIX` by ``api.app``.

The design studies' router lives with the studies (:mod:`api.studies`), which read the routers here to learn
each endpoint's response model.
"""

from __future__ import annotations

import importlib
import pkgutil

from fastapi import APIRouter

# Every design endpoint lives under this prefix; the studies name endpoints by their full path.
PREFIX = "/v1"


def all_routers() -> list[APIRouter]:
    """Every ``router`` in ``api.routers``, in module-name order."""
    found = []
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda i: i.name):
        module = importlib.import_module(f"{__name__}.{info.name}")
        if isinstance(getattr(module, "router", None), APIRouter):
            found.append(module.router)
    return found
