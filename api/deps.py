"""Shared request dependencies as ``Annotated`` aliases: the app's settings and its solvers."""

from __future__ import annotations

import time
from typing import Annotated

from fastapi import Depends, Request

from .settings import Settings
from .execution.admission import RequestSolvers, Solvers


def get_settings(request: Request) -> Settings:
    """The settings the app was created with."""
    settings: Settings = request.app.state.settings
    return settings


def get_solvers(request: Request) -> RequestSolvers:
    """The app's solvers with this request's one deadline, counted from now."""
    solvers: Solvers = request.app.state.solvers
    return RequestSolvers(solvers, time.monotonic() + solvers.settings.request_deadline_s)


SettingsDep = Annotated[Settings, Depends(get_settings)]
SolverDep = Annotated[RequestSolvers, Depends(get_solvers)]
