"""Shared request dependencies as ``Annotated`` aliases: the app's settings and its solvers (with the answer's
precision for the endpoints that answer with a computed result)."""

from __future__ import annotations

import time
from dataclasses import replace
from typing import Annotated

from fastapi import Depends, Request

from .media import PrecisionQuery
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


def get_answer_solvers(request: Request, precision: PrecisionQuery = "single") -> RequestSolvers:
    """The request's solvers (:func:`get_solvers`) answering with the digits ``?precision=`` asks for."""
    return replace(get_solvers(request), precision=precision)


SettingsDep = Annotated[Settings, Depends(get_settings)]
SolverDep = Annotated[RequestSolvers, Depends(get_solvers)]
#: The solvers of an endpoint answering with a computed result: it takes ``?precision=`` too.
AnswerSolverDep = Annotated[RequestSolvers, Depends(get_answer_solvers)]
